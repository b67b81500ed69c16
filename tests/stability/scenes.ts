// Scene parts shared by the torture files.
import { addEntity } from 'bitecs'
import { createCloth, pinRow, setTransform } from '../../src/index'
import type { Scene } from './harness'

/** A character (Transform entity) with a small cape pinned to it by its top row. */
export function heroWithCape(
  world: object,
  options: { resolution?: number | [number, number]; substeps?: number; bending?: 'distance' | 'both' } = {},
) {
  const hero = addEntity(world)
  setTransform(world, hero, [0, 1.6, 0])
  const cape = createCloth(world, {
    width: 0.5, height: 0.8, resolution: options.resolution ?? [6, 8], position: [0, 1.5, -0.15],
    substeps: options.substeps ?? 8, material: 'cotton', bending: options.bending ?? 'distance',
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

