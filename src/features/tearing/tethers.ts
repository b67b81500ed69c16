import { createAnchorScratch, loosenTethers, nearestAnchorsAlongMesh, type AnchorScratch, type TetherSet } from '../../model/tethers'
import type { ClothState, ClothWorldState } from '../../world/state'
import type { ClothTear } from './types'
import { newArray, touchLayout } from '../../core/shared'
import { anchorsMoveTogether } from '../pins/step'

/**
 * Rebuilds a tearable cloth's tethers without allocating: each free particle is tied to the
 * `perParticle` pinned particles nearest to it along the split mesh (multi-source Dijkstra on a
 * typed-array heap), with the straight rest distance ('euclidean') or the path length
 * ('geodesic'). Measured along the mesh, the nearest anchors are never across a tear and never in
 * another piece, so torn pieces hang free and a crack is not held shut by the pins on its far
 * side. Runs in the sync phase after pins changed or the cloth tore.
 */
export function rebuildTearTethers(state: ClothWorldState, c: ClothState): void {
  const T = c.tear!
  // more tethers per particle than reserved (setClothTethers, a restored snapshot): reserve again
  const ct = c.tethers
  if (ct.perParticle > T.scratch.kCap) reserveTearTethers(T, ct.perParticle)
  const t = T.topology
  const s = T.scratch
  const out = T.tethers
  const n = c.count
  const K = ct.perParticle
  let A = 0
  for (let i = 0; i < n; i++) if (c.pinCount[i] > 0) s.anchors[A++] = i
  out.count = 0
  if (ct.set !== out) touchLayout()
  ct.set = out
  state.stats.tetherRebuilds++
  if (A === 0) return
  // anchors chosen along the split mesh (so a tether never reaches across a tear, and never into
  // another piece); the rest length is the straight distance ('euclidean') or the path ('geodesic')
  const rest = t.restPositions
  nearestAnchorsAlongMesh(rest, n, t.edges, t.edgeCount, s, A, K)
  const best = s.bestAnchor, dist = s.bestDist
  const straight = ct.mode !== 'geodesic'
  const slack = 1 + ct.slack
  let m = 0
  for (let i = 0; i < n; i++) {
    if (c.pinCount[i] > 0) continue
    for (let k = 0; k < K; k++) {
      const a = best[i * K + k]
      if (a < 0) continue
      out.particle[m] = i
      out.anchor[m] = a
      let d = dist[i * K + k]
      if (straight) {
        const dx = rest[3 * a] - rest[3 * i], dy = rest[3 * a + 1] - rest[3 * i + 1], dz = rest[3 * a + 2] - rest[3 * i + 2]
        d = Math.sqrt(dx * dx + dy * dy + dz * dz)
      }
      out.rest[m] = d * slack
      m++
    }
  }
  out.count = m
  // pins on things that move apart may have lengthened the old tethers (see `solveTethers`): the
  // new ones start no tighter than the cloth is, or a tear would snap it back at once
  if (ct.loosen || !anchorsMoveTogether(state, c)) loosenTethers(out, c.pos)
  ct.loosen = false
}

/** Reserves a tearable cloth's tether arrays again for `perParticle` tethers per particle at its particle capacity. */
function reserveTearTethers(T: ClothTear, perParticle: number): void {
  Object.assign(T, tetherStore(T.particleCapacity, T.topology.edges.length / 2, perParticle))
}

/** Tether arrays and their scratch for P particles, E mesh edges and K tethers per particle. */
export function tetherStore(P: number, E: number, K: number): { tethers: TetherSet; scratch: AnchorScratch } {
  return {
    tethers: { particle: newArray(Int32Array, P * K), anchor: newArray(Int32Array, P * K), rest: newArray(Float64Array, P * K), count: 0 },
    scratch: createAnchorScratch(P, E, K),
  }
}
