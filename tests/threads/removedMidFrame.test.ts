// A cloth entity removed with bitECS's removeEntity between beginClothStep and endClothStep (game
// logic runs there) in a step where it tears: its events, still in the workers' output, are
// dropped as a removal drops its pending ones (they threw a TypeError with 2 workers).
import { addEntity, removeEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  addCapsuleCollider,
  addSphereCollider,
  beginClothStep,
  createCloth,
  disposeClothWorld,
  endClothStep,
  getClothMesh,
  getClothStats,
  getClothTearCount,
  onClothTear,
  pinRow,
  setClothInertia,
  setTransform,
  stepCloth,
} from '../../src/index'
import { flatSheet } from '../collision/scenes'
import { gameWorld as threadedWorld, sheetOnHands } from './scene'

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

describe('entities removed mid-frame', () => {
  /**
   * A character with a cape and a body collider, and a sheet on a ball whose body entity goes too:
   * the character is removed between beginClothStep and endClothStep (killed by game logic while
   * its cape is being stepped), the ball's body a frame later. Positions after every frame.
   */
  function run(threads: number): Float64Array[] {
    const world = threadedWorld(threads)
    const frames: Float64Array[] = []
    try {
      const hero = addEntity(world)
      setTransform(world, hero, [0, 0, 0])
      const torso = addEntity(world)
      addCapsuleCollider(world, torso, { body: hero, offset: [0, 1.15, 0], radius: 0.19, halfHeight: 0.22 })
      const cape = createCloth(world, { width: 0.55, height: 1.05, resolution: [28, 48], position: [0, 1.47, -0.2], material: 'wool' })
      pinRow(world, cape, 0, hero)
      setClothInertia(world, cape, { linear: 0.5, angular: 0.5, centrifugal: 0.5 })
      const ballBody = addEntity(world)
      setTransform(world, ballBody, [3, 1, 0])
      addSphereCollider(world, addEntity(world), { body: ballBody, radius: 0.4 })
      const sheet = flatSheet(world, 3, 1.6, 0, 1.6, 40)
      for (let f = 0; f < 70; f++) {
        const a = f * 0.05
        if (f < 30) setTransform(world, hero, [Math.cos(a), 0, Math.sin(a)], [0, Math.sin(-a / 2), 0, Math.cos(-a / 2)])
        beginClothStep(world, 1 / 60)
        if (f === 30) removeEntity(world, hero)
        if (f === 31) removeEntity(world, ballBody)
        endClothStep(world)
        frames.push(Float64Array.from([...getClothMesh(world, cape).positions, ...getClothMesh(world, sheet).positions]))
      }
    } finally {
      disposeClothWorld(world)
    }
    return frames
  }

  it('a character and a collider body removed while the workers step: the same bytes with 0, 1 and 2 workers', () => {
    const plain = run(0)
    for (const threads of [1, 2]) {
      const threaded = run(threads)
      let first = -1
      for (let f = 0; f < plain.length && first < 0; f++) {
        if (Buffer.compare(Buffer.from(plain[f].buffer), Buffer.from(threaded[f].buffer)) !== 0) first = f
      }
      expect({ threads, first }).toEqual({ threads, first: -1 })
    }
    // the cape fell once its character was gone, the sheet once the ball was
    const last = plain[plain.length - 1], before = plain[29]
    expect(last[1]).toBeLessThan(before[1] - 0.1)
  })
})

describe('entities spawned past the capacity mid-frame', () => {
  /** A tearing sheet, and a game spawning entities with Transforms mid-frame past the stores' capacity. */
  function run(threads: number): { tears: number; bytes: Float64Array } {
    const world = threadedWorld(threads, { capacity: 16 })
    try {
      const { hands, sheet } = sheetOnHands(world, 0.05)
      for (let f = 0; f < 90; f++) {
        const spread = Math.min(0.9, 0.02 * f)
        setTransform(world, hands[0], [2.5 - spread, 2, 0])
        setTransform(world, hands[1], [3.5 + spread, 2, 0])
        beginClothStep(world, 1 / 60)
        // a burst of spawns each frame: the stores grow while the step is in flight
        for (let k = 0; k < 8; k++) setTransform(world, addEntity(world), [k, 0, f])
        endClothStep(world)
      }
      return { tears: getClothTearCount(world, sheet), bytes: Float64Array.from(getClothMesh(world, sheet).positions) }
    } finally {
      disposeClothWorld(world)
    }
  }

  it('tear counts and pin blends written by the workers survive the stores growing: the same with 0 and 2 workers', () => {
    const plain = run(0)
    expect(plain.tears).toBeGreaterThan(3)
    const threaded = run(2)
    expect(threaded.tears).toBe(plain.tears)
    expect(Buffer.compare(Buffer.from(threaded.bytes.buffer), Buffer.from(plain.bytes.buffer))).toBe(0)
  })
})
