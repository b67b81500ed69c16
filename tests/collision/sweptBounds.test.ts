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
  getClothState,
  getClothStats,
  pinRow,
  removeCollider,
  restoreClothState,
  saveClothState,
  setTransform,
  stepCloth,
} from '../../src/index'
import { sweepColliderBounds } from '../../src/features/collision/colliders'
import { liveColliders } from '../../src/features/collision/list'
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
      for (const e of liveColliders(state.collision)) {
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

describe('a body whose scale leaps', () => {
  /**
   * A curtain (top row pinned) with a ball in front of it on an offset (0, 0, −0.5) of a body at
   * z = +1; over one frame the body's scale goes 1 → `to` (6 puts the ball 2.5 m on, behind the
   * curtain), or over 30 frames. Returns the curtain's fastest particle and its farthest back.
   */
  function grow(to: number, frames: number, teleport = false) {
    const world = makeWorld({ sleep: false })
    const rail = addEntity(world)
    setTransform(world, rail, [0, 2, 0])
    const sheet = createCloth(world, { width: 1, height: 1, resolution: 16, position: [0, 1.5, 0], material: 'cotton' })
    pinRow(world, sheet, 0, rail)
    const body = addEntity(world)
    setTransform(world, body, [0, 1, 1])
    addSphereCollider(world, addEntity(world), { body, offset: [0, 0, -0.5], radius: 0.2 })
    for (let f = 0; f < 120; f++) stepCloth(world, 1 / 60)
    const c = getClothState(world, sheet)
    let vmax = 0, zmin = Infinity
    for (let f = 1; f <= 60; f++) {
      const s = 1 + (to - 1) * Math.min(1, f / frames)
      // (with `teleport`, the body is also put 3 m aside and back in the same frame: a jump as well)
      const x = teleport && f === 1 ? 3 : 0
      if (teleport && f === 1) {
        setTransform(world, body, [x, 1, 1], [0, 0, 0, 1], [1, 1, 1])
        stepCloth(world, 1 / 60)
        setTransform(world, body, [0, 1, 1], [0, 0, 0, 1], [s, s, s])
      } else setTransform(world, body, [0, 1, 1], [0, 0, 0, 1], [s, s, s])
      stepCloth(world, 1 / 60)
      for (let i = 0; i < c.count; i++) {
        vmax = Math.max(vmax, Math.hypot(c.vel[3 * i], c.vel[3 * i + 1], c.vel[3 * i + 2]))
        zmin = Math.min(zmin, c.pos[3 * i + 2])
      }
    }
    return { vmax, zmin, resets: getClothStats(world).guardResets }
  }
  it('is taken at once, as a jump of position is: the ball does not sweep through the curtain (99 m/s, 2596 % stretch); grown over half a second it pushes it', () => {
    const snap = grow(6, 1)
    expect(snap.vmax).toBeLessThan(0.5) // measured 0.00 m/s
    expect(snap.resets).toBe(0)
    const smooth = grow(6, 30) // 8 cm a frame: swept, the curtain is pushed back
    expect(smooth.zmin).toBeLessThan(-0.2)
    const small = grow(1.9, 1) // not a leap (under twice): swept, a push
    expect(small.zmin).toBeLessThan(-0.05)
    // the leap in the frame its body teleports back (a respawn as a giant): unswept too (99 m/s)
    expect(grow(6, 1, true).vmax).toBeLessThan(0.5)
  })
})
