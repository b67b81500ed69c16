// Snapshots across modes: a snapshot saved from a threaded world holds the same bytes as one saved
// from a single-threaded world fed the same inputs, and restoring either into either mode replays
// the run byte for byte.
import { addEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  addSphereCollider,
  createCloth,
  createWindZone,
  disposeClothWorld,
  enableSelfCollision,
  getClothState,
  pinRow,
  restoreClothState,
  saveClothState,
  setTransform,
  stepCloth,
  type ClothSnapshot,
} from '../../src/index'
import { hashBytes } from '../helpers'
import { heroWithBody, poseLegs } from '../stability/scenes'
import { threadedWorld } from './scene'

function scene(threads: number) {
  const world = threadedWorld(threads)
  const body = heroWithBody(world, { resolution: [7, 9] })
  enableSelfCollision(world, body.cloths[0])
  const flag = createCloth(world, { width: 1, height: 0.6, resolution: [9, 6], position: [2, 2, 0] })
  const pole = addEntity(world)
  setTransform(world, pole, [2, 2, 0])
  pinRow(world, flag, 0, pole)
  const ball = addEntity(world)
  setTransform(world, ball, [2, 1.6, 0.3])
  addSphereCollider(world, ball, { radius: 0.25 })
  createWindZone(world, { direction: [0, 0, 1], strength: 6, turbulence: 0.5, seed: 9 })
  const cloths = [body.cloths[0], flag]
  const frame = (f: number) => {
    const a = 0.04 * f
    const p = [Math.cos(a), 1.6, Math.sin(a)]
    setTransform(world, body.hero, p, [0, Math.sin(-a / 2), 0, Math.cos(-a / 2)])
    poseLegs({ ...body, world }, p, -a, f / 60)
    setTransform(world, ball, [2 + 0.5 * Math.sin(a * 3), 1.6, 0.3])
    stepCloth(world, (f % 3 === 0 ? 1.4 : 0.8) / 60)
  }
  const hash = () =>
    cloths.map((e) => {
      const c = getClothState(world, e)
      return hashBytes(c.pos.subarray(0, 3 * c.count)) + hashBytes(c.prev.subarray(0, 3 * c.count)) +
        hashBytes(c.vel.subarray(0, 3 * c.count))
    }).join('')
  return { world, cloths, frame, hash }
}

/** Every array and number of a snapshot, as text (tethers by value). */
function snapshotBytes(s: ClothSnapshot): string {
  return Object.entries(s).map(([k, v]) => {
    if (ArrayBuffer.isView(v)) return `${k}:${hashBytes(v)}`
    if (v !== null && typeof v === 'object')
      return `${k}:{${Object.entries(v).map(([a, b]) => `${a}=${ArrayBuffer.isView(b) ? hashBytes(b) : String(b)}`).join(',')}}`
    return `${k}:${String(v)}`
  }).sort().join(' ')
}

describe('snapshots in threaded worlds', () => {
  it('save the same bytes as single-threaded, and restore across modes to replay the run byte for byte', () => {
    const one = scene(0), two = scene(2), ref = scene(0)
    try {
      for (let f = 0; f < 90; f++) for (const s of [one, two, ref]) s.frame(f)
      const fromOne = one.cloths.map((e) => saveClothState(one.world, e))
      const fromTwo = two.cloths.map((e) => saveClothState(two.world, e))
      const fromRef = ref.cloths.map((e) => saveClothState(ref.world, e))
      for (let k = 0; k < fromOne.length; k++) expect(snapshotBytes(fromTwo[k])).toBe(snapshotBytes(fromOne[k]))
      const at90 = ref.hash()
      for (let f = 90; f < 150; f++) for (const s of [one, two, ref]) s.frame(f)
      const at150 = ref.hash()
      expect(at150).not.toBe(at90)
      // roll back: the threaded world to the single-threaded world's snapshot and the other way round
      one.cloths.forEach((e, k) => restoreClothState(one.world, e, fromTwo[k]))
      two.cloths.forEach((e, k) => restoreClothState(two.world, e, fromOne[k]))
      ref.cloths.forEach((e, k) => restoreClothState(ref.world, e, fromRef[k]))
      expect(two.hash()).toBe(at90)
      expect(one.hash()).toBe(at90)
      for (let f = 90; f < 150; f++) {
        for (const s of [one, two, ref]) s.frame(f)
        expect(two.hash(), `frame ${f}`).toBe(ref.hash())
        expect(one.hash(), `frame ${f}`).toBe(ref.hash())
      }
      expect(ref.hash()).toBe(at150)
    } finally {
      for (const s of [one, two, ref]) disposeClothWorld(s.world)
    }
  })
})
