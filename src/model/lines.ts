import { newArray } from '../core/shared'
import { STRETCH, type ClothTopology } from './topology'

/**
 * Lines of structural edges for the direct line solve (`src/kernels/lines.ts`, the cloth option
 * `lineSolve`): on a grid its rows and columns; on any mesh, chains of edges that run on nearly
 * straight at each particle. Each edge is in at most one line; a closed loop (a sleeve's ring) is
 * opened at one edge, which the sweep alone solves.
 */
export interface ClothLines {
  /** Number of lines. */
  count: number
  /** Line q's particles are `ids[start[q]] .. ids[start[q + 1] − 1]` (count + 1 entries). */
  start: Int32Array
  ids: Int32Array
  /** Rest length and compliance of the edge from ids[k] to ids[k + 1] (the last slot of a line unused). */
  rest: Float64Array
  compliance: Float64Array
  /** XPBD multipliers per slot, accumulated over a substep's iterations (several iterations only). */
  lambda: Float64Array
  /** Scratch for the solve: edge directions (3 per slot) and the elimination's two columns. */
  n: Float64Array
  cc: Float64Array
  dd: Float64Array
  /**
   * The topology's other distance constraints (those in no line: shear, bend springs, edges left
   * out), in solver order, for the sweep: offsets (particle × 3, 2 per constraint), rest, compliance
   * and multipliers. The edges in lines are solved by the lines alone, so each constraint is solved
   * once per iteration and a compliant one keeps its compliance.
   */
  sweepOffsets: Int32Array
  sweepRest: Float64Array
  sweepCompliance: Float64Array
  sweepLambda: Float64Array
  sweepCount: number
}

/** Edges meeting at a particle continue one line when they are within this angle of straight (cos 150°). */
const STRAIGHT = -Math.cos(Math.PI / 6)

/**
 * Builds the lines of a topology's structural edges. Deterministic: lines come in the order of their
 * first edge in the solver's distance list (outward from where the cloth is pinned).
 */
export function buildLines(t: ClothTopology): ClothLines {
  const { edgeA, edgeB, rest, compliance, m, constraint } = structuralEdges(t)
  const links = linkStraight(t, edgeA, edgeB, m)
  const ids: number[] = [], start: number[] = [0], slotRest: number[] = [], slotCompliance: number[] = []
  const used = new Uint8Array(m)
  const lined = new Uint8Array(m) // in a line that was kept
  const lineEdges: number[] = [] // the current line's edges
  const stamp = new Int32Array(t.particleCount) // the line a particle was last put in, + 1
  let lineNo = 0
  for (let e0 = 0; e0 < m; e0++) {
    if (used[e0] === 1) continue
    // walk back to the line's first free edge (or once round a loop), then forward along it
    let e = e0, from = edgeA[e0]
    for (let guard = 0; guard < m; guard++) {
      const back = links[2 * e + (from === edgeA[e] ? 0 : 1)]
      if (back < 0 || back === e0 || used[back] === 1) break
      from = edgeA[back] === from ? edgeB[back] : edgeA[back]
      e = back
    }
    // forward; a line never visits a particle twice (a loop is opened at its last edge)
    const first = ids.length
    lineEdges.length = 0
    stamp[from] = ++lineNo
    ids.push(from)
    let at = from
    while (e >= 0 && used[e] === 0) {
      const next = edgeA[e] === at ? edgeB[e] : edgeA[e]
      if (stamp[next] === lineNo) break
      used[e] = 1
      lineEdges.push(e)
      slotRest.push(rest[e])
      slotCompliance.push(compliance[e])
      stamp[next] = lineNo
      ids.push(next)
      at = next
      e = links[2 * e + (at === edgeA[e] ? 0 : 1)]
    }
    slotRest.push(0)
    slotCompliance.push(0)
    if (ids.length - first < 3) {
      // a lone edge: the sweep solves it as well alone
      ids.length = first
      slotRest.length = first
      slotCompliance.length = first
      continue
    }
    for (const le of lineEdges) lined[le] = 1
    start.push(ids.length)
  }
  const slots = ids.length
  const lines: ClothLines = {
    count: start.length - 1,
    start: newArray(Int32Array, start.length),
    ids: newArray(Int32Array, slots),
    rest: newArray(Float64Array, slots),
    compliance: newArray(Float64Array, slots),
    lambda: newArray(Float64Array, slots),
    n: newArray(Float64Array, 3 * slots),
    cc: newArray(Float64Array, slots),
    dd: newArray(Float64Array, slots),
    ...sweepList(t, lined, constraint, m),
  }
  lines.start.set(start)
  lines.ids.set(ids)
  lines.rest.set(slotRest)
  lines.compliance.set(slotCompliance)
  return lines
}

/** The distance constraints in no line (`ClothLines.sweepOffsets` and the rest), in solver order. */
function sweepList(t: ClothTopology, lined: Uint8Array, constraint: Int32Array, m: number) {
  const inLine = new Uint8Array(t.distCount)
  for (let e = 0; e < m; e++) if (lined[e] === 1) inLine[constraint[e]] = 1
  const sweep: number[] = []
  for (let k = 0; k < t.distCount; k++) if (inLine[k] === 0) sweep.push(k)
  const out = {
    sweepOffsets: newArray(Int32Array, 2 * sweep.length),
    sweepRest: newArray(Float64Array, sweep.length),
    sweepCompliance: newArray(Float64Array, sweep.length),
    sweepLambda: newArray(Float64Array, sweep.length),
    sweepCount: sweep.length,
  }
  for (let q = 0; q < sweep.length; q++) {
    const k = sweep[q]
    out.sweepOffsets[2 * q] = t.distOffsets[2 * k]
    out.sweepOffsets[2 * q + 1] = t.distOffsets[2 * k + 1]
    out.sweepRest[q] = t.distRest[k]
    out.sweepCompliance[q] = t.distCompliance[k]
  }
  return out
}

/** The topology's structural distance constraints, in solver order. */
function structuralEdges(t: ClothTopology) {
  let m = 0
  for (let k = 0; k < t.distCount; k++) if (t.distKind[k] === STRETCH) m++
  const edgeA = new Int32Array(m), edgeB = new Int32Array(m), constraint = new Int32Array(m)
  const rest = new Float64Array(m), compliance = new Float64Array(m)
  for (let k = 0, j = 0; k < t.distCount; k++) {
    if (t.distKind[k] !== STRETCH) continue
    constraint[j] = k
    edgeA[j] = t.distOffsets[2 * k] / 3
    edgeB[j] = t.distOffsets[2 * k + 1] / 3
    rest[j] = t.distRest[k]
    compliance[j++] = t.distCompliance[k]
  }
  return { edgeA, edgeB, rest, compliance, m, constraint }
}

/**
 * At each particle, pairs its edges that run on nearly straight (most nearly opposite first, each
 * edge in one pair per end): links[2e] is the edge continuing edge e past its first particle,
 * links[2e + 1] past its second (−1: the line ends there).
 */
function linkStraight(t: ClothTopology, edgeA: Int32Array, edgeB: Int32Array, m: number): Int32Array {
  const n = t.particleCount, r = t.restPositions
  const links = new Int32Array(2 * m).fill(-1)
  const at: number[][] = Array.from({ length: n }, () => [])
  for (let e = 0; e < m; e++) {
    at[edgeA[e]].push(e)
    at[edgeB[e]].push(e)
  }
  const dir = (e: number, p: number, out: number[]) => {
    const q = edgeA[e] === p ? edgeB[e] : edgeA[e]
    const dx = r[3 * q] - r[3 * p], dy = r[3 * q + 1] - r[3 * p + 1], dz = r[3 * q + 2] - r[3 * p + 2]
    const l = Math.hypot(dx, dy, dz) || 1
    out[0] = dx / l
    out[1] = dy / l
    out[2] = dz / l
  }
  const u = [0, 0, 0], v = [0, 0, 0]
  for (let p = 0; p < n; p++) {
    const es = at[p]
    const pairs: [number, number, number][] = []
    for (let i = 0; i < es.length; i++) {
      dir(es[i], p, u)
      for (let j = i + 1; j < es.length; j++) {
        dir(es[j], p, v)
        const dot = u[0] * v[0] + u[1] * v[1] + u[2] * v[2]
        if (dot < STRAIGHT) pairs.push([dot, es[i], es[j]])
      }
    }
    pairs.sort((x, y) => x[0] - y[0] || x[1] - y[1] || x[2] - y[2])
    for (const [, e, f] of pairs) {
      const se = 2 * e + (edgeA[e] === p ? 0 : 1), sf = 2 * f + (edgeA[f] === p ? 0 : 1)
      if (links[se] >= 0 || links[sf] >= 0) continue
      links[se] = f
      links[sf] = e
    }
  }
  return links
}
