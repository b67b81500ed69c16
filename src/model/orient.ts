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
  // the first triangle with each vertex set; later ones are its copies
  const first = new Int32Array(count).fill(-1)
  const byVertices = new Map<string, number>()
  for (let t = 0; t < count; t++) {
    const v = [tris[3 * t], tris[3 * t + 1], tris[3 * t + 2]].sort((p, q) => p - q)
    const key = `${v[0]},${v[1]},${v[2]}`
    const f = byVertices.get(key)
    if (f === undefined) byVertices.set(key, t)
    else first[t] = f
  }
  // the distinct triangles on each undirected edge
  const onEdge = new Map<number, number[]>()
  for (let t = 0; t < count; t++) {
    if (first[t] >= 0) continue
    for (let k = 0; k < 3; k++) {
      const key = edgeKey(tris[3 * t + k], tris[3 * t + ((k + 1) % 3)], n)
      const list = onEdge.get(key)
      if (list === undefined) onEdge.set(key, [t])
      else list.push(t)
    }
  }
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
        const list = onEdge.get(edgeKey(a, b, n))!
        if (list.length !== 2) continue
        const u = list[0] === t ? list[1] : list[0]
        if (seen[u]) continue
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

function edgeKey(a: number, b: number, n: number): number {
  return a < b ? a * n + b : b * n + a
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
