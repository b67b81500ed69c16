/** Mesh analysis for the topology builders: edges, wings, areas, hinges, and a growable pair list. */

export interface MeshInfo {
  edges: Int32Array
  /** Opposite vertex in the first and second adjacent triangle (−1 for a boundary edge). */
  edgeWing: Int32Array
  /** Summed area of the triangles adjacent to each edge, m². */
  edgeArea: Float64Array
  edgeCount: number
  /** e0, e1, w0, w1 per interior edge, oriented so triangle A = (e0, e1, w0). */
  hinges: Int32Array
  triangleArea: Float64Array
}

/** Finds unique edges, their wings and areas, and hinges. Edges with 3+ triangles get no hinge. */
export function analyseMesh(rest: Float64Array, tris: Uint32Array, n: number): MeshInfo {
  const triCount = (tris.length / 3) | 0
  const index = new Map<number, number>()
  const edgeA: number[] = []
  const edgeB: number[] = []
  const wing0: number[] = []
  const wing1: number[] = []
  const firstOrientedFrom: number[] = [] // e0 as seen from the first triangle's winding
  const area: number[] = []
  const nonManifold = new Set<number>()
  const triangleArea = new Float64Array(triCount)
  for (let t = 0; t < triCount; t++) {
    const v = [tris[3 * t], tris[3 * t + 1], tris[3 * t + 2]]
    const A = triArea(rest, v[0], v[1], v[2])
    triangleArea[t] = A
    for (let k = 0; k < 3; k++) {
      const a = v[k]
      const b = v[(k + 1) % 3]
      const opposite = v[(k + 2) % 3]
      const key = a < b ? a * n + b : b * n + a
      const found = index.get(key)
      if (found === undefined) {
        index.set(key, edgeA.length)
        edgeA.push(Math.min(a, b))
        edgeB.push(Math.max(a, b))
        wing0.push(opposite)
        wing1.push(-1)
        firstOrientedFrom.push(a)
        area.push(A)
      } else {
        area[found] += A
        if (wing1[found] === -1) wing1[found] = opposite
        else nonManifold.add(found)
      }
    }
  }
  const m = edgeA.length
  const edges = new Int32Array(2 * m)
  const edgeWing = new Int32Array(2 * m)
  const hingeList: number[] = []
  for (let e = 0; e < m; e++) {
    edges[2 * e] = edgeA[e]
    edges[2 * e + 1] = edgeB[e]
    edgeWing[2 * e] = wing0[e]
    edgeWing[2 * e + 1] = nonManifold.has(e) ? -1 : wing1[e]
    if (wing1[e] >= 0 && !nonManifold.has(e)) {
      // triangle A = (e0, e1, w0) in its own winding, so e0 is where the first triangle's edge starts
      const e0 = firstOrientedFrom[e]
      const e1 = e0 === edgeA[e] ? edgeB[e] : edgeA[e]
      hingeList.push(e0, e1, wing0[e], wing1[e])
    }
  }
  return { edges, edgeWing, edgeArea: Float64Array.from(area), edgeCount: m, hinges: Int32Array.from(hingeList), triangleArea }
}

export function triArea(p: Float64Array, a: number, b: number, c: number): number {
  const ux = p[3 * b] - p[3 * a], uy = p[3 * b + 1] - p[3 * a + 1], uz = p[3 * b + 2] - p[3 * a + 2]
  const vx = p[3 * c] - p[3 * a], vy = p[3 * c + 1] - p[3 * a + 1], vz = p[3 * c + 2] - p[3 * a + 2]
  const cx = uy * vz - uz * vy, cy = uz * vx - ux * vz, cz = ux * vy - uy * vx
  return 0.5 * Math.sqrt(cx * cx + cy * cy + cz * cz)
}

export function dist(p: ArrayLike<number>, a: number, b: number): number {
  const x = p[3 * b] - p[3 * a], y = p[3 * b + 1] - p[3 * a + 1], z = p[3 * b + 2] - p[3 * a + 2]
  return Math.sqrt(x * x + y * y + z * z)
}

/** True when edge (a, b) is the longest edge of both its triangles and the quad is nearly planar. */
export function isQuadDiagonal(p: Float64Array, a: number, b: number, w0: number, w1: number): boolean {
  const d = dist(p, a, b) * (1 - 1e-6)
  if (d <= dist(p, a, w0) || d <= dist(p, b, w0) || d <= dist(p, a, w1) || d <= dist(p, b, w1)) return false
  // the cross diagonal must be about as long as the diagonal (a rectangle-ish quad)
  const cross = dist(p, w0, w1)
  return cross > 0.7 * d && cross < 1.3 * d
}

// ---------------------------------------------------------------------------------------------
// Assembly: compliance, masses, order

export class PairList {
  a: number[] = []
  b: number[] = []
  kind: number[] = []
  push(a: number, b: number, kind: number): void {
    if (a === b) return // a particle is never constrained to itself
    this.a.push(a)
    this.b.push(b)
    this.kind.push(kind)
  }
  get length(): number {
    return this.a.length
  }
}
