import { describe, expect, it } from 'vitest'
import { dampPairs } from '../../src/kernels/damping'
import { P_STRETCH_DAMP, createKernelParams } from '../../src/kernels/params'

describe('dampPairs', () => {
  const params = createKernelParams()
  params[P_STRETCH_DAMP] = 0.25

  for (const length of [0.5, 1, 10]) {
    it(`removes exactly the given fraction of relative stretch velocity (pair at ${length}× rest)`, () => {
      const pos = Float64Array.from([0, 0, 0, length, 0, 0])
      const vel = Float64Array.from([-1, 2, 0, 3, -1, 0]) // relative along x: 4 m/s; across: −3 m/s
      const w = Float64Array.from([1, 3])
      dampPairs(pos, vel, w, Int32Array.from([0, 1]), 1, params)
      expect(vel[3] - vel[0]).toBeCloseTo(4 * 0.75, 12) // never amplified, whatever the strain
      expect(vel[4] - vel[1]).toBeCloseTo(-3, 12) // motion across the pair untouched
      // momentum unchanged: masses 1 and 1/3
      expect(vel[0] + vel[3] / 3).toBeCloseTo(-1 + 1, 12)
    })
  }

  it('skips collapsed and fully pinned pairs', () => {
    const vel = Float64Array.from([1, 0, 0, -1, 0, 0])
    dampPairs(Float64Array.from([0, 0, 0, 0, 0, 0]), vel, Float64Array.from([1, 1]), Int32Array.from([0, 1]), 1, params)
    dampPairs(Float64Array.from([0, 0, 0, 1, 0, 0]), vel, Float64Array.from([0, 0]), Int32Array.from([0, 1]), 1, params)
    expect(Array.from(vel)).toEqual([1, 0, 0, -1, 0, 0])
  })
})
