// A snapshot saves each tracked body once (colliders and wind zones may share one), whatever the
// number of colliders: the save marks bodies per slot (it scanned every earlier entry for each,
// quadratic in the colliders: 141 ms with 4,000; found by a hunt).
import { addEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  addBoxCollider,
  addSphereCollider,
  createCloth,
  createWindZone,
  getClothState,
  restoreClothState,
  saveClothState,
  setTransform,
  stepCloth,
} from '../src/index'
import { hashBytes, makeWorld } from './helpers'

describe('snapshot bodies', () => {
  it('each body once, in the order of its first collider or zone; the run replays byte for byte', () => {
    const world = makeWorld({ sleep: false })
    const cloth = createCloth(world, { width: 1, height: 1, resolution: 10, position: [0, 2, 0] })
    let shared = -1
    const bodies: number[] = []
    for (let i = 0; i < 300; i++) {
      const b = addEntity(world)
      setTransform(world, b, [10 + i, 0, 0])
      addBoxCollider(world, b, { halfExtents: [0.2, 0.2, 0.2] })
      bodies.push(b)
      if (i === 100) {
        shared = createWindZone(world, { shape: 'sphere', size: 3, strength: 4, direction: [1, 0, 0], position: [0, 0.5, 0] })
        addSphereCollider(world, addEntity(world), { body: shared, radius: 0.3 })
      }
    }
    addSphereCollider(world, addEntity(world), { body: shared, radius: 0.2, offset: [0.5, 0, 0] })
    addSphereCollider(world, addEntity(world), { body: bodies[7], radius: 0.2 })
    for (let f = 0; f < 30; f++) {
      setTransform(world, shared, [0.01 * f, 0.5, 0])
      stepCloth(world, 1 / 60)
    }
    const s = saveClothState(world, cloth) as unknown as { bodies: Int32Array }
    expect(Array.from(s.bodies)).toEqual([...bodies.slice(0, 101), shared, ...bodies.slice(101)])
    const run = () => {
      for (let f = 30; f < 60; f++) {
        setTransform(world, shared, [0.01 * f, 0.5, 0])
        stepCloth(world, 1 / 60)
      }
      return hashBytes(getClothState(world, cloth).pos)
    }
    const first = run()
    setTransform(world, shared, [0.29, 0.5, 0])
    restoreClothState(world, cloth, s as never)
    expect(run()).toBe(first)
  })
})
