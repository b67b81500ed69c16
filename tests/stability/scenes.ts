// Scene parts shared by the torture files.
import { addEntity } from 'bitecs'
import { addCapsuleCollider, addPlaneCollider, addSphereCollider, createCloth, pinRow, setTransform } from '../../src/index'
import type { Scene } from './harness'

/** A character (Transform entity) with a small cape pinned to it by its top row. */
export function heroWithCape(
  world: object,
  options: { resolution?: number | [number, number]; substeps?: number; bending?: 'distance' | 'both' } = {},
) {
  const hero = addEntity(world)
  setTransform(world, hero, [0, 1.6, 0])
  const cape = createCloth(world, {
    width: 0.5,
    height: 0.8,
    resolution: options.resolution ?? [6, 8],
    position: [0, 1.5, -0.15],
    substeps: options.substeps ?? 8,
    material: 'cotton',
    bending: options.bending ?? 'distance',
  })
  pinRow(world, cape, 0, hero)
  return { cloths: [cape], hero }
}

/** Largest distance between two poses, m. */
export function maxDistance(a: Float64Array, b: Float64Array, n: number): number {
  let d = 0
  for (let i = 0; i < n; i++) d = Math.max(d, Math.hypot(a[3 * i] - b[3 * i], a[3 * i + 1] - b[3 * i + 1], a[3 * i + 2] - b[3 * i + 2]))
  return d
}

/** Walks the hero in a circle of radius 2 m at `speed` m/s, facing along the path, at time t. */
export function walk(s: Scene<{ cloths: number[]; hero: number }>, t: number, speed = 3) {
  const a = (speed / 2) * t
  setTransform(s.world, s.hero, [2 * Math.cos(a) - 2, 1.6, 2 * Math.sin(a)], [0, Math.sin(-a / 2), 0, Math.cos(-a / 2)])
}

/**
 * `heroWithCape` plus a body the cape collides with: a torso capsule and a head sphere following the
 * hero at offsets, two leg capsules on their own bone entities (moved with `poseLegs`), and a ground
 * plane that follows the hero's feet. All on layer 2 (the hero's body); the cape collides with it.
 */
export function heroWithBody(
  world: object,
  options: { resolution?: number | [number, number]; substeps?: number; bending?: 'distance' | 'both' } = {},
) {
  const scene = heroWithCape(world, options)
  const { hero } = scene
  const body = { layer: 2 }
  const torso = addEntity(world)
  addCapsuleCollider(world, torso, { body: hero, offset: [0, -0.55, 0.02], radius: 0.12, halfHeight: 0.2, ...body })
  const head = addEntity(world)
  addSphereCollider(world, head, { body: hero, offset: [0, 0.12, 0.02], radius: 0.1, ...body })
  const legs = [addEntity(world), addEntity(world)]
  for (const leg of legs) {
    setTransform(world, leg, [0, 0.8, 0])
    addCapsuleCollider(world, leg, { radius: 0.07, halfHeight: 0.3, ...body })
  }
  const ground = addEntity(world)
  addPlaneCollider(world, ground, { body: hero, offset: [0, -1.6, 0], ...body })
  return { ...scene, torso, head, legs, ground }
}

/** Places the leg bones of `heroWithBody` under the hero at position p with yaw `yaw`, swinging with phase t. */
export function poseLegs(s: Scene<ReturnType<typeof heroWithBody>>, p: ArrayLike<number>, yaw: number, t: number) {
  for (let k = 0; k < 2; k++) {
    const side = k === 0 ? -1 : 1
    const swing = side * 0.5 * Math.sin(8 * t)
    // hip at (±0.09, −0.85) in the hero's frame; the leg hangs 0.35 m below it, swung about x
    const lx = side * 0.09, ly = -0.85 - 0.35 * Math.cos(swing), lz = -0.35 * Math.sin(swing)
    const c = Math.cos(yaw), s_ = Math.sin(yaw)
    const q = [
      Math.sin(swing / 2) * Math.cos(yaw / 2),
      Math.cos(swing / 2) * Math.sin(yaw / 2),
      -Math.sin(swing / 2) * Math.sin(yaw / 2),
      Math.cos(swing / 2) * Math.cos(yaw / 2),
    ]
    setTransform(s.world, s.legs[k], [p[0] + c * lx + s_ * lz, p[1] + ly, p[2] - s_ * lx + c * lz], q)
  }
}
