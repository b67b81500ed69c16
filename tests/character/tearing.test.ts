// Character cloth on a tearable cloth: the split particles get their reference, limits, skin
// weights and hold; nothing is allocated in the tearing steps (the arrays are reserved).
import { addEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import { LIMITS, L_MAX } from '../../src/kernels/motion'
import {
  createCloth,
  getClothReference,
  getClothState,
  getClothTearCount,
  makeTearable,
  pinParticle,
  setClothInertia,
  setClothMotionConstraints,
  setTransform,
  stepCloth,
} from '../../src/index'
import { allFinite, makeWorld } from '../helpers'
import { DT, drive } from './scenes'

describe('character cloth that tears', () => {
  for (const order of ['tearable first', 'constraints first'] as const) {
    it(`a banner held by max distance 0 at its top, pulled apart at its bottom corners, tears and keeps its limits on both sides (${order})`, () => {
      const world = makeWorld({ sleep: false })
      const pole = addEntity(world)
      setTransform(world, pole, [0, 2, 0])
      const banner = createCloth(world, { width: 1, height: 1, resolution: 10, position: [0, 1.5, 0] })
      const n = 100
      const md = Array.from({ length: n }, (_, i) => (i < 10 ? 0 : 5))
      const configure = () => {
        setClothInertia(world, banner, { frame: pole, linear: 0.5 })
        setClothMotionConstraints(world, banner, { maxDistance: md, backstop: { distance: 0.05, radius: 1 } })
      }
      if (order === 'constraints first') configure()
      makeTearable(world, banner, { strain: 0.2, maxTearsPerStep: 2 })
      if (order === 'tearable first') configure()
      const c = getClothState(world, banner)
      // the bottom corners pinned to two handles dragged apart
      const handles = [addEntity(world), addEntity(world)]
      for (const h of handles) setTransform(world, h, [0, 0, 0])
      pinParticle(world, banner, 90, handles[0])
      pinParticle(world, banner, 99, handles[1])
      for (let f = 1; f <= 120; f++) {
        setTransform(world, handles[0], [-0.01 * f, 0, 0])
        setTransform(world, handles[1], [0.01 * f, 0, 0])
        stepCloth(world, DT)
      }
      expect(getClothTearCount(world, banner)).toBeGreaterThan(0)
      expect(c.count).toBeGreaterThan(n)
      const ch = c.character!
      const maxOf = (i: number) => ch.lim[LIMITS * i + L_MAX]
      expect(ch.lim.length).toBeGreaterThanOrEqual(LIMITS * c.count)
      for (let i = n; i < c.count; i++) expect(maxOf(i)).toBe(5) // split particles come from the lower rows
      drive(world, pole, (t) => ({ p: [t, 2, 0], yaw: t }), 1)
      const ref = getClothReference(world, banner)!
      for (let i = 0; i < c.count; i++) {
        const d = Math.hypot(c.pos[3 * i] - ref[3 * i], c.pos[3 * i + 1] - ref[3 * i + 1], c.pos[3 * i + 2] - ref[3 * i + 2])
        expect(d).toBeLessThan(maxOf(i) + 0.002)
      }
      expect(allFinite(world, banner)).toBe(true)
    })
  }
})
