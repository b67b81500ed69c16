// An entity that stops dead from a speed above the teleport distance per frame: that stop is no
// jump. It was taken for a jump back at every frame after, the entity's last velocity kept for good:
// a cape behind a character stopped from 130 m/s streamed out at 200 m/s, 397 % stretch, for as
// long as it stood (and with a cloth's own teleport distance of 5 cm, after an ordinary 4 m/s run).
// A frame of a huge time step while the character runs is no jump either (the jump taken as
// x − x₀ − v·span lost it to rounding: every frame after was a jump, 2,654 % stretch).
import { addEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import { getClothState, getClothStats, getClothStretch, pinRow, setClothInertia, setTransform, stepCloth } from '../../src/index'
import { capeBehind, yawQuat } from '../character/scenes'
import { makeWorld } from '../helpers'

const DT = 1 / 60

/** A cape pinned to a hero running along +z up to `speed`, standing still from frame 60 on; `teleport`: the cape's own distance (a character cloth). */
function deadStop(speed: number, world: object, teleport?: number, dt = (_f: number) => DT) {
  const hero = addEntity(world)
  setTransform(world, hero, [0, 1.6, 0])
  const cape = capeBehind(world, [8, 12], 2)
  pinRow(world, cape, 0, hero)
  if (teleport !== undefined)
    setClothInertia(world, cape, { linear: 0.5, angular: 0.5, centrifugal: 0.5, teleport: { distance: teleport } })
  let z = 0, teleports = 0, speedEnd = 0, stretchEnd = 0
  const c = getClothState(world, cape)
  for (let f = 1; f <= 240; f++) {
    const h = dt(f)
    // (reaching its speed over 30 frames: a start from rest at it is itself a jump at every frame)
    if (f < 60) z += speed * Math.min(f / 30, 1) * Math.min(h, 1e6)
    setTransform(world, hero, [0, 1.6, z], yawQuat(Math.PI))
    if (f === 60) teleports = getClothStats(world).teleports
    stepCloth(world, h)
    if (f > 180) {
      stretchEnd = Math.max(stretchEnd, getClothStretch(world, cape).max)
      for (let i = 0; i < c.count; i++) speedEnd = Math.max(speedEnd, Math.hypot(c.vel[3 * i], c.vel[3 * i + 1], c.vel[3 * i + 2]))
    }
  }
  return { teleports: getClothStats(world).teleports - teleports, speedEnd, stretchEnd }
}

describe('a dead stop is no jump', () => {
  it('from 130 m/s (2.2 m a frame, over the 2 m teleport distance): no teleport after it, the cape swings under its pins instead of streaming out', () => {
    const r = deadStop(130, makeWorld({ sleep: false }))
    expect(r.teleports).toBe(0)
    expect(r.speedEnd).toBeLessThan(3) // (still swinging from the stop; streaming, it was 200 m/s)
    expect(r.stretchEnd).toBeLessThan(0.05)
  })

  it("with a cloth's own teleport distance of 5 cm, after a 4 m/s run: no teleport, no streaming", () => {
    const r = deadStop(4, makeWorld({ sleep: false }), 0.05)
    expect(r.teleports).toBe(0)
    expect(r.speedEnd).toBeLessThan(3) // (still swinging from the stop; streaming, it was 200 m/s)
    expect(r.stretchEnd).toBeLessThan(0.05)
  })

  it('one frame of a 1e18 s time step while running at 4 m/s: no jump in the frames after', () => {
    const world = makeWorld({ sleep: false })
    const r = deadStop(4, world, undefined, (f) => (f === 30 ? 1e18 : DT))
    expect(r.teleports).toBe(0)
    expect(r.stretchEnd).toBeLessThan(0.05)
  })
})

describe('a jump that turns its entity', () => {
  // a cart at 50 m/s along +z through a portal that puts it 1 km away turned 90°, driving along +x:
  // the jump was measured against its old velocity unturned, so for a frame it went on along +z
  // while the cloth's velocities were turned: the banner's pinned row dragged, 106 % stretch
  // (49–58 % with character settings at shares 0.5)
  const portal = (turn: number, inertia: boolean) => {
    const world = makeWorld({ sleep: false })
    const cart = addEntity(world)
    setTransform(world, cart, [0, 2, 0])
    const banner = capeBehind(world, [10, 10], 2)
    pinRow(world, banner, 0, cart)
    if (inertia) setClothInertia(world, banner, { linear: 0.5, angular: 0.5, centrifugal: 0.5 })
    const c = getClothState(world, banner)
    let z = 0, x = 0, heading = 0, stretch = 0
    for (let f = 1; f <= 150; f++) {
      const v = 50 * Math.min(f / 60, 1)
      if (f === 100) {
        x = 1000
        heading = turn
      }
      if (heading === 0) z += v * DT
      else x += v * DT
      setTransform(world, cart, [x, 2, z], yawQuat(heading))
      stepCloth(world, DT)
      if (f >= 100 && f < 110) stretch = Math.max(stretch, getClothStretch(world, banner).max)
    }
    // the pinned row goes the cart's new way
    const pinned = [c.vel[0], c.vel[1], c.vel[2]]
    return { stretch, pinned }
  }
  for (const inertia of [false, true]) {
    it(`goes on at its velocity turned: the cloth as after a straight jump${inertia ? ' (character settings)' : ''}`, () => {
      const straight = portal(0, inertia), turned = portal(Math.PI / 2, inertia)
      expect(turned.stretch).toBeLessThan(straight.stretch + 0.02)
      expect(turned.pinned[0]).toBeCloseTo(50, 3)
      expect(Math.abs(turned.pinned[2])).toBeLessThan(1e-6)
    })
  }
})
