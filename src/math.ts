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

/**
 * Normalised spherical interpolation of unit quaternions a → b at t, shortest arc, into out[o..o+3].
 * Falls back to normalised lerp when the two are nearly equal.
 */
export function slerpQuat(
  a: Float64Array, ao: number, b: Float64Array, bo: number, t: number,
  out: Float64Array, o: number,
): void {
  const ax = a[ao], ay = a[ao + 1], az = a[ao + 2], aw = a[ao + 3]
  let bx = b[bo], by = b[bo + 1], bz = b[bo + 2], bw = b[bo + 3]
  let cos = ax * bx + ay * by + az * bz + aw * bw
  if (cos < 0) {
    cos = -cos
    bx = -bx
    by = -by
    bz = -bz
    bw = -bw
  }
  let s0: number, s1: number
  if (cos > 0.9995) {
    s0 = 1 - t
    s1 = t
  } else {
    const omega = Math.acos(cos)
    const sin = Math.sin(omega)
    s0 = Math.sin((1 - t) * omega) / sin
    s1 = Math.sin(t * omega) / sin
  }
  let x = s0 * ax + s1 * bx, y = s0 * ay + s1 * by, z = s0 * az + s1 * bz, w = s0 * aw + s1 * bw
  const l = Math.sqrt(x * x + y * y + z * z + w * w)
  x /= l
  y /= l
  z /= l
  w /= l
  out[o] = x
  out[o + 1] = y
  out[o + 2] = z
  out[o + 3] = w
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
