/**
 * Distances from points to a triangle mesh, by brute force over every triangle: the proxy tests'
 * reference, independent of the library's closest-triangle search.
 */

/** Distance² from (px, py, pz) to the segment from a to b (xyz at offsets a, b of pos). */
function segment2(px: number, py: number, pz: number, pos: ArrayLike<number>, a: number, b: number): number {
  const dx = pos[b] - pos[a], dy = pos[b + 1] - pos[a + 1], dz = pos[b + 2] - pos[a + 2]
  const l2 = dx * dx + dy * dy + dz * dz
  let s = l2 > 0 ? ((px - pos[a]) * dx + (py - pos[a + 1]) * dy + (pz - pos[a + 2]) * dz) / l2 : 0
  s = s < 0 ? 0 : s > 1 ? 1 : s
  const ex = pos[a] + s * dx - px, ey = pos[a + 1] + s * dy - py, ez = pos[a + 2] + s * dz - pz
  return ex * ex + ey * ey + ez * ez
}

/** (q − o) × (r − o) · n ≥ 0 for corners o, q (offsets into pos) and point r: r is on q's inner side. */
function inner(
  pos: ArrayLike<number>,
  o: number,
  q: number,
  rx: number,
  ry: number,
  rz: number,
  nx: number,
  ny: number,
  nz: number,
): boolean {
  const ux = pos[q] - pos[o], uy = pos[q + 1] - pos[o + 1], uz = pos[q + 2] - pos[o + 2]
  const vx = rx - pos[o], vy = ry - pos[o + 1], vz = rz - pos[o + 2]
  return (uy * vz - uz * vy) * nx + (uz * vx - ux * vz) * ny + (ux * vy - uy * vx) * nz >= 0
}

/**
 * Distance from (px, py, pz) to triangle (a, b, c) (particle indices into pos): to its plane where
 * the point projects inside it, else to its nearest edge.
 */
export function triangleDistance(px: number, py: number, pz: number, pos: ArrayLike<number>, a: number, b: number, c: number): number {
  a *= 3
  b *= 3
  c *= 3
  const ux = pos[b] - pos[a], uy = pos[b + 1] - pos[a + 1], uz = pos[b + 2] - pos[a + 2]
  const vx = pos[c] - pos[a], vy = pos[c + 1] - pos[a + 1], vz = pos[c + 2] - pos[a + 2]
  const nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx
  const l = Math.hypot(nx, ny, nz)
  if (
    l > 0 && inner(pos, a, b, px, py, pz, nx, ny, nz) && inner(pos, b, c, px, py, pz, nx, ny, nz) &&
    inner(pos, c, a, px, py, pz, nx, ny, nz)
  ) {
    return Math.abs((px - pos[a]) * nx + (py - pos[a + 1]) * ny + (pz - pos[a + 2]) * nz) / l
  }
  return Math.sqrt(Math.min(segment2(px, py, pz, pos, a, b), segment2(px, py, pz, pos, b, c), segment2(px, py, pz, pos, c, a)))
}

/**
 * Distance from each of the `points` (xyz) to the nearest of `triCount` triangles of a mesh. A
 * triangle whose bounding sphere lies farther than the best distance so far is skipped.
 */
export function surfaceDistances(
  points: ArrayLike<number>,
  pos: ArrayLike<number>,
  tris: ArrayLike<number>,
  triCount: number,
): Float64Array {
  const sphere = new Float64Array(4 * triCount)
  for (let t = 0; t < triCount; t++) {
    const a = 3 * tris[3 * t], b = 3 * tris[3 * t + 1], c = 3 * tris[3 * t + 2]
    let r = 0
    for (let k = 0; k < 3; k++) sphere[4 * t + k] = (pos[a + k] + pos[b + k] + pos[c + k]) / 3
    for (const v of [a, b, c])
      r = Math.max(r, Math.hypot(pos[v] - sphere[4 * t], pos[v + 1] - sphere[4 * t + 1], pos[v + 2] - sphere[4 * t + 2]))
    sphere[4 * t + 3] = r
  }
  const out = new Float64Array(points.length / 3)
  for (let i = 0; i < out.length; i++) {
    const px = points[3 * i], py = points[3 * i + 1], pz = points[3 * i + 2]
    let best = Infinity
    for (let t = 0; t < triCount; t++) {
      const o = 4 * t
      if (Math.hypot(px - sphere[o], py - sphere[o + 1], pz - sphere[o + 2]) - sphere[o + 3] > best) continue
      const d = triangleDistance(px, py, pz, pos, tris[3 * t], tris[3 * t + 1], tris[3 * t + 2])
      if (d < best) best = d
    }
    out[i] = best
  }
  return out
}

/** A render edge's length against its rest length (rest positions in the x-y plane, as `buildGridMesh` gives them). */
export function edgeStretch(positions: ArrayLike<number>, rest: ArrayLike<number>, p: number, q: number): number {
  const now = Math.hypot(
    positions[3 * p] - positions[3 * q],
    positions[3 * p + 1] - positions[3 * q + 1],
    positions[3 * p + 2] - positions[3 * q + 2],
  )
  return now / Math.hypot(rest[3 * p] - rest[3 * q], rest[3 * p + 1] - rest[3 * q + 1])
}
