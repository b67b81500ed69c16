import { describe, expect, it } from 'vitest'
import { solveCompression, solveDistances, solveDistancesXpbd, spreadInverseMasses } from '../../src/kernels/distance'
import { P_INV_H2, createKernelParams } from '../../src/kernels/params'

/** Kernel parameters with 1/h² set (the only scalar these kernels read). */
const params = (invH2: number) => {
  const p = createKernelParams()
  p[P_INV_H2] = invH2
  return p
}

/** Two particles on the x axis; `w`/`ids` as the compression loop takes them, `w3`/`offsets` as the distance loops do. */
function pair(ax: number, bx: number, wa = 1, wb = 1) {
  const w = Float64Array.from([wa, wb])
  const w3 = new Float64Array(6)
  spreadInverseMasses(w, w3, 2)
  return {
    pos: Float64Array.from([ax, 0, 0, bx, 0, 0]),
    w,
    ids: Int32Array.from([0, 1]),
    w3,
    offsets: Int32Array.from([0, 3]),
    rest: Float64Array.from([1]),
    comp: Float64Array.from([0]),
    lambda: new Float64Array(1),
  }
}

describe('solveDistances', () => {
  it('converges a stretched rigid pair to its rest length, moving both ends by inverse mass', () => {
    const p = pair(0, 2, 1, 3)
    for (let i = 0; i < 50; i++) solveDistances(p.pos, p.w3, p.offsets, p.rest, p.comp, params(3600), 0, 1)
    expect(p.pos[3] - p.pos[0]).toBeCloseTo(1, 9)
    // centre of mass (masses 1 and 1/3) does not move: 1·0 + (1/3)·2 = (4/3)·x_cm
    const xcm = (1 * p.pos[0] + (1 / 3) * p.pos[3]) / (4 / 3)
    expect(xcm).toBeCloseTo(0.5, 12)
  })

  it('leaves a pinned end where it is and never overshoots a stretched pair past rest', () => {
    for (const stretched of [1.01, 1.1, 1.5, 2, 3, 10]) {
      const p = pair(0, stretched, 0, 1)
      solveDistances(p.pos, p.w3, p.offsets, p.rest, p.comp, params(3600), 0, 1)
      expect(p.pos[0]).toBe(0)
      expect(p.pos[3]).toBeGreaterThanOrEqual(1)
      expect(p.pos[3]).toBeLessThan(stretched)
    }
    // near rest one projection is almost exact (second-order accurate)
    const p = pair(0, 1.1, 0, 1)
    solveDistances(p.pos, p.w3, p.offsets, p.rest, p.comp, params(3600), 0, 1)
    expect(p.pos[3] - 1).toBeLessThan(0.001)
  })

  it('one rigid projection takes back the exact correction within 0.25 % up to 10 % stretch and 0.3 % at 10 % compression, never more (the Padé factor)', () => {
    for (const strain of [-0.1, -0.05, -0.01, 0.01, 0.05, 0.1]) {
      const p = pair(0, 1 + strain, 0, 1)
      solveDistances(p.pos, p.w3, p.offsets, p.rest, p.comp, params(3600), 0, 1)
      const share = (1 + strain - p.pos[3]) / strain // of the exact correction, which puts the pair at rest length
      expect(share, `strain ${strain}`).toBeGreaterThan(strain > 0 ? 0.9975 : 0.997) // (measured 0.99784 at +10 %, 0.99709 at −10 %)
      expect(share, `strain ${strain}`).toBeLessThanOrEqual(1)
    }
  })

  it('skips a pair with both ends pinned and a collapsed pair without producing NaN', () => {
    const p = pair(0, 3, 0, 0)
    solveDistances(p.pos, p.w3, p.offsets, p.rest, p.comp, params(3600), 0, 1)
    expect(Array.from(p.pos)).toEqual([0, 0, 0, 3, 0, 0])
    const q = pair(0.5, 0.5)
    q.rest[0] = 0
    solveDistances(q.pos, q.w3, q.offsets, q.rest, q.comp, params(3600), 0, 1)
    expect(Array.from(q.pos).every(Number.isFinite)).toBe(true)
  })

  it('pushes a collapsed pair with non-zero rest length apart along any direction without NaN', () => {
    const p = pair(0.25, 0.25 + 1e-9)
    solveDistances(p.pos, p.w3, p.offsets, p.rest, p.comp, params(3600), 0, 1)
    expect(Array.from(p.pos).every(Number.isFinite)).toBe(true)
    expect(p.pos[3] - p.pos[0]).toBeGreaterThan(2.9e-9) // apart: about 3× per projection while collapsed
    for (let i = 0; i < 60; i++) solveDistances(p.pos, p.w3, p.offsets, p.rest, p.comp, params(3600), 0, 1)
    expect(p.pos[3] - p.pos[0]).toBeCloseTo(1, 9) // and back to its rest length
  })

  it('with compliance, converges to the XPBD force balance regardless of iteration count', () => {
    // particle hanging under gravity on a compliant spring: equilibrium extension = m·g·compliance
    // (0.5 % strain here, where the Green-strain spring is linear to within 1 %)
    const hang = (iterations: number) => {
      const pos = Float64Array.from([0, 0, 0, 0, -1, 0])
      const prev = Float64Array.from(pos)
      const w3 = Float64Array.from([0, 0, 0, 1 / 0.5, 0, 0]) // 0.5 kg, at position offsets
      const offsets = Int32Array.from([0, 3])
      const rest = Float64Array.from([1])
      const comp = Float64Array.from([0.001]) // m/N
      const lambda = new Float64Array(1)
      const h = 1 / 240
      let vy = 0
      for (let s = 0; s < 240 * 20; s++) {
        vy = vy * Math.exp(-5 * h) - 9.81 * h
        prev[4] = pos[4]
        pos[4] += vy * h
        lambda.fill(0)
        for (let it = 0; it < iterations; it++) solveDistancesXpbd(pos, w3, offsets, rest, comp, lambda, params(1 / (h * h)), 0, 1)
        vy = (pos[4] - prev[4]) / h
      }
      return -pos[4] - 1
    }
    const expected = 0.5 * 9.81 * 0.001
    expect(Math.abs(hang(1) / expected - 1)).toBeLessThan(0.02)
    expect(Math.abs(hang(10) / expected - 1)).toBeLessThan(0.02)
    expect(Math.abs(hang(10) / hang(1) - 1)).toBeLessThan(0.005)
  })
})

describe('solveCompression', () => {
  it('pushes a compressed pair apart but never pulls a stretched one', () => {
    const c = pair(0, 0.5)
    solveCompression(c.pos, c.w, c.ids, c.rest, c.comp, null, params(3600), 0, 1)
    expect(c.pos[3] - c.pos[0]).toBeGreaterThan(0.5)
    const s = pair(0, 1.5)
    solveCompression(s.pos, s.w, s.ids, s.rest, s.comp, null, params(3600), 0, 1)
    expect(Array.from(s.pos)).toEqual([0, 0, 0, 1.5, 0, 0])
  })
})
