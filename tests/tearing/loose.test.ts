import { describe, expect, it } from 'vitest'
import { pinParticle, setTransform, stepCloth, teleportCloth } from '../../src/index'
import { DT, tornCapeOnGround } from '../character/scenes'
import { allFinite } from '../helpers'

describe('a piece torn off a cloth pinned to an entity, lying on the ground', () => {
  const torn = () => tornCapeOnGround(null)
  const events: [string, (world: object, hero: number, z: number) => void][] = [
    ['its pin target teleports 10 m', (world, hero, z) => {
      setTransform(world, hero, [10, 0, z])
      for (let f = 0; f < 30; f++) stepCloth(world, DT)
    }],
    ['a 0.5 s hitch while its pin target walks on', (world, hero, z) => {
      setTransform(world, hero, [0, 0, z + 1])
      stepCloth(world, 0.5)
      for (let f = 0; f < 10; f++) stepCloth(world, DT)
    }],
  ]
  for (const [name, event] of events) {
    it(`stays where it lies when ${name}, while the pinned piece goes along`, () => {
      const s = torn()
      expect(s.off.length).toBeGreaterThan(0)
      const before = s.at(s.off), pinnedBefore = s.at(s.on)
      event(s.world, s.hero, s.z)
      expect(Math.max(...s.moved(s.off, before))).toBeLessThan(0.02)
      // the piece the pins hold went with them (its collar row by the whole motion)
      const collar = s.moved(s.on, pinnedBefore).slice(0, s.cols)
      expect(Math.min(...collar)).toBeGreaterThan(0.9)
      expect(allFinite(s.world, s.cape)).toBe(true)
    })
  }
  it('goes along with teleportCloth, which moves the whole cloth', () => {
    const s = torn()
    const before = s.at(s.off)
    teleportCloth(s.world, s.cape, [10, 0, 0])
    for (const d of s.moved(s.off, before)) expect(d).toBeCloseTo(10, 6)
  })
  it('is carried again once a pin on an entity holds it', () => {
    const s = torn()
    pinParticle(s.world, s.cape, s.off[0], s.hero)
    expect(s.c.detached[0]).toBe(0)
    const before = s.at(s.off)
    setTransform(s.world, s.hero, [10, 0, s.z])
    stepCloth(s.world, DT)
    expect(Math.min(...s.moved(s.off, before))).toBeGreaterThan(9)
  })
})
