import { ClothError } from '../core/errors'
import { writeRenderMesh } from '../kernels/mesh'
import { FRAME_SIZE, embedFrame } from '../kernels/proxy'

/** Tangential offsets up to this are taken as none, m (below float32 resolution at metre scale). */
const TANGENT_OFFSET = 1e-7
/** Tangential normal components up to this are taken as none (float32 normals carry ~1e-7 noise). */
const TANGENT_NORMAL = 1e-6

/**
 * How a render mesh is embedded in a cloth (see `kernels/proxy.ts`): built once from the two rest
 * shapes, read-only afterwards. Float32 weights, offsets and normals (36 bytes per render vertex
 * with the triangle index): finer than the float32 output they make.
 */
export interface ProxyBinding {
  readonly vertexCount: number
  readonly triangleCount: number
  /** Render triangles, 3 vertex indices each. */
  readonly indices: Uint32Array
  /** Simulated triangle of each render vertex. */
  readonly tri: Int32Array
  /** Barycentric weights of that triangle's corners 0 and 1, 2 per vertex (corner 2 has the rest). */
  readonly bary: Float32Array
  /** Offset from the embedded point in its frame (T, B, N), 3 per vertex, m. */
  readonly offset: Float32Array
  /** The render vertex's rest normal in the same frame, 3 per vertex (unit). */
  readonly normal: Float32Array
  /** Seams of each render triangle: `seamStart[k]` .. `seamStart[k + 1]` (see `updateProxySeams`). */
  readonly seamStart: Int32Array
  /** Two simulated triangles and their two corners per seam. */
  readonly seamTri: Int32Array
  readonly seamCorner: Uint8Array
  /** Largest distance of a render vertex from the simulated rest surface, m. */
  readonly maxOffset: number
}

/**
 * Embeds a render mesh (`positions` xyz and `indices`, already checked) in a simulated rest mesh
 * (`rest`, `tris`, `count` particles): each render vertex in the simulated triangle closest to it,
 * at the closest point's barycentric weights, with its offset from that point and its own rest
 * normal (area-weighted over the render triangles) expressed in the frame there. A render vertex
 * farther than `maxOffset` from the simulated surface is a ClothError naming `arg`: the two meshes
 * are most likely in different frames.
 */
export function bindProxy(
  rest: Float64Array,
  tris: Uint32Array,
  triCount: number,
  count: number,
  positions: ArrayLike<number>,
  indices: ArrayLike<number>,
  maxOffset: number,
  arg: string,
): ProxyBinding {
  const nv = (positions.length / 3) | 0
  const nt = (indices.length / 3) | 0
  const simNormal = new Float32Array(3 * count)
  writeRenderMesh(rest, count, tris, triCount, new Float32Array(3 * count), simNormal)
  const render = Float64Array.from(positions)
  const renderIndices = Uint32Array.from(indices)
  const renderNormal = new Float32Array(3 * nv)
  writeRenderMesh(render, nv, renderIndices, nt, new Float32Array(3 * nv), renderNormal)

  const grid = new TriangleGrid(rest, tris, triCount)
  const tri = new Int32Array(nv), bary = new Float32Array(2 * nv)
  const offset = new Float32Array(3 * nv), normal = new Float32Array(3 * nv)
  const hit = new Float64Array(4)
  const f = new Float64Array(FRAME_SIZE)
  let worst = 0
  for (let v = 0; v < nv; v++) {
    const x = render[3 * v], y = render[3 * v + 1], z = render[3 * v + 2]
    const t = grid.closest(x, y, z, maxOffset, hit)
    const d = Math.sqrt(hit[0])
    if (t < 0 || d > maxOffset) {
      throw new ClothError(
        `${arg}[${3 * v}..${3 * v + 2}]`,
        [x, y, z],
        `lies ${
          t < 0 ? 'more than ' + maxOffset : d.toPrecision(3)
        } m from the cloth's rest surface, farther than maxOffset (${maxOffset} m): ` +
          "give render positions in the cloth's rest frame (createCloth: the sheet's local frame, the middle of its top edge at the origin; createClothFromMesh: the positions it was given)",
      )
    }
    if (d > worst) worst = d
    tri[v] = t
    bary[2 * v] = hit[1]
    bary[2 * v + 1] = hit[2]
    embedFrame(rest, simNormal, tris, t, bary, 2 * v, f)
    const ox = x - f[0], oy = y - f[1], oz = z - f[2]
    const rx = renderNormal[3 * v], ry = renderNormal[3 * v + 1], rz = renderNormal[3 * v + 2]
    for (let k = 0; k < 3; k++) {
      const ex = f[3 + 3 * k], ey = f[4 + 3 * k], ez = f[5 + 3 * k]
      offset[3 * v + k] = ox * ex + oy * ey + oz * ez
      normal[3 * v + k] = rx * ex + ry * ey + rz * ez
    }
    // along the normal within float32 resolution: exact zeros let the update take its short path
    if (Math.abs(offset[3 * v]) <= TANGENT_OFFSET && Math.abs(offset[3 * v + 1]) <= TANGENT_OFFSET) offset[3 * v] = offset[3 * v + 1] = 0
    if (Math.abs(normal[3 * v]) <= TANGENT_NORMAL && Math.abs(normal[3 * v + 1]) <= TANGENT_NORMAL) {
      normal[3 * v] = normal[3 * v + 1] = 0
      normal[3 * v + 2] = normal[3 * v + 2] < 0 ? -1 : 1
    }
  }
  return {
    vertexCount: nv,
    triangleCount: nt,
    indices: renderIndices,
    tri,
    bary,
    offset,
    normal,
    ...seams(rest, tris, tri, renderIndices, nt),
    maxOffset: worst,
  }
}

/**
 * The seams of each render triangle: for every two of its corners in different simulated
 * triangles, the corners of those triangles that lie at the same rest point (one shared vertex, or
 * a vertex and the copy a tear made of it). Two triangles that share a single rest point are
 * joined across the triangles between them around it (the fewest such steps, both ways round on a
 * tie): the seams are those of each step, so a crack ending at that point (its tip, one particle
 * still) splits them too. A pair sharing no rest point gets no seam.
 */
function seams(rest: Float64Array, tris: Uint32Array, tri: Int32Array, indices: Uint32Array, nt: number) {
  const fans = new Fans(rest, tris)
  const seamStart = new Int32Array(nt + 1)
  for (let k = 0; k < nt; k++) {
    for (let e = 0; e < 3; e++) {
      const ta = tri[indices[3 * k + e]], tb = tri[indices[3 * k + ((e + 1) % 3)]]
      if (ta !== tb) fans.between(ta, tb)
    }
    seamStart[k + 1] = fans.count
  }
  const n = fans.count, pairs = fans.pairs
  const seamTri = new Int32Array(2 * n), seamCorner = new Uint8Array(2 * n)
  for (let s = 0; s < n; s++) {
    seamTri[2 * s] = pairs[4 * s]
    seamTri[2 * s + 1] = pairs[4 * s + 1]
    seamCorner[2 * s] = pairs[4 * s + 2]
    seamCorner[2 * s + 1] = pairs[4 * s + 3]
  }
  return { seamStart, seamTri, seamCorner }
}

/**
 * The simulated rest mesh by rest point (creation time only): each particle's point (particles at
 * the same rest position are one point: a vertex and its torn copies), and the triangles around
 * each point.
 */
class Fans {
  /** Rest point of each triangle corner. */
  private readonly point: Int32Array
  /** Triangles around each point: `around[start[p]]` .. `around[start[p + 1]]`. */
  private readonly start: Int32Array
  private readonly around: Int32Array

  constructor(rest: Float64Array, tris: Uint32Array) {
    const ids = new Map<string, number>()
    const nt = tris.length / 3
    this.point = new Int32Array(tris.length)
    for (let c = 0; c < tris.length; c++) {
      const p = 3 * tris[c]
      const key = `${rest[p]},${rest[p + 1]},${rest[p + 2]}`
      let id = ids.get(key)
      if (id === undefined) ids.set(key, id = ids.size)
      this.point[c] = id
    }
    this.start = new Int32Array(ids.size + 1)
    for (let c = 0; c < tris.length; c++) this.start[this.point[c] + 1]++
    for (let p = 0; p < ids.size; p++) this.start[p + 1] += this.start[p]
    const fill = this.start.slice(0, ids.size)
    this.around = new Int32Array(tris.length)
    for (let t = 0; t < nt; t++) for (let c = 0; c < 3; c++) this.around[fill[this.point[3 * t + c]]++] = t
  }

  /** How many rest points triangles a and b share; the last one found in `last`. */
  shared(a: number, b: number): number {
    let n = 0
    for (let ca = 0; ca < 3; ca++) {
      const p = this.point[3 * a + ca]
      if ((ca > 0 && p === this.point[3 * a]) || (ca > 1 && p === this.point[3 * a + 1])) continue // (a degenerate triangle's repeated point)
      if (p === this.point[3 * b] || p === this.point[3 * b + 1] || p === this.point[3 * b + 2]) {
        n++
        this.last = p
      }
    }
    return n
  }

  /** The point `shared` found last. */
  last = -1

  /** Adds a seam for each pair of corners of triangles a and b at the same rest point. */
  private seam(a: number, b: number): void {
    for (let ca = 0; ca < 3; ca++) {
      for (let cb = 0; cb < 3; cb++) if (this.point[3 * a + ca] === this.point[3 * b + cb]) this.add(a, b, ca, cb)
    }
  }

  /** Appends the seams between triangles a and b (see `seams`). */
  between(a: number, b: number): void {
    if (this.shared(a, b) === 1) this.steps(this.last, a, b)
    else this.seam(a, b)
  }

  /** The seams found so far: triangle, triangle, corner, corner each. */
  pairs = new Int32Array(1024)
  count = 0

  private add(a: number, b: number, ca: number, cb: number): void {
    if (4 * this.count + 4 > this.pairs.length) {
      const grown = new Int32Array(2 * this.pairs.length)
      grown.set(this.pairs)
      this.pairs = grown
    }
    const o = 4 * this.count++
    this.pairs[o] = a
    this.pairs[o + 1] = b
    this.pairs[o + 2] = ca
    this.pairs[o + 3] = cb
  }

  /**
   * The seams of each step from triangle a to triangle b around rest point p, over triangles
   * around p sharing an edge (two rest points), along every way with the fewest steps (when no
   * such way joins them: the pair at p itself).
   */
  private steps(p: number, a: number, b: number): void {
    const { fan, d } = this.fanOf(p)
    const f = fan.length, ia = fan.indexOf(a), ib = fan.indexOf(b)
    const length = d[ia * f + ib]
    if (!(length < Infinity)) {
      this.seam(a, b)
      return
    }
    // each step s → t on a way of the fewest steps
    for (let s = 0; s < f; s++) {
      if (d[ia * f + s] + d[s * f + ib] !== length) continue
      for (let t = 0; t < f; t++) {
        if (d[s * f + t] === 1 && d[ia * f + t] === d[ia * f + s] + 1 && d[ia * f + t] + d[t * f + ib] === length)
          this.seam(fan[s], fan[t])
      }
    }
  }

  /** The triangles around point p and the fewest steps between each two across shared edges (f × f, Infinity: none), found once per point. */
  private fanOf(p: number): { fan: Int32Array; d: Float64Array } {
    let known = this.fans.get(p)
    if (known !== undefined) return known
    const fan = this.around.slice(this.start[p], this.start[p + 1])
    const f = fan.length
    const d = new Float64Array(f * f).fill(Infinity)
    for (let s = 0; s < f; s++) {
      d[s * f + s] = 0
      for (let t = 0; t < f; t++) if (t !== s && this.shared(fan[s], fan[t]) >= 2) d[s * f + t] = 1
    }
    for (let m = 0; m < f; m++) {
      for (let s = 0; s < f; s++) {
        for (let t = 0; t < f; t++) if (d[s * f + m] + d[m * f + t] < d[s * f + t]) d[s * f + t] = d[s * f + m] + d[m * f + t]
      }
    }
    this.fans.set(p, known = { fan, d })
    return known
  }

  private readonly fans = new Map<number, { fan: Int32Array; d: Float64Array }>()
}

/**
 * A uniform grid over a triangle mesh's bounds, each cell listing the triangles whose bounding box
 * meets it, for closest-triangle queries (creation time only). Cells are about the mean triangle
 * size; a query searches rings of cells around the point's cell until no nearer triangle can be
 * left outside them.
 */
class TriangleGrid {
  private readonly min = new Float64Array(3)
  private readonly dims = new Int32Array(3)
  private readonly h: number
  private readonly start: Int32Array
  private readonly list: Int32Array
  private readonly stamp: Int32Array
  private query = 0

  constructor(private readonly rest: Float64Array, private readonly tris: Uint32Array, triCount: number) {
    const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity]
    let size = 0
    for (let t = 0; t < triCount; t++) {
      let ext = 0
      for (let k = 0; k < 3; k++) {
        let a = Infinity, b = -Infinity
        for (let c = 0; c < 3; c++) {
          const x = rest[3 * tris[3 * t + c] + k]
          if (x < a) a = x
          if (x > b) b = x
        }
        if (a < lo[k]) lo[k] = a
        if (b > hi[k]) hi[k] = b
        if (b - a > ext) ext = b - a
      }
      size += ext
    }
    let h = triCount > 0 ? size / triCount : 1
    const span = Math.max(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2])
    if (!(h > span * 1e-6)) h = span > 0 ? span / 64 : 1
    // at most about 8 cells per triangle (a few sliver triangles must not make a huge grid)
    const cellsFor = (hh: number) =>
      (Math.floor((hi[0] - lo[0]) / hh) + 1) * (Math.floor((hi[1] - lo[1]) / hh) + 1) * (Math.floor((hi[2] - lo[2]) / hh) + 1)
    while (cellsFor(h) > 8 * triCount + 64) h *= 1.5
    this.h = h
    for (let k = 0; k < 3; k++) {
      this.min[k] = lo[k]
      this.dims[k] = Math.floor((hi[k] - lo[k]) / h) + 1
    }
    const cells = this.dims[0] * this.dims[1] * this.dims[2]
    const start = new Int32Array(cells + 1)
    let list = new Int32Array(0)
    const box = new Int32Array(6)
    for (let pass = 0; pass < 2; pass++) {
      // first count the triangles of each cell, then list them
      if (pass === 1) {
        for (let i = 0; i < cells; i++) start[i + 1] += start[i]
        list = new Int32Array(start[cells])
      }
      const fill = pass === 1 ? start.slice() : null
      for (let t = 0; t < triCount; t++) {
        this.cellBox(t, box)
        for (let i = box[0]; i <= box[3]; i++) {
          for (let j = box[1]; j <= box[4]; j++) {
            for (let k = box[2]; k <= box[5]; k++) {
              const cell = (i * this.dims[1] + j) * this.dims[2] + k
              if (fill) list[fill[cell]++] = t
              else start[cell + 1]++
            }
          }
        }
      }
    }
    this.start = start
    this.list = list
    this.stamp = new Int32Array(triCount).fill(-1)
  }

  private cellBox(t: number, box: Int32Array): void {
    for (let k = 0; k < 3; k++) {
      let a = Infinity, b = -Infinity
      for (let c = 0; c < 3; c++) {
        const x = this.rest[3 * this.tris[3 * t + c] + k]
        if (x < a) a = x
        if (x > b) b = x
      }
      box[k] = this.cell(a, k)
      box[k + 3] = this.cell(b, k)
    }
  }

  private cell(x: number, k: number): number {
    const i = Math.floor((x - this.min[k]) / this.h)
    return i < 0 ? 0 : i >= this.dims[k] ? this.dims[k] - 1 : i
  }

  /**
   * The triangle closest to (x, y, z), or −1 when none lies within `within`; out = [squared
   * distance, w0, w1, w2] of its closest point. Ties go to the lower triangle index.
   */
  closest(x: number, y: number, z: number, within: number, out: Float64Array): number {
    const q = this.query++
    const ci = this.cell(x, 0), cj = this.cell(y, 1), ck = this.cell(z, 2)
    const [ni, nj, nk] = this.dims
    const maxRing = Math.max(ni, nj, nk)
    let best = -1, bestD2 = Infinity, b0 = 0, b1 = 0, b2 = 0
    for (let r = 0; r <= maxRing; r++) {
      for (let i = Math.max(0, ci - r); i <= Math.min(ni - 1, ci + r); i++) {
        for (let j = Math.max(0, cj - r); j <= Math.min(nj - 1, cj + r); j++) {
          for (let k = Math.max(0, ck - r); k <= Math.min(nk - 1, ck + r); k++) {
            if (Math.max(Math.abs(i - ci), Math.abs(j - cj), Math.abs(k - ck)) !== r) continue
            const cell = (i * nj + j) * nk + k
            for (let p = this.start[cell]; p < this.start[cell + 1]; p++) {
              const t = this.list[p]
              if (this.stamp[t] === q) continue
              this.stamp[t] = q
              closestOnTriangle(this.rest, this.tris, t, x, y, z, out)
              if (out[0] < bestD2 || (out[0] === bestD2 && t < best)) {
                best = t
                bestD2 = out[0]
                b0 = out[1]
                b1 = out[2]
                b2 = out[3]
              }
            }
          }
        }
      }
      // every cell of the next ring is at least r cells away from the point along some axis
      const reach = r * this.h
      if (bestD2 <= reach * reach || reach > within) break
    }
    out[0] = bestD2
    out[1] = b0
    out[2] = b1
    out[3] = b2
    return best
  }
}

/**
 * The point of triangle t closest to p: out = [squared distance, w0, w1, w2] (its barycentric
 * weights). Regions tested in turn: the three corners, the three edges, the face.
 */
function closestOnTriangle(rest: Float64Array, tris: Uint32Array, t: number, px: number, py: number, pz: number, out: Float64Array): void {
  const a = 3 * tris[3 * t], b = 3 * tris[3 * t + 1], c = 3 * tris[3 * t + 2]
  const abx = rest[b] - rest[a], aby = rest[b + 1] - rest[a + 1], abz = rest[b + 2] - rest[a + 2]
  const acx = rest[c] - rest[a], acy = rest[c + 1] - rest[a + 1], acz = rest[c + 2] - rest[a + 2]
  const apx = px - rest[a], apy = py - rest[a + 1], apz = pz - rest[a + 2]
  const d1 = abx * apx + aby * apy + abz * apz, d2 = acx * apx + acy * apy + acz * apz
  let u = 1, v = 0, w = 0
  if (!(d1 <= 0 && d2 <= 0)) {
    const bpx = px - rest[b], bpy = py - rest[b + 1], bpz = pz - rest[b + 2]
    const d3 = abx * bpx + aby * bpy + abz * bpz, d4 = acx * bpx + acy * bpy + acz * bpz
    const cpx = px - rest[c], cpy = py - rest[c + 1], cpz = pz - rest[c + 2]
    const d5 = abx * cpx + aby * cpy + abz * cpz, d6 = acx * cpx + acy * cpy + acz * cpz
    const vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4
    if (d3 >= 0 && d4 <= d3) {
      u = 0
      v = 1
    } else if (d6 >= 0 && d5 <= d6) {
      u = 0
      w = 1
    } else if (vc <= 0 && d1 >= 0 && d3 <= 0) {
      v = d1 / (d1 - d3)
      u = 1 - v
    } else if (vb <= 0 && d2 >= 0 && d6 <= 0) {
      w = d2 / (d2 - d6)
      u = 1 - w
    } else if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
      w = (d4 - d3) / (d4 - d3 + (d5 - d6))
      v = 1 - w
      u = 0
    } else {
      const s = 1 / (va + vb + vc)
      v = vb * s
      w = vc * s
      u = 1 - v - w
    }
    if (!(Number.isFinite(v) && Number.isFinite(w))) {
      // a degenerate triangle: its first corner stands for it
      u = 1
      v = 0
      w = 0
    }
  }
  const qx = u * rest[a] + v * rest[b] + w * rest[c] - px
  const qy = u * rest[a + 1] + v * rest[b + 1] + w * rest[c + 1] - py
  const qz = u * rest[a + 2] + v * rest[b + 2] + w * rest[c + 2] - pz
  out[0] = qx * qx + qy * qy + qz * qz
  out[1] = u
  out[2] = v
  out[3] = w
}
