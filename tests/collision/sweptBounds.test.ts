// Colliders at rest keep the swept bounds they had at rest (`sweepColliders`): at every step of a
// life of rest, motion, stops, scale changes, teleports, a restored cloth, and removal and re-adding
// on the same entity with another size, each collider's bounds are what computing them afresh gives.
import { addEntity, removeEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  addBoxCollider,
  addCapsuleCollider,
  addPlaneCollider,
  addSphereCollider,
  createCloth,
  removeCollider,
  restoreClothState,
  saveClothState,
  setTransform,
  stepCloth,
} from '../../src/index'
import { sweepColliderBounds } from '../../src/features/collision/colliders'
import { getClothWorld } from '../../src/world/access'
import { makeWorld } from '../helpers'

describe('swept collider bounds', () => {
  it('are at every step what computing them afresh gives, colliders at rest or not', () => {
    const world = makeWorld({ sleep: false })
    const state = getClothWorld(world)
    const cloth = createCloth(world, { width: 1, height: 1, resolution: 6, position: [0, 1, 0] })
    const bodies = [addEntity(world), addEntity(world), addEntity(world), addEntity(world)]
    bodies.forEach((b, i) => setTransform(world, b, [i, 0.5, 0]))
    const colliders = [addEntity(world), addEntity(world), addEntity(world), addEntity(world)]
    addSphereCollider(world, colliders[0], { body: bodies[0], radius: 0.3 })
    addCapsuleCollider(world, colliders[1], { body: bodies[1], radius: 0.1, halfHeight: 0.4, offset: [0, 0.2, 0] })
    addBoxCollider(world, colliders[2], { body: bodies[2], halfExtents: [0.2, 0.3, 0.4] })
    addPlaneCollider(world, colliders[3], { body: bodies[3] })
    const snap = saveClothState(world, cloth)
    let checked = 0
    const check = (label: string) => {
      const C = state.collision.Collider
      for (const e of state.collision.colliders) {
        const kept = C.swept.slice(8 * e, 8 * e + 8)
        sweepColliderBounds(state, e)
        expect(Array.from(kept), `${label}, collider ${e}`).toEqual(Array.from(C.swept.slice(8 * e, 8 * e + 8)))
        checked++
      }
    }
    for (let f = 0; f < 120; f++) {
      const t = f / 60
      // body 0 rests, moves for a while, stops at a new place; body 1 turns from frame 30 and stops;
      // body 2 rests, is scaled at 50, jumps 20 m at 70; body 3 (the plane) tilts once at 90
      if (f >= 20 && f < 40) setTransform(world, bodies[0], [0.05 * (f - 20), 0.5, 0])
      if (f >= 30 && f < 45) setTransform(world, bodies[1], [1, 0.5, 0], [0, Math.sin(0.05 * (f - 30)), 0, Math.cos(0.05 * (f - 30))])
      if (f === 50) setTransform(world, bodies[2], [2, 0.5, 0], undefined, [1.5, 1.5, 1.5])
      if (f === 70) setTransform(world, bodies[2], [22, 0.5, 0])
      if (f === 90) setTransform(world, bodies[3], [3, 0.5, 0], [Math.sin(0.1), 0, 0, Math.cos(0.1)])
      if (f === 100) restoreClothState(world, cloth, snap)
      if (f === 105) {
        // the same entity made a larger sphere, its body at rest
        removeCollider(world, colliders[0])
        addSphereCollider(world, colliders[0], { body: bodies[0], radius: 0.6 })
      }
      if (f === 110) {
        removeEntity(world, colliders[1])
        const again = addEntity(world) // (a recycled id, maybe)
        addBoxCollider(world, again, { body: bodies[1], halfExtents: [0.5, 0.5, 0.5] })
        colliders[1] = again
      }
      stepCloth(world, 1 / 60)
      check(`frame ${f} (${t.toFixed(2)} s)`)
    }
    expect(checked).toBe(480)
  })
})
