import type { ConvexHull } from '../core/shapes'
import { ClothError, checkFiniteArray } from '../core/errors'

/** Most distinct face planes a convex-hull collider may have (each costs a dot product per particle). */
export const MAX_HULL_PLANES = 256

/**
 * Convex hull of a point cloud (xyz interleaved), by incremental construction: start from a
 * tetrahedron of extreme points, then add each remaining point, replacing the faces it sees with a
 * fan from the point to their horizon. Coplanar triangles are merged into one plane each, so a box
 * given by its 8 corners has 6 planes. Runs once, when a collider is created (O(points × faces)).
 *
 * Throws ClothError when the points are not finite or do not span a volume, or when the hull has
 * more than MAX_HULL_PLANES planes.
 */
export function buildConvexHull(points: ArrayLike<number>, argument = 'points'): ConvexHull {
  const p = checkFiniteArray(argument, points, 3)
  const n = p.length / 3
  if (n < 4) throw new ClothError(argument, points, 'must hold at least 4 points (xyz interleaved)')
  const X = (i: number) => p[3 * i], Y = (i: number) => p[3 * i + 1], Z = (i: number) => p[3 * i + 2]
  let minX = Infinity, minY = Infinity, minZ = Infinity, maxX = -Infinity, maxY = -Infinity, maxZ = -Infinity
  for (let i = 0; i < n; i++) {
    minX = Math.min(minX, X(i)); maxX = Math.max(maxX, X(i))
    minY = Math.min(minY, Y(i)); maxY = Math.max(maxY, Y(i))
    minZ = Math.min(minZ, Z(i)); maxZ = Math.max(maxZ, Z(i))
  }
  const scale = Math.hypot(maxX - minX, maxY - minY, maxZ - minZ)
  const eps = 1e-9 * Math.max(scale, 1e-12)
  const flat = () => new ClothError(argument, points, 'must span a volume (they are coincident, collinear or coplanar)')
  if (!(scale > 0)) throw flat()

  // initial tetrahedron: two far-apart points, the farthest from their line, the farthest from that plane
  let a = 0
  for (let i = 1; i < n; i++) if (X(i) < X(a)) a = i
  let b = a, best = -1
  for (let i = 0; i < n; i++) {
    const d = (X(i) - X(a)) ** 2 + (Y(i) - Y(a)) ** 2 + (Z(i) - Z(a)) ** 2
    if (d > best) { best = d; b = i }
  }
  let c = a
  best = -1
  for (let i = 0; i < n; i++) {
    const cx = (Y(b) - Y(a)) * (Z(i) - Z(a)) - (Z(b) - Z(a)) * (Y(i) - Y(a))
    const cy = (Z(b) - Z(a)) * (X(i) - X(a)) - (X(b) - X(a)) * (Z(i) - Z(a))
    const cz = (X(b) - X(a)) * (Y(i) - Y(a)) - (Y(b) - Y(a)) * (X(i) - X(a))
    const d = cx * cx + cy * cy + cz * cz
    if (d > best) { best = d; c = i }
  }
  if (!(Math.sqrt(best) > eps * scale)) throw flat()
  const nx0 = (Y(b) - Y(a)) * (Z(c) - Z(a)) - (Z(b) - Z(a)) * (Y(c) - Y(a))
  const ny0 = (Z(b) - Z(a)) * (X(c) - X(a)) - (X(b) - X(a)) * (Z(c) - Z(a))
  const nz0 = (X(b) - X(a)) * (Y(c) - Y(a)) - (Y(b) - Y(a)) * (X(c) - X(a))
  const l0 = Math.hypot(nx0, ny0, nz0)
  let d4 = a
  best = -1
  for (let i = 0; i < n; i++) {
    const d = Math.abs((nx0 * (X(i) - X(a)) + ny0 * (Y(i) - Y(a)) + nz0 * (Z(i) - Z(a))) / l0)
    if (d > best) { best = d; d4 = i }
  }
  if (!(best > eps)) throw flat()

  // faces as vertex triples, counter-clockwise seen from outside; plane n·x = d per face
  const faces: number[][] = []
  const fn: number[][] = []
  const alive: boolean[] = []
  const cx = (X(a) + X(b) + X(c) + X(d4)) / 4, cy = (Y(a) + Y(b) + Y(c) + Y(d4)) / 4, cz = (Z(a) + Z(b) + Z(c) + Z(d4)) / 4
  const addFace = (i: number, j: number, k: number) => {
    let nx = (Y(j) - Y(i)) * (Z(k) - Z(i)) - (Z(j) - Z(i)) * (Y(k) - Y(i))
    let ny = (Z(j) - Z(i)) * (X(k) - X(i)) - (X(j) - X(i)) * (Z(k) - Z(i))
    let nz = (X(j) - X(i)) * (Y(k) - Y(i)) - (Y(j) - Y(i)) * (X(k) - X(i))
    const l = Math.hypot(nx, ny, nz) || 1
    nx /= l; ny /= l; nz /= l
    // keep the interior point (centroid of the first tetrahedron) behind every face
    if (nx * (cx - X(i)) + ny * (cy - Y(i)) + nz * (cz - Z(i)) > 0) {
      faces.push([i, k, j])
      fn.push([-nx, -ny, -nz, -(nx * X(i) + ny * Y(i) + nz * Z(i))])
    } else {
      faces.push([i, j, k])
      fn.push([nx, ny, nz, nx * X(i) + ny * Y(i) + nz * Z(i)])
    }
    alive.push(true)
  }
  addFace(a, b, c)
  addFace(a, b, d4)
  addFace(a, c, d4)
  addFace(b, c, d4)

  const edges = new Map<number, number>()
  for (let q = 0; q < n; q++) {
    if (q === a || q === b || q === c || q === d4) continue
    const qx = X(q), qy = Y(q), qz = Z(q)
    edges.clear()
    let visible = 0
    for (let f = 0; f < faces.length; f++) {
      if (!alive[f]) continue
      const m = fn[f]
      if (m[0] * qx + m[1] * qy + m[2] * qz - m[3] <= eps) continue
      alive[f] = false
      visible++
      const [i, j, k] = faces[f]
      edges.set(i * n + j, 1)
      edges.set(j * n + k, 1)
      edges.set(k * n + i, 1)
    }
    if (visible === 0) continue // inside the current hull
    // horizon: directed edges of visible faces whose reverse is not on a visible face
    for (const key of edges.keys()) {
      const i = Math.floor(key / n), j = key % n
      if (edges.has(j * n + i)) continue
      addFace(i, j, q)
    }
  }

  // vertices used by the live faces, renumbered
  const remap = new Int32Array(n).fill(-1)
  const verts: number[] = []
  const tris: number[] = []
  const planes: number[] = []
  for (let f = 0; f < faces.length; f++) {
    if (!alive[f]) continue
    for (const v of faces[f]) {
      if (remap[v] < 0) {
        remap[v] = verts.length / 3
        verts.push(X(v), Y(v), Z(v))
      }
      tris.push(remap[v])
    }
    const m = fn[f]
    let dup = false
    for (let k = 0; k < planes.length; k += 4) {
      if (m[0] * planes[k] + m[1] * planes[k + 1] + m[2] * planes[k + 2] > 1 - 1e-6 && Math.abs(m[3] - planes[k + 3]) < 1e-6 * scale) {
        dup = true
        break
      }
    }
    if (!dup) planes.push(m[0], m[1], m[2], m[3])
  }
  const planeCount = planes.length / 4
  if (planeCount > MAX_HULL_PLANES) {
    throw new ClothError(argument, points, `has a hull of ${planeCount} planes; at most ${MAX_HULL_PLANES} are supported (use fewer points)`)
  }
  return { planes: Float64Array.from(planes), planeCount, vertices: Float64Array.from(verts), indices: Uint32Array.from(tris) }
}
