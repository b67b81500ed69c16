import { describe, expect, it } from 'vitest'
import {
  SELF_PARAM_COUNT,
  S_CONTACT_SCALE,
  S_DIST,
  S_INV_CELL,
  S_LIMIT,
  S_MU_K,
  S_MU_S,
  S_RADIUS,
  S_REST_FILTER,
  S_SLOP,
  S_W_A,
  S_W_B,
  buildHash,
  clampRelativeMotion,
  gatherPairs,
  solvePairs,
} from '../../src/kernels/selfCollide'
import { rng } from '../helpers'

function params(values: Record<number, number>) {
  const p = new Float64Array(SELF_PARAM_COUNT)
  p[S_W_A] = 1
  p[S_W_B] = 1
  p[S_CONTACT_SCALE] = 1
  for (const [k, v] of Object.entries(values)) p[Number(k)] = v
  return p
}

function randomPoints(n: number, seed: number, size = 1) {
  const r = rng(seed)
  const pos = new Float64Array(3 * n)
  for (let i = 0; i < 3 * n; i++) pos[i] = (r() - 0.5) * size
  return pos
}

function hash(pos: Float64Array, n: number, cell: number) {
  let table = 16
  while (table < 2 * n) table *= 2
  const start = new Int32Array(table + 1), entries = new Int32Array(n), bucket = new Int32Array(n), sorted = new Float64Array(3 * n)
  buildHash(pos, n, start, entries, bucket, sorted, table - 1, params({ [S_INV_CELL]: 1 / cell }))
  return { start, entries, bucket, sorted, mask: table - 1, visited: new Int32Array(table + 1) }
}

const dist2 = (a: Float64Array, i: number, b: Float64Array, j: number) =>
  (a[3 * i] - b[3 * j]) ** 2 + (a[3 * i + 1] - b[3 * j + 1]) ** 2 + (a[3 * i + 2] - b[3 * j + 2]) ** 2

describe('particle hash and pairs', () => {
  it('the counting-sort hash lists every particle once, in its bucket, ascending', () => {
    const n = 500
    const pos = randomPoints(n, 1)
    const h = hash(pos, n, 0.05)
    expect(h.start[h.mask + 1]).toBe(n)
    const seen = new Set<number>()
    for (let b = 0; b <= h.mask; b++) {
      for (let e = h.start[b]; e < h.start[b + 1]; e++) {
        const i = h.entries[e]
        expect(h.bucket[i]).toBe(b)
        for (let k = 0; k < 3; k++) expect(h.sorted[3 * e + k]).toBe(pos[3 * i + k])
        if (e > h.start[b]) expect(i).toBeGreaterThan(h.entries[e - 1])
        seen.add(i)
      }
    }
    expect(seen.size).toBe(n)
  })

  it('gathers exactly the pairs within the radius (self: j > i, minus pairs closer than the filter at rest)', () => {
    const n = 400
    const pos = randomPoints(n, 2)
    const rest = randomPoints(n, 3, 2)
    const R = 0.12, D = 0.1
    const h = hash(pos, n, 2 * R)
    const w = new Float64Array(n).fill(1)
    const pairs = new Int32Array(2 * 50 * n)
    const p = params({ [S_RADIUS]: R, [S_INV_CELL]: 1 / (2 * R), [S_REST_FILTER]: D })
    const count = gatherPairs(h.sorted, h.entries, w, n, rest, h.sorted, h.entries, w, h.start, h.mask, h.visited, pairs, 0, 50 * n, p)
    const found = new Set<string>()
    for (let q = 0; q < count; q++) {
      const i = pairs[2 * q], j = pairs[2 * q + 1]
      found.add(i < j ? `${i},${j}` : `${j},${i}`)
    }
    expect(found.size).toBe(count) // no pair twice, even where two cells share a bucket
    const expected = new Set<string>()
    for (let i = 0; i < n; i++) {
      for (let j = i + 1; j < n; j++) {
        if (dist2(pos, i, pos, j) <= R * R && dist2(rest, i, rest, j) >= D * D) expected.add(`${i},${j}`)
      }
    }
    expect(expected.size).toBeGreaterThan(50)
    expect(found).toEqual(expected)
  })

  it('gathers pairs between two point sets through the second one’s hash, and stops at capacity', () => {
    const n = 300
    const a = randomPoints(n, 4), b = randomPoints(n, 5)
    const R = 0.1
    const ha = hash(a, n, 0.13), h = hash(b, n, R) // the query may be larger or smaller than B's cells
    const w = new Float64Array(n).fill(1)
    const pairs = new Int32Array(2 * 20 * n)
    const p = params({ [S_RADIUS]: R, [S_INV_CELL]: 1 / R })
    const count = gatherPairs(ha.sorted, ha.entries, w, n, null, h.sorted, h.entries, w, h.start, h.mask, h.visited, pairs, 0, 20 * n, p)
    let expected = 0
    for (let i = 0; i < n; i++) for (let j = 0; j < n; j++) if (dist2(a, i, b, j) <= R * R) expected++
    expect(count).toBe(expected)
    expect(gatherPairs(ha.sorted, ha.entries, w, n, null, h.sorted, h.entries, w, h.start, h.mask, h.visited, pairs, 0, 10, p)).toBe(10)
  })
})

describe('particle pair response', () => {
  it('pushes an overlapping pair apart to the collision distance, keeping the centre of mass', () => {
    const pos = Float64Array.from([0, 0, 0, 0.06, 0, 0])
    const prev = pos.slice()
    const w = Float64Array.from([1, 3])
    const touched = new Uint8Array(2)
    const pairs = Int32Array.from([0, 1])
    const p = params({ [S_DIST]: 0.1 })
    expect(solvePairs(pos, prev, w, touched, pos, prev, w, touched, pairs, 0, 1, p)).toBe(1)
    expect(pos[3] - pos[0]).toBeCloseTo(0.1, 12)
    // masses 1 and 1/3: 1·x0 + (1/3)·x1 stays (1/3)·0.06
    expect(pos[0] + pos[3] / 3).toBeCloseTo(0.02, 12)
  })

  it('an immovable side (inverse mass 0, or a cloth sitting the substep out) does not move', () => {
    const a = Float64Array.from([0, 0, 0]), b = Float64Array.from([0, 0.05, 0])
    const touched = new Uint8Array(1)
    const pairs = Int32Array.from([0, 0])
    solvePairs(
      a,
      a.slice(),
      Float64Array.from([1]),
      touched,
      b,
      b.slice(),
      Float64Array.from([1]),
      touched,
      pairs,
      0,
      1,
      params({ [S_DIST]: 0.1, [S_W_A]: 0 }),
    )
    expect(Array.from(a)).toEqual([0, 0, 0])
    expect(b[1]).toBeCloseTo(0.1, 12)
  })

  it('static friction makes touching particles move together; a resolved old overlap adds no velocity', () => {
    // B slid 1 mm sideways relative to A while pressing 1 cm into it: the slip is undone
    const pos = Float64Array.from([0, 0, 0, 0.001, 0.09, 0])
    const prev = Float64Array.from([0, 0, 0, 0, 0.1, 0])
    const w = Float64Array.from([1, 1])
    const touched = new Uint8Array(2)
    const p = params({ [S_DIST]: 0.1, [S_MU_S]: 0.5, [S_MU_K]: 0.5, [S_SLOP]: 1 })
    solvePairs(pos, prev, w, touched, pos, prev, w, touched, Int32Array.from([0, 1]), 0, 1, p)
    const relX = pos[3] - prev[3] - (pos[0] - prev[0])
    expect(Math.abs(relX)).toBeLessThan(1e-6) // of 1e-3 (what is left lies along the contact normal)
    // two particles overlapping by 4 cm at rest: pushed apart, but their prev goes along (beyond the slop)
    const q = Float64Array.from([0, 0, 0, 0, 0.06, 0])
    const qp = q.slice()
    solvePairs(q, qp, w, touched, q, qp, w, touched, Int32Array.from([0, 1]), 0, 1, params({ [S_DIST]: 0.1, [S_SLOP]: 0.001 }))
    expect(q[4] - q[1]).toBeCloseTo(0.1, 12)
    const separating = q[4] - qp[4] - (q[1] - qp[1])
    expect(separating).toBeCloseTo(0.001, 12) // only the slop became velocity
  })

  it('a particle resting on a collider counts as heavier', () => {
    const pos = Float64Array.from([0, 0, 0, 0, 0.05, 0])
    const w = Float64Array.from([1, 1])
    const touched = Uint8Array.from([1, 0])
    solvePairs(
      pos,
      pos.slice(),
      w,
      touched,
      pos,
      pos.slice(),
      w,
      touched,
      Int32Array.from([0, 1]),
      0,
      1,
      params({ [S_DIST]: 0.1, [S_CONTACT_SCALE]: 0.25 }),
    )
    expect(pos[1]).toBeCloseTo(-0.01, 12) // 1/5 of the 5 cm
    expect(pos[4]).toBeCloseTo(0.09, 12)
  })
})

describe('relative motion clamp', () => {
  it('limits motion relative to the cloth’s mean, leaving a common motion alone', () => {
    const n = 4
    const prev = new Float64Array(3 * n)
    const pos = new Float64Array(3 * n)
    for (let i = 0; i < n; i++) pos[3 * i] = 1 // everything moves 1 m in x
    pos[3 * 3 + 1] = 0.5 // one particle also 0.5 m in y
    const w = new Float64Array(n).fill(1)
    clampRelativeMotion(pos, prev, w, n, params({ [S_LIMIT]: 0.1 }), true)
    // mean motion (1, 0.125, 0); the outlier's deviation (0, 0.375, 0) is cut to 0.1 and the
    // others' (0, −0.125, 0) to −0.1; the 0.2 m of motion taken out in y is given back to all
    // four alike (0.05 each), so the total motion (momentum) is what it was
    expect(pos[3 * 3]).toBeCloseTo(1, 12)
    expect(pos[3 * 3 + 1]).toBeCloseTo(0.125 + 0.1 + 0.05, 12)
    expect(pos[1]).toBeCloseTo(0.125 - 0.1 + 0.05, 12)
    expect(pos[0]).toBeCloseTo(1, 12)
    let sy = 0
    for (let i = 0; i < n; i++) sy += pos[3 * i + 1]
    expect(sy).toBeCloseTo(0.5, 12)
    // without `conserve` (a pinned cloth, whose pins take momentum anyway) nothing is given back
    const kept = new Float64Array(3 * n)
    for (let i = 0; i < n; i++) kept[3 * i] = 1
    kept[3 * 3 + 1] = 0.5
    clampRelativeMotion(kept, prev, w, n, params({ [S_LIMIT]: 0.1 }), false)
    expect(kept[3 * 3 + 1]).toBeCloseTo(0.125 + 0.1, 12)
    expect(kept[1]).toBeCloseTo(0.125 - 0.1, 12)
  })

  it('conserves momentum (Σ m·Δx) for any masses and motions, and keeps any two particles’ relative motion within twice the limit', () => {
    for (let seed = 1; seed <= 50; seed++) {
      const r = rng(seed)
      const n = 2 + Math.floor(r() * 30)
      const prev = randomPoints(n, seed)
      const pos = new Float64Array(3 * n)
      const w = new Float64Array(n)
      for (let i = 0; i < n; i++) {
        w[i] = r() < 0.15 ? 0 : 10 ** (2 * r() - 1) // some pinned, masses 0.1…10 kg
        const fast = r() < 0.3 ? 5 : 0.05 // an uneven spread: a few fast ones
        for (let k = 0; k < 3; k++) pos[3 * i + k] = prev[3 * i + k] + (r() - 0.3) * fast
      }
      const momentum = (a: Float64Array) => {
        const p = [0, 0, 0]
        for (let i = 0; i < n; i++) if (w[i] > 0) { for (let k = 0; k < 3; k++) p[k] += (a[3 * i + k] - prev[3 * i + k]) / w[i] }
        return p
      }
      const before = momentum(pos)
      const pinned = pos.filter((_, j) => w[Math.floor(j / 3)] === 0)
      const lim = 0.1
      clampRelativeMotion(pos, prev, w, n, params({ [S_LIMIT]: lim }), true)
      const after = momentum(pos)
      for (let k = 0; k < 3; k++) expect(after[k]).toBeCloseTo(before[k], 9)
      expect(pos.filter((_, j) => w[Math.floor(j / 3)] === 0)).toEqual(pinned) // pinned particles untouched
      for (let i = 0; i < n; i++) {
        for (let j = 0; j < n; j++) {
          if (w[i] === 0 || w[j] === 0) continue
          const d = Math.hypot(...[0, 1, 2].map((k) => pos[3 * i + k] - prev[3 * i + k] - (pos[3 * j + k] - prev[3 * j + k])))
          expect(d).toBeLessThanOrEqual(2 * lim + 1e-12)
        }
      }
    }
  })
})
