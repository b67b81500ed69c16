import { P_STRETCH_DAMP } from './params'

/**
 * Stretch damping, a velocity pass after the velocity update: for each pair, removes the fraction
 * `params[P_STRETCH_DAMP]` of the particles' relative velocity along the pair, split by inverse mass (momentum is
 * unchanged). Only stretching motion is damped; rigid motion, swinging and bending (which do not
 * change the pair's length to first order) are not. The pair direction is normalised by the rest
 * length (`invRest2` = 1/rest²) rather than the current one, which differs only at large strain
 * and saves a division per pair.
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
    const vr = ((vel[b] - vel[a]) * dx + (vel[b + 1] - vel[a + 1]) * dy + (vel[b + 2] - vel[a + 2]) * dz) * invRest2[k]
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
