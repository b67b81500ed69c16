import type { ClothMaterialSpec } from './materials'
import { dist, triArea, type MeshInfo, type PairList } from './meshInfo'
import { BEND, SHEAR, STRETCH, dihedralAngle, type ClothTopology, type TopologyOptions } from './topology'

/**
 * Rest data from a mesh and its constraint lists: each list in solver order (swept outward from
 * `options.orderFrom`, or from the top), with rest lengths and compliances from the material.
 */
export function assemble(
  rest: Float64Array,
  tris: Uint32Array,
  mesh: MeshInfo,
  pairs: PairList,
  comp: PairList,
  lines: number[],
  hinges: Int32Array,
  material: ClothMaterialSpec,
  options: TopologyOptions,
  columns: number,
  rows: number,
): ClothTopology {
  const n = (rest.length / 3) | 0
  const unused = unusedVertices(tris, n)
  const levels = particleLevels(rest, n, mesh, unused, options.orderFrom)
  const complianceOf = pairCompliance(mesh, material, n)
  const d = distanceConstraints(rest, pairs, levels, complianceOf)
  const c = compressionConstraints(rest, comp, levels, complianceOf)
  const l = lineConstraints(rest, lines, levels, material)
  hinges = dropDegenerateHinges(rest, hinges, mesh)
  const h = hingeConstraints(rest, hinges, material)
  const side = options.bendSide ?? 'both'
  const s = stretchList(d.distOffsets, d.distRest, d.distKind)
  const edgeRest = new Float64Array(mesh.edgeCount)
  for (let e = 0; e < mesh.edgeCount; e++) edgeRest[e] = dist(rest, mesh.edges[2 * e], mesh.edges[2 * e + 1])
  return {
    particleCount: n,
    restPositions: rest,
    masses: particleMasses(rest, tris, mesh.triangleArea, material.density, unused),
    unused,
    ...meshPieces(tris, n, unused),
    triangles: tris,
    triangleCount: (tris.length / 3) | 0,
    edges: mesh.edges,
    edgeRest,
    edgeCount: mesh.edgeCount,
    ...s,
    ...d,
    ...c,
    ...l,
    hingeIds: hinges,
    ...h,
    // folding toward the front gives a negative angle (see the dihedral kernel)
    hingeSide: side === 'front' ? -1 : side === 'back' ? 1 : 0,
    columns,
    rows,
  }
}

type Compliance = (a: number, b: number, kind: number, L: number) => number

/** Compliance of a two-particle constraint: shear and bend from the material, stretch scaled by the edge's area. */
function pairCompliance(mesh: MeshInfo, material: ClothMaterialSpec, n: number): Compliance {
  const edgeAreaByKey = new Map<number, number>()
  for (let e = 0; e < mesh.edgeCount; e++) {
    edgeAreaByKey.set(mesh.edges[2 * e] * n + mesh.edges[2 * e + 1], mesh.edgeArea[e])
  }
  return (a, b, kind, L) => {
    if (kind === SHEAR) return material.shearCompliance
    if (kind === BEND) return (material.bendCompliance * L * L) / 192 // half-length L/2: (L/2)²/48
    const key = a < b ? a * n + b : b * n + a
    const A = edgeAreaByKey.get(key)
    // a mesh edge: L²/A × membrane compliance (1 on a square grid); a non-mesh pair: as on a grid
    return A && A > 0 ? (material.stretchCompliance * L * L) / A : material.stretchCompliance
  }
}

/** The two-sided distance constraints, in solver order, as position offsets (particle × 3). */
function distanceConstraints(rest: Float64Array, pairs: PairList, levels: Int32Array, complianceOf: Compliance) {
  const order = orderPairs(pairs, levels)
  const m = order.length
  const distOffsets = new Int32Array(2 * m)
  const distRest = new Float64Array(m)
  const distCompliance = new Float64Array(m)
  const distKind = new Uint8Array(m)
  for (let k = 0; k < m; k++) {
    const j = order[k]
    const a = pairs.a[j], b = pairs.b[j]
    distOffsets[2 * k] = 3 * a
    distOffsets[2 * k + 1] = 3 * b
    distRest[k] = dist(rest, a, b)
    distKind[k] = pairs.kind[j]
    distCompliance[k] = Math.min(MAX_COMPLIANCE, complianceOf(a, b, pairs.kind[j], distRest[k]))
  }
  return { distOffsets, distRest, distCompliance, distKind, distCount: m }
}

/** The compression-only constraints, in solver order. */
function compressionConstraints(rest: Float64Array, comp: PairList, levels: Int32Array, complianceOf: Compliance) {
  const order = orderPairs(comp, levels)
  const mc = order.length
  const compIds = new Int32Array(2 * mc)
  const compRest = new Float64Array(mc)
  const compCompliance = new Float64Array(mc)
  for (let k = 0; k < mc; k++) {
    const j = order[k]
    compIds[2 * k] = comp.a[j]
    compIds[2 * k + 1] = comp.b[j]
    compRest[k] = dist(rest, comp.a[j], comp.b[j])
    compCompliance[k] = Math.min(MAX_COMPLIANCE, complianceOf(comp.a[j], comp.b[j], comp.kind[j], compRest[k]))
  }
  return { compIds, compRest, compCompliance, compCount: mc }
}

/** Line-bending triples: solve order by the level of their nearest particle, interleaved like the pairs. */
function lineConstraints(rest: Float64Array, lines: number[], levels: Int32Array, material: ClothMaterialSpec) {
  const order = orderItems(lines, 3, null, levels)
  const lc = order.length
  const lineIds = new Int32Array(3 * lc)
  const lineRest = new Float64Array(lc)
  const lineCompliance = new Float64Array(lc)
  for (let k = 0; k < lc; k++) {
    const j = order[k]
    const a = lines[3 * j], v = lines[3 * j + 1], b = lines[3 * j + 2]
    lineIds[3 * k] = a
    lineIds[3 * k + 1] = v
    lineIds[3 * k + 2] = b
    const dx = rest[3 * v] - 0.5 * (rest[3 * a] + rest[3 * b])
    const dy = rest[3 * v + 1] - 0.5 * (rest[3 * a + 1] + rest[3 * b + 1])
    const dz = rest[3 * v + 2] - 0.5 * (rest[3 * a + 2] + rest[3 * b + 2])
    const L = 0.5 * (dist(rest, a, v) + dist(rest, v, b))
    // straight within a millionth of its segments counts as straight (the kernel's vector form)
    const kink = Math.sqrt(dx * dx + dy * dy + dz * dz)
    lineRest[k] = kink > 1e-6 * L ? kink : 0
    lineCompliance[k] = Math.min(MAX_COMPLIANCE, (material.bendCompliance * L * L) / 4)
  }
  return { lineIds, lineRest, lineCompliance, lineCount: lc }
}

/** Rest angles and compliances of the dihedral hinges. */
function hingeConstraints(rest: Float64Array, hinges: Int32Array, material: ClothMaterialSpec) {
  const hc = (hinges.length / 4) | 0
  const hingeRest = new Float64Array(hc)
  const hingeCompliance = new Float64Array(hc)
  for (let h = 0; h < hc; h++) {
    const e0 = hinges[4 * h], e1 = hinges[4 * h + 1], w0 = hinges[4 * h + 2], w1 = hinges[4 * h + 3]
    hingeRest[h] = dihedralAngle(rest, e0, e1, w0, w1)
    const L = dist(rest, e0, e1)
    const areas = triArea(rest, e0, e1, w0) + triArea(rest, e1, e0, w1)
    hingeCompliance[h] = Math.min(MAX_COMPLIANCE, (material.bendCompliance * areas) / (3 * L * L))
  }
  return { hingeRest, hingeCompliance, hingeCount: hc }
}

/** The structural (STRETCH) distance constraints again, as particle pairs, for measuring stretch. */
function stretchList(distOffsets: Int32Array, distRest: Float64Array, distKind: Uint8Array) {
  const m = distKind.length
  let sc = 0
  for (let k = 0; k < m; k++) if (distKind[k] === STRETCH) sc++
  const stretchIds = new Int32Array(2 * sc)
  const stretchRest = new Float64Array(sc)
  for (let k = 0, j = 0; k < m; k++) {
    if (distKind[k] !== STRETCH) continue
    stretchIds[2 * j] = distOffsets[2 * k] / 3
    stretchIds[2 * j + 1] = distOffsets[2 * k + 1] / 3
    stretchRest[j++] = distRest[k]
  }
  return { stretchIds, stretchRest, stretchCount: sc }
}

/**
 * Per-constraint compliance cap, m/N or 1/(N·m). A material may ask for any finite compliance, but
 * beyond ~1e305 the XPBD term compliance/h² overflows to Infinity and Infinity × 0 is NaN; 1e30 is
 * already no stiffness at all.
 */
const MAX_COMPLIANCE = 1e30

/**
 * Removes hinges whose rest geometry defines no angle: a shared edge of (almost) zero length or a
 * triangle of (almost) zero area. Such a hinge would get compliance 0 (rigid) and a rest angle of 0
 * by convention, and once the particles separate it would fight the cloth with a made-up target.
 */
function dropDegenerateHinges(rest: Float64Array, hinges: Int32Array, mesh: MeshInfo): Int32Array {
  let sum = 0
  for (let e = 0; e < mesh.edgeCount; e++) sum += dist(rest, mesh.edges[2 * e], mesh.edges[2 * e + 1])
  const minL = mesh.edgeCount > 0 ? 1e-6 * (sum / mesh.edgeCount) : 0
  const keep: number[] = []
  for (let h = 0; h < hinges.length; h += 4) {
    const e0 = hinges[h], e1 = hinges[h + 1], w0 = hinges[h + 2], w1 = hinges[h + 3]
    const L = dist(rest, e0, e1)
    // each triangle's height over the shared edge at least 1e-6 of the edge (area ≥ 5e-7·L²)
    const minArea = 5e-7 * L * L
    if (!(L > minL) || !(triArea(rest, e0, e1, w0) > minArea) || !(triArea(rest, e1, e0, w1) > minArea)) continue
    keep.push(e0, e1, w0, w1)
  }
  return keep.length === hinges.length ? hinges : Int32Array.from(keep)
}

/** Connected pieces of the triangles (see `ClothTopology.pieces`): union-find over the triangles' corners. */
function meshPieces(tris: Uint32Array, n: number, unused: Uint8Array | null): { pieces: Int32Array | null; pieceCount: number } {
  const root = new Int32Array(n)
  for (let i = 0; i < n; i++) root[i] = i
  const find = (i: number): number => {
    while (root[i] !== i) {
      root[i] = root[root[i]]
      i = root[i]
    }
    return i
  }
  for (let k = 0; k + 2 < tris.length; k += 3) {
    const a = find(tris[k]), b = find(tris[k + 1]), c = find(tris[k + 2])
    const m = a < b ? (a < c ? a : c) : b < c ? b : c
    root[a] = m
    root[b] = m
    root[c] = m
  }
  const pieces = new Int32Array(n)
  let count = 0
  for (let i = 0; i < n; i++) {
    if (unused !== null && unused[i] === 1) continue // (piece 0; the guard skips them)
    const r = find(i)
    pieces[i] = r === i ? count++ : pieces[r]
  }
  return count > 1 ? { pieces, pieceCount: count } : { pieces: null, pieceCount: 1 }
}

/** 1 for each vertex no triangle uses, or null when every vertex is used (see `ClothTopology.unused`). */
function unusedVertices(tris: Uint32Array, n: number): Uint8Array | null {
  const unused = new Uint8Array(n).fill(1)
  for (let k = 0; k < tris.length; k++) unused[tris[k]] = 0
  for (let i = 0; i < n; i++) if (unused[i] === 1) return unused
  return null
}

/**
 * Masses from areal density: each triangle gives a third of its mass to each corner. A particle
 * with tiny or no adjacent area would get a tiny mass and an extreme mass ratio with its
 * neighbours, which Gauss-Seidel handles badly, so masses are clamped to at least 10 % of the mean
 * (over the vertices triangles use; a vertex no triangle uses gets 0: it is no part of the cloth).
 */
function particleMasses(
  rest: Float64Array,
  tris: Uint32Array,
  areas: Float64Array,
  density: number,
  unused: Uint8Array | null,
): Float64Array {
  const n = (rest.length / 3) | 0
  const mass = new Float64Array(n)
  for (let t = 0; t < areas.length; t++) {
    const share = (areas[t] * density) / 3
    mass[tris[3 * t]] += share
    mass[tris[3 * t + 1]] += share
    mass[tris[3 * t + 2]] += share
  }
  let total = 0, used = 0
  for (let i = 0; i < n; i++) {
    if (unused !== null && unused[i] === 1) continue
    total += mass[i]
    used++
  }
  const floor = total > 0 ? (0.1 * total) / used : density * 1e-4
  for (let i = 0; i < n; i++) if (mass[i] < floor && (unused === null || unused[i] === 0)) mass[i] = floor
  return mass
}

/**
 * Per-particle sweep level: breadth-first distance (in edges) from `from`, or, by default, height
 * bands of one mean edge length counted down from the highest particle a triangle uses. Particles
 * not reached get the largest level.
 */
function particleLevels(rest: Float64Array, n: number, mesh: MeshInfo, unused: Uint8Array | null, from?: ArrayLike<number>): Int32Array {
  const level = new Int32Array(n)
  if (from && from.length > 0) {
    const adjStart = new Int32Array(n + 1)
    for (let e = 0; e < mesh.edgeCount; e++) {
      adjStart[mesh.edges[2 * e] + 1]++
      adjStart[mesh.edges[2 * e + 1] + 1]++
    }
    for (let i = 0; i < n; i++) adjStart[i + 1] += adjStart[i]
    const adj = new Int32Array(adjStart[n])
    const fill = adjStart.slice(0, n)
    for (let e = 0; e < mesh.edgeCount; e++) {
      const a = mesh.edges[2 * e], b = mesh.edges[2 * e + 1]
      adj[fill[a]++] = b
      adj[fill[b]++] = a
    }
    level.fill(-1)
    const queue = new Int32Array(n)
    let head = 0, tail = 0
    for (let k = 0; k < from.length; k++) {
      const i = from[k]
      if (level[i] < 0) {
        level[i] = 0
        queue[tail++] = i
      }
    }
    while (head < tail) {
      const i = queue[head++]
      for (let k = adjStart[i]; k < adjStart[i + 1]; k++) {
        const j = adj[k]
        if (level[j] < 0) {
          level[j] = level[i] + 1
          queue[tail++] = j
        }
      }
    }
    let max = 0
    for (let i = 0; i < n; i++) max = Math.max(max, level[i])
    for (let i = 0; i < n; i++) if (level[i] < 0) level[i] = max + 1
    return level
  }
  let top = -Infinity
  for (let i = 0; i < n; i++) if (unused === null || unused[i] === 0) top = Math.max(top, rest[3 * i + 1])
  let sum = 0
  for (let e = 0; e < mesh.edgeCount; e++) sum += dist(rest, mesh.edges[2 * e], mesh.edges[2 * e + 1])
  const band = mesh.edgeCount > 0 && sum > 0 ? (sum / mesh.edgeCount) * 0.5 : 1
  for (let i = 0; i < n; i++) level[i] = Math.floor((top - rest[3 * i + 1]) / band + 1e-6)
  return level
}

/**
 * Solver order for a list of constraints. Gauss-Seidel propagates corrections in sweep order, so
 * constraints are sorted outward from the anchors (by the level of their nearest particle, then
 * kind, then farthest particle): a hanging sheet swept from its pins converges far faster than
 * swept from its hem. Within that order, constraints are interleaved so that none shares a
 * particle with the two before it, which removes the store-to-load dependency between neighbours
 * in the sweep and lets the CPU overlap them.
 *
 * @param items particle indices, `arity` per constraint
 * @param kinds per-constraint kind (sort key after the level), or null
 */
function orderItems(items: ArrayLike<number>, arity: number, kinds: ArrayLike<number> | null, level: Int32Array): Int32Array {
  const m = (items.length / arity) | 0
  const lo = new Int32Array(m), hi = new Int32Array(m)
  for (let k = 0; k < m; k++) {
    let a = Infinity, b = -Infinity
    for (let j = 0; j < arity; j++) {
      const l = level[items[arity * k + j]]
      if (l < a) a = l
      if (l > b) b = l
    }
    lo[k] = a
    hi[k] = b
  }
  const order = Array.from({ length: m }, (_, k) => k)
  order.sort((p, q) => lo[p] - lo[q] || (kinds ? kinds[p] - kinds[q] : 0) || hi[p] - hi[q] || p - q)

  const out = new Int32Array(m)
  const pending: number[] = []
  const recent = new Int32Array(2 * arity).fill(-1)
  let next = 0
  const LOOKAHEAD = 48
  for (let k = 0; k < m; k++) {
    while (pending.length < LOOKAHEAD && next < m) pending.push(order[next++])
    let pick = 0
    for (let s = 0; s < pending.length; s++) {
      const j = pending[s]
      let clash = false
      for (let p = 0; p < arity && !clash; p++) {
        const v = items[arity * j + p]
        for (let r = 0; r < recent.length; r++) {
          if (recent[r] === v) {
            clash = true
            break
          }
        }
      }
      if (!clash) {
        pick = s
        break
      }
    }
    const j = pending.splice(pick, 1)[0]
    out[k] = j
    recent.copyWithin(arity, 0, arity)
    for (let p = 0; p < arity; p++) recent[p] = items[arity * j + p]
  }
  return out
}

/** Solver order of a pair list (see `orderItems`). */
function orderPairs(list: PairList, level: Int32Array): Int32Array {
  const flat = new Int32Array(2 * list.length)
  for (let k = 0; k < list.length; k++) {
    flat[2 * k] = list.a[k]
    flat[2 * k + 1] = list.b[k]
  }
  return orderItems(flat, 2, list.kind, level)
}
