import { ClothError, checkBoundedArray } from '../core/errors'

/**
 * Texture coordinates of cloths and render proxies, two per vertex (u, v), float32.
 *
 * Convention (the one `THREE.PlaneGeometry` uses, so a texture loaded with three.js's default
 * `flipY` reads upright): seen from the front, u runs left to right and v bottom to top, each over
 * 0..1. On a grid, u = column / (columns − 1) and v = 1 − row / (rows − 1): the top-left particle
 * (row 0, column 0) has uv (0, 1), the bottom-right one (1, 0).
 */

/** Largest accepted |u| or |v|: a texture repeated a million times over a cloth is already noise. */
export const MAX_UV = 1e6

/** Texture coordinates of a grid of `columns` × `rows` vertices, row-major from the top left. */
export function gridUvs(columns: number, rows: number): Float32Array {
  const out = new Float32Array(2 * columns * rows)
  for (let r = 0; r < rows; r++) {
    for (let c = 0; c < columns; c++) {
      const i = r * columns + c
      out[2 * i] = c / (columns - 1)
      out[2 * i + 1] = 1 - r / (rows - 1)
    }
  }
  return out
}

/**
 * Default texture coordinates of a mesh: a planar projection of its rest shape. The plane faces
 * the mesh's front (the axis the area-weighted sum of its triangle normals points along most; +z
 * when they cancel out, as on a closed tube), and the projection is seen from that side: u to the
 * right, v up (+y up; for a horizontal mesh, −z up seen from above, +z seen from below). Each of u
 * and v spans 0..1 over the rest shape's bounds, as on a grid, so a mesh with the rest shape of a
 * `createCloth` sheet gets that sheet's uvs.
 */
export function planarUvs(rest: ArrayLike<number>, n: number, tris: ArrayLike<number>, triCount: number): Float32Array {
  let sx = 0, sy = 0, sz = 0
  for (let t = 0; t < triCount; t++) {
    const a = 3 * tris[3 * t], b = 3 * tris[3 * t + 1], c = 3 * tris[3 * t + 2]
    const ux = rest[b] - rest[a], uy = rest[b + 1] - rest[a + 1], uz = rest[b + 2] - rest[a + 2]
    const vx = rest[c] - rest[a], vy = rest[c + 1] - rest[a + 1], vz = rest[c + 2] - rest[a + 2]
    sx += uy * vz - uz * vy
    sy += uz * vx - ux * vz
    sz += ux * vy - uy * vx
  }
  const ax = Math.abs(sx), ay = Math.abs(sy), az = Math.abs(sz)
  // right and up directions of the view from the front: right × up = the front normal
  let rx = 1, ry = 0, rz = 0, upx = 0, upy = 1, upz = 0
  if (ax > ay && ax > az) {
    const s = sx > 0 ? 1 : -1
    rx = 0
    rz = -s
  } else if (ay > az) {
    const s = sy > 0 ? 1 : -1
    upy = 0
    upz = -s
  } else if (sz < 0) {
    rx = -1
  }
  let u0 = Infinity, u1 = -Infinity, v0 = Infinity, v1 = -Infinity
  const out = new Float32Array(2 * n)
  for (let i = 0; i < n; i++) {
    const x = rest[3 * i], y = rest[3 * i + 1], z = rest[3 * i + 2]
    const u = x * rx + y * ry + z * rz, v = x * upx + y * upy + z * upz
    out[2 * i] = u
    out[2 * i + 1] = v
    if (u < u0) u0 = u
    if (u > u1) u1 = u
    if (v < v0) v0 = v
    if (v > v1) v1 = v
  }
  const fu = u1 > u0 ? 1 / (u1 - u0) : 0, fv = v1 > v0 ? 1 / (v1 - v0) : 0
  for (let i = 0; i < n; i++) {
    out[2 * i] = (out[2 * i] - u0) * fu
    out[2 * i + 1] = (out[2 * i + 1] - v0) * fv
  }
  return out
}

/** Checks user texture coordinates: 2 finite numbers within ±MAX_UV per vertex of `n`. */
export function checkUvs(argument: string, uvs: unknown, n: number): ArrayLike<number> {
  const a = checkBoundedArray(argument, uvs, 2, MAX_UV)
  if (a.length !== 2 * n) throw new ClothError(argument, uvs, `must hold 2 numbers (u, v) per vertex: ${2 * n}, not ${a.length}`)
  return a
}
