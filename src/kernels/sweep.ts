/**
 * A broadphase for a few hundred boxes (sort and sweep along one axis), in two passes:
 * `sweepPairs` finds the pairs whose extents along the axis overlap, `pairsByFirst` lists each
 * box's partners in ascending order, so that a caller visits the pairs in the order a loop over
 * all pairs (i < j) would, for the same results.
 */

/**
 * Sorts `order` (a permutation of 0..n−1, kept from the last call) by (lo, index) by insertion:
 * boxes move little from one step to the next, so it is nearly sorted and this is about linear.
 * The result does not depend on the order it started from. Then writes each pair of boxes i < j
 * whose extents [lo, hi] overlap within `margin` to pairs[2k], pairs[2k + 1], up to `capacity`
 * pairs, and returns how many there are (more than `capacity`: call again with room for them).
 * A NaN extent overlaps everything (lo −∞, hi +∞ are to be passed for it).
 */
export function sweepPairs(
  lo: Float64Array,
  hi: Float64Array,
  order: Int32Array,
  n: number,
  margin: number,
  pairs: Int32Array,
  capacity: number,
): number {
  for (let p = 1; p < n; p++) {
    const i = order[p], key = lo[i]
    let q = p - 1
    while (q >= 0 && (lo[order[q]] > key || (lo[order[q]] === key && order[q] > i))) {
      order[q + 1] = order[q]
      q--
    }
    order[q + 1] = i
  }
  let m = 0
  for (let p = 0; p < n; p++) {
    const i = order[p], reach = hi[i] + margin
    for (let q = p + 1; q < n; q++) {
      const j = order[q]
      if (lo[j] > reach) break
      if (m < capacity) {
        pairs[2 * m] = i < j ? i : j
        pairs[2 * m + 1] = i < j ? j : i
      }
      m++
    }
  }
  return m
}

/**
 * The m pairs of `sweepPairs` grouped by their first box: box i's partners, ascending, are
 * list[head[i]..head[i + 1]) (head has n + 1 entries).
 */
export function pairsByFirst(pairs: Int32Array, m: number, n: number, head: Int32Array, list: Int32Array): void {
  head.fill(0, 0, n + 1)
  for (let k = 0; k < m; k++) head[pairs[2 * k] + 1]++
  for (let i = 0; i < n; i++) head[i + 1] += head[i]
  // (head[i] runs ahead while box i's partners are placed, then is set back)
  for (let k = 0; k < m; k++) list[head[pairs[2 * k]]++] = pairs[2 * k + 1]
  for (let i = n; i > 0; i--) head[i] = head[i - 1]
  head[0] = 0
  for (let i = 0; i < n; i++) {
    for (let p = head[i] + 1; p < head[i + 1]; p++) {
      const j = list[p]
      let q = p - 1
      while (q >= head[i] && list[q] > j) {
        list[q + 1] = list[q]
        q--
      }
      list[q + 1] = j
    }
  }
}
