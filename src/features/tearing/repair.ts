import type { ClothTear, HingeSet, LineSet, PairSet } from './types'

/** Re-reading constraints from the split triangles (see the tearing module comment in api.ts). */

/** Re-reads every constraint from the triangles, duplicates split edges, drops broken supports. */
export function repairConstraints(T: ClothTear): void {
  const t = T.topology
  const tris = t.triangles
  t.stretchCount = repairPairs(T.stretch, tris)
  t.edgeCount = repairPairs(T.edges, tris)
  t.distCount = repairPairs(T.dist, tris)
  t.compCount = repairPairs(T.comp, tris)
  t.lineCount = repairLines(T.lines, tris)
  t.hingeCount = repairHinges(T.hinges, tris)
}

function repairPairs(s: PairSet, tris: Uint32Array): number {
  // 1. edges whose two triangles came apart get a second constraint, one per side
  const n = s.count
  for (let k = 0; k < n; k++) {
    const t2 = s.twinT[k]
    if (t2 < 0) continue
    const t1 = s.endT[2 * k]
    const a1 = tris[3 * t1 + s.endC[2 * k]], b1 = tris[3 * t1 + s.endC[2 * k + 1]]
    const a2 = tris[3 * t2 + s.twinC[2 * k]], b2 = tris[3 * t2 + s.twinC[2 * k + 1]]
    if (a1 === a2 && b1 === b2) continue
    s.twinT[k] = -1
    if (s.count >= s.cap) continue // out of room: this side keeps no constraint on the edge
    const m = s.count++
    copyPair(s, k, m)
    s.endT[2 * m] = t2
    s.endT[2 * m + 1] = t2
    s.endC[2 * m] = s.twinC[2 * k]
    s.endC[2 * m + 1] = s.twinC[2 * k + 1]
    s.twinT[m] = -1
    if (s.over !== null) s.over[m] = 0
  }
  // 2. re-read particles, drop the unsupported, compact in order
  let w = 0
  const chkT = s.chkT, chkC = s.chkC
  for (let k = 0; k < s.count; k++) {
    let ok = true
    for (let j = 0; j < 4; j += 2) {
      const ta = chkT[4 * k + j]
      if (ta < 0) continue
      const tb = chkT[4 * k + j + 1]
      if (tris[3 * ta + chkC[4 * k + j]] !== tris[3 * tb + chkC[4 * k + j + 1]]) ok = false
    }
    if (!ok) continue
    if (w !== k) copyPair(s, k, w)
    const tA = s.endT[2 * w]
    if (tA >= 0) {
      s.ids[2 * w] = s.scale * tris[3 * tA + s.endC[2 * w]]
      s.ids[2 * w + 1] = s.scale * tris[3 * s.endT[2 * w + 1] + s.endC[2 * w + 1]]
    }
    w++
  }
  s.count = w
  return w
}

function copyPair(s: PairSet, from: number, to: number): void {
  s.ids[2 * to] = s.ids[2 * from]
  s.ids[2 * to + 1] = s.ids[2 * from + 1]
  for (let i = 0; i < s.f64.length; i++) s.f64[i][to] = s.f64[i][from]
  for (let i = 0; i < s.u8.length; i++) s.u8[i][to] = s.u8[i][from]
  s.endT[2 * to] = s.endT[2 * from]
  s.endT[2 * to + 1] = s.endT[2 * from + 1]
  s.endC[2 * to] = s.endC[2 * from]
  s.endC[2 * to + 1] = s.endC[2 * from + 1]
  for (let j = 0; j < 4; j++) {
    s.chkT[4 * to + j] = s.chkT[4 * from + j]
    s.chkC[4 * to + j] = s.chkC[4 * from + j]
  }
  s.twinT[to] = s.twinT[from]
  s.twinC[2 * to] = s.twinC[2 * from]
  s.twinC[2 * to + 1] = s.twinC[2 * from + 1]
}

/** Drops triples whose middle particle was split between their two supports, re-reads the rest. */
function repairLines(l: LineSet, tris: Uint32Array): number {
  let w = 0
  for (let k = 0; k < l.count; k++) {
    if (tris[3 * l.chkT[2 * k] + l.chkC[2 * k]] !== tris[3 * l.chkT[2 * k + 1] + l.chkC[2 * k + 1]]) continue
    if (w !== k) {
      for (let j = 0; j < 3; j++) l.endC[3 * w + j] = l.endC[3 * k + j]
      for (let j = 0; j < 2; j++) {
        l.endT[2 * w + j] = l.endT[2 * k + j]
        l.chkT[2 * w + j] = l.chkT[2 * k + j]
        l.chkC[2 * w + j] = l.chkC[2 * k + j]
      }
      for (let i = 0; i < l.f64.length; i++) l.f64[i][w] = l.f64[i][k]
    }
    const A = 3 * l.endT[2 * w], B = 3 * l.endT[2 * w + 1]
    l.ids[3 * w] = tris[A + l.endC[3 * w]]
    l.ids[3 * w + 1] = tris[A + l.endC[3 * w + 1]]
    l.ids[3 * w + 2] = tris[B + l.endC[3 * w + 2]]
    w++
  }
  l.count = w
  return w
}

function repairHinges(h: HingeSet, tris: Uint32Array): number {
  let w = 0
  for (let k = 0; k < h.count; k++) {
    const ta = h.chkT[4 * k], tb = h.chkT[4 * k + 1]
    if (tris[3 * ta + h.chkC[4 * k]] !== tris[3 * tb + h.chkC[4 * k + 1]]) continue
    if (tris[3 * h.chkT[4 * k + 2] + h.chkC[4 * k + 2]] !== tris[3 * h.chkT[4 * k + 3] + h.chkC[4 * k + 3]]) continue
    if (w !== k) {
      for (let j = 0; j < 4; j++) {
        h.endC[4 * w + j] = h.endC[4 * k + j]
        h.chkT[4 * w + j] = h.chkT[4 * k + j]
        h.chkC[4 * w + j] = h.chkC[4 * k + j]
      }
      h.endT[2 * w] = h.endT[2 * k]
      h.endT[2 * w + 1] = h.endT[2 * k + 1]
      for (let i = 0; i < h.f64.length; i++) h.f64[i][w] = h.f64[i][k]
    }
    const A = 3 * h.endT[2 * w], B = 3 * h.endT[2 * w + 1]
    h.ids[4 * w] = tris[A + h.endC[4 * w]]
    h.ids[4 * w + 1] = tris[A + h.endC[4 * w + 1]]
    h.ids[4 * w + 2] = tris[A + h.endC[4 * w + 2]]
    h.ids[4 * w + 3] = tris[B + h.endC[4 * w + 3]]
    w++
  }
  h.count = w
  return w
}
