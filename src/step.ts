import { clothFixedStep } from '../systems/pipeline'
import { ClothError } from './errors'
import { getClothWorld } from './state'

/**
 * Advances every cloth of the world by a frame of `dt` seconds using a fixed-step accumulator:
 * whole fixed steps are run, the remainder waits for the next frame. At most `maxStepsPerFrame`
 * steps run per call; time beyond that is dropped, so a long hitch (or a 10 s frame) is never
 * simulated as one giant step. Returns the number of fixed steps run.
 */
export function stepCloth(world: object, dt: number): number {
  const state = getClothWorld(world)
  if (typeof dt !== 'number' || !Number.isFinite(dt) || dt < 0) {
    throw new ClothError('dt', dt, 'must be a finite number of seconds ≥ 0')
  }
  const fixed = state.fixedTimeStep
  state.accumulator += Math.min(dt, state.maxStepsPerFrame * fixed)
  let steps = 0
  // the tolerance keeps 1/60-s frames from drifting into an alternating 0/2-step pattern
  while (state.accumulator >= fixed * (1 - 1e-9) && steps < state.maxStepsPerFrame) {
    clothFixedStep(world)
    state.accumulator -= fixed
    steps++
  }
  if (state.accumulator >= fixed) state.accumulator = 0
  if (state.accumulator < 0) state.accumulator = 0
  return steps
}
