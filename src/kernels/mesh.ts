/**
 * Render output: copies positions to float32 and computes area-weighted vertex normals
 * (unnormalised triangle normals summed, then normalised). Degenerate normals fall back to +z
 * rather than NaN.
 */
export function writeRenderMesh(
  pos: Float64Array,
  count: number,
  tris: Uint32Array,
  triCount: number,
  outPos: Float32Array,
  outNormal: Float32Array,
): void {
  for (let j = 0; j < 3 * count; j++) {
    outPos[j] = pos[j]
    outNormal[j] = 0
  }
  for (let t = 0; t < triCount; t++) {
    const a = 3 * tris[3 * t], b = 3 * tris[3 * t + 1], c = 3 * tris[3 * t + 2]
    const ux = pos[b] - pos[a], uy = pos[b + 1] - pos[a + 1], uz = pos[b + 2] - pos[a + 2]
    const vx = pos[c] - pos[a], vy = pos[c + 1] - pos[a + 1], vz = pos[c + 2] - pos[a + 2]
    const nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx
    outNormal[a] += nx
    outNormal[a + 1] += ny
    outNormal[a + 2] += nz
    outNormal[b] += nx
    outNormal[b + 1] += ny
    outNormal[b + 2] += nz
    outNormal[c] += nx
    outNormal[c + 1] += ny
    outNormal[c + 2] += nz
  }
  for (let i = 0; i < count; i++) {
    const j = 3 * i
    const x = outNormal[j], y = outNormal[j + 1], z = outNormal[j + 2]
    const l2 = x * x + y * y + z * z
    if (l2 > 1e-30) {
      const f = 1 / Math.sqrt(l2)
      outNormal[j] = x * f
      outNormal[j + 1] = y * f
      outNormal[j + 2] = z * f
    } else {
      outNormal[j] = 0
      outNormal[j + 1] = 0
      outNormal[j + 2] = 1
    }
  }
}

/** Edge strain statistics: mean and max of max(0, |d|/rest − 1) over the given edges. */
export function measureStretch(
  pos: ArrayLike<number>,
  edges: Int32Array,
  edgeRest: Float64Array,
  edgeCount: number,
  out: { mean: number; max: number },
): { mean: number; max: number } {
  let sum = 0
  let max = 0
  let n = 0
  for (let e = 0; e < edgeCount; e++) {
    const r = edgeRest[e]
    if (!(r > 0)) continue
    const a = 3 * edges[2 * e], b = 3 * edges[2 * e + 1]
    const dx = pos[b] - pos[a], dy = pos[b + 1] - pos[a + 1], dz = pos[b + 2] - pos[a + 2]
    const s = Math.sqrt(dx * dx + dy * dy + dz * dz) / r - 1
    if (s > 0) {
      sum += s
      if (s > max) max = s
    }
    n++
  }
  out.mean = n > 0 ? sum / n : 0
  out.max = max
  return out
}

/**
 * Largest edge strain max(0, |d|/rest − 1) over the given edges, written to out[o] (a double
 * returned from a function that is not inlined would be boxed; a slot is not). Rest lengths ≤ 0
 * are skipped.
 */
export function maxEdgeStrain(
  pos: Float64Array,
  edges: Int32Array,
  edgeRest: Float64Array,
  edgeCount: number,
  out: Float64Array,
  o: number,
): void {
  let max2 = 0
  for (let e = 0; e < edgeCount; e++) {
    const r = edgeRest[e]
    if (!(r > 0)) continue
    const a = 3 * edges[2 * e], b = 3 * edges[2 * e + 1]
    const dx = pos[b] - pos[a], dy = pos[b + 1] - pos[a + 1], dz = pos[b + 2] - pos[a + 2]
    const s2 = (dx * dx + dy * dy + dz * dz) / (r * r) // squared length ratio: one sqrt at the end
    if (s2 > max2) max2 = s2
  }
  out[o] = max2 > 1 ? Math.sqrt(max2) - 1 : 0
}

/**
 * Axis-aligned bounds of particles [0, count) into out[o..o+5] (min xyz, max xyz), for culling
 * wind zones against a cloth and the box a cloth sleeps in. Particles with `skip[i]` = 1 (vertices
 * no triangle uses) are left out.
 */
export function particleBounds(pos: Float64Array, count: number, out: Float64Array, o: number, skip: Uint8Array | null = null): void {
  let x0 = Infinity, y0 = Infinity, z0 = Infinity, x1 = -Infinity, y1 = -Infinity, z1 = -Infinity
  for (let k = 0; k < count; k++) {
    if (skip !== null && skip[k] === 1) continue
    const i = 3 * k
    const x = pos[i], y = pos[i + 1], z = pos[i + 2]
    if (x < x0) x0 = x
    if (x > x1) x1 = x
    if (y < y0) y0 = y
    if (y > y1) y1 = y
    if (z < z0) z0 = z
    if (z > z1) z1 = z
  }
  out[o] = x0
  out[o + 1] = y0
  out[o + 2] = z0
  out[o + 3] = x1
  out[o + 4] = y1
  out[o + 5] = z1
}
