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
  // written like the distance loops (truncated index arithmetic, one test for pinned and
  // degenerate pairs): a pinned pair's zero weights leave its velocities as they are
  for (let k = 0; k < count; k++) {
    const i0 = ids[k << 1], i1 = ids[((k << 1) + 1) | 0]
    const wa = invMass[i0], wb = invMass[i1]
    const a = (3 * i0) | 0, b = (3 * i1) | 0
    const a1 = (a + 1) | 0, a2 = (a + 2) | 0, b1 = (b + 1) | 0, b2 = (b + 2) | 0
    const dx = pos[b] - pos[a], dy = pos[b1] - pos[a1], dz = pos[b2] - pos[a2]
    const den = (wa + wb) * (dx * dx + dy * dy + dz * dz)
    if (!(den >= 1e-30)) continue
    const vax = vel[a], vay = vel[a1], vaz = vel[a2]
    const vbx = vel[b], vby = vel[b1], vbz = vel[b2]
    const s = (factor * ((vbx - vax) * dx + (vby - vay) * dy + (vbz - vaz) * dz)) / den
    const sa = wa * s, sb = wb * s
    vel[a] = vax + sa * dx
    vel[a1] = vay + sa * dy
    vel[a2] = vaz + sa * dz
    vel[b] = vbx - sb * dx
    vel[b1] = vby - sb * dy
    vel[b2] = vbz - sb * dz
  }
}
