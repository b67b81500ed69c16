// Tear events in cloth creation order in every mode, when a self-colliding tearable cloth (which the
// pipeline steps after the others) is older than a plain tearable one and both tear in the same
// steps. With one worker they came out plain cloth first: the worker sorted by a Cloth store it
// does not have (found by a hunt).
import { addEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  clothFixedStep,
  createCloth,
  disposeClothWorld,
  enableSelfCollision,
  getClothState,
  makeTearable,
  onClothTear,
  pinParticle,
  setTransform,
} from '../../src/index'
import { hashBytes } from '../helpers'
import { threadedWorld } from './scene'

function scene(threads: number) {
  const world = threadedWorld(threads)
  const tears: string[] = []
  onClothTear(world, (e) => tears.push(`${e.cloth}:${e.particle}>${e.newParticle}`))
  const hands: number[][] = []
  const cloths: number[] = []
  for (let k = 0; k < 2; k++) {
    const x = 3 * k
    const h = [addEntity(world as never), addEntity(world as never)]
    setTransform(world, h[0], [x - 0.5, 2, 0])
    setTransform(world, h[1], [x + 0.5, 2, 0])
    const c = createCloth(world, { width: 1, height: 1, resolution: 8, position: [x, 2, 0] })
    pinParticle(world, c, 0, h[0])
    pinParticle(world, c, 7, h[1])
    makeTearable(world, c, { strain: 0.1, maxTearsPerStep: 2 })
    if (k === 0) enableSelfCollision(world, c) // the older cloth self-collides
    hands.push(h)
    cloths.push(c)
  }
  const frame = (f: number) => {
    const spread = Math.min(0.6, 0.02 * f)
    for (let k = 0; k < 2; k++) {
      setTransform(world, hands[k][0], [3 * k - 0.5 - spread, 2, 0])
      setTransform(world, hands[k][1], [3 * k + 0.5 + spread, 2, 0])
    }
    clothFixedStep(world)
  }
  return { world, tears, frame, cloths }
}

describe('tear events of a self-colliding cloth and a plain one in the same step', () => {
  it('come in creation order with 0, 1 and 2 workers, and the cloths are the same bytes', { timeout: 60_000 }, () => {
    const runs = [scene(0), scene(1), scene(2)]
    try {
      for (let f = 0; f < 60; f++) for (const r of runs) r.frame(f)
      for (let k = 0; k < 2; k++) {
        const h = runs.map((r) => hashBytes(getClothState(r.world, r.cloths[k]).pos))
        expect(h[1]).toBe(h[0])
        expect(h[2]).toBe(h[0])
      }
      // both tore
      expect(new Set(runs[0].tears.map((t) => t.split(':')[0])).size).toBe(2)
      expect(runs[2].tears).toEqual(runs[0].tears)
      expect(runs[1].tears).toEqual(runs[0].tears)
    } finally {
      for (const r of runs) disposeClothWorld(r.world)
    }
  })
})
