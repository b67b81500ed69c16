import { findOverstrained } from '../../kernels/strain'
import type { ClothState, ClothWorldState } from '../../world/state'
import { copyGuardParticle } from '../guard/api'
import { refreshClothWind } from '../wind/step'
import { repairConstraints } from './repair'
import { EV, type ClothTear } from './types'

/** Tear phase for one cloth on its last substep of the step: measure, split, repair. */
export function tearStep(state: ClothWorldState, c: ClothState): void {
  const T = c.tear!
  if (!T.enabled) return
  const store = state.components.Tearable
  const eid = c.eid
  const t = T.topology
  const S = T.edges
  const strain = store.strain[eid]
  const max = store.maxTearsPerStep[eid]
  const p = T.params
  p[0] = (1 + strain) * (1 + strain)
  p[1] = store.hysteresis[eid]
  // more candidates than tears allowed: an edge that cannot split yet must not block the others
  p[2] = Math.min(T.cand.length, 2 * max + 4)
  const n = findOverstrained(c.pos, t.edges, t.edgeRest, S.count, T.over, p, T.cand, T.candRatio)
  state.stats.strainChecks += S.count
  if (n === 0) return
  const tris = t.triangles
  const tw = state.tearing
  let tears = 0
  for (let q = 0; q < n; q++) {
    if (c.count >= T.particleCapacity || tears >= max) break
    const k = T.cand[q]
    // the edge's particles now (an earlier split this step may have re-indexed them)
    const tA = S.endT[2 * k]
    const a = tA >= 0 ? tris[3 * tA + S.endC[2 * k]] : t.edges[2 * k]
    const b = tA >= 0 ? tris[3 * S.endT[2 * k + 1] + S.endC[2 * k + 1]] : t.edges[2 * k + 1]
    let first = a, second = b
    if (c.pinCount[a] > 0 && c.pinCount[b] === 0) {
      first = b
      second = a
    }
    // a clean cut across the edge at either end; failing that (a fan already cut into a sliver),
    // cut the edge's own triangles away from the rest of an end's fan
    let split = first
    let nv = splitParticle(c, T, first, second, 0)
    if (nv < 0) nv = splitParticle(c, T, (split = second), first, 0)
    if (nv < 0) nv = splitParticle(c, T, (split = first), second, 1)
    if (nv < 0) nv = splitParticle(c, T, (split = second), first, 1)
    // both ends hold only the edge's own two triangles (a diamond left between two cracks): part them
    if (nv < 0) nv = splitParticle(c, T, (split = first), second, 2)
    if (nv < 0) continue
    T.over[k] = 0
    tears++
    if ((tw.pendingCount + 1) * EV <= tw.pending.length) {
      const o = tw.pendingCount++ * EV
      const pos = c.pos
      tw.pending[o] = eid
      tw.pending[o + 1] = pos[3 * split]
      tw.pending[o + 2] = pos[3 * split + 1]
      tw.pending[o + 3] = pos[3 * split + 2]
      tw.pending[o + 4] = split
      tw.pending[o + 5] = nv
      tw.pending[o + 6] = Math.sqrt(T.candRatio[q] * p[0]) - 1
    }
  }
  if (tears === 0) return
  repairConstraints(T)
  labelPieces(c, T)
  if (c.tethers.enabled) c.tethers.dirty = true
  refreshClothWind(c)
  store.tears[eid] += tears
  state.stats.tears += tears
}

/**
 * Splits particle v. Mode 0: across the plane through v perpendicular to v → o (rest shape), the
 * far side's triangles moving to the new particle. Mode 1: the triangles that hold o move. Mode 2:
 * all but the first triangle move. Returns
 * the new particle, or −1 when every triangle of v lies on one side (nothing to split) or the
 * capacity is used up.
 */
function splitParticle(c: ClothState, T: ClothTear, v: number, o: number, mode: number): number {
  const t = T.topology
  const tris = t.triangles
  const pos = c.pos
  // classified on the rest shape: a fan stretched to many times its size can have every centroid
  // on the far side in the current pose, while at rest it is a clean fan the plane cuts in two
  const rest = t.restPositions
  const px = rest[3 * v], py = rest[3 * v + 1], pz = rest[3 * v + 2]
  const dx = rest[3 * o] - px, dy = rest[3 * o + 1] - py, dz = rest[3 * o + 2] - pz
  const fan = T.fan, corner = T.fanCorner, side = T.fanSide
  let fc = 0, plus = 0
  for (let tt = 0; tt < t.triangleCount; tt++) {
    const base = 3 * tt
    const i0 = tris[base], i1 = tris[base + 1], i2 = tris[base + 2]
    const k = i0 === v ? 0 : i1 === v ? 1 : i2 === v ? 2 : -1
    if (k < 0) continue
    const sx = rest[3 * i0] + rest[3 * i1] + rest[3 * i2] - 3 * px
    const sy = rest[3 * i0 + 1] + rest[3 * i1 + 1] + rest[3 * i2 + 1] - 3 * py
    const sz = rest[3 * i0 + 2] + rest[3 * i1 + 2] + rest[3 * i2 + 2] - 3 * pz
    const s = mode === 0 ? (sx * dx + sy * dy + sz * dz > 0 ? 1 : 0) : mode === 1 ? (i0 === o || i1 === o || i2 === o ? 1 : 0) : fc > 0 ? 1 : 0
    fan[fc] = tt
    corner[fc] = k
    side[fc] = s
    plus += s
    fc++
  }
  if (plus === 0 || plus === fc) return -1
  const nv = c.count
  if (nv >= T.particleCapacity) return -1
  let areaPlus = 0, areaAll = 0
  for (let f = 0; f < fc; f++) {
    const base = 3 * fan[f]
    const ra = 3 * tris[base], rb = 3 * tris[base + 1], rc = 3 * tris[base + 2]
    const ux = rest[rb] - rest[ra], uy = rest[rb + 1] - rest[ra + 1], uz = rest[rb + 2] - rest[ra + 2]
    const vx = rest[rc] - rest[ra], vy = rest[rc + 1] - rest[ra + 1], vz = rest[rc + 2] - rest[ra + 2]
    const cx = uy * vz - uz * vy, cy = uz * vx - ux * vz, cz = ux * vy - uy * vx
    const A = Math.sqrt(cx * cx + cy * cy + cz * cz) // twice the area: only ratios matter
    areaAll += A
    if (side[f] === 1) {
      areaPlus += A
      tris[base + corner[f]] = nv
    }
  }
  for (let j = 0; j < 3; j++) {
    pos[3 * nv + j] = pos[3 * v + j]
    c.prev[3 * nv + j] = c.prev[3 * v + j]
    c.vel[3 * nv + j] = c.vel[3 * v + j]
    rest[3 * nv + j] = rest[3 * v + j]
  }
  const uvs = c.render.uvs
  uvs[2 * nv] = uvs[2 * v]
  uvs[2 * nv + 1] = uvs[2 * v + 1]
  copyGuardParticle(c, v, nv)
  // share the mass by rest area, neither part below 20 % (extreme mass ratios hurt Gauss-Seidel)
  let frac = areaAll > 0 ? areaPlus / areaAll : 0.5
  if (frac < 0.2) frac = 0.2
  else if (frac > 0.8) frac = 0.8
  const m = 1 / c.baseInvMass[v]
  const mPlus = m * frac, mMinus = m - mPlus
  t.masses[nv] = mPlus
  t.masses[v] = mMinus
  c.baseInvMass[nv] = 1 / mPlus
  c.baseInvMass[v] = 1 / mMinus
  c.invMass[nv] = 1 / mPlus
  if (c.pinCount[v] === 0) c.invMass[v] = 1 / mMinus
  c.pinCount[nv] = 0
  c.count = nv + 1
  t.particleCount = nv + 1
  return nv
}

/**
 * Labels the connected pieces of the split mesh (triangles joined through shared particles):
 * union-find with the smaller index as root, so labels follow the lowest particle of each piece.
 */
export function labelPieces(c: ClothState, T: ClothTear): void {
  const count = c.count
  const t = T.topology
  const tris = t.triangles
  const root = T.pieceRoot, label = c.piece!
  for (let i = 0; i < count; i++) root[i] = i
  for (let k = 0; k < t.triangleCount; k++) {
    const a = findRoot(root, tris[3 * k])
    const b = findRoot(root, tris[3 * k + 1])
    const c = findRoot(root, tris[3 * k + 2])
    const m = a < b ? (a < c ? a : c) : b < c ? b : c
    root[a] = m
    root[b] = m
    root[c] = m
  }
  let n = 0
  for (let i = 0; i < count; i++) {
    const r = findRoot(root, i)
    label[i] = r === i ? n++ : label[r]
  }
  c.pieceCount = n
}

function findRoot(root: Int32Array, i: number): number {
  while (root[i] !== i) {
    root[i] = root[root[i]]
    i = root[i]
  }
  return i
}
