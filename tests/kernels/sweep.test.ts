// The broadphase between self-colliding cloths (kernels/sweep.ts) against the loop over all pairs
// it replaced: the same pairs, each cloth's partners in ascending order, whatever order the boxes
// were kept in from the last step; a box that is not a number (passed as −∞..+∞) meets every other.
import { fc, test } from '@fast-check/vitest'
import { describe, expect, it } from 'vitest'
import { pairsByFirst, sweepPairs } from '../../src/kernels/sweep'

/** Each box's partners by sort and sweep, as `buildSelfCollisionPairs` lists them. */
function swept(lo: number[], hi: number[], margin: number, start: number[]): number[][] {
  const n = lo.length
  const order = Int32Array.from(start)
  const L = Float64Array.from(lo), H = Float64Array.from(hi)
  let pairs = new Int32Array(2)
  let m = sweepPairs(L, H, order, n, margin, pairs, 1)
  if (m > 1) {
    pairs = new Int32Array(2 * m)
    m = sweepPairs(L, H, order, n, margin, pairs, m)
  }
  const head = new Int32Array(n + 1), list = new Int32Array(m)
  pairsByFirst(pairs, m, n, head, list)
  // the order it kept: sorted by (lo, index)
  for (let p = 1; p < n; p++) {
    const a = order[p - 1], b = order[p]
    expect(lo[a] < lo[b] || (lo[a] === lo[b] && a < b)).toBe(true)
  }
  return Array.from({ length: n }, (_, i) => Array.from(list.subarray(head[i], head[i + 1])))
}

/** The loop over all pairs i < j. */
function allPairs(lo: number[], hi: number[], margin: number): number[][] {
  return lo.map((_, i) => lo.flatMap((_, j) => (j > i && !(lo[i] > hi[j] + margin) && !(lo[j] > hi[i] + margin) ? [j] : [])))
}

describe('sort and sweep', () => {
  const box = fc.tuple(fc.integer({ min: -20, max: 20 }), fc.integer({ min: 0, max: 6 }), fc.boolean())
  test.prop([fc.array(box, { minLength: 0, maxLength: 40 }), fc.integer({ min: 0, max: 3 }), fc.integer({ min: 0, max: 1000 })], {
    numRuns: 300,
  })(
    'finds the pairs the loop over all pairs finds, in its order, from any kept order',
    (boxes, margin, seed) => {
      // (integers: ties in lo and touching boxes are common; one box in ten not a number)
      const lo = boxes.map(([l, , broken], i) => (broken && i % 10 === 0 ? -Infinity : l))
      const hi = boxes.map(([l, w, broken], i) => (broken && i % 10 === 0 ? Infinity : l + w))
      const n = lo.length
      const start = Array.from({ length: n }, (_, i) => i)
      for (let i = n - 1; i > 0; i--) {
        const j = (seed * (i + 7)) % (i + 1)
        ;[start[i], start[j]] = [start[j], start[i]]
      }
      expect(swept(lo, hi, margin, start)).toEqual(allPairs(lo, hi, margin))
    },
  )

  it('boxes apart along the axis give no pairs; one box spanning them all meets each', () => {
    const lo = [0, 2, 4, 6, -1], hi = [1, 3, 5, 7, 8]
    expect(swept(lo.slice(0, 4), hi.slice(0, 4), 0.5, [3, 2, 1, 0])).toEqual([[], [], [], []])
    expect(swept(lo, hi, 0, [0, 1, 2, 3, 4])).toEqual([[4], [4], [4], [4], []])
  })
})
