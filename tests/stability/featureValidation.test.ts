// Input validation of the collider, wind and self-collision APIs at the far end of the number
// line: huge but finite sizes and speeds are refused (ClothError naming the argument). Accepted,
// a plane distance, sphere radius, wind strength, turbulence, gust or air density of 1e308
// overflowed to Infinity inside a step and put NaN into the cloth (the fuzz property in
// properties.test.ts found the first two); the other sizes are bounded alike, at ±1e9 m as
// positions are.
import { addEntity, createWorld } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  ClothError,
  addBoxCollider,
  addCapsuleCollider,
  addConvexHullCollider,
  addPlaneCollider,
  addSphereCollider,
  createWindZone,
  enableSelfCollision,
  getClothState,
  gustWind,
  installClothPlugin,
  setClothCollision,
  setTransform,
  setWindZone,
  stepCloth,
} from '../../src/index'
import { hangingSheet } from './harness'

function scene() {
  const world = installClothPlugin(createWorld(), { guard: false })
  const sheet = hangingSheet(world)
  const e = addEntity(world)
  setTransform(world, e, [0, 1, 0])
  return { world, sheet, e }
}

describe('huge but finite inputs', () => {
  const cases: [string, (w: object, sheet: number, e: number) => void, string][] = [
    ['plane distance 1e308', (w, _s, e) => addPlaneCollider(w, e, { distance: 1e308 }), 'options.distance'],
    ['sphere radius 1e308', (w, _s, e) => addSphereCollider(w, e, { radius: 1e308 }), 'options.radius'],
    ['capsule half-height 1e308', (w, _s, e) => addCapsuleCollider(w, e, { radius: 0.1, halfHeight: 1e308 }), 'options.halfHeight'],
    ['box half-extents 1e308', (w, _s, e) => addBoxCollider(w, e, { halfExtents: [1, 1e308, 1] }), 'options.halfExtents'],
    [
      'hull point 1e308',
      (w, _s, e) => addConvexHullCollider(w, e, { points: [0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1e308] }),
      'options.points[11]',
    ],
    ['collider offset 1e308', (w, _s, e) => addSphereCollider(w, e, { radius: 0.1, offset: [0, 1e308, 0] }), 'options.offset'],
    ['wind strength 1e308', (w) => createWindZone(w, { direction: [1, 0, 0], strength: 1e308 }), 'options.strength'],
    ['wind strength 1e100', (w) => createWindZone(w, { direction: [1, 0, 0], strength: 1e100 }), 'options.strength'],
    ['wind turbulence 1e308', (w) => createWindZone(w, { direction: [1, 0, 0], strength: 10, turbulence: 1e308 }), 'options.turbulence'],
    [
      'wind turbulence scale 1e-300',
      (w) => createWindZone(w, { direction: [1, 0, 0], strength: 10, turbulence: 0.3, turbulenceScale: 1e-300 }),
      'options.turbulenceScale',
    ],
    [
      'zone size 1e308',
      (w) => createWindZone(w, { shape: 'box', direction: [1, 0, 0], strength: 10, size: [1, 1e308, 1] }),
      'options.size',
    ],
    ['gust 1e308', (w) => gustWind(w, createWindZone(w, { direction: [1, 0, 0], strength: 1 }), { strength: 1e308 }), 'options.strength'],
    [
      'zone strength set to 1e308',
      (w) => setWindZone(w, createWindZone(w, { direction: [1, 0, 0], strength: 1 }), { strength: 1e308 }),
      'options.strength',
    ],
    ['air density 1e308', (w) => createWindZone(w, { direction: [1, 0, 0], strength: 1, airDensity: 1e308 }), 'options.airDensity'],
    ['collision thickness 1e308', (w, s) => setClothCollision(w, s, { thickness: 1e308 }), 'options.thickness'],
    ['self-collision thickness 1e308', (w, s) => enableSelfCollision(w, s, { thickness: 1e308 }), 'options.thickness'],
  ]
  for (const [name, call, argument] of cases) {
    it(`${name}: ClothError naming ${argument}; the cloth stays finite`, () => {
      const { world, sheet, e } = scene()
      let error: unknown
      try {
        call(world, sheet, e)
      } catch (err) {
        error = err
      }
      expect(error).toBeInstanceOf(ClothError)
      expect((error as ClothError).argument).toBe(argument)
      for (let f = 0; f < 10; f++) stepCloth(world, 1 / 60)
      expect(getClothState(world, sheet).pos.every(Number.isFinite)).toBe(true)
    })
  }

  it('the largest accepted values still give finite cloth (1e9 m sizes, 1e6 m/s wind with turbulence 100)', () => {
    const { world, sheet, e } = scene()
    addSphereCollider(world, e, { radius: 0.1, offset: [0, 0, 1e9] })
    const p = addEntity(world)
    setTransform(world, p, [0, 0, 0])
    addPlaneCollider(world, p, { distance: -1e9 })
    const z = createWindZone(world, { direction: [1, 0.3, 0.2], strength: 1e6, turbulence: 100, turbulenceScale: 1e-3 })
    gustWind(world, z, { strength: 1e6 })
    for (let f = 0; f < 60; f++) stepCloth(world, 1 / 60)
    expect(getClothState(world, sheet).pos.every(Number.isFinite)).toBe(true)
  })
})
