import { grownArray } from '../../core/store'
import { growClothParticles } from '../../world/capacity'
import type { ClothState, ClothWorldState } from '../../world/state'
import { allocateSelfCollision } from '../collision/selfCollision'
import { reserveGuard } from '../guard/api'
import { reserveCharacter } from '../character/api'
import { ensureClothWind } from '../wind/step'
import { labelPieces } from './step'
import { tetherStore } from './tethers'
import type { ClothTopology } from '../../model/topology'
import type { HingeSet, LineSet, PairSet, TearTopology } from './types'
import { newArray, arrayOf } from '../../core/shared'

/**
 * Gives cloth `c` its own rest data with room for `extra` more particles and the constraints their
 * splits add, and grows every per-particle array of the cloth and of its features to that capacity
 * (creation time: allocation allowed; a step never allocates, tear or not).
 */
export function reserve(state: ClothWorldState, c: ClothState, extra: number, maxTears: number): void {
  const src = c.topology
  const P = c.count + extra
  const room = 4 * extra
  const E = src.edgeCount + room, S = src.stretchCount + room, D = src.distCount + room, C = src.compCount + room
  const t = reserveTopology(src, c.count, P, E, S, D, C)
  const mesh = new MeshIndex(t.triangles, t.triangleCount)
  const over = newArray(Uint8Array, E)
  const stretch = pairSet(t.stretchIds, 1, t.stretchCount, S, [t.stretchRest], [], null, mesh, t.restPositions)
  const edges = pairSet(t.edges, 1, t.edgeCount, E, [t.edgeRest], [over], over, mesh, t.restPositions)
  const dist = pairSet(t.distOffsets, 3, t.distCount, D, [t.distRest, t.distCompliance], [t.distKind], null, mesh, t.restPositions)
  const comp = pairSet(t.compIds, 1, t.compCount, C, [t.compRest, t.compCompliance], [], null, mesh, t.restPositions)
  const lines = lineSet(t, mesh)
  t.lineCount = lines.count
  const hinges = hingeSet(t, mesh)
  t.hingeCount = hinges.count

  growClothParticles(c, P)
  c.distLambda = newArray(Float64Array, D)
  c.compLambda = newArray(Float64Array, C)
  c.lineLambda = newArray(Float64Array, Math.max(1, 3 * t.lineCount))
  c.hingeLambda = newArray(Float64Array, Math.max(1, t.hingeCount))
  c.render.indices = t.triangles
  c.topology = t
  c.piece = newArray(Int32Array, P)
  c.detached = grownArray(c.detached, P + 1)
  c.pieceCount = 1

  c.tear = {
    enabled: true,
    topology: t,
    particleCapacity: P,
    stretch,
    edges,
    dist,
    comp,
    lines,
    hinges,
    over,
    ...vertexTriangles(t, P),
    tip: newArray(Uint8Array, P),
    splitAt: newArray(Int32Array, P),
    stepCount: 0,
    grewAt: -2,
    fan: newArray(Int32Array, t.triangleCount),
    fanCorner: newArray(Uint8Array, t.triangleCount),
    fanSide: newArray(Uint8Array, t.triangleCount),
    fanP: newArray(Int32Array, t.triangleCount),
    fanQ: newArray(Int32Array, t.triangleCount),
    fanCount: 0,
    walk: newArray(Int32Array, t.triangleCount),
    walkW: newArray(Int32Array, t.triangleCount),
    chains: newArray(Int32Array, 3 * t.triangleCount),
    chainEntry: newArray(Int32Array, t.triangleCount),
    chainCount: 0,
    seam: newArray(Int32Array, 2),
    vec: newArray(Float64Array, 12),
    mat: newArray(Float64Array, 9),
    triSide: newArray(Uint8Array, t.triangleCount),
    seen: newArray(Int32Array, t.triangleCount),
    stamp: 0,
    queue: newArray(Int32Array, MAX_MIN_PIECE + 1),
    cand: newArray(Int32Array, 2 * maxTears + 4),
    candRatio: newArray(Float64Array, 2 * maxTears + 4),
    params: newArray(Float64Array, 3),
    ...tetherStore(P, E, c.tethers.perParticle),
    pieceRoot: newArray(Int32Array, P),
  }
  labelPieces(c, c.tear)
  c.tethers.dirty = true
  // every feature's per-particle arrays follow the new capacity, whatever was enabled before
  reserveGuard(c, P)
  reserveCharacter(c, P)
  if (c.wind !== null) ensureClothWind(c)
  if (c.collision.self !== null) allocateSelfCollision(state, c)
}

/** Largest `minPiece` (the smallest-piece test's queue holds that many triangles). */
export const MAX_MIN_PIECE = 4096

/** Triangles around each of the mesh's particles, room for P particles (a split divides a slice). */
function vertexTriangles(t: TearTopology, P: number): { vertStart: Int32Array; vertLen: Int32Array; vertTris: Int32Array } {
  const vertStart = newArray(Int32Array, P), vertLen = newArray(Int32Array, P), vertTris = newArray(Int32Array, 3 * t.triangleCount)
  const tris = t.triangles
  for (let k = 0; k < 3 * t.triangleCount; k++) vertLen[tris[k]]++
  for (let p = 1; p < t.particleCount; p++) vertStart[p] = vertStart[p - 1] + vertLen[p - 1]
  const fill = new Int32Array(P)
  for (let k = 0; k < t.triangleCount; k++) {
    for (let j = 0; j < 3; j++) {
      const p = tris[3 * k + j]
      vertTris[vertStart[p] + fill[p]++] = k
    }
  }
  return { vertStart, vertLen, vertTris }
}

/** A copy of the shared rest data with room for P particles and E, S, D, C edges, stretch, distance and compression constraints. */
function reserveTopology(src: ClothTopology, count: number, P: number, E: number, S: number, D: number, C: number): TearTopology {
  const t: TearTopology = {
    ...src,
    particleCount: count,
    restPositions: grownArray(src.restPositions, 3 * P),
    masses: grownArray(src.masses, P),
    unused: src.unused === null ? null : grownArray(src.unused, P), // (particles made by tears are used)
    triangles: arrayOf(Uint32Array, src.triangles),
    edges: grownArray(src.edges.subarray(0, 2 * src.edgeCount), 2 * E),
    edgeRest: grownArray(src.edgeRest.subarray(0, src.edgeCount), E),
    stretchIds: grownArray(src.stretchIds.subarray(0, 2 * src.stretchCount), 2 * S),
    stretchRest: grownArray(src.stretchRest.subarray(0, src.stretchCount), S),
    distOffsets: grownArray(src.distOffsets.subarray(0, 2 * src.distCount), 2 * D),
    distRest: grownArray(src.distRest.subarray(0, src.distCount), D),
    distCompliance: grownArray(src.distCompliance.subarray(0, src.distCount), D),
    distKind: grownArray(src.distKind.subarray(0, src.distCount), D),
    compIds: grownArray(src.compIds.subarray(0, 2 * src.compCount), 2 * C),
    compRest: grownArray(src.compRest.subarray(0, src.compCount), C),
    compCompliance: grownArray(src.compCompliance.subarray(0, src.compCount), C),
    lineIds: arrayOf(Int32Array, src.lineIds.subarray(0, 3 * src.lineCount)),
    lineRest: arrayOf(Float64Array, src.lineRest.subarray(0, src.lineCount)),
    lineCompliance: arrayOf(Float64Array, src.lineCompliance.subarray(0, src.lineCount)),
    hingeIds: arrayOf(Int32Array, src.hingeIds.subarray(0, 4 * src.hingeCount)),
    hingeRest: arrayOf(Float64Array, src.hingeRest.subarray(0, src.hingeCount)),
    hingeCompliance: arrayOf(Float64Array, src.hingeCompliance.subarray(0, src.hingeCount)),
  }
  return t
}

/** Triangles around each edge and vertex of a mesh (creation time). */
class MeshIndex {
  /** Triangles holding edge (min, max): key min·2²⁶… as a string-free number key. */
  readonly edgeTris = new Map<number, number[]>()
  readonly neighbours = new Map<number, Set<number>>()
  /** Across-edge pairs: key of (w0, w1) → [e0, e1, tA (holds w0), tB (holds w1)]. */
  readonly wings = new Map<number, [number, number, number, number]>()
  constructor(readonly tris: Uint32Array, triCount: number) {
    for (let t = 0; t < triCount; t++) {
      for (let k = 0; k < 3; k++) {
        const a = tris[3 * t + k], b = tris[3 * t + ((k + 1) % 3)]
        const key = pairKey(a, b)
        let list = this.edgeTris.get(key)
        if (!list) this.edgeTris.set(key, list = [])
        list.push(t)
        this.link(a, b)
      }
    }
    for (const [key, list] of this.edgeTris) {
      if (list.length !== 2) continue
      const e0 = Math.floor(key / KEY), e1 = key % KEY
      const w0 = this.third(list[0], e0, e1), w1 = this.third(list[1], e0, e1)
      const wk = pairKey(w0, w1)
      if (!this.wings.has(wk)) this.wings.set(wk, w0 < w1 ? [e0, e1, list[0], list[1]] : [e0, e1, list[1], list[0]])
    }
  }
  private link(a: number, b: number): void {
    let s = this.neighbours.get(a)
    if (!s) this.neighbours.set(a, s = new Set())
    s.add(b)
    let r = this.neighbours.get(b)
    if (!r) this.neighbours.set(b, r = new Set())
    r.add(a)
  }
  corner(t: number, v: number): number {
    const tr = this.tris
    return tr[3 * t] === v ? 0 : tr[3 * t + 1] === v ? 1 : tr[3 * t + 2] === v ? 2 : -1
  }
  third(t: number, a: number, b: number): number {
    for (let k = 0; k < 3; k++) {
      const v = this.tris[3 * t + k]
      if (v !== a && v !== b) return v
    }
    return -1
  }
  /** True when triangle t runs a → b in its winding. */
  runs(t: number, a: number, b: number): boolean {
    const ca = this.corner(t, a)
    return ca >= 0 && this.tris[3 * t + ((ca + 1) % 3)] === b
  }
}

const KEY = 1 << 26
function pairKey(a: number, b: number): number {
  return a < b ? a * KEY + b : b * KEY + a
}

function pairSet(
  ids: Int32Array,
  scale: number,
  count: number,
  cap: number,
  f64: Float64Array[],
  u8: Uint8Array[],
  over: Uint8Array | null,
  mesh: MeshIndex,
  rest: Float64Array,
): PairSet {
  const s: PairSet = {
    ids,
    scale,
    f64,
    u8,
    over,
    count,
    cap,
    endT: newArray(Int32Array, 2 * cap).fill(-1),
    endC: newArray(Uint8Array, 2 * cap),
    chkT: newArray(Int32Array, 4 * cap).fill(-1),
    chkC: newArray(Uint8Array, 4 * cap),
    twinT: newArray(Int32Array, cap).fill(-1),
    twinC: newArray(Uint8Array, 2 * cap),
  }
  for (let k = 0; k < count; k++) {
    const a = ids[2 * k] / scale, b = ids[2 * k + 1] / scale
    const tris = mesh.edgeTris.get(pairKey(a, b))
    if (tris) {
      // an edge: read from its first triangle; the second one is its twin
      const t1 = tris[0]
      s.endT[2 * k] = s.endT[2 * k + 1] = t1
      s.endC[2 * k] = mesh.corner(t1, a)
      s.endC[2 * k + 1] = mesh.corner(t1, b)
      if (tris.length === 2) {
        s.twinT[k] = tris[1]
        s.twinC[2 * k] = mesh.corner(tris[1], a)
        s.twinC[2 * k + 1] = mesh.corner(tris[1], b)
      }
      continue
    }
    const wing = mesh.wings.get(pairKey(a, b))
    if (wing) {
      // across an edge: a in one triangle, b in the other, and they must still share the edge
      const [e0, e1, t0, t1] = wing
      const tA = mesh.corner(t0, a) >= 0 ? t0 : t1, tB = tA === t0 ? t1 : t0
      s.endT[2 * k] = tA
      s.endT[2 * k + 1] = tB
      s.endC[2 * k] = mesh.corner(tA, a)
      s.endC[2 * k + 1] = mesh.corner(tB, b)
      setCheck(s.chkT, s.chkC, 4 * k, tA, mesh.corner(tA, e0), tB, mesh.corner(tB, e0))
      setCheck(s.chkT, s.chkC, 4 * k + 2, tA, mesh.corner(tA, e1), tB, mesh.corner(tB, e1))
      continue
    }
    skipOneEnds(s, k, a, b, mesh, rest)
  }
  return s
}

/** A skip-one pair a – m – b: read from the two triangles along its edges, on the same side of the line. */
function skipOneEnds(s: PairSet, k: number, a: number, b: number, mesh: MeshIndex, rest: Float64Array): void {
  // skip-one: a – m – b along two edges that must keep meeting at the same m
  const na = mesh.neighbours.get(a), nb = mesh.neighbours.get(b)
  if (!na || !nb) return
  let m = -1, best = Infinity
  for (const x of na) {
    if (!nb.has(x)) continue
    let d = 0
    for (let j = 0; j < 3; j++) {
      const mid = 0.5 * (rest[3 * a + j] + rest[3 * b + j]) - rest[3 * x + j]
      d += mid * mid
    }
    if (d < best) {
      best = d
      m = x
    }
  }
  if (m < 0) return
  const ta = mesh.edgeTris.get(pairKey(a, m))!, tb = mesh.edgeTris.get(pairKey(m, b))!
  // take both triangles from the same side of the line a – m – b (same winding direction)
  let tA = ta[0], tB = -1
  const forward = mesh.runs(tA, a, m)
  for (const x of tb) if (mesh.runs(x, m, b) === forward) tB = x
  if (tB < 0) tB = tb[0]
  s.endT[2 * k] = tA
  s.endT[2 * k + 1] = tB
  s.endC[2 * k] = mesh.corner(tA, a)
  s.endC[2 * k + 1] = mesh.corner(tB, b)
  setCheck(s.chkT, s.chkC, 4 * k, tA, mesh.corner(tA, m), tB, mesh.corner(tB, m))
}

function setCheck(chkT: Int32Array, chkC: Uint8Array, o: number, ta: number, ca: number, tb: number, cb: number): void {
  chkT[o] = ta
  chkT[o + 1] = tb
  chkC[o] = ca
  chkC[o + 1] = cb
}

function lineSet(t: TearTopology, mesh: MeshIndex): LineSet {
  const n = t.lineCount
  const l: LineSet = {
    ids: t.lineIds,
    f64: [t.lineRest, t.lineCompliance],
    count: n,
    endT: newArray(Int32Array, 2 * n),
    endC: newArray(Uint8Array, 3 * n),
    chkT: newArray(Int32Array, 2 * n),
    chkC: newArray(Uint8Array, 2 * n),
  }
  let w = 0
  for (let k = 0; k < n; k++) {
    const a = t.lineIds[3 * k], v = t.lineIds[3 * k + 1], b = t.lineIds[3 * k + 2]
    const ta = mesh.edgeTris.get(pairKey(a, v)), tb = mesh.edgeTris.get(pairKey(v, b))
    if (!ta || !tb) continue // not along mesh edges (quad grids' rows are): keep no support, drop
    // both triangles from the same side of the line a – v – b (same winding direction)
    const tA = ta[0]
    const forward = mesh.runs(tA, a, v)
    let tB = -1
    for (const x of tb) if (mesh.runs(x, v, b) === forward) tB = x
    if (tB < 0) tB = tb[0]
    for (let j = 0; j < 3; j++) t.lineIds[3 * w + j] = t.lineIds[3 * k + j]
    t.lineRest[w] = t.lineRest[k]
    t.lineCompliance[w] = t.lineCompliance[k]
    l.endT[2 * w] = tA
    l.endT[2 * w + 1] = tB
    l.endC[3 * w] = mesh.corner(tA, a)
    l.endC[3 * w + 1] = mesh.corner(tA, v)
    l.endC[3 * w + 2] = mesh.corner(tB, b)
    l.chkT[2 * w] = tA
    l.chkT[2 * w + 1] = tB
    l.chkC[2 * w] = mesh.corner(tA, v)
    l.chkC[2 * w + 1] = mesh.corner(tB, v)
    w++
  }
  l.count = w
  return l
}

function hingeSet(t: TearTopology, mesh: MeshIndex): HingeSet {
  const n = t.hingeCount
  const h: HingeSet = {
    ids: t.hingeIds,
    f64: [t.hingeRest, t.hingeCompliance],
    count: n,
    endT: newArray(Int32Array, 2 * n),
    endC: newArray(Uint8Array, 4 * n),
    chkT: newArray(Int32Array, 4 * n),
    chkC: newArray(Uint8Array, 4 * n),
  }
  let w = 0
  for (let k = 0; k < n; k++) {
    const e0 = t.hingeIds[4 * k], e1 = t.hingeIds[4 * k + 1], w0 = t.hingeIds[4 * k + 2], w1 = t.hingeIds[4 * k + 3]
    const list = mesh.edgeTris.get(pairKey(e0, e1))
    if (!list) continue
    let tA = -1, tB = -1
    for (const x of list) {
      if (mesh.corner(x, w0) >= 0) tA = x
      if (mesh.corner(x, w1) >= 0) tB = x
    }
    if (tA < 0 || tB < 0) continue
    for (let j = 0; j < 4; j++) t.hingeIds[4 * w + j] = t.hingeIds[4 * k + j]
    t.hingeRest[w] = t.hingeRest[k]
    t.hingeCompliance[w] = t.hingeCompliance[k]
    h.endT[2 * w] = tA
    h.endT[2 * w + 1] = tB
    h.endC[4 * w] = mesh.corner(tA, e0)
    h.endC[4 * w + 1] = mesh.corner(tA, e1)
    h.endC[4 * w + 2] = mesh.corner(tA, w0)
    h.endC[4 * w + 3] = mesh.corner(tB, w1)
    setCheck(h.chkT, h.chkC, 4 * w, tA, mesh.corner(tA, e0), tB, mesh.corner(tB, e0))
    setCheck(h.chkT, h.chkC, 4 * w + 2, tA, mesh.corner(tA, e1), tB, mesh.corner(tB, e1))
    w++
  }
  h.count = w
  return h
}
