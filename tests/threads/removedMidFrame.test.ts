// A cloth entity removed with bitECS's removeEntity between beginClothStep and endClothStep (game
// logic runs there) in a step where it tears: its events, still in the workers' output, are
// dropped as a removal drops its pending ones (they threw a TypeError with 2 workers).
import { removeEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import { beginClothStep, disposeClothWorld, endClothStep, getClothStats, onClothTear, setTransform, stepCloth } from '../../src/index'
import { getClothWorld } from '../../src/world/access'
import { sheetOnHands, threadedWorld as verifiedWorld } from './scene'

/** A threaded world as a game makes it (no verify mode). */
function threadedWorld(threads: number): object {
  const world = verifiedWorld(threads)
  const th = getClothWorld(world).threads
  if (th !== null) th.verify = false
  return world
}

describe('a tearing cloth removed mid-frame', () => {
  it('a cloth entity removed mid-frame in a step where it tears: no TypeError (0 and 2 workers)', () => {
    // find a frame whose step tears the sheet, single-threaded
    const tearFrames: number[] = []
    {
      const world = threadedWorld(0)
      const { hands } = sheetOnHands(world, 0.05)
      onClothTear(world, () => {})
      for (let f = 0; f < 120; f++) {
        const spread = Math.min(0.9, 0.02 * f)
        setTransform(world, hands[0], [2.5 - spread, 2, 0])
        setTransform(world, hands[1], [3.5 + spread, 2, 0])
        const before = getClothStats(world).tears
        stepCloth(world, 1 / 60)
        if (getClothStats(world).tears > before) tearFrames.push(f)
      }
    }
    expect(tearFrames.length).toBeGreaterThan(0)
    const at = tearFrames[0]
    const errors: Record<number, string | null> = {}
    for (const threads of [0, 2]) {
      const world = threadedWorld(threads)
      try {
        const { hands, sheet } = sheetOnHands(world, 0.05)
        onClothTear(world, () => {})
        let err: unknown = null
        for (let f = 0; f <= at; f++) {
          const spread = Math.min(0.9, 0.02 * f)
          setTransform(world, hands[0], [2.5 - spread, 2, 0])
          setTransform(world, hands[1], [3.5 + spread, 2, 0])
          beginClothStep(world, 1 / 60)
          if (f === at) removeEntity(world, sheet) // game logic removes the sheet while it is being stepped
          try {
            endClothStep(world)
          } catch (e) {
            err = e
          }
        }
        errors[threads] = err === null ? null : String(err)
      } finally {
        disposeClothWorld(world)
      }
    }
    expect(errors).toEqual({ 0: null, 2: null })
  })
})
