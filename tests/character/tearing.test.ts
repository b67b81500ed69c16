// Character cloth on a tearable cloth: the split particles get their reference, limits, skin
// weights and hold; nothing is allocated in the tearing steps (the arrays are reserved).
import { addEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import { LIMITS, L_MAX } from '../../src/kernels/motion'
import {
  createCloth,
  getClothReference,
  getClothStats,
  getClothState,
  getClothStretch,
  getClothTearCount,
  makeTearable,
  pinParticle,
  pinRow,
  setClothInertia,
  setClothMotionConstraints,
  setTransform,
  stepCloth,
} from '../../src/index'
import { allFinite, makeWorld } from '../helpers'
import { DT, drive, tornCapeOnGround, woolCape } from './scenes'

describe('character cloth that tears', () => {
  for (const order of ['tearable first', 'constraints first'] as const) {
    it(`a banner held by max distance 0 at its top, pulled apart at its bottom corners, tears and keeps its limits on both sides of the cut, while held at the top (${order})`, () => {
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
      // split particles come from the lower rows: they keep the limits while their piece is held at
      // the top; a piece torn off whole (held by a handle only) has none (see below)
      const held = new Set(Array.from({ length: 10 }, (_, i) => c.piece![i]))
      for (let i = n; i < c.count; i++) expect(maxOf(i)).toBe(held.has(c.piece![i]) ? 5 : Infinity)
      expect(Array.from({ length: c.count - n }, (_, q) => maxOf(n + q)).filter((m) => m === 5).length).toBeGreaterThan(0)
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

describe('a piece torn off a character cloth', () => {
  // a cape with the demo's painted max distance and a backstop, nailed to the world at its left
  // edge while its character runs off: the piece the tear frees from the character kept its
  // limits, so a triangle spanned the nail and the running character (34,657 % stretch for good)
  it('leaves its motion constraints behind: the cape tears free as it does without them', () => {
    const cols = 14, rows = 24
    const run = (limits: boolean) => {
      const world = makeWorld({ sleep: false })
      const hero = addEntity(world)
      setTransform(world, hero, [0, 0, 0])
      const cape = woolCape(world, cols, rows)
      pinRow(world, cape, 0, hero)
      setClothInertia(world, cape, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5 })
      if (limits) {
        const maxDistance = Array.from({ length: cols * rows }, (_, i) => {
          const u = Math.floor(i / cols) / (rows - 1)
          return u === 1 ? Infinity : 0.9 * u * u
        })
        setClothMotionConstraints(world, cape, { maxDistance, backstop: { distance: 0.02, radius: 0.5 } })
      }
      makeTearable(world, cape, { strain: 0.4, maxTearsPerStep: 8 })
      pinParticle(world, cape, (rows / 2) * cols) // nailed to the world
      for (let f = 0; f < 300; f++) {
        setTransform(world, hero, [0, 0, (3 * f) / 60]) // runs 15 m at 3 m/s
        stepCloth(world, DT)
      }
      const c = getClothState(world, cape)
      return { stretch: getClothStretch(world, cape).max, pieces: c.pieceCount, finite: allFinite(world, cape), c }
    }
    const free = run(false), limited = run(true)
    expect(free.pieces).toBeGreaterThan(1)
    expect(limited.pieces).toBeGreaterThan(1)
    expect(limited.finite).toBe(true)
    expect(limited.stretch).toBeLessThan(Math.max(0.25, 2 * free.stretch)) // (free: 18.8 %)
    // the nailed piece is free of limits; the collar's piece keeps its painting
    const c = limited.c, lim = c.character!.lim
    const nail = (rows / 2) * cols
    expect(c.piece![nail]).not.toBe(c.piece![cols])
    expect(lim[LIMITS * nail + L_MAX]).toBe(Infinity)
    expect(lim[LIMITS * cols + L_MAX]).toBeCloseTo(0.9 / (rows - 1) ** 2, 6)
  })
})

describe('a piece torn off a character cloth, lying on the ground', () => {
  // it moved with the character: carried 10 m by its teleport, 0.87 m by a hitch's dropped
  // motion, swung 4.4 m round it turning on the spot (inertia 0), slid 0.84 m as it sprinted
  // (inertia 0.5)
  const events: [string, number, (world: object, hero: number, z: number) => void][] = [
    ['its character teleports 10 m', 0.5, (world, hero, z) => {
      setTransform(world, hero, [10, 0, z])
      for (let f = 0; f < 30; f++) stepCloth(world, DT)
    }],
    ['its character turns 180° on the spot (inertia 0)', 0, (world, hero, z) => {
      for (let f = 1; f <= 30; f++) {
        setTransform(world, hero, [0, 0, z], [0, Math.sin((Math.PI * f) / 60), 0, Math.cos((Math.PI * f) / 60)])
        stepCloth(world, DT)
      }
    }],
    ['its character sprints 4 m (inertia 0.5)', 0.5, (world, hero, z) => {
      for (let f = 1; f <= 60; f++) {
        setTransform(world, hero, [0, 0, z + 4 * (f / 60) ** 2])
        stepCloth(world, DT)
      }
    }],
    ['a 0.5 s hitch while its character walks on', 0.5, (world, hero, z) => {
      setTransform(world, hero, [0, 0, z + 1])
      stepCloth(world, 0.5)
      for (let f = 0; f < 10; f++) stepCloth(world, DT)
    }],
  ]
  for (const [name, inertia, event] of events) {
    it(`stays where it lies when ${name}`, () => {
      const s = tornCapeOnGround(inertia)
      expect(s.off.length).toBeGreaterThan(0)
      const before = s.at(s.off)
      event(s.world, s.hero, s.z)
      expect(Math.max(...s.moved(s.off, before))).toBeLessThan(0.02)
    })
  }
  it("stays where it lies when its character teleports 10 m with teleport mode 'reset', while the cape goes onto its reference", () => {
    const s = tornCapeOnGround(0.5)
    setClothInertia(s.world, s.cape, { frame: s.hero, linear: 0.5, angular: 0.5, centrifugal: 0.5, teleport: { mode: 'reset' } })
    expect(s.c.detached[0]).toBeGreaterThan(0)
    const off = s.at(s.off), on = s.at(s.on)
    setTransform(s.world, s.hero, [0, 0, s.z + 10])
    stepCloth(s.world, DT)
    // (all 38 were put on the cape's reference pose 10 m away: moved up to 11.8 m)
    expect(Math.max(...s.moved(s.off, off))).toBeLessThan(0.02)
    // the piece still on the collar went with the character: 10 m along z
    const carried = s.at(s.on).map((p, q) => p[2] - on[q][2])
    expect(Math.min(...carried)).toBeGreaterThan(9)
    expect(getClothStats(s.world).guardResets).toBe(0)
  })
})
