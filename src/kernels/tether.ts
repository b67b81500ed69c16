/**
 * Long-range attachment constraints (one-sided, rigid): particle i may be at most `rest` away from
 * its anchor. Inactive tethers cost one squared-distance test and no square root. The anchor is
 * normally pinned (inverse mass 0), so the particle takes the whole correction.
 *
 * `restPos` (the rest positions) is given when the anchors need not keep their rest distances
 * (pins on different targets, which may move apart): then a particle's tethers (consecutive in the
 * set) lengthen by the ratio its first two anchors moved apart, |x_a − x_b| / |r_a − r_b| when
 * above 1, so that both can still be met at once (on the straight line between them at rest they
 * add up to exactly that distance) instead of the last one dragging the particle away from the
 * other's anchor: one corner edge then took all of the pins' separation. Null: every anchor
 * follows the same thing, and the rest lengths stand.
 */
export function solveTethers(
  pos: Float64Array,
  invMass: Float64Array,
  particle: Int32Array,
  anchor: Int32Array,
  rest: Float64Array,
  restPos: Float64Array | null,
  count: number,
): void {
  let owner = -1, scale = 1
  for (let t = 0; t < count; t++) {
    const i = particle[t]
    if (restPos !== null && i !== owner) {
      owner = i
      scale = 1
      if (t + 1 < count && particle[t + 1] === i) {
        const a = 3 * anchor[t], b = 3 * anchor[t + 1]
        const ax = pos[a] - pos[b], ay = pos[a + 1] - pos[b + 1], az = pos[a + 2] - pos[b + 2]
        const rx = restPos[a] - restPos[b], ry = restPos[a + 1] - restPos[b + 1], rz = restPos[a + 2] - restPos[b + 2]
        const d2 = ax * ax + ay * ay + az * az, r2 = rx * rx + ry * ry + rz * rz
        if (d2 > r2 && r2 > 0) scale = Math.sqrt(d2 / r2)
      }
    }
    const wi = invMass[i]
    if (wi === 0) continue
    const pi = 3 * i, pa = 3 * anchor[t]
    const dx = pos[pi] - pos[pa], dy = pos[pi + 1] - pos[pa + 1], dz = pos[pi + 2] - pos[pa + 2]
    const d2 = dx * dx + dy * dy + dz * dz
    const L = rest[t] * scale
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
