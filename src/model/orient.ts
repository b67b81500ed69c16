/**
 * Consistent winding for a user's mesh (build time). Exports often mix windings (flipped faces) or
 * hold each face twice, once per side: the vertex normals of such a mesh cancel, so the wind found
 * no surface to push (a sheet with every other triangle flipped took 43 % less force, a double-sided
 * one none) and its drawn normals fell back to a fixed axis.
 */

/**
 * Flips triangles of `tris` (3 indices each, in place) so that each agrees with its neighbours
 * across every edge that exactly two of its distinct triangles share (a shared edge is walked in
 * opposite directions), each connected patch keeping the winding most of its triangles had (so the
 * front stays the front). A triangle with the same three vertices as an earlier one (the back of a
 * double-sided face) takes that one's winding. Edges with more than two triangles do not connect
 * (non-manifold); a non-orientable patch keeps one seam of disagreeing triangles. A mesh that is
 * consistent already is left as it is. Returns the number of triangles flipped.
 */
export function orientTriangles(tris: Uint32Array, n: number): number {
  const count = (tris.length / 3) | 0
  const { start, around } = vertexTriangles(tris, n)
  const first = copiesOf(tris, start, around)
  let flipped = 0
  const seen = new Uint8Array(count)
  const queue = new Int32Array(count)
  for (let seed = 0; seed < count; seed++) {
    if (seen[seed] || first[seed] >= 0) continue
    seen[seed] = 1
    let head = 0, tail = 0, turned = 0
    queue[tail++] = seed
    while (head < tail) {
      const t = queue[head++]
      for (let k = 0; k < 3; k++) {
        const a = tris[3 * t + k], b = tris[3 * t + ((k + 1) % 3)]
        // the other distinct triangle on edge a–b, when there is exactly one
        let u = -1, others = 0
        for (let q = start[a]; q < start[a + 1]; q++) {
          const w = around[q]
          if (w === t || first[w] >= 0 || (q > start[a] && around[q - 1] === w) || !has(tris, w, b)) continue
          u = w
          others++
        }
        if (others !== 1 || seen[u]) continue
        seen[u] = 1
        // t walks a → b: u agrees when it walks b → a
        if (walks(tris, u, a, b)) {
          flip(tris, u)
          turned++
        }
        queue[tail++] = u
      }
    }
    // most of the patch was turned: turn it all back instead (the majority's winding stays)
    if (2 * turned > tail) {
      for (let q = 0; q < tail; q++) flip(tris, queue[q])
      turned = tail - turned
    }
    flipped += turned
  }
  for (let t = 0; t < count; t++) {
    const f = first[t]
    if (f < 0) continue
    if (!walks(tris, t, tris[3 * f], tris[3 * f + 1])) {
      flip(tris, t)
      flipped++
    }
  }
  return flipped
}

/**
 * The faces of a user's mesh the cloth is made of (build time, after `orientTriangles`): all but
 * the copies of a face held twice (once per side) and the zero-area triangles whose three vertices
 * lie on one piece of the triangles with area and that would be a third face on an edge. Both had been cloth: a double-sided sheet weighed twice its density ×
 * area, and with four triangles on each edge lost every bending hinge and took its shear as
 * stretch; a sliver an exporter left along a row put a third triangle on two edges, which a tear
 * then could not part (drawn metres long across the opening, it joined the falling piece to the
 * pinned one). Returns `tris` itself when none goes.
 */
export function simulatedFaces(tris: Uint32Array, rest: Float64Array, n: number): Uint32Array {
  const count = (tris.length / 3) | 0
  const { start, around } = vertexTriangles(tris, n)
  const first = copiesOf(tris, start, around)
  const flat = new Uint8Array(count)
  const held = new Int32Array(n) // kept faces of area at each vertex
  for (let t = 0; t < count; t++) {
    if (first[t] >= 0) continue
    flat[t] = zeroArea(tris, rest, t) ? 1 : 0
    if (flat[t] === 0) { for (let k = 0; k < 3; k++) held[tris[3 * t + k]]++ }
  }
  // the pieces the faces of area make (a flat triangle joining two of them, as a collapsed row
  // does, stays: without it they fell apart)
  const piece = new Int32Array(n)
  for (let v = 0; v < n; v++) piece[v] = v
  for (let t = 0; t < count; t++) {
    if (first[t] >= 0 || flat[t] === 1) continue
    for (let k = 1; k < 3; k++) join(piece, tris[3 * t], tris[3 * t + k])
  }
  let kept = 0
  const keep = new Uint8Array(count)
  for (let t = 0; t < count; t++) {
    const a = tris[3 * t], b = tris[3 * t + 1], c = tris[3 * t + 2]
    // (a flat triangle that closes a T-junction, each of its edges on one face of area at most,
    // stays: dropped, the seam it covered opened as a hole in the drawn mesh)
    const spare = flat[t] === 1 && held[a] > 0 && held[b] > 0 && held[c] > 0 && root(piece, a) === root(piece, b) &&
      root(piece, a) === root(piece, c) && (onFaces(tris, start, around, first, flat, a, b) > 1 ||
        onFaces(tris, start, around, first, flat, b, c) > 1 || onFaces(tris, start, around, first, flat, a, c) > 1)
    keep[t] = first[t] < 0 && !spare ? 1 : 0
    kept += keep[t]
  }
  if (kept === count) return tris
  const out = new Uint32Array(3 * kept)
  let w = 0
  for (let t = 0; t < count; t++) if (keep[t] === 1) { for (let k = 0; k < 3; k++) out[w++] = tris[3 * t + k] }
  return out
}

/** How many faces with area (not later copies) have the edge a–b. */
function onFaces(
  tris: Uint32Array,
  start: Int32Array,
  around: Int32Array,
  first: Int32Array,
  flat: Uint8Array,
  a: number,
  b: number,
): number {
  let faces = 0
  for (let q = start[a]; q < start[a + 1]; q++) {
    const u = around[q]
    if (first[u] < 0 && flat[u] === 0 && has(tris, u, b)) faces++
  }
  return faces
}

/** The root of v's set (path halving). */
function root(parent: Int32Array, v: number): number {
  while (parent[v] !== v) {
    parent[v] = parent[parent[v]]
    v = parent[v]
  }
  return v
}

function join(parent: Int32Array, a: number, b: number): void {
  const ra = root(parent, a), rb = root(parent, b)
  if (ra !== rb) parent[ra < rb ? rb : ra] = ra < rb ? ra : rb
}

/** Whether triangle t has no area: its sides' cross product within rounding of its longest side squared. */
function zeroArea(tris: Uint32Array, rest: Float64Array, t: number): boolean {
  const a = 3 * tris[3 * t], b = 3 * tris[3 * t + 1], c = 3 * tris[3 * t + 2]
  const ux = rest[b] - rest[a], uy = rest[b + 1] - rest[a + 1], uz = rest[b + 2] - rest[a + 2]
  const vx = rest[c] - rest[a], vy = rest[c + 1] - rest[a + 1], vz = rest[c + 2] - rest[a + 2]
  const wx = rest[c] - rest[b], wy = rest[c + 1] - rest[b + 1], wz = rest[c + 2] - rest[b + 2]
  const cross = Math.hypot(uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx)
  const longest = Math.max(ux * ux + uy * uy + uz * uz, vx * vx + vy * vy + vz * vz, wx * wx + wy * wy + wz * wz)
  return cross <= 1e-9 * longest
}

/** Each vertex's triangles (counting sort: no maps, linear in the mesh; 180,000 triangles took 0.7 s with a map of edges). */
function vertexTriangles(tris: Uint32Array, n: number): { start: Int32Array; around: Int32Array } {
  const count = (tris.length / 3) | 0
  const start = new Int32Array(n + 1)
  for (let k = 0; k < 3 * count; k++) start[tris[k] + 1]++
  for (let v = 0; v < n; v++) start[v + 1] += start[v]
  const around = new Int32Array(3 * count)
  const fill = start.slice(0, n)
  for (let k = 0; k < 3 * count; k++) around[fill[tris[k]]++] = (k / 3) | 0
  return { start, around }
}

/** Per triangle, the first triangle with its vertex set when it is a later copy of one, else −1. */
function copiesOf(tris: Uint32Array, start: Int32Array, around: Int32Array): Int32Array {
  const count = (tris.length / 3) | 0
  const first = new Int32Array(count).fill(-1)
  for (let t = 0; t < count; t++) {
    const a = tris[3 * t]
    for (let q = start[a]; q < start[a + 1]; q++) {
      const u = around[q]
      if (u >= t) break // (listed in triangle order)
      if (first[u] < 0 && sameVertices(tris, u, t)) {
        first[t] = u
        break
      }
    }
  }
  return first
}

/** Whether triangle t has vertex v. */
function has(tris: Uint32Array, t: number, v: number): boolean {
  return tris[3 * t] === v || tris[3 * t + 1] === v || tris[3 * t + 2] === v
}

/** Whether triangles t and u have the same three vertices (in any order; repeated ones count once). */
function sameVertices(tris: Uint32Array, t: number, u: number): boolean {
  for (let k = 0; k < 3; k++) if (!has(tris, u, tris[3 * t + k]) || !has(tris, t, tris[3 * u + k])) return false
  return true
}

/** Whether triangle t visits a then b (cyclically). */
function walks(tris: Uint32Array, t: number, a: number, b: number): boolean {
  const o = 3 * t
  return (tris[o] === a && tris[o + 1] === b) || (tris[o + 1] === a && tris[o + 2] === b) || (tris[o + 2] === a && tris[o] === b)
}

function flip(tris: Uint32Array, t: number): void {
  const b = tris[3 * t + 1]
  tris[3 * t + 1] = tris[3 * t + 2]
  tris[3 * t + 2] = b
}
