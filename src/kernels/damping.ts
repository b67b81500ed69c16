import { P_STRETCH_DAMP } from './params'

/**
 * Stretch damping, a velocity pass after the velocity update: for each pair, removes the fraction
 * `params[P_STRETCH_DAMP]` of the particles' relative velocity along the pair, split by inverse mass (momentum is
 * unchanged). Only stretching motion is damped; rigid motion, swinging and bending (which do not
 * change the pair's length to first order) are not. The pair direction is normalised by the rest
 * length (`invRest2` = 1/rest²) while the pair is not longer than at rest, which saves a division
 * per pair, and by its current length once it is stretched: the removed fraction never exceeds
 * `factor`, so the pass can only take energy out, however far the pair is pulled.
 */
export function dampPairs(
  pos: Float64Array,
  vel: Float64Array,
  invMass: Float64Array,
  ids: Int32Array,
  invRest2: Float64Array,
  count: number,
  params: Float64Array,
): void {
  const factor = params[P_STRETCH_DAMP]
  for (let k = 0; k < count; k++) {
    const i0 = ids[2 * k], i1 = ids[2 * k + 1]
    const wa = invMass[i0], wb = invMass[i1]
    const ws = wa + wb
    if (ws === 0) continue
    const a = 3 * i0, b = 3 * i1
    const dx = pos[b] - pos[a], dy = pos[b + 1] - pos[a + 1], dz = pos[b + 2] - pos[a + 2]
    // normalise by the larger of rest² and length²: dividing a stretched pair by rest² alone
    // removed (length/rest)² × the relative velocity, which beyond ~1.8× length reversed and amplified it
    // (a cloth pulled apart gained energy until it went NaN)
    const l2 = dx * dx + dy * dy + dz * dz
    let inv = invRest2[k]
    if (l2 * inv > 1 || (inv === 0 && l2 > 1e-24)) inv = 1 / l2
    const vr = ((vel[b] - vel[a]) * dx + (vel[b + 1] - vel[a + 1]) * dy + (vel[b + 2] - vel[a + 2]) * dz) * inv
    const s = (factor * vr) / ws
    const sa = wa * s, sb = wb * s
    vel[a] += sa * dx
    vel[a + 1] += sa * dy
    vel[a + 2] += sa * dz
    vel[b] -= sb * dx
    vel[b + 1] -= sb * dy
    vel[b + 2] -= sb * dz
  }
}
