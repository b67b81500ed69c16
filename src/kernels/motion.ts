import { P_H, P_INV_H, P_MAX_SPEED, P_MAX_V2, P_STEP_FRACTION, P_STEP_START } from './params'

/**
 * Character cloth kernels: prediction in a moving frame, and the motion constraints that hold
 * particles near a reference pose.
 *
 * Frame parameters of `predictInFrame` (a Float64Array of FRAME_PARAMS, filled per substep by
 * `frameSubstep` in features/character):
 */
/** The frame's origin at the start of the substep, m. */
export const F_ORIGIN = 0
/** A (row-major 3×3): the new velocity's part linear in the old one. */
export const F_A = 3
/** Q (row-major 3×3, 1/s): its part linear in the offset from the origin. */
export const F_Q = 12
/** c (m/s): its constant part, gravity included. */
export const F_C = 21
export const FRAME_PARAMS = 24

/**
 * Predict step of a cloth simulated in a moving frame (symplectic Euler like `predictPositions`):
 *
 *   v ← A·v + Q·(x − origin) + c + a·h,   prev ← x,   x ← x + v·h
 *
 * With w = v − u₀(x) the velocity relative to the frame's motion in the previous substep, this is
 * v + ΔV + M·r + N·w + g·h (`frameSubstep` folds it into A, Q, c): ΔV, M and N carry the share of
 * the frame's acceleration and rotation the cloth does not feel, and damp w (not v), so damping
 * acts relative to the frame. With every share 0 this moves each particle exactly as if rigidly
 * attached to the frame (plus its own relative motion, turned with the frame); with every share 1
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
  const a00 = f[F_A], a01 = f[F_A + 1], a02 = f[F_A + 2], a10 = f[F_A + 3], a11 = f[F_A + 4], a12 = f[F_A + 5], a20 = f[F_A + 6], a21 = f[F_A + 7], a22 = f[F_A + 8]
  const q00 = f[F_Q], q01 = f[F_Q + 1], q02 = f[F_Q + 2], q10 = f[F_Q + 3], q11 = f[F_Q + 4], q12 = f[F_Q + 5], q20 = f[F_Q + 6], q21 = f[F_Q + 7], q22 = f[F_Q + 8]
  const cx = f[F_C], cy = f[F_C + 1], cz = f[F_C + 2]
  for (let i = 0; i < count; i++) {
    const j = 3 * i
    const x = pos[j], y = pos[j + 1], z = pos[j + 2]
    prev[j] = x
    prev[j + 1] = y
    prev[j + 2] = z
    if (invMass[i] === 0) continue
    const rx = x - ox, ry = y - oy, rz = z - oz
    const vx = vel[j], vy = vel[j + 1], vz = vel[j + 2]
    let nx = a00 * vx + a01 * vy + a02 * vz + q00 * rx + q01 * ry + q02 * rz + cx
    let ny = a10 * vx + a11 * vy + a12 * vz + q10 * rx + q11 * ry + q12 * rz + cy
    let nz = a20 * vx + a21 * vy + a22 * vz + q20 * rx + q21 * ry + q22 * rz + cz
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
 * Per-particle reference data of the motion kernels, interleaved (REF float32 values per
 * particle) so the pass over a cloth reads one short stream: the reference position at the start
 * of the step and at its end, each as an offset from an anchor (the frame's origin then: float32
 * keeps ~0.1 µm at a metre from it), the reference normal at the end, the max distance (m,
 * Infinity = free), the backstop's distance and radius (radius 0 = none). The anchors are
 * anchor[from..from+2] and anchor[to..to+2].
 */
export const R_FROM = 0
export const R_TO = 3
export const R_NORMAL = 6
export const R_MAX = 9
export const R_BACK = 10
export const R_RADIUS = 11
export const REF = 12

/**
 * Places the listed particles on their reference positions, interpolated to the end of the
 * substep (params[P_STEP_FRACTION] of the way through the step; particles held with max distance 0).
 */
export function placeOnReference(
  pos: Float64Array, list: Int32Array, listCount: number, ref: Float32Array, anchor: Float64Array, from: number, to: number, params: Float64Array,
): void {
  const f = params[P_STEP_FRACTION]
  const ax = anchor[from] + (anchor[to] - anchor[from]) * f
  const ay = anchor[from + 1] + (anchor[to + 1] - anchor[from + 1]) * f
  const az = anchor[from + 2] + (anchor[to + 2] - anchor[from + 2]) * f
  for (let q = 0; q < listCount; q++) {
    const i = list[q]
    const j = 3 * i, o = REF * i
    pos[j] = ax + ref[o] + (ref[o + 3] - ref[o]) * f
    pos[j + 1] = ay + ref[o + 1] + (ref[o + 4] - ref[o + 1]) * f
    pos[j + 2] = az + ref[o + 2] + (ref[o + 5] - ref[o + 2]) * f
  }
}

/**
 * The writeback of a cloth with motion constraints: first the constraints around its reference
 * pose, then the velocities from the substep's motion, in one pass (the positions are read once
 * for both).
 *
 * Constraints, for each free particle (inverse mass > 0), with r its reference position
 * interpolated to the end of the substep (params[P_STEP_FRACTION] of the way through the step) and
 * n its reference normal (`ref`, see R_*):
 * 1. drive (when `drive` is given: a frequency ω per particle, rad/s): a critically damped spring
 *    (stiffness m·ω², damping 2m·ω) pulls the offset e = x − r toward 0, its damping acting on the
 *    offset's change over the substep (e_prev from `prev` and the reference at the substep's
 *    start, params[P_STEP_START]); integrated implicitly, Δx = −(a²·e + 2a·(e − e_prev))/(1 + a)²,
 *    a = ω·h: independent of the mass, stable for any ω; ω = Infinity puts x on r;
 * 2. max distance: x is brought back onto the sphere of that radius around r when outside it;
 * 3. backstop: x is pushed out of the sphere of radius ρ centred at r − n·(distance + ρ), then
 *    step 2 once more (the two regions are not convex together; r itself satisfies both).
 * Positions are written only where something moved them.
 *
 * Velocities, for every particle: v = (x − prev)/h, so a particle stopped at its limit loses its
 * outward speed; a speed above params[P_MAX_SPEED] is scaled down to it, the largest squared
 * speed before that goes to params[P_MAX_V2] (as `updateVelocities` in integrate.ts, whose loop
 * this repeats rather than calls: a second pass over the positions is what this kernel saves).
 */
export function constrainAndUpdateVelocities(
  pos: Float64Array,
  prev: Float64Array,
  vel: Float64Array,
  invMass: Float64Array,
  ref: Float32Array,
  anchor: Float64Array,
  from: number,
  to: number,
  drive: Float64Array | null,
  params: Float64Array,
  count: number,
): void {
  const f = params[P_STEP_FRACTION], f0 = params[P_STEP_START], h = params[P_H], invH = params[P_INV_H]
  const maxSpeed = params[P_MAX_SPEED]
  const max2 = maxSpeed * maxSpeed
  let top = 0
  const ax = anchor[from] + (anchor[to] - anchor[from]) * f
  const ay = anchor[from + 1] + (anchor[to + 1] - anchor[from + 1]) * f
  const az = anchor[from + 2] + (anchor[to + 2] - anchor[from + 2]) * f
  for (let i = 0; i < count; i++) {
    const j = 3 * i
    let x = pos[j], y = pos[j + 1], z = pos[j + 2]
    if (invMass[i] !== 0) {
      const o = REF * i
      const fx = ref[o], fy = ref[o + 1], fz = ref[o + 2]
      const rx = ax + fx + (ref[o + 3] - fx) * f
      const ry = ay + fy + (ref[o + 4] - fy) * f
      const rz = az + fz + (ref[o + 5] - fz) * f
      let moved = false
      const om = drive === null ? 0 : drive[i]
      if (om > 0) {
        moved = true
        if (om === Infinity) {
          x = rx
          y = ry
          z = rz
        } else {
          const a = om * h
          const inv = 1 / ((1 + a) * (1 + a))
          const ex = x - rx, ey = y - ry, ez = z - rz
          // the offset at the substep's start
          const qx = prev[j] - anchor[from] - (anchor[to] - anchor[from]) * f0 - fx - (ref[o + 3] - fx) * f0
          const qy = prev[j + 1] - anchor[from + 1] - (anchor[to + 1] - anchor[from + 1]) * f0 - fy - (ref[o + 4] - fy) * f0
          const qz = prev[j + 2] - anchor[from + 2] - (anchor[to + 2] - anchor[from + 2]) * f0 - fz - (ref[o + 5] - fz) * f0
          x -= (a * a * ex + 2 * a * (ex - qx)) * inv
          y -= (a * a * ey + 2 * a * (ey - qy)) * inv
          z -= (a * a * ez + 2 * a * (ez - qz)) * inv
        }
      }
      const r = ref[o + R_MAX]
      const r2 = r * r // Infinity when free
      let ex = x - rx, ey = y - ry, ez = z - rz
      let d2 = ex * ex + ey * ey + ez * ez
      if (d2 > r2) {
        const s = r / Math.sqrt(d2)
        ex *= s
        ey *= s
        ez *= s
        x = rx + ex
        y = ry + ey
        z = rz + ez
        moved = true
      }
      const rho = ref[o + R_RADIUS]
      // the sphere lies wholly `distance` or more behind the reference: a particle less deep is clear
      if (rho > 0 && ex * ref[o + 6] + ey * ref[o + 7] + ez * ref[o + 8] < -ref[o + R_BACK]) {
        const nx = ref[o + 6], ny = ref[o + 7], nz = ref[o + 8]
        const back = ref[o + R_BACK] + rho
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
          moved = true
        }
      }
      if (moved) {
        pos[j] = x
        pos[j + 1] = y
        pos[j + 2] = z
      }
    }
    let vx = (x - prev[j]) * invH
    let vy = (y - prev[j + 1]) * invH
    let vz = (z - prev[j + 2]) * invH
    const s2 = vx * vx + vy * vy + vz * vz
    if (!(s2 <= top)) top = s2 // NaN sticks: a broken cloth never counts as still
    if (s2 > max2) {
      const k = maxSpeed / Math.sqrt(s2)
      vx *= k
      vy *= k
      vz *= k
    }
    vel[j] = vx
    vel[j + 1] = vy
    vel[j + 2] = vz
  }
  params[P_MAX_V2] = top
}
