// Pieces torn off a cloth with no character settings, pinned to an entity: the automatic rigid
// carries of that entity's motion (a teleport, a hitch's dropped motion) move only the pieces its
// pins hold. A piece torn off and lying on the ground had jumped 10 m with its pole's teleport.
import { addEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  addPlaneCollider,
  getClothState,
  makeTearable,
  pinParticle,
  pinRow,
  setTransform,
  stepCloth,
  teleportCloth,
  unpin,
} from '../../src/index'
import { DT, woolCape } from '../character/scenes'
import { allFinite, makeWorld } from '../helpers'

describe('a piece torn off a cloth pinned to an entity, lying on the ground', () => {
  const cols = 14, rows = 24
  const torn = () => {
    const world = makeWorld({ sleep: false })
    const hero = addEntity(world)
    setTransform(world, hero, [0, 0, 0])
    const ground = addEntity(world)
    setTransform(world, ground, [0, 0, 0])
    addPlaneCollider(world, ground)
    const cape = woolCape(world, cols, rows)
    pinRow(world, cape, 0, hero)
    makeTearable(world, cape, { strain: 0.4, maxTearsPerStep: 8 })
    const nail = pinParticle(world, cape, (rows / 2) * cols)
    for (let f = 0; f < 60; f++) { // walks 2 m away, tearing the nailed part off
      setTransform(world, hero, [0, 0, (2 * f) / 60])
      stepCloth(world, DT)
    }
    unpin(world, nail)
    for (let f = 0; f < 120; f++) stepCloth(world, DT) // the piece falls and settles
    const c = getClothState(world, cape)
    const off: number[] = [], on: number[] = []
    for (let i = 0; i < c.count; i++) (c.piece![i] !== c.piece![0] ? off : on).push(i)
    const at = (list: number[]) => list.map((i) => [c.pos[3 * i], c.pos[3 * i + 1], c.pos[3 * i + 2]])
    const moved = (list: number[], before: number[][]) =>
      at(list).map((p, q) => Math.hypot(p[0] - before[q][0], p[1] - before[q][1], p[2] - before[q][2]))
    return { world, hero, cape, c, off, on, at, moved, z: (2 * 59) / 60 }
  }
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
      const collar = s.moved(s.on, pinnedBefore).slice(0, cols)
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
