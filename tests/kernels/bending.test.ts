import { describe, expect, it } from 'vitest'
import { solveLineBending } from '../../src/kernels/bending'
import { P_INV_H2, createKernelParams } from '../../src/kernels/params'

const params = (invH2: number) => {
  const p = createKernelParams()
  p[P_INV_H2] = invH2
  return p
}
const ids = Int32Array.from([0, 1, 2])

describe('solveLineBending', () => {
  it('straightens a kinked triple and conserves momentum', () => {
    const pos = Float64Array.from([0, 0, 0, 1, 0.2, 0.1, 2, 0, 0])
    const w = Float64Array.from([1, 2, 0.5])
    const momentum = () => [0, 1, 2].map((k) => pos[k] / w[0] + pos[3 + k] / w[1] + pos[6 + k] / w[2])
    const before = momentum()
    solveLineBending(pos, w, ids, Float64Array.from([0]), Float64Array.from([0]), null, params(3600), 0, 1)
    // middle on the midpoint of its neighbours after one rigid projection (the constraint is linear in the kink)
    for (let k = 0; k < 3; k++) expect(pos[3 + k]).toBeCloseTo(0.5 * (pos[k] + pos[6 + k]), 12)
    const after = momentum()
    for (let k = 0; k < 3; k++) expect(after[k]).toBeCloseTo(before[k], 12)
  })

  it('keeps a curved rest shape at its rest kink and leaves pinned particles alone', () => {
    const pos = Float64Array.from([0, 0, 0, 1, 0.5, 0, 2, 0, 0])
    const w = Float64Array.from([0, 1, 0])
    for (let i = 0; i < 5; i++) solveLineBending(pos, w, ids, Float64Array.from([0.2]), Float64Array.from([0]), null, params(3600), 0, 1)
    expect(pos[4]).toBeCloseTo(0.2, 12)
    expect([pos[0], pos[6]]).toEqual([0, 2])
  })

  it('is soft with compliance and a no-op on a straight line', () => {
    const soft = Float64Array.from([0, 0, 0, 1, 0.1, 0, 2, 0, 0])
    solveLineBending(soft, Float64Array.from([1, 1, 1]), ids, Float64Array.from([0]), Float64Array.from([1e-3]), null, params(3600), 0, 1)
    expect(soft[4]).toBeGreaterThan(0.01)
    expect(soft[4]).toBeLessThan(0.1)
    const straight = Float64Array.from([0, 0, 0, 1, 0, 0, 2, 0, 0])
    solveLineBending(straight, Float64Array.from([1, 1, 1]), ids, Float64Array.from([0]), Float64Array.from([0]), null, params(3600), 0, 1)
    expect(Array.from(straight)).toEqual([0, 0, 0, 1, 0, 0, 2, 0, 0])
  })

  it('with multipliers converges to the compliant (implicit) answer, for the vector and the scalar form alike', () => {
    // ends pinned, the middle kinked by 0.1 m; compliance α with α̃ = α/h²: the XPBD fixed point of a
    // linear spring is the backward-Euler one, kink × α̃ / (w + α̃)
    const alpha = 2e-4, invH2 = 3600, w1 = 2
    const expected = (0.1 * alpha * invH2) / (w1 + alpha * invH2)
    for (const rest of [0, 1e-3]) {
      const pos = Float64Array.from([0, 0, 0, 1, 0.1, 0, 2, 0, 0])
      const lambda = new Float64Array(3)
      for (let i = 0; i < 200; i++)
        solveLineBending(
          pos,
          Float64Array.from([0, w1, 0]),
          ids,
          Float64Array.from([rest]),
          Float64Array.from([alpha]),
          lambda,
          params(invH2),
          0,
          1,
        )
      // (the scalar form's rest kink shifts its answer by rest × w/(w + α̃))
      expect(pos[4]).toBeCloseTo(expected + (rest * w1) / (w1 + alpha * invH2), 9)
    }
  })
})
