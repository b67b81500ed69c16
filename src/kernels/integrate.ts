import { P_DAMP, P_GX, P_GY, P_GZ, P_H, P_INV_H, P_MAX_SPEED, P_MAX_V2 } from './params'

/**
 * Predict step of position-based dynamics (symplectic Euler on velocities, Verlet-style on
 * positions): v ← v·damp + (g + a)·h, prev ← x, x ← x + v·h, for every particle with inverse mass
 * > 0. Kinematic particles (inverse mass 0, i.e. pinned) only record prev; the pin phase places them.
 *
 * @param accel optional per-particle extra acceleration (xyz, m/s²), e.g. aerodynamic forces / mass
 * @param params kernel parameters (see `params.ts`): h, gravity and the damping factor
 * @param list null: particles 0 to count − 1; else only those at list[1..list[0]] (a character
 *   cloth's pieces torn free of it, predicted in the world after the predict in its frame)
 */
export function predictPositions(
  pos: Float64Array,
  prev: Float64Array,
  vel: Float64Array,
  invMass: Float64Array,
  accel: Float64Array | null,
  params: Float64Array,
  count: number,
  list: Int32Array | null = null,
): void {
  const h = params[P_H], damp = params[P_DAMP]
  const ax = params[P_GX] * h, ay = params[P_GY] * h, az = params[P_GZ] * h
  const n = list === null ? count : list[0]
  for (let q = 0; q < n; q++) {
    const i = list === null ? q : list[q + 1]
    const j = 3 * i
    const x = pos[j], y = pos[j + 1], z = pos[j + 2]
    prev[j] = x
    prev[j + 1] = y
    prev[j + 2] = z
    if (invMass[i] === 0) continue
    let vx = vel[j] * damp + ax
    let vy = vel[j + 1] * damp + ay
    let vz = vel[j + 2] * damp + az
    if (accel !== null) {
      vx += accel[j] * h
      vy += accel[j + 1] * h
      vz += accel[j + 2] * h
    }
    vel[j] = vx
    vel[j + 1] = vy
    vel[j + 2] = vz
    pos[j] = x + vx * h
    pos[j + 1] = y + vy * h
    pos[j + 2] = z + vz * h
  }
}

/**
 * Reads velocities back from the motion of the substep: v = (x − prev)/h. A speed above the
 * limit (`params[P_MAX_SPEED]`, m/s) is scaled down to it: a last line of defence against runaway
 * energy. Positions are left where the solve put them, so a cloth can follow a pin that jumps
 * (a runaway position is the explosion guard's job, once per step). The largest squared speed
 * before the limit goes to `params[P_MAX_V2]` (the sleep test reads it).
 */
export function updateVelocities(
  pos: Float64Array,
  prev: Float64Array,
  vel: Float64Array,
  params: Float64Array,
  count: number,
): void {
  const invH = params[P_INV_H]
  const maxSpeed = params[P_MAX_SPEED]
  const max2 = maxSpeed * maxSpeed
  let top = 0
  for (let i = 0; i < count; i++) {
    const j = 3 * i
    let vx = (pos[j] - prev[j]) * invH
    let vy = (pos[j + 1] - prev[j + 1]) * invH
    let vz = (pos[j + 2] - prev[j + 2]) * invH
    const s2 = vx * vx + vy * vy + vz * vz
    if (!(s2 <= top)) top = s2 // NaN sticks: a broken cloth never counts as still
    if (s2 > max2) {
      const f = maxSpeed / Math.sqrt(s2)
      vx *= f
      vy *= f
      vz *= f
    }
    vel[j] = vx
    vel[j + 1] = vy
    vel[j + 2] = vz
  }
  params[P_MAX_V2] = top
}
