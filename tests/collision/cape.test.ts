import { addEntity } from 'bitecs'
import { glMatrix, quat, vec3 } from 'gl-matrix'
import { describe, expect, it } from 'vitest'
import { addCapsuleCollider, createCloth, getClothStretch, pinRow, setTransform, stepCloth } from '../../src/index'
import { allFinite, makeWorld } from '../helpers'
import { clearance, type Shape } from './scenes'

glMatrix.setMatrixArrayType(Array)

/**
 * A character running in circles at 4 m/s with a cape pinned to its shoulders: a torso capsule on
 * a child entity that follows the character's Transform at an offset, and two legs on their own
 * entities (like bones) that swing. With `mask: 0` the colliders exist but touch nothing, which
 * gives the same scene without collisions.
 */
function run(collide: boolean) {
  const world = makeWorld()
  const hero = addEntity(world)
  const p = vec3.create(), q = quat.create()
  setTransform(world, hero, [3, 0, 0])
  const mask = collide ? 0xffffffff : 0
  const torso = addEntity(world)
  addCapsuleCollider(world, torso, { body: hero, offset: [0, 1.15, 0], radius: 0.19, halfHeight: 0.22, mask })
  const legs = [addEntity(world), addEntity(world)]
  for (const leg of legs) {
    setTransform(world, leg, [0, 0, 0])
    addCapsuleCollider(world, leg, { radius: 0.08, halfHeight: 0.3, mask })
  }
  const capsules: [number, Shape][] = [
    [torso, { kind: 'capsule', radius: 0.19, halfHeight: 0.22 }],
    [legs[0], { kind: 'capsule', radius: 0.08, halfHeight: 0.3 }],
    [legs[1], { kind: 'capsule', radius: 0.08, halfHeight: 0.3 }],
  ]
  const local = (x: number, y: number, z: number) => vec3.add(vec3.create(), vec3.transformQuat(vec3.create(), [x, y, z], q), p)
  const pose = (t: number) => {
    const heading = (4 / 3) * t // 4 m/s on a 3 m circle
    vec3.set(p, 3 * Math.cos(heading), 0.04 * Math.abs(Math.sin(12 * t)), 3 * Math.sin(heading))
    quat.setAxisAngle(q, [0, 1, 0], Math.atan2(-Math.sin(heading), Math.cos(heading))) // facing along the circle
    setTransform(world, hero, p, q)
    for (let s = 0; s < 2; s++) {
      const side = s === 0 ? -1 : 1
      const leg = quat.rotateX(quat.create(), q, side * 0.6 * Math.sin(12 * t))
      const hip = local(side * 0.1, 0.77, 0)
      setTransform(world, legs[s], vec3.add(hip, hip, vec3.transformQuat(vec3.create(), [0, -0.3, 0], leg)), leg)
    }
  }
  pose(0)
  const cape = createCloth(world, { width: 0.55, height: 1.05, resolution: [14, 24], position: local(0, 1.47, -0.2), rotation: q })
  pinRow(world, cape, 0, hero)
  let worst = Infinity
  for (let f = 1; f <= 480; f++) {
    pose(f / 60)
    stepCloth(world, 1 / 60)
    for (const [eid, shape] of capsules) worst = Math.min(worst, clearance(world, cape, eid, shape))
  }
  return { world, cape, worst }
}

describe('cape on a running character', () => {
  it('never penetrates the capsules of its torso and legs while the character runs in circles', () => {
    const { world, cape, worst } = run(true)
    expect(worst).toBeGreaterThanOrEqual(0.9 * 0.005)
    expect(allFinite(world, cape)).toBe(true)
    expect(getClothStretch(world, cape).max).toBeLessThan(0.1)
  })

  it('without the colliders the same cape swings through the body', () => {
    expect(run(false).worst).toBeLessThan(-0.02)
  })
})
