import { describe, expect, it } from 'vitest'
import { solveDihedrals } from '../../src/kernels/dihedral'
import { dihedralAngle } from '../../src/model/topology'
import { P_INV_H2, createKernelParams } from '../../src/kernels/params'

/** Kernel parameters with 1/h² set (the only scalar these kernels read). */
const params = (invH2: number) => {
  const p = createKernelParams()
  p[P_INV_H2] = invH2
  return p
}

// Hinge e0 = (0,0,0), e1 = (1,0,0); triangle A = (e0, e1, w0) faces +z when flat.
function hinge(w1Angle: number): Float64Array {
  // w1 rotated about the edge (x axis) by w1Angle from the flat position (0.5, −1, 0)
  return Float64Array.from([0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -Math.cos(w1Angle), Math.sin(w1Angle)])
}
const ids = Int32Array.from([0, 1, 2, 3])

function relax(pos: Float64Array, rest: number, w: Float64Array, side = 0, iterations = 200): void {
  const restArr = Float64Array.from([rest])
  const comp = new Float64Array(1)
  const lambda = null
  for (let i = 0; i < iterations; i++) solveDihedrals(pos, w, ids, restArr, comp, lambda, side, params(3600), 0, 1)
}

describe('dihedral angle', () => {
  it('is 0 when flat and negative when the wing folds toward the front (+z)', () => {
    expect(dihedralAngle(hinge(0), 0, 1, 2, 3)).toBeCloseTo(0, 12)
    expect(dihedralAngle(hinge(0.3), 0, 1, 2, 3)).toBeCloseTo(-0.3, 12)
    expect(dihedralAngle(hinge(-0.3), 0, 1, 2, 3)).toBeCloseTo(0.3, 12)
  })

  it('has the gradients the kernel uses (checked against finite differences)', () => {
    // one unconstrained projection with w = 1 moves each vertex by −C·∇ᵢ/Σ|∇|²; compare the
    // direction of the move with numeric gradients of the angle
    const pos = Float64Array.from([0.05, -0.02, 0.01, 1.1, 0.03, -0.04, 0.4, 1.05, 0.2, 0.62, -0.9, 0.35])
    const grad = new Float64Array(12)
    const eps = 1e-7
    for (let j = 0; j < 12; j++) {
      const p = Float64Array.from(pos), m = Float64Array.from(pos)
      p[j] += eps
      m[j] -= eps
      grad[j] = (dihedralAngle(p, 0, 1, 2, 3) - dihedralAngle(m, 0, 1, 2, 3)) / (2 * eps)
    }
    const moved = Float64Array.from(pos)
    const theta = dihedralAngle(pos, 0, 1, 2, 3)
    const restArr = Float64Array.from([theta + 1e-4]) // C = −1e-4: a tiny, linear step
    solveDihedrals(moved, Float64Array.from([1, 1, 1, 1]), ids, restArr, new Float64Array(1), null, 0, params(1), 0, 1)
    let g2 = 0
    for (let j = 0; j < 12; j++) g2 += grad[j] * grad[j]
    for (let j = 0; j < 12; j++) expect((moved[j] - pos[j]) / 1e-4).toBeCloseTo(grad[j] / g2, 4)
  })
})

describe('solveDihedrals', () => {
  const locked = Float64Array.from([0, 0, 0, 1]) // only w1 moves
  // Rest shapes from flat to folded onto itself, each disturbed in four directions (Jolt's sweep)
  for (const restDeg of [0, 45, 90, -90, 135, 179]) {
    it(`returns to a ${restDeg}° rest angle from four disturbances, finite throughout`, () => {
      const rest = (-restDeg * Math.PI) / 180
      for (const d of [[0.2, 0, 0], [-0.2, 0, 0], [0, 0.15, 0], [0, 0, -0.15]]) {
        const pos = hinge((restDeg * Math.PI) / 180)
        pos[9] += d[0]
        pos[10] += d[1]
        pos[11] += d[2]
        relax(pos, rest, locked)
        expect(pos.every(Number.isFinite)).toBe(true)
        const err = Math.abs(dihedralAngle(pos, 0, 1, 2, 3) - rest)
        expect(Math.min(err, 2 * Math.PI - err)).toBeLessThan(1e-3)
      }
    })
  }

  it('stays finite when the hinge is folded exactly flat onto itself or a triangle collapses', () => {
    const folded = Float64Array.from([0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, 1, 0]) // w1 on top of w0
    relax(folded, 0, Float64Array.from([1, 1, 1, 1]), 0, 10)
    expect(folded.every(Number.isFinite)).toBe(true)
    const collapsed = Float64Array.from([0, 0, 0, 1, 0, 0, 0.5, 0, 0, 0.5, -1, 0]) // w0 on the edge
    relax(collapsed, 0, Float64Array.from([1, 1, 1, 1]), 0, 10)
    expect(collapsed.every(Number.isFinite)).toBe(true)
    const zeroEdge = Float64Array.from([0, 0, 0, 0, 0, 0, 0.5, 1, 0, 0.5, -1, 0])
    relax(zeroEdge, 0, Float64Array.from([1, 1, 1, 1]), 0, 10)
    expect(zeroEdge.every(Number.isFinite)).toBe(true)
  })

  it('one-sided: resists folding toward the front, lets the cloth fold toward the back', () => {
    const front = hinge(0.5) // folded toward the front: θ = −0.5
    relax(front, 0, locked, -1)
    expect(dihedralAngle(front, 0, 1, 2, 3)).toBeCloseTo(0, 3)
    const back = hinge(-0.5) // folded toward the back: θ = +0.5, left alone
    const before = Float64Array.from(back)
    relax(back, 0, locked, -1)
    expect(Array.from(back)).toEqual(Array.from(before))
  })

  it('with compliance, a soft hinge moves less per step than a rigid one', () => {
    const rigid = hinge(0.5), soft = hinge(0.5)
    const restArr = Float64Array.from([0])
    solveDihedrals(rigid, locked, ids, restArr, Float64Array.from([0]), null, 0, params(3600), 0, 1)
    solveDihedrals(soft, locked, ids, restArr, Float64Array.from([1]), null, 0, params(3600), 0, 1)
    const a0 = -0.5
    expect(Math.abs(dihedralAngle(rigid, 0, 1, 2, 3))).toBeLessThan(Math.abs(dihedralAngle(soft, 0, 1, 2, 3)))
    expect(Math.abs(dihedralAngle(soft, 0, 1, 2, 3))).toBeLessThan(Math.abs(a0))
  })
})
