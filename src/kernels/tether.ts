/**
 * Long-range attachment constraints (one-sided, rigid): particle i may be at most `rest` away from
 * its anchor. Inactive tethers cost one squared-distance test and no square root. The anchor is
 * normally pinned (inverse mass 0), so the particle takes the whole correction.
 */
export function solveTethers(
  pos: Float64Array,
  invMass: Float64Array,
  particle: Int32Array,
  anchor: Int32Array,
  rest: Float64Array,
  count: number,
): void {
  for (let t = 0; t < count; t++) {
    const i = particle[t]
    const wi = invMass[i]
    if (wi === 0) continue
    const pi = 3 * i, pa = 3 * anchor[t]
    const dx = pos[pi] - pos[pa], dy = pos[pi + 1] - pos[pa + 1], dz = pos[pi + 2] - pos[pa + 2]
    const d2 = dx * dx + dy * dy + dz * dz
    const L = rest[t]
    if (d2 <= L * L) continue
    const d = Math.sqrt(d2)
    const wa = invMass[anchor[t]]
    const f = (d - L) / (d * (wi + wa))
    const fi = wi * f
    pos[pi] -= fi * dx
    pos[pi + 1] -= fi * dy
    pos[pi + 2] -= fi * dz
    if (wa !== 0) {
      const fa = wa * f
      pos[pa] += fa * dx
      pos[pa + 1] += fa * dy
      pos[pa + 2] += fa * dz
    }
  }
}
