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
  let minX = Infinity, minY = Infinity, minZ = Infinity, maxX = -Infinity, maxY = -Infinity, maxZ = -Infinity
  for (let i = 0; i < n; i++) {
    minX = Math.min(minX, p[3 * i])
    maxX = Math.max(maxX, p[3 * i])
    minY = Math.min(minY, p[3 * i + 1])
    maxY = Math.max(maxY, p[3 * i + 1])
    minZ = Math.min(minZ, p[3 * i + 2])
    maxZ = Math.max(maxZ, p[3 * i + 2])
  }
  const scale = Math.hypot(maxX - minX, maxY - minY, maxZ - minZ)
  const eps = 1e-9 * Math.max(scale, 1e-12)
  const tetra = scale > 0 ? initialTetrahedron(p, n, eps, scale) : null
  if (tetra === null) throw new ClothError(argument, points, 'must span a volume (they are coincident, collinear or coplanar)')
  const hull = new HullFaces(p, tetra)
  for (let q = 0; q < n; q++) if (!tetra.includes(q)) hull.add(q, eps)
  const out = hull.compact(scale)
  if (out.planeCount > MAX_HULL_PLANES) {
    throw new ClothError(
      argument,
      points,
      `has a hull of ${out.planeCount} planes; at most ${MAX_HULL_PLANES} are supported (use fewer points)`,
    )
  }
  return out
}

/**
 * Four extreme points spanning a volume: two far-apart points, the farthest from their line, the
 * farthest from that plane; null when the points are (nearly) collinear or coplanar.
 */
function initialTetrahedron(p: ArrayLike<number>, n: number, eps: number, scale: number): number[] | null {
  const X = (i: number) => p[3 * i], Y = (i: number) => p[3 * i + 1], Z = (i: number) => p[3 * i + 2]
  let a = 0
  for (let i = 1; i < n; i++) if (X(i) < X(a)) a = i
  let b = a, best = -1
  for (let i = 0; i < n; i++) {
    const d = (X(i) - X(a)) ** 2 + (Y(i) - Y(a)) ** 2 + (Z(i) - Z(a)) ** 2
    if (d > best) {
      best = d
      b = i
    }
  }
  let c = a
  best = -1
  for (let i = 0; i < n; i++) {
    const cx = (Y(b) - Y(a)) * (Z(i) - Z(a)) - (Z(b) - Z(a)) * (Y(i) - Y(a))
    const cy = (Z(b) - Z(a)) * (X(i) - X(a)) - (X(b) - X(a)) * (Z(i) - Z(a))
    const cz = (X(b) - X(a)) * (Y(i) - Y(a)) - (Y(b) - Y(a)) * (X(i) - X(a))
    const d = cx * cx + cy * cy + cz * cz
    if (d > best) {
      best = d
      c = i
    }
  }
  if (!(Math.sqrt(best) > eps * scale)) return null
  const nx0 = (Y(b) - Y(a)) * (Z(c) - Z(a)) - (Z(b) - Z(a)) * (Y(c) - Y(a))
  const ny0 = (Z(b) - Z(a)) * (X(c) - X(a)) - (X(b) - X(a)) * (Z(c) - Z(a))
  const nz0 = (X(b) - X(a)) * (Y(c) - Y(a)) - (Y(b) - Y(a)) * (X(c) - X(a))
  const l0 = Math.hypot(nx0, ny0, nz0)
  let d4 = a
  best = -1
  for (let i = 0; i < n; i++) {
    const d = Math.abs((nx0 * (X(i) - X(a)) + ny0 * (Y(i) - Y(a)) + nz0 * (Z(i) - Z(a))) / l0)
    if (d > best) {
      best = d
      d4 = i
    }
  }
  return best > eps ? [a, b, c, d4] : null
}

/** The hull under construction: faces as vertex triples, counter-clockwise seen from outside, with their planes n·x = d. */
class HullFaces {
  readonly faces: number[][] = []
  readonly planes: number[][] = []
  readonly alive: boolean[] = []
  /** Centroid of the first tetrahedron: inside every face. */
  private readonly cx: number
  private readonly cy: number
  private readonly cz: number
  private readonly edges = new Map<number, number>()

  constructor(private readonly p: ArrayLike<number>, [a, b, c, d]: number[]) {
    this.cx = (p[3 * a] + p[3 * b] + p[3 * c] + p[3 * d]) / 4
    this.cy = (p[3 * a + 1] + p[3 * b + 1] + p[3 * c + 1] + p[3 * d + 1]) / 4
    this.cz = (p[3 * a + 2] + p[3 * b + 2] + p[3 * c + 2] + p[3 * d + 2]) / 4
    this.addFace(a, b, c)
    this.addFace(a, b, d)
    this.addFace(a, c, d)
    this.addFace(b, c, d)
  }

  private addFace(i: number, j: number, k: number): void {
    const p = this.p
    const X = (v: number) => p[3 * v], Y = (v: number) => p[3 * v + 1], Z = (v: number) => p[3 * v + 2]
    let nx = (Y(j) - Y(i)) * (Z(k) - Z(i)) - (Z(j) - Z(i)) * (Y(k) - Y(i))
    let ny = (Z(j) - Z(i)) * (X(k) - X(i)) - (X(j) - X(i)) * (Z(k) - Z(i))
    let nz = (X(j) - X(i)) * (Y(k) - Y(i)) - (Y(j) - Y(i)) * (X(k) - X(i))
    const l = Math.hypot(nx, ny, nz) || 1
    nx /= l
    ny /= l
    nz /= l
    // keep the interior point behind every face
    if (nx * (this.cx - X(i)) + ny * (this.cy - Y(i)) + nz * (this.cz - Z(i)) > 0) {
      this.faces.push([i, k, j])
      this.planes.push([-nx, -ny, -nz, -(nx * X(i) + ny * Y(i) + nz * Z(i))])
    } else {
      this.faces.push([i, j, k])
      this.planes.push([nx, ny, nz, nx * X(i) + ny * Y(i) + nz * Z(i)])
    }
    this.alive.push(true)
  }

  /** Adds point q: the faces it sees are replaced by a fan from q to their horizon (nothing when q is inside). */
  add(q: number, eps: number): void {
    const p = this.p
    const n = p.length / 3
    const qx = p[3 * q], qy = p[3 * q + 1], qz = p[3 * q + 2]
    const edges = this.edges
    edges.clear()
    let visible = 0
    for (let f = 0; f < this.faces.length; f++) {
      if (!this.alive[f]) continue
      const m = this.planes[f]
      if (m[0] * qx + m[1] * qy + m[2] * qz - m[3] <= eps) continue
      this.alive[f] = false
      visible++
      const [i, j, k] = this.faces[f]
      edges.set(i * n + j, 1)
      edges.set(j * n + k, 1)
      edges.set(k * n + i, 1)
    }
    if (visible === 0) return
    // horizon: directed edges of visible faces whose reverse is not on a visible face
    for (const key of edges.keys()) {
      const i = Math.floor(key / n), j = key % n
      if (edges.has(j * n + i)) continue
      this.addFace(i, j, q)
    }
  }

  /** The live faces' vertices renumbered, their triangles, and one plane per set of coplanar faces. */
  compact(scale: number): ConvexHull {
    const p = this.p
    const n = p.length / 3
    const remap = new Int32Array(n).fill(-1)
    const verts: number[] = []
    const tris: number[] = []
    const planes: number[] = []
    for (let f = 0; f < this.faces.length; f++) {
      if (!this.alive[f]) continue
      for (const v of this.faces[f]) {
        if (remap[v] < 0) {
          remap[v] = verts.length / 3
          verts.push(p[3 * v], p[3 * v + 1], p[3 * v + 2])
        }
        tris.push(remap[v])
      }
      const m = this.planes[f]
      let dup = false
      for (let k = 0; k < planes.length; k += 4) {
        if (m[0] * planes[k] + m[1] * planes[k + 1] + m[2] * planes[k + 2] > 1 - 1e-6 && Math.abs(m[3] - planes[k + 3]) < 1e-6 * scale) {
          dup = true
          break
        }
      }
      if (!dup) planes.push(m[0], m[1], m[2], m[3])
    }
    return {
      planes: Float64Array.from(planes),
      planeCount: planes.length / 4,
      vertices: Float64Array.from(verts),
      indices: Uint32Array.from(tris),
    }
  }
}
