// disposeClothWorld called from a tear listener (a game shutting the cloth workers down when
// something happens). It should either throw a ClothError or stop the workers and leave the world
// stepping exactly as it would have (same bytes, same stats), in every mode.
import { describe, expect, it } from 'vitest'
import { ClothError, disposeClothWorld, getClothState, getClothStats, onClothTear, setTransform, stepCloth } from '../../src/index'
import { getClothWorld } from '../../src/world/access'
import { hashBytes } from '../helpers'
import { sheetOnHands, threadedWorld as verifiedWorld } from './scene'

function threadedWorld(threads: number): object {
  const world = verifiedWorld(threads)
  const th = getClothWorld(world).threads
  if (th !== null) th.verify = false
  return world
}

function run(threads: number, disposeInListener: boolean, dt: number) {
  const world = threadedWorld(threads)
  const { hands, sheet } = sheetOnHands(world, 0.03)
  const events: string[] = []
  onClothTear(world, (e) => events.push(`${e.cloth} ${e.particle}>${e.newParticle}`))
  let disposed = false
  let error = 'none'
  onClothTear(world, () => {
    if (!disposeInListener || disposed) return
    disposed = true
    try {
      disposeClothWorld(world)
    } catch (e) {
      error = e instanceof ClothError ? 'ClothError' : String(e)
    }
  })
  try {
    for (let f = 0; f < 60; f++) {
      const spread = Math.min(0.9, 0.02 * f)
      setTransform(world, hands[0], [2.5 - spread, 2, 0])
      setTransform(world, hands[1], [3.5 + spread, 2, 0])
      stepCloth(world, dt)
    }
    const c = getClothState(world, sheet)
    const s = getClothStats(world)
    return {
      error,
      disposed,
      events: events.join(','),
      steps: s.steps,
      substeps: s.substeps,
      bytes: hashBytes(c.pos.subarray(0, 3 * c.count)),
    }
  } finally {
    disposeClothWorld(world)
  }
}

describe('disposeClothWorld from a listener', () => {
  for (const threads of [0, 2]) {
    it(`${threads} workers, 2 fixed steps per frame: a ClothError, or the run goes on unchanged`, () => {
      const ref = run(threads, false, 2 / 60)
      const got = run(threads, true, 2 / 60)
      expect(got.disposed).toBe(true)
      if (got.error === 'ClothError') return
      expect({ ...got, disposed: undefined, error: undefined }).toEqual({ ...ref, disposed: undefined, error: undefined })
      expect(got.error).toBe('none')
    })
  }
})
