import { P_GX, P_GY, P_GZ, P_H, P_STEP_FRACTION, P_STEP_START } from './params'

/**
 * Character cloth kernels: prediction in a moving frame, and the motion constraints that hold
 * particles near a reference pose.
 *
 * Frame parameters of `predictInFrame` (a Float64Array of FRAME_PARAMS, filled per substep):
 */
/** The frame's origin at the start of the substep, m. */
export const F_ORIGIN = 0
/** The frame's linear velocity during the previous substep, m/s. */
export const F_U0 = 3
/** (I − R₀ᵀ)/h, row-major, R₀ the frame's rotation over the previous substep: u₀(x) = U₀ + P·(x − origin). */
export const F_P = 6
/** Velocity change carried rigidly this substep (the part of the frame's acceleration the cloth does not feel), m/s. */
export const F_DV = 15
/** Carried velocity change per metre from the origin (rotation: angular and centrifugal parts not felt), 1/s. */
export const F_M = 18
/** Applied to the velocity relative to the frame: damping, and the carried turn of that velocity. */
export const F_ND = 27
export const FRAME_PARAMS = 36

/**
 * Predict step of a cloth simulated in a moving frame (symplectic Euler like `predictPositions`).
 * With w = v − u₀(x), the particle's velocity relative to the frame's motion in the previous
 * substep:
 *
 *   v ← v + ΔV + M·(x − origin) + N·w + (g + a)·h,   prev ← x,   x ← x + v·h
 *
 * ΔV, M and N (see `frameSubstep` in features/character) carry the share of the frame's
 * acceleration and rotation the cloth does not feel, and damp w (not v): damping acts relative to
 * the frame. With every share 0 this moves each particle exactly as if rigidly attached to the
 * frame (plus its own relative motion, turned with the frame); with every share 1, ΔV = M = 0 and
 * only the damping differs from the world-space predict. Inverse mass 0: only prev is recorded.
 */
export function predictInFrame(
  pos: Float64Array,
  prev: Float64Array,
  vel: Float64Array,
  invMass: Float64Array,
  accel: Float64Array | null,
  params: Float64Array,
  f: Float64Array,
  count: number,
): void {
  const h = params[P_H]
  const ox = f[F_ORIGIN], oy = f[F_ORIGIN + 1], oz = f[F_ORIGIN + 2]
  const ux = f[F_U0], uy = f[F_U0 + 1], uz = f[F_U0 + 2]
  const p00 = f[F_P], p01 = f[F_P + 1], p02 = f[F_P + 2], p10 = f[F_P + 3], p11 = f[F_P + 4], p12 = f[F_P + 5], p20 = f[F_P + 6], p21 = f[F_P + 7], p22 = f[F_P + 8]
  const m00 = f[F_M], m01 = f[F_M + 1], m02 = f[F_M + 2], m10 = f[F_M + 3], m11 = f[F_M + 4], m12 = f[F_M + 5], m20 = f[F_M + 6], m21 = f[F_M + 7], m22 = f[F_M + 8]
  const n00 = f[F_ND], n01 = f[F_ND + 1], n02 = f[F_ND + 2], n10 = f[F_ND + 3], n11 = f[F_ND + 4], n12 = f[F_ND + 5], n20 = f[F_ND + 6], n21 = f[F_ND + 7], n22 = f[F_ND + 8]
  // constant per substep: the carried velocity change plus gravity
  const cx = f[F_DV] + params[P_GX] * h, cy = f[F_DV + 1] + params[P_GY] * h, cz = f[F_DV + 2] + params[P_GZ] * h
  for (let i = 0; i < count; i++) {
    const j = 3 * i
    const x = pos[j], y = pos[j + 1], z = pos[j + 2]
    prev[j] = x
    prev[j + 1] = y
    prev[j + 2] = z
    if (invMass[i] === 0) continue
    const rx = x - ox, ry = y - oy, rz = z - oz
    const vx = vel[j], vy = vel[j + 1], vz = vel[j + 2]
    const wx = vx - ux - (p00 * rx + p01 * ry + p02 * rz)
    const wy = vy - uy - (p10 * rx + p11 * ry + p12 * rz)
    const wz = vz - uz - (p20 * rx + p21 * ry + p22 * rz)
    let nx = vx + cx + m00 * rx + m01 * ry + m02 * rz + n00 * wx + n01 * wy + n02 * wz
    let ny = vy + cy + m10 * rx + m11 * ry + m12 * rz + n10 * wx + n11 * wy + n12 * wz
    let nz = vz + cz + m20 * rx + m21 * ry + m22 * rz + n20 * wx + n21 * wy + n22 * wz
    if (accel !== null) {
      nx += accel[j] * h
      ny += accel[j + 1] * h
      nz += accel[j + 2] * h
    }
    vel[j] = nx
    vel[j + 1] = ny
    vel[j + 2] = nz
    pos[j] = x + nx * h
    pos[j + 1] = y + ny * h
    pos[j + 2] = z + nz * h
  }
}

/**
 * Places the listed particles on their reference positions, interpolated to the end of the
 * substep: from + (to − from)·params[P_STEP_FRACTION] (particles held with max distance 0).
 */
export function placeOnReference(
  pos: Float64Array,
  list: Int32Array,
  listCount: number,
  refFrom: Float64Array,
  refTo: Float64Array,
  params: Float64Array,
): void {
  const f = params[P_STEP_FRACTION]
  for (let q = 0; q < listCount; q++) {
    const j = 3 * list[q]
    pos[j] = refFrom[j] + (refTo[j] - refFrom[j]) * f
    pos[j + 1] = refFrom[j + 1] + (refTo[j + 1] - refFrom[j + 1]) * f
    pos[j + 2] = refFrom[j + 2] + (refTo[j + 2] - refFrom[j + 2]) * f
  }
}

/**
 * Motion constraints around a reference pose, after the solve and the collisions of a substep.
 * For each free particle (inverse mass > 0), with r its reference position interpolated to the end
 * of the substep (params[P_STEP_FRACTION] between `refFrom` and `refTo`) and n its reference
 * normal; `limits` holds 4 values per particle (max distance, backstop distance, backstop radius,
 * drive frequency ω):
 * 1. drive: a critically damped spring (stiffness m·ω², damping 2m·ω) pulls the offset e = x − r
 *    toward 0, its damping acting on the offset's change over the substep (e_prev from `prev` and
 *    the reference at the substep's start, params[P_STEP_START]); integrated implicitly,
 *    Δx = −(a²·e + 2a·(e − e_prev))/(1 + a)², a = ω·h: independent of the mass, stable for any ω,
 *    and ω = Infinity puts x on r;
 * 2. max distance: x is brought back onto the sphere of that radius around r when outside it;
 * 3. backstop: x is pushed out of the sphere of radius ρ centred at r − n·(distance + ρ), then
 *    step 2 once more (the two regions are not convex together; r itself satisfies both).
 * Velocities follow from the positions in the writeback (v = Δx/h), so a particle stopped at its
 * limit loses its outward speed.
 */
export function constrainToReference(
  pos: Float64Array,
  prev: Float64Array,
  invMass: Float64Array,
  refFrom: Float64Array,
  refTo: Float64Array,
  refNormal: Float64Array,
  limits: Float64Array,
  params: Float64Array,
  count: number,
): void {
  const f = params[P_STEP_FRACTION], f0 = params[P_STEP_START], h = params[P_H]
  for (let i = 0; i < count; i++) {
    if (invMass[i] === 0) continue
    const j = 3 * i, l = 4 * i
    const rx = refFrom[j] + (refTo[j] - refFrom[j]) * f
    const ry = refFrom[j + 1] + (refTo[j + 1] - refFrom[j + 1]) * f
    const rz = refFrom[j + 2] + (refTo[j + 2] - refFrom[j + 2]) * f
    let x = pos[j], y = pos[j + 1], z = pos[j + 2]
    const om = limits[l + 3]
    if (om === Infinity) {
      x = rx
      y = ry
      z = rz
    } else if (om > 0) {
      const a = om * h
      const inv = 1 / ((1 + a) * (1 + a))
      const ex = x - rx, ey = y - ry, ez = z - rz
      // the offset at the substep's start
      const qx = prev[j] - refFrom[j] - (refTo[j] - refFrom[j]) * f0
      const qy = prev[j + 1] - refFrom[j + 1] - (refTo[j + 1] - refFrom[j + 1]) * f0
      const qz = prev[j + 2] - refFrom[j + 2] - (refTo[j + 2] - refFrom[j + 2]) * f0
      x -= (a * a * ex + 2 * a * (ex - qx)) * inv
      y -= (a * a * ey + 2 * a * (ey - qy)) * inv
      z -= (a * a * ez + 2 * a * (ez - qz)) * inv
    }
    const r = limits[l]
    const r2 = r * r // Infinity when free
    let ex = x - rx, ey = y - ry, ez = z - rz
    let d2 = ex * ex + ey * ey + ez * ez
    if (d2 > r2) {
      const s = r / Math.sqrt(d2)
      x = rx + ex * s
      y = ry + ey * s
      z = rz + ez * s
    }
    const rho = limits[l + 2]
    if (rho > 0) {
      const nx = refNormal[j], ny = refNormal[j + 1], nz = refNormal[j + 2]
      const back = limits[l + 1] + rho
      const cx = rx - nx * back, cy = ry - ny * back, cz = rz - nz * back
      const bx = x - cx, by = y - cy, bz = z - cz
      const b2 = bx * bx + by * by + bz * bz
      if (b2 < rho * rho) {
        if (b2 > 1e-24) {
          const s = rho / Math.sqrt(b2)
          x = cx + bx * s
          y = cy + by * s
          z = cz + bz * s
        } else {
          x = cx + nx * rho
          y = cy + ny * rho
          z = cz + nz * rho
        }
        ex = x - rx
        ey = y - ry
        ez = z - rz
        d2 = ex * ex + ey * ey + ez * ez
        if (d2 > r2) {
          const s = r / Math.sqrt(d2)
          x = rx + ex * s
          y = ry + ey * s
          z = rz + ez * s
        }
      }
    }
    pos[j] = x
    pos[j + 1] = y
    pos[j + 2] = z
  }
}
