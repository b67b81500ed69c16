// The scene of the hitch tests (hitches.test.ts, hitchFeatures.test.ts): the README character
// guide's cape on a hero standing at the origin.
import { addEntity } from 'bitecs'
import {
  addCapsuleCollider,
  addPlaneCollider,
  addSphereCollider,
  createCloth,
  createWindZone,
  pinRow,
  setClothInertia,
  setClothMotionConstraints,
  setTransform,
} from '../../src/index'
import { makeWorld } from '../helpers'

export const yq = (a: number): [number, number, number, number] => [0, Math.sin(a / 2), 0, Math.cos(a / 2)]

export interface HitchSceneOptions {
  /** Inertia 0.5, the demo's painted max distance and a backstop (default true). */
  character?: boolean
  /** Torso and head capsules on the hero, and a ground plane (default true). */
  colliders?: boolean
  /** Two leg capsules on their own entities, which the caller moves with the hero (default false). */
  legs?: boolean
  /** The cape's length, m (default 1.05). */
  height?: number
  /** Cape position z behind the hero, m (default −0.2). */
  behind?: number
  world?: Parameters<typeof makeWorld>[0]
}

/** A 14×24 wool cape pinned by its top row to the hero (a still air zone in the world). */
export function capeScene(o: HitchSceneOptions = {}) {
  const world = makeWorld({ sleep: false, ...(o.world ?? {}) })
  const hero = addEntity(world)
  setTransform(world, hero, [0, 0, 0])
  if (o.colliders !== false) {
    addCapsuleCollider(world, addEntity(world), { body: hero, offset: [0, 1.15, 0], radius: 0.19, halfHeight: 0.22 })
    addSphereCollider(world, addEntity(world), { body: hero, offset: [0, 1.68, 0.02], radius: 0.13 })
    const ground = addEntity(world)
    setTransform(world, ground, [0, 0, 0])
    addPlaneCollider(world, ground)
  }
  const legs: number[] = []
  if (o.legs) {
    for (let s = 0; s < 2; s++) {
      const leg = addEntity(world)
      setTransform(world, leg, [s ? 0.1 : -0.1, 0.45, -0.02])
      addCapsuleCollider(world, leg, { radius: 0.09, halfHeight: 0.3 })
      legs.push(leg)
    }
  }
  const cape = createCloth(world, {
    width: 0.55,
    height: o.height ?? 1.05,
    resolution: [14, 24],
    position: [0, 1.47, o.behind ?? -0.2],
    rotation: [0, 1, 0, 0],
    material: 'wool',
  })
  pinRow(world, cape, 0, hero)
  if (o.character !== false) {
    setClothInertia(world, cape, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5 })
    const maxDistance = Array.from({ length: 14 * 24 }, (_, i) => {
      const u = Math.floor(i / 14) / 23
      return u === 1 ? Infinity : 0.9 * u * u
    })
    setClothMotionConstraints(world, cape, { maxDistance, backstop: { distance: 0.02, radius: 0.5 } })
  }
  createWindZone(world, { direction: [1, 0, 0], strength: 0 })
  return { world, hero, cape, legs }
}
