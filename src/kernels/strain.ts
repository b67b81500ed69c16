/**
 * Strain check of the tearing phase over pairs [0, count): a pair whose length exceeds
 * (1 + strain)·rest counts up `over[k]` (saturating at 255), any other resets it to 0. Pairs whose
 * counter reached `hysteresis` are candidates; the `max` most strained of them (largest
 * length²/limit²) are written to cand/candRatio, most strained first. No square root.
 *
 * @param params params[0] = (1 + strain)², params[1] = hysteresis (steps), params[2] = max candidates
 * @returns the number of candidates written
 */
export function findOverstrained(
  pos: Float64Array,
  ids: Int32Array,
  rest: Float64Array,
  count: number,
  over: Uint8Array,
  params: Float64Array,
  cand: Int32Array,
  candRatio: Float64Array,
): number {
  const f2 = params[0]
  const hysteresis = params[1]
  const max = params[2] | 0
  let n = 0
  for (let k = 0; k < count; k++) {
    const a = 3 * ids[2 * k], b = 3 * ids[2 * k + 1]
    const dx = pos[b] - pos[a], dy = pos[b + 1] - pos[a + 1], dz = pos[b + 2] - pos[a + 2]
    const l2 = dx * dx + dy * dy + dz * dz
    const r = rest[k]
    const limit2 = f2 * r * r
    // (an edge of no rest length, a collapsed row, has no strain to measure: it never tears)
    if (!(l2 > limit2) || !(r > 0)) {
      over[k] = 0
      continue
    }
    const o = over[k] < 255 ? over[k] + 1 : 255
    over[k] = o
    if (o < hysteresis) continue
    const ratio = l2 / limit2
    // insertion into the short sorted candidate list
    let q = n < max ? n++ : max
    if (q === max && (max === 0 || ratio <= candRatio[max - 1])) continue
    if (q === max) q = max - 1
    while (q > 0 && candRatio[q - 1] < ratio) {
      candRatio[q] = candRatio[q - 1]
      cand[q] = cand[q - 1]
      q--
    }
    candRatio[q] = ratio
    cand[q] = k
  }
  return n
}
