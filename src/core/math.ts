/**
 * Quaternion and vector helpers, written once for the whole library. They write into an output
 * array at an offset and never allocate. Quaternions are [x, y, z, w] like gl-matrix.
 */

/** out[o..o+2] = q ⊗ v ⊗ q⁻¹ for a unit quaternion q. */
export function rotateVec3(
  qx: number,
  qy: number,
  qz: number,
  qw: number,
  vx: number,
  vy: number,
  vz: number,
  out: Float64Array | number[],
  o: number,
): void {
  // t = 2 q × v;  v' = v + w t + q × t
  const tx = 2 * (qy * vz - qz * vy)
  const ty = 2 * (qz * vx - qx * vz)
  const tz = 2 * (qx * vy - qy * vx)
  out[o] = vx + qw * tx + (qy * tz - qz * ty)
  out[o + 1] = vy + qw * ty + (qz * tx - qx * tz)
  out[o + 2] = vz + qw * tz + (qx * ty - qy * tx)
}

/** Writes q normalised (identity if it is zero or not finite) into out[o..o+3]. */
export function normalizeQuat(x: number, y: number, z: number, w: number, out: Float64Array, o: number): void {
  out[o] = x
  out[o + 1] = y
  out[o + 2] = z
  out[o + 3] = w
  normalizeQuatAt(out, o)
}

/**
 * Normalises the quaternion at q[o..o+3] in place; identity when it is zero or holds a non-finite
 * component. Any other quaternion is a rotation, however large or small its components: when their
 * squares overflow (a component beyond ~1e154) or vanish, it is first divided by its largest
 * component. (Array and offset: called per tracked entity in a step, where doubles passed to a
 * call would be boxed.)
 */
export function normalizeQuatAt(q: Float64Array, o: number): void {
  let x = q[o], y = q[o + 1], z = q[o + 2], w = q[o + 3]
  let l = Math.sqrt(x * x + y * y + z * z + w * w)
  if (!(l > 1e-150 && l < 1e150)) {
    let m = x < 0 ? -x : x
    const ay = y < 0 ? -y : y, az = z < 0 ? -z : z, aw = w < 0 ? -w : w
    if (ay > m) m = ay
    if (az > m) m = az
    if (aw > m) m = aw
    // (x − x is NaN for NaN or ±∞, which the comparisons above let through)
    if (!(m > 0 && m < Infinity) || x - x + (y - y) + (z - z) + (w - w) !== 0) {
      q[o] = 0
      q[o + 1] = 0
      q[o + 2] = 0
      q[o + 3] = 1
      return
    }
    x /= m
    y /= m
    z /= m
    w /= m
    l = Math.sqrt(x * x + y * y + z * z + w * w)
  }
  q[o] = x / l
  q[o + 1] = y / l
  q[o + 2] = z / l
  q[o + 3] = w / l
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

/**
 * q normalised with `Math.hypot`, as a new array: for rotations given at the API (creation time,
 * teleports), never in a step.
 */
export function normalizedQuat(q: ArrayLike<number>): number[] {
  const l = Math.hypot(q[0], q[1], q[2], q[3])
  return [q[0] / l, q[1] / l, q[2] / l, q[3] / l]
}

/** out[oo..oo+2] = q·v for the unit quaternion at q[qo..qo+3] and v = v[vo..vo+2] (arrays only: nothing is boxed). */
export function rotateVecAt(q: Float64Array, qo: number, v: Float64Array, vo: number, out: Float64Array, oo: number): void {
  const qx = q[qo], qy = q[qo + 1], qz = q[qo + 2], qw = q[qo + 3]
  const vx = v[vo], vy = v[vo + 1], vz = v[vo + 2]
  const tx = 2 * (qy * vz - qz * vy), ty = 2 * (qz * vx - qx * vz), tz = 2 * (qx * vy - qy * vx)
  out[oo] = vx + qw * tx + (qy * tz - qz * ty)
  out[oo + 1] = vy + qw * ty + (qz * tx - qx * tz)
  out[oo + 2] = vz + qw * tz + (qx * ty - qy * tx)
}

/**
 * out[oo..oo+3] = a ⊗ b (Hamilton product) for quaternions at a[ao..] and b[bo..]. `out` may be
 * `b` at the same offset (both are read before anything is written).
 */
export function multiplyQuatAt(a: Float64Array, ao: number, b: Float64Array, bo: number, out: Float64Array, oo: number): void {
  const ax = a[ao], ay = a[ao + 1], az = a[ao + 2], aw = a[ao + 3]
  const bx = b[bo], by = b[bo + 1], bz = b[bo + 2], bw = b[bo + 3]
  out[oo] = aw * bx + ax * bw + ay * bz - az * by
  out[oo + 1] = aw * by - ax * bz + ay * bw + az * bx
  out[oo + 2] = aw * bz + ax * by - ay * bx + az * bw
  out[oo + 3] = aw * bw - ax * bx - ay * by - az * bz
}

/**
 * out[oo..oo+3] = to ⊗ from⁻¹ for unit quaternions: the rotation that turns orientation `from`
 * into orientation `to`.
 */
export function relativeRotationAt(to: Float64Array, to0: number, from: Float64Array, from0: number, out: Float64Array, oo: number): void {
  const tx = to[to0], ty = to[to0 + 1], tz = to[to0 + 2], tw = to[to0 + 3]
  const fx = -from[from0], fy = -from[from0 + 1], fz = -from[from0 + 2], fw = from[from0 + 3]
  out[oo] = tw * fx + tx * fw + ty * fz - tz * fy
  out[oo + 1] = tw * fy - tx * fz + ty * fw + tz * fx
  out[oo + 2] = tw * fz + tx * fy - ty * fx + tz * fw
  out[oo + 3] = tw * fw - tx * fx - ty * fy - tz * fz
}
