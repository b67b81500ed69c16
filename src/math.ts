/**
 * Scalar quaternion and vector helpers for the pin, teleport, collider and wind-zone paths. They write into an output
 * array at an offset and never allocate. Quaternions are [x, y, z, w] like gl-matrix.
 */

/** out[o..o+2] = q ⊗ v ⊗ q⁻¹ for a unit quaternion q. */
export function rotateVec3(
  qx: number, qy: number, qz: number, qw: number,
  vx: number, vy: number, vz: number,
  out: Float64Array | number[], o: number,
): void {
  // t = 2 q × v;  v' = v + w t + q × t
  const tx = 2 * (qy * vz - qz * vy)
  const ty = 2 * (qz * vx - qx * vz)
  const tz = 2 * (qx * vy - qy * vx)
  out[o] = vx + qw * tx + (qy * tz - qz * ty)
  out[o + 1] = vy + qw * ty + (qz * tx - qx * tz)
  out[o + 2] = vz + qw * tz + (qx * ty - qy * tx)
}

/** Writes q normalised (identity if degenerate) into out[o..o+3]. */
export function normalizeQuat(x: number, y: number, z: number, w: number, out: Float64Array, o: number): void {
  const l = Math.sqrt(x * x + y * y + z * z + w * w)
  if (!(l > 1e-12) || !Number.isFinite(l)) {
    out[o] = 0
    out[o + 1] = 0
    out[o + 2] = 0
    out[o + 3] = 1
    return
  }
  out[o] = x / l
  out[o + 1] = y / l
  out[o + 2] = z / l
  out[o + 3] = w / l
}

/**
 * Row-major rotation matrix of the unit quaternion at q[qo..qo+3] into m[mo..mo+8]. Arrays and
 * offsets only: it runs per collider and substep, and a double passed to a call V8 does not
 * inline is boxed on the heap.
 */
export function quatToMatrix(q: Float64Array, qo: number, m: Float64Array, mo: number): void {
  const x = q[qo], y = q[qo + 1], z = q[qo + 2], w = q[qo + 3]
  const xx = x * x, yy = y * y, zz = z * z, xy = x * y, xz = x * z, yz = y * z, wx = w * x, wy = w * y, wz = w * z
  m[mo] = 1 - 2 * (yy + zz)
  m[mo + 1] = 2 * (xy - wz)
  m[mo + 2] = 2 * (xz + wy)
  m[mo + 3] = 2 * (xy + wz)
  m[mo + 4] = 1 - 2 * (xx + zz)
  m[mo + 5] = 2 * (yz - wx)
  m[mo + 6] = 2 * (xz - wy)
  m[mo + 7] = 2 * (yz + wx)
  m[mo + 8] = 1 - 2 * (xx + yy)
}
