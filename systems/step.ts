import { clothFixedStep } from './pipeline'
import { ClothError } from '../src/core/errors'
import { K_SINCE_SAMPLE, K_STEP_FRACTION } from '../src/world/kinematics'
import { getClothWorld } from '../src/world/access'

/**
 * Advances every cloth of the world by a frame of `dt` seconds using a fixed-step accumulator:
 * whole fixed steps are run, the remainder waits for the next frame. At most `maxStepsPerFrame`
 * steps run per call; time beyond that is dropped, so a long hitch (or a 10 s frame) is never
 * simulated as one giant step. Returns the number of fixed steps run.
 *
 * Pin targets are sampled once per call and interpolated in time across the steps it runs: each
 * step sees exactly the motion of its own time slice, however the frame and step lengths line up.
 */
export function stepCloth(world: object, dt: number): number {
  const state = getClothWorld(world)
  if (typeof dt !== 'number' || !Number.isFinite(dt) || dt < 0) {
    throw new ClothError('dt', dt, 'must be a finite number of seconds ≥ 0')
  }
  const k = state.kinematics
  const time = k.time
  const fixed = state.fixedTimeStep
  const d = Math.min(dt, state.maxStepsPerFrame * fixed)
  state.accumulator += d
  time[K_SINCE_SAMPLE] += d
  // the tolerance keeps 1/60-s frames from drifting into an alternating 0/2-step pattern
  let steps = Math.floor(state.accumulator / fixed + 1e-9)
  const overflow = steps > state.maxStepsPerFrame
  if (overflow) steps = state.maxStepsPerFrame
  if (steps === 0) return 0
  k.framed = true
  try {
    for (let s = 1; s <= steps; s++) {
      state.accumulator -= fixed
      // where this step ends within the time since the last sample (all of it when time is dropped)
      const since = time[K_SINCE_SAMPLE]
      time[K_STEP_FRACTION] = overflow ? s / steps : Math.min(1, (since - Math.max(0, state.accumulator)) / since)
      clothFixedStep(world)
    }
  } finally {
    // also when a step threw (a host transform refused in the sync phase): the next call starts a
    // frame of its own and samples the transforms again
    k.framed = false
    k.newFrame = true
  }
  k.newFrame = true
  if (overflow || state.accumulator < 0) state.accumulator = 0
  time[K_SINCE_SAMPLE] = 0
  return steps
}
