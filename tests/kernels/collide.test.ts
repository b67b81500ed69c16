import { fc, test } from '@fast-check/vitest'
import { describe, expect, it } from 'vitest'
import { SHAPE_BOX, SHAPE_CAPSULE, SHAPE_HULL, SHAPE_PLANE, SHAPE_SPHERE } from '../../components/Collider'
import { ClothError } from '../../src/core/errors'
import { buildConvexHull } from '../../src/model/hull'
import { collideBox, collideCapsule, collideHull, collidePlane, collideSphere } from '../../src/kernels/collide'
import {
  COLLIDE_SCRATCH,
  FRAME_SIZE,
  F_BC,
  F_LIM2,
  F_M,
  F_MU_K,
  F_MU_S,
  F_PC,
  F_PE,
  F_PN,
  F_PS,
  F_RADIUS,
  F_RE,
  F_RS,
  F_S0,
  F_SW,
  F_SWR,
  closestPoint,
  segmentHits,
} from '../../src/kernels/colliderFrame'

/** A frame for a collider with identity rotation moving from `from` to `to` during the substep. */
function frame(size: number[], r: number, from = [0, 0, 0], to = from, muS = 0, muK = 0, lim2 = Infinity, bound = 10) {
  const f = new Float64Array(FRAME_SIZE)
  for (let k = 0; k < 3; k++) {
    f[F_PS + k] = from[k]
    f[F_PE + k] = to[k]
  }
  for (const o of [F_RS, F_RE, F_M]) {
    f[o] = 1
    f[o + 4] = 1
    f[o + 8] = 1
  }
  for (let k = 0; k < size.length; k++) f[F_S0 + k] = size[k]
  f[F_RADIUS] = r
  f[F_MU_S] = muS
  f[F_MU_K] = muK
  f[F_LIM2] = lim2
  f[F_BC + 3] = bound
  f[F_SWR] = Infinity // no world bound: every fast particle goes through the frame's own test
  return f
}

const scratch = () => new Float64Array(COLLIDE_SCRATCH)

/** closestPoint for a local point: [point, normal, distance]. */
function closest(shape: number, f: Float64Array, p: number[], planes: Float64Array | null = null, count = 0) {
  const s = scratch()
  s[0] = p[0]
  s[1] = p[1]
  s[2] = p[2]
  closestPoint(shape, f, planes, count, s)
  return { q: [s[3], s[4], s[5]], n: [s[6], s[7], s[8]], d: s[9] }
}

function expectVec(a: number[], b: number[], digits = 12) {
  for (let k = 0; k < 3; k++) expect(a[k]).toBeCloseTo(b[k], digits)
}

/** One particle at `x` that was at `prev` at the start of the substep. */
function particle(x: number[], prev = x) {
  return { pos: Float64Array.from(x), prev: Float64Array.from(prev), w: Float64Array.from([1]) }
}

describe('collider distances and normals', () => {
  it('sphere: distance to the surface along the radius, inside negative', () => {
    const f = frame([0.5], 0)
    let c = closest(SHAPE_SPHERE, f, [0, 0, 2])
    expect(c.d).toBeCloseTo(1.5, 12)
    expectVec(c.n, [0, 0, 1])
    expectVec(c.q, [0, 0, 0.5])
    c = closest(SHAPE_SPHERE, f, [0.3, 0, 0])
    expect(c.d).toBeCloseTo(-0.2, 12)
    expectVec(c.n, [1, 0, 0])
    c = closest(SHAPE_SPHERE, f, [0, 0, 0]) // the centre: a fixed normal, no NaN
    expect(c.d).toBeCloseTo(-0.5, 12)
    expectVec(c.n, [0, 1, 0])
  })

  it('capsule: side and caps along local y', () => {
    const f = frame([0.2, 0.5], 0)
    let c = closest(SHAPE_CAPSULE, f, [1, 0.3, 0])
    expect(c.d).toBeCloseTo(0.8, 12)
    expectVec(c.n, [1, 0, 0])
    expectVec(c.q, [0.2, 0.3, 0])
    c = closest(SHAPE_CAPSULE, f, [0, 1, 0])
    expect(c.d).toBeCloseTo(0.3, 12)
    expectVec(c.n, [0, 1, 0])
    c = closest(SHAPE_CAPSULE, f, [0, -0.5, 0.1])
    expect(c.d).toBeCloseTo(-0.1, 12)
    expectVec(c.n, [0, 0, 1])
    c = closest(SHAPE_CAPSULE, f, [0, 0.2, 0]) // on the axis: a normal across it
    expect(c.d).toBeCloseTo(-0.2, 12)
    expect(c.n[1]).toBe(0)
  })

  it('box: faces, edges and corners outside; the nearest face inside', () => {
    const f = frame([1, 2, 3], 0)
    let c = closest(SHAPE_BOX, f, [1.5, 0, 0])
    expect(c.d).toBeCloseTo(0.5, 12)
    expectVec(c.n, [1, 0, 0])
    c = closest(SHAPE_BOX, f, [2, 3, 0]) // edge
    expect(c.d).toBeCloseTo(Math.SQRT2, 12)
    expectVec(c.n, [Math.SQRT1_2, Math.SQRT1_2, 0])
    c = closest(SHAPE_BOX, f, [2, 3, 4]) // corner
    expect(c.d).toBeCloseTo(Math.sqrt(3), 12)
    c = closest(SHAPE_BOX, f, [0.2, -1.9, 0]) // inside, 0.1 from the bottom face
    expect(c.d).toBeCloseTo(-0.1, 12)
    expectVec(c.n, [0, -1, 0])
    expectVec(c.q, [0.2, -2, 0])
  })

  it('hull: the largest face-plane distance (exact inside and off a face)', () => {
    const hull = buildConvexHull([-1, -1, -1, 1, -1, -1, -1, 1, -1, 1, 1, -1, -1, -1, 1, 1, -1, 1, -1, 1, 1, 1, 1, 1])
    expect(hull.planeCount).toBe(6)
    const f = frame([], 0)
    let c = closest(SHAPE_HULL, f, [0, 0, 1.25], hull.planes, hull.planeCount)
    expect(c.d).toBeCloseTo(0.25, 12)
    expectVec(c.n, [0, 0, 1])
    c = closest(SHAPE_HULL, f, [0.9, 0, 0], hull.planes, hull.planeCount)
    expect(c.d).toBeCloseTo(-0.1, 12)
    expectVec(c.n, [1, 0, 0])
    // every hull plane has every input point behind it
    for (let k = 0; k < hull.planeCount; k++) {
      for (let v = 0; v < hull.vertices.length; v += 3) {
        const d = hull.planes[4 * k] * hull.vertices[v] + hull.planes[4 * k + 1] * hull.vertices[v + 1] +
          hull.planes[4 * k + 2] * hull.vertices[v + 2] - hull.planes[4 * k + 3]
        expect(d).toBeLessThan(1e-9)
      }
    }
  })

  it('plane: height along the normal above the offset plane', () => {
    const f = frame([0, 0, 1, 0.5], 0)
    const c = closest(SHAPE_PLANE, f, [3, 4, 2])
    expect(c.d).toBeCloseTo(1.5, 12)
    expectVec(c.n, [0, 0, 1])
    expectVec(c.q, [3, 4, 0.5])
  })
})

describe('contact response', () => {
  it('pushes a particle out to the surface plus the thickness, along the normal', () => {
    const r = 0.01
    const cases: [string, (p: ReturnType<typeof particle>, f: Float64Array) => number, number[], number[]][] = [
      ['sphere', (p, f) => collideSphere(p.pos, p.prev, p.w, 1, f, scratch()), [0.5], [0, 0.45, 0]],
      ['capsule', (p, f) => collideCapsule(p.pos, p.prev, p.w, 1, f, scratch()), [0.5, 1], [0, 0.8, 0.45]],
      ['box', (p, f) => collideBox(p.pos, p.prev, p.w, 1, f, scratch()), [1, 1, 0.5], [0.2, 0.3, 0.45]],
    ]
    for (const [, run, size, at] of cases) {
      const p = particle(at)
      const f = frame(size, r)
      expect(run(p, f)).toBe(1)
      expect(Math.hypot(p.pos[0] - at[0], p.pos[1] - at[1], p.pos[2] - at[2])).toBeCloseTo(0.05 + r, 12)
    }
    // a particle already farther than the thickness is left alone
    const far = particle([0, 0.52, 0])
    expect(collideSphere(far.pos, far.prev, far.w, 1, frame([0.5], r), scratch())).toBe(0)
    expect(far.pos[1]).toBe(0.52)
  })

  it('never moves a particle with inverse mass 0', () => {
    const p = particle([0, 0, 0])
    p.w[0] = 0
    const f = frame([0, 1, 0, 0], 0.01)
    f[F_PN + 1] = 1
    expect(collidePlane(p.pos, p.prev, p.w, 1, f, scratch())).toBe(0)
    expect(p.pos[1]).toBe(0)
  })

  it('turns only the approach into a velocity change: an old penetration is resolved with prev moved along', () => {
    const f = frame([0, 1, 0, 0], 0.01)
    f[F_PN + 1] = 1
    f[F_PC] = 0
    // started 5 cm inside and stayed there: pushed out, but no separating velocity
    const old = particle([0, -0.05, 0], [0, -0.05, 0])
    collidePlane(old.pos, old.prev, old.w, 1, f, scratch())
    expect(old.pos[1]).toBeCloseTo(0.01, 12)
    expect(old.pos[1] - old.prev[1]).toBeCloseTo(0, 12)
    // came from above: it stops at the surface (v_n = 0), prev untouched
    const hit = particle([0, -0.05, 0], [0, 0.2, 0])
    collidePlane(hit.pos, hit.prev, hit.w, 1, f, scratch())
    expect(hit.pos[1]).toBeCloseTo(0.01, 12)
    expect(hit.prev[1]).toBe(0.2)
  })

  it('Coulomb friction: a slip within μs × the normal correction is undone, a larger one reduced by μk × it', () => {
    const f = frame([0, 1, 0, 0], 0, [0, 0, 0], [0, 0, 0], 0.5, 0.4)
    f[F_PN + 1] = 1
    // normal correction 0.1; tangential slip 0.04 < 0.5·0.1: sticks where it started
    const stick = particle([0.04, -0.1, 0], [0, 0, 0])
    collidePlane(stick.pos, stick.prev, stick.w, 1, f, scratch())
    expectVec(Array.from(stick.pos), [0, 0, 0])
    // slip 0.2 > 0.05: kinetic, the slip shrinks by μk·0.1 = 0.04
    const slide = particle([0.2, -0.1, 0], [0, 0, 0])
    collidePlane(slide.pos, slide.prev, slide.w, 1, f, scratch())
    expectVec(Array.from(slide.pos), [0.16, 0, 0])
  })

  it('friction is measured against the moving surface: static friction carries the particle along', () => {
    // the box's top moves +x by 0.005 this substep; the particle (pressed in by 0.01) did not move
    // sideways: its slip relative to the surface is within μs·0.01 = 0.006, so it moves with it
    const f = frame([1, 1, 1], 0, [0, 0, 0], [0.005, 0, 0], 0.6, 0.6)
    const p = particle([0, 0.99, 0], [0, 1, 0])
    collideBox(p.pos, p.prev, p.w, 1, f, scratch())
    expectVec(Array.from(p.pos), [0.005, 1, 0])
    // a faster surface (0.03) drags it by μk·0.01 = 0.006 only
    const fast = particle([0, 0.99, 0], [0, 1, 0])
    collideBox(fast.pos, fast.prev, fast.w, 1, frame([1, 1, 1], 0, [0, 0, 0], [0.03, 0, 0], 0.6, 0.6), scratch())
    expectVec(Array.from(fast.pos), [0.006, 1, 0])
    // without friction it stays behind
    const g = frame([1, 1, 1], 0, [0, 0, 0], [0.005, 0, 0])
    const q = particle([0, 0.99, 0], [0, 1, 0])
    collideBox(q.pos, q.prev, q.w, 1, g, scratch())
    expectVec(Array.from(q.pos), [0, 1, 0])
  })

  it('a particle (or collider) moving through a shape within one substep stays on the side it came from', () => {
    const r = 0.01
    // the particle crosses a sphere of radius 0.3 from z = −1 to z = +1 in one substep
    const p = particle([0, 0, 1], [0, 0, -1])
    expect(collideSphere(p.pos, p.prev, p.w, 1, frame([0.3], r, [0, 0, 0], [0, 0, 0], 0, 0, 0.01, 0.3), scratch())).toBe(1)
    expect(p.pos[2]).toBeCloseTo(-0.31, 12)
    // the same crossing when only the closest point is tested ends on the far side
    const q = particle([0, 0, 0.1], [0, 0, -1])
    collideSphere(q.pos, q.prev, q.w, 1, frame([0.3], r), scratch())
    expect(q.pos[2]).toBeGreaterThan(0.3)
    // a box moving 1 m in z through a resting particle pushes it ahead
    const b = particle([0, 0, 0.5], [0, 0, 0.5])
    expect(collideBox(b.pos, b.prev, b.w, 1, frame([0.3, 0.3, 0.05], r, [0, 0, 0], [0, 0, 1], 0, 0, -1, 0.5), scratch())).toBe(1)
    expect(b.pos[2]).toBeCloseTo(1.06, 12)
    // a hull too
    const hull = buildConvexHull([
      -1,
      -1,
      -0.05,
      1,
      -1,
      -0.05,
      -1,
      1,
      -0.05,
      1,
      1,
      -0.05,
      -1,
      -1,
      0.05,
      1,
      -1,
      0.05,
      -1,
      1,
      0.05,
      1,
      1,
      0.05,
    ])
    const h = particle([0, 0, 0.5], [0, 0, 0.5])
    expect(collideHull(h.pos, h.prev, h.w, 1, frame([], r, [0, 0, 0], [0, 0, 1], 0, 0, -1, 1.5), hull.planes, hull.planeCount, scratch()))
      .toBe(1)
    expect(h.pos[2]).toBeCloseTo(1.06, 12)
    // a particle passing well beside a fast capsule is not touched
    const side = particle([0.5, 0, 0.5], [0.5, 0, 0.5])
    expect(collideCapsule(side.pos, side.prev, side.w, 1, frame([0.1, 0.2], r, [0, 0, 0], [0, 0, 1], 0, 0, -1, 0.3), scratch())).toBe(0)
    expect(side.pos[0]).toBe(0.5)
  })

  it('segment tests: capsule and box, hits and misses', () => {
    const s = scratch()
    const seg = (a: number[], b: number[]) => {
      s[14] = a[0]
      s[15] = a[1]
      s[16] = a[2]
      s[17] = b[0]
      s[18] = b[1]
      s[19] = b[2]
    }
    const cap = frame([0.1, 0.5], 0.01)
    seg([-1, 0.4, 0], [1, 0.4, 0])
    expect(segmentHits(SHAPE_CAPSULE, cap, null, 0, s)).toBe(1)
    seg([-1, 0.7, 0], [1, 0.7, 0]) // above the top cap (0.5 + 0.1 + 0.01)
    expect(segmentHits(SHAPE_CAPSULE, cap, null, 0, s)).toBe(0)
    seg([-1, 0.6, 0], [1, 0.6, 0]) // grazes the top cap
    expect(segmentHits(SHAPE_CAPSULE, cap, null, 0, s)).toBe(1)
    seg([0.2, -1, 0], [0.2, 1, 0]) // parallel to the axis, outside
    expect(segmentHits(SHAPE_CAPSULE, cap, null, 0, s)).toBe(0)
    seg([-1, 0, 0.3], [-0.5, 0, 0.3])
    expect(segmentHits(SHAPE_CAPSULE, cap, null, 0, s)).toBe(0)
    const box = frame([0.5, 0.5, 0.5], 0)
    seg([-1, 0.4, 0], [1, 0.4, 0])
    expect(segmentHits(SHAPE_BOX, box, null, 0, s)).toBe(1)
    seg([-1, 0.6, 0], [1, 0.6, 0])
    expect(segmentHits(SHAPE_BOX, box, null, 0, s)).toBe(0)
    seg([-1, -1, 0], [-0.6, 0, 0])
    expect(segmentHits(SHAPE_BOX, box, null, 0, s)).toBe(0)
  })
})

describe('properties', () => {
  const coord = fc.double({ min: -2, max: 2, noNaN: true })
  const point = fc.tuple(coord, coord, coord)

  test.prop([point, point, fc.double({ min: 0, max: 0.05, noNaN: true })], { numRuns: 300 })(
    'after a contact pass every particle is at least the thickness outside sphere, capsule and box (exact distances)',
    (p, motion, r) => {
      const cases: [number[], (q: ReturnType<typeof particle>, f: Float64Array) => void, (x: number, y: number, z: number) => number][] = [
        [[0.5], (q, f) => collideSphere(q.pos, q.prev, q.w, 1, f, scratch()), (x, y, z) => Math.hypot(x, y, z) - 0.5],
        [
          [0.3, 0.6],
          (q, f) => collideCapsule(q.pos, q.prev, q.w, 1, f, scratch()),
          (x, y, z) => Math.hypot(x, y - Math.max(-0.6, Math.min(0.6, y)), z) - 0.3,
        ],
        [[0.7, 0.4, 0.2], (q, f) => collideBox(q.pos, q.prev, q.w, 1, f, scratch()), (x, y, z) => {
          const qx = Math.abs(x) - 0.7, qy = Math.abs(y) - 0.4, qz = Math.abs(z) - 0.2
          return Math.hypot(Math.max(qx, 0), Math.max(qy, 0), Math.max(qz, 0)) + Math.min(Math.max(qx, qy, qz), 0)
        }],
      ]
      for (const [size, run, sdf] of cases) {
        // the particle arrives at p from p − motion/10 (slow: the closest-point path) ...
        const q = particle(p, [p[0] - motion[0] / 10, p[1] - motion[1] / 10, p[2] - motion[2] / 10])
        run(q, frame(size, r, [0, 0, 0], [0, 0, 0], 0.5, 0.4))
        expect(sdf(q.pos[0], q.pos[1], q.pos[2])).toBeGreaterThanOrEqual(r - 1e-9)
        // ... or from anywhere within 2 m, with every particle swept
        const s = particle(p, motion)
        run(s, frame(size, r, [0, 0, 0], [0, 0, 0], 0.5, 0.4, -1, 1))
        expect(Number.isFinite(s.pos[0] + s.pos[1] + s.pos[2])).toBe(true)
        expect(sdf(s.pos[0], s.pos[1], s.pos[2])).toBeGreaterThanOrEqual(r - 1e-9)
      }
    },
  )

  test.prop([fc.array(point, { minLength: 1, maxLength: 30 }), point, point, fc.double({ min: 0.001, max: 0.05, noNaN: true })], {
    numRuns: 200,
  })(
    'the world-space bound in front of the swept test skips only particles the swept test would leave alone',
    (ends, from, to, r) => {
      const shapes: [number[], number, (pos: Float64Array, prev: Float64Array, w: Float64Array, n: number, f: Float64Array) => number][] = [
        [[0.5], 0.5, (pos, prev, w, n, f) => collideSphere(pos, prev, w, n, f, scratch())],
        [[0.3, 0.6], 0.9, (pos, prev, w, n, f) => collideCapsule(pos, prev, w, n, f, scratch())],
        [[0.7, 0.4, 0.2], Math.hypot(0.7, 0.4, 0.2), (pos, prev, w, n, f) => collideBox(pos, prev, w, n, f, scratch())],
      ]
      for (const [size, bound, run] of shapes) {
        // a collider translating from `from` to `to` in one substep, every particle swept; the
        // particles end at `ends` and started 1 m to the side
        const pos = Float64Array.from(ends.flat()), prev = pos.map((x, i) => (i % 3 === 0 ? x - 1 : x))
        const w = new Float64Array(ends.length).fill(1)
        const open = frame(size, r, from, to, 0.5, 0.4, -1, bound)
        const bounded = frame(size, r, from, to, 0.5, 0.4, -1, bound)
        for (let k = 0; k < 3; k++) bounded[F_SW + k] = to[k]
        bounded[F_SWR] = bound + r + Math.hypot(to[0] - from[0], to[1] - from[1], to[2] - from[2])
        const a = { pos: pos.slice(), prev: prev.slice() }, b = { pos: pos.slice(), prev: prev.slice() }
        expect(run(b.pos, b.prev, w, ends.length, bounded)).toBe(run(a.pos, a.prev, w, ends.length, open))
        expect([...b.pos, ...b.prev]).toEqual([...a.pos, ...a.prev])
      }
    },
  )

  test.prop([fc.array(point, { minLength: 4, maxLength: 60 })], { numRuns: 100 })(
    'a convex hull keeps every input point behind each of its planes, and each plane touches the hull',
    (pts) => {
      let hull
      try {
        hull = buildConvexHull(pts.flat())
      } catch (e) {
        expect(e).toBeInstanceOf(ClothError) // coplanar or coincident points, rejected with a clear error
        return
      }
      for (let k = 0; k < hull.planeCount; k++) {
        const [nx, ny, nz, d] = [hull.planes[4 * k], hull.planes[4 * k + 1], hull.planes[4 * k + 2], hull.planes[4 * k + 3]]
        let touching = 0
        for (const [x, y, z] of pts) {
          const e = nx * x + ny * y + nz * z - d
          expect(e).toBeLessThan(1e-7)
          if (e > -1e-7) touching++
        }
        expect(touching).toBeGreaterThanOrEqual(3)
      }
    },
  )
})
