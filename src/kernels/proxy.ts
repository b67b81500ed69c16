/**
 * Render proxies: a render mesh driven by the simulated one. Each render vertex is embedded in a
 * simulated triangle at barycentric weights (w0, w1, w2 = 1 − w0 − w1). At that point the
 * triangle carries a frame:
 * - P = w0·a + w1·b + w2·c, the embedded point;
 * - N, the simulated vertex normals interpolated with the same weights and normalised (smooth across
 *   triangles: on a shared edge it depends on the edge's two vertices only);
 * - T, the triangle's first edge (b − a) made perpendicular to N, and B = N × T.
 * The render vertex sits at P + oT·T + oB·B + oN·N and its normal is nT·T + nB·B + nN·N, with the
 * offsets and normal components measured in the rest shape's frame (`model/proxy.ts`): a vertex on
 * the surface has o = 0, a thick layer's vertices oN = ±thickness, and the rest shape comes back
 * exactly.
 */

/** Slots of a frame written by `embedFrame`: P xyz, T xyz, B xyz, N xyz. */
export const FRAME_SIZE = 12

/**
 * Writes the frame of the point at weights (w[o], w[o + 1]) of triangle `t` into f[0..11] (P, T,
 * B, N). The weights come in an array, not as arguments: doubles passed to a call V8 does not
 * inline are boxed. Degenerate input falls back (N: the face normal, else +z; T: any direction
 * perpendicular to N), so the frame is always orthonormal and finite for finite positions.
 */
export function embedFrame(
  pos: ArrayLike<number>,
  normal: ArrayLike<number>,
  tris: Uint32Array,
  t: number,
  w: ArrayLike<number>,
  o: number,
  f: Float64Array,
): void {
  const a = 3 * tris[3 * t], b = 3 * tris[3 * t + 1], c = 3 * tris[3 * t + 2]
  const w0 = w[o], w1 = w[o + 1], w2 = 1 - w0 - w1
  const ax = pos[a], ay = pos[a + 1], az = pos[a + 2]
  const bx = pos[b], by = pos[b + 1], bz = pos[b + 2]
  const cx = pos[c], cy = pos[c + 1], cz = pos[c + 2]
  f[0] = w0 * ax + w1 * bx + w2 * cx
  f[1] = w0 * ay + w1 * by + w2 * cy
  f[2] = w0 * az + w1 * bz + w2 * cz
  let nx = w0 * normal[a] + w1 * normal[b] + w2 * normal[c]
  let ny = w0 * normal[a + 1] + w1 * normal[b + 1] + w2 * normal[c + 1]
  let nz = w0 * normal[a + 2] + w1 * normal[b + 2] + w2 * normal[c + 2]
  const ex = bx - ax, ey = by - ay, ez = bz - az
  let l2 = nx * nx + ny * ny + nz * nz
  if (!(l2 > 1e-24)) {
    // opposite vertex normals cancelled out (a fold back onto itself): the face's own normal
    const gx = cx - ax, gy = cy - ay, gz = cz - az
    nx = ey * gz - ez * gy
    ny = ez * gx - ex * gz
    nz = ex * gy - ey * gx
    l2 = nx * nx + ny * ny + nz * nz
    if (!(l2 > 1e-36)) {
      nx = 0
      ny = 0
      nz = 1
      l2 = 1
    }
  }
  let s = 1 / Math.sqrt(l2)
  nx *= s
  ny *= s
  nz *= s
  const d = ex * nx + ey * ny + ez * nz
  let tx = ex - d * nx, ty = ey - d * ny, tz = ez - d * nz
  l2 = tx * tx + ty * ty + tz * tz
  if (!(l2 > 1e-36)) {
    // the edge is along N (or has no length): any perpendicular will do
    if (Math.abs(nx) < 0.9) {
      tx = 0
      ty = nz
      tz = -ny
    } else {
      tx = -nz
      ty = 0
      tz = nx
    }
    l2 = tx * tx + ty * ty + tz * tz
  }
  s = 1 / Math.sqrt(l2)
  tx *= s
  ty *= s
  tz *= s
  f[3] = tx
  f[4] = ty
  f[5] = tz
  f[6] = ny * tz - nz * ty
  f[7] = nz * tx - nx * tz
  f[8] = nx * ty - ny * tx
  f[9] = nx
  f[10] = ny
  f[11] = nz
}

/**
 * Moves `count` render vertices with their simulated triangles: positions and unit normals (float32)
 * from the simulated positions `pos` and vertex normals `simNormal`, the triangles `tris` as they
 * are now (a torn triangle carries its render vertices along), and each vertex's triangle, weights,
 * offset and normal in the frame (`tri`, `bary` 2 per vertex, `offset` and `normal` 3 per vertex).
 * `f` is FRAME_SIZE scratch.
 *
 * Most render vertices lie along the interpolated normal (no tangential offset or normal
 * component: `model/proxy.ts` stores those as exact zeros), and need only P and N: the loop works
 * those out itself and calls `embedFrame` for the others (and for a degenerate N).
 *
 * The vertices go in runs of PROXY_RUN, one call each. A single loop over thousands of vertices,
 * entered once per frame, is one V8 may only ever optimize on the stack (OSR): every frame then
 * starts it unoptimized, and its first iteration boxes its doubles (~1 KB of garbage a frame). A
 * short loop called many times is optimized as a whole from its call count.
 */
export function updateProxyVertices(
  pos: Float64Array,
  simNormal: Float32Array,
  tris: Uint32Array,
  tri: Int32Array,
  bary: Float32Array,
  offset: Float32Array,
  normal: Float32Array,
  count: number,
  outPos: Float32Array,
  outNormal: Float32Array,
  f: Float64Array,
): void {
  for (let s = 0; s < count; s += PROXY_RUN) {
    moveRun(pos, simNormal, tris, tri, bary, offset, normal, s, s + PROXY_RUN < count ? s + PROXY_RUN : count, outPos, outNormal, f)
  }
}

/** Render vertices per call of `moveRun`. */
const PROXY_RUN = 64

function moveRun(
  pos: Float64Array,
  simNormal: Float32Array,
  tris: Uint32Array,
  tri: Int32Array,
  bary: Float32Array,
  offset: Float32Array,
  normal: Float32Array,
  from: number,
  to: number,
  outPos: Float32Array,
  outNormal: Float32Array,
  f: Float64Array,
): void {
  for (let v = from; v < to; v++) {
    const j = 3 * v
    const oT = offset[j], oB = offset[j + 1], oN = offset[j + 2]
    const nT = normal[j], nB = normal[j + 1], nN = normal[j + 2]
    const t = 3 * tri[v]
    const a = 3 * tris[t], b = 3 * tris[t + 1], c = 3 * tris[t + 2]
    const w0 = bary[2 * v], w1 = bary[2 * v + 1], w2 = 1 - w0 - w1
    const nx = w0 * simNormal[a] + w1 * simNormal[b] + w2 * simNormal[c]
    const ny = w0 * simNormal[a + 1] + w1 * simNormal[b + 1] + w2 * simNormal[c + 1]
    const nz = w0 * simNormal[a + 2] + w1 * simNormal[b + 2] + w2 * simNormal[c + 2]
    const l2 = nx * nx + ny * ny + nz * nz
    if (oT === 0 && oB === 0 && nT === 0 && nB === 0 && l2 > 1e-24) {
      const s = 1 / Math.sqrt(l2)
      const o = oN * s, m = nN * s
      outPos[j] = w0 * pos[a] + w1 * pos[b] + w2 * pos[c] + o * nx
      outPos[j + 1] = w0 * pos[a + 1] + w1 * pos[b + 1] + w2 * pos[c + 1] + o * ny
      outPos[j + 2] = w0 * pos[a + 2] + w1 * pos[b + 2] + w2 * pos[c + 2] + o * nz
      outNormal[j] = m * nx
      outNormal[j + 1] = m * ny
      outNormal[j + 2] = m * nz
      continue
    }
    embedFrame(pos, simNormal, tris, tri[v], bary, 2 * v, f)
    outPos[j] = f[0] + oT * f[3] + oB * f[6] + oN * f[9]
    outPos[j + 1] = f[1] + oT * f[4] + oB * f[7] + oN * f[10]
    outPos[j + 2] = f[2] + oT * f[5] + oB * f[8] + oN * f[11]
    outNormal[j] = nT * f[3] + nB * f[6] + nN * f[9]
    outNormal[j + 1] = nT * f[4] + nB * f[7] + nN * f[10]
    outNormal[j + 2] = nT * f[5] + nB * f[8] + nN * f[11]
  }
}

/**
 * Hides the render triangles that span a tear. A render triangle whose corners sit in different
 * simulated triangles lists seams (`seamStart[k]` .. `seamStart[k + 1]`): pairs of simulated
 * triangle corners (`seamTri`, `seamCorner`, 2 per seam) that held the same rest vertex when the
 * proxy was made. While every pair still holds one particle the triangle is drawn as given
 * (`indices`); once tearing gave one of them a new particle it is written to `out` collapsed onto
 * its first corner (drawn as nothing). Returns how many triangles changed.
 */
export function updateProxySeams(
  tris: Uint32Array,
  seamStart: Int32Array,
  seamTri: Int32Array,
  seamCorner: Uint8Array,
  indices: Uint32Array,
  triCount: number,
  out: Uint32Array,
): number {
  let changed = 0
  for (let k = 0; k < triCount; k++) {
    const s0 = seamStart[k], s1 = seamStart[k + 1]
    if (s0 === s1) continue
    let whole = true
    for (let s = s0; s < s1; s++) {
      if (tris[3 * seamTri[2 * s] + seamCorner[2 * s]] !== tris[3 * seamTri[2 * s + 1] + seamCorner[2 * s + 1]]) {
        whole = false
        break
      }
    }
    const j = 3 * k
    const shown = out[j + 1] !== out[j]
    if (whole === shown) continue
    changed++
    out[j] = indices[j]
    out[j + 1] = whole ? indices[j + 1] : indices[j]
    out[j + 2] = whole ? indices[j + 2] : indices[j]
  }
  return changed
}
