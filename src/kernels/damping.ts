import { P_STRETCH_DAMP } from './params'

/**
 * Stretch damping, a velocity pass after the velocity update: for each pair, removes the fraction
 * `params[P_STRETCH_DAMP]` of the particles' relative velocity along the pair, split by inverse mass (momentum is
 * unchanged). Only stretching motion is damped; rigid motion, swinging and bending (which do not
 * change the pair's length to first order) are not. The relative velocity is projected on the
 * current pair direction: normalising by the rest length instead (saving a division) scales the
 * correction by (length/rest)², which turned this damper into an amplifier on over-stretched edges
 * and blew a sheet up.
 */
export function dampPairs(
  pos: Float64Array,
  vel: Float64Array,
  invMass: Float64Array,
  ids: Int32Array,
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
    const d2 = dx * dx + dy * dy + dz * dz
    if (d2 < 1e-24) continue
    const vr = ((vel[b] - vel[a]) * dx + (vel[b + 1] - vel[a + 1]) * dy + (vel[b + 2] - vel[a + 2]) * dz) / d2
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
