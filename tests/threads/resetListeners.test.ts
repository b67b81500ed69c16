// Reset listeners (onClothReset) are called at the same point of a frame in every mode: after the
// step, with the frame still open, as tear listeners are. So they may change the world (remove the
// cloth) but not step it, whether the reset happened in a frame's first or second fixed step and
// whether the step ran on the workers, on the calling thread of a threaded world, or without workers.
import { addEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  ClothError,
  createCloth,
  disposeClothWorld,
  getClothState,
  getClothStats,
  getCloths,
  onClothReset,
  pinRow,
  removeCloth,
  setClothBudget,
  setTransform,
  stepCloth,
} from '../../src/index'
import { threadedWorld } from './scene'
import { CHEAP_CALIBRATION } from '../helpers'

const MODES = [
  { name: 'no workers', threads: 0, options: {} },
  { name: '2 workers', threads: 2, options: {} },
  { name: '2 workers, steps small enough for the calling thread', threads: 2, options: { threadMinStepMs: 1e6 } },
]

/**
 * A far cloth stepped every 2nd fixed step, its particle made NaN before a frame of two fixed steps:
 * the guard resets it in the frame's first or second step (`warm` frames before set which).
 * `listener` runs on the reset. Returns the frame's fixed steps and where the reset landed.
 */
function resetFrame(threads: number, options: object, warm: number, listener: (world: object, cloth: number) => void) {
  const world = threadedWorld(threads, options)
  try {
    const viewer = addEntity(world)
    setTransform(world, viewer, [0, 0, 0])
    const far = createCloth(world, { width: 1, height: 1, resolution: 6, position: [100, 2, 0] })
    pinRow(world, far, 0)
    setClothBudget(world, { viewer, near: 5, far: 20, farStepEvery: 2, calibration: CHEAP_CALIBRATION, adapt: false, interval: 1 })
    let resetStep = -1
    onClothReset(world, (e) => {
      resetStep = e.step
      listener(world, e.cloth)
    })
    for (let f = 0; f < warm; f++) stepCloth(world, 1 / 60)
    const before = getClothStats(world).steps
    getClothState(world, far).pos[60] = NaN
    const ran = stepCloth(world, 2 / 60)
    return { ran, steps: getClothStats(world).steps - before, inStep: resetStep - before, cloths: getCloths(world).length }
  } finally {
    disposeClothWorld(world)
  }
}

describe('reset listeners', () => {
  for (const mode of MODES) {
    for (const [warm, which] of [[5, 1], [6, 2]] as const) {
      it(`${mode.name}, reset in a frame's fixed step ${which}: a listener may remove the cloth`, () => {
        const r = resetFrame(mode.threads, mode.options, warm, (world, cloth) => removeCloth(world, cloth))
        expect(r.inStep).toBe(which)
        expect(r.ran).toBe(2)
        expect(r.steps).toBe(2)
        expect(r.cloths).toBe(0)
      })

      it(`${mode.name}, reset in a frame's fixed step ${which}: a listener may not step the world (the frame is still open)`, () => {
        const errors: unknown[] = []
        const r = resetFrame(mode.threads, mode.options, warm, (world) => {
          try {
            stepCloth(world, 1 / 60)
          } catch (e) {
            errors.push(e)
          }
        })
        expect(r.inStep).toBe(which)
        expect(errors.length).toBe(1)
        expect(errors[0]).toBeInstanceOf(ClothError)
        expect(String(errors[0])).toMatch(/already stepping a frame/)
        expect(r.steps).toBe(2) // no nested frame ran
        expect(r.cloths).toBe(1)
      })
    }
  }
})
