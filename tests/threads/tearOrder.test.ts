// Tear events in cloth creation order in every mode, when a self-colliding tearable cloth (which the
// pipeline steps after the others) is older than a plain tearable one and both tear in the same
// steps. With one worker they came out plain cloth first: the worker sorted by a Cloth store it
// does not have (found by a hunt).
import { describe, expect, it } from 'vitest'
import { clothFixedStep, disposeClothWorld, enableSelfCollision, getClothState, onClothTear, setTransform } from '../../src/index'
import { hashBytes } from '../helpers'
import { sheetOnHands, threadedWorld } from './scene'

function scene(threads: number) {
  const world = threadedWorld(threads)
  const tears: string[] = []
  onClothTear(world, (e) => tears.push(`${e.cloth}:${e.particle}>${e.newParticle}`))
  const held = [0, 1].map((k) => sheetOnHands(world, 0.1, 3 * k))
  enableSelfCollision(world, held[0].sheet) // the older cloth self-collides
  const frame = (f: number) => {
    const spread = Math.min(0.6, 0.02 * f)
    for (let k = 0; k < 2; k++) {
      setTransform(world, held[k].hands[0], [3 * k - 0.5 - spread, 2, 0])
      setTransform(world, held[k].hands[1], [3 * k + 0.5 + spread, 2, 0])
    }
    clothFixedStep(world)
    tears.push('|') // (the step's end)
  }
  return { world, tears, frame, cloths: held.map((h) => h.sheet) }
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
      // both tore, in the same steps too, and each step's events came cloth by cloth in creation order
      const [older, newer] = runs[0].cloths.map(String)
      const steps = runs[0].tears.join(' ').split('|').map((s) => s.trim().split(' ').filter((t) => t !== '').map((t) => t.split(':')[0]))
      expect(steps.some((cl) => cl.includes(older) && cl.includes(newer))).toBe(true)
      for (const cl of steps) expect(cl.join(' ')).toBe([...cl.filter((x) => x === older), ...cl.filter((x) => x === newer)].join(' '))
      expect(runs[2].tears).toEqual(runs[0].tears)
      expect(runs[1].tears).toEqual(runs[0].tears)
    } finally {
      for (const r of runs) disposeClothWorld(r.world)
    }
  })
})
