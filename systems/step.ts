import { finishFixedStep, refuseNestedStep, startFixedStep } from './pipeline'
import { ClothError } from '../src/core/errors'
import { K_DROPPED, K_SINCE_SAMPLE, K_STEP_FRACTION } from '../src/world/kinematics'
import { getClothWorld } from '../src/world/access'
import type { ClothWorldState } from '../src/world/state'
import { stopThreads } from '../src/threads/bind'
import { waitForWorkersAsync } from '../src/threads/pool'
import { landRemovals, landStores } from '../src/world/flight'

/**
 * Advances every cloth of the world by a frame of `dt` seconds using a fixed-step accumulator:
 * whole fixed steps are run, the remainder waits for the next frame. At most `maxStepsPerFrame`
 * steps run per call; time beyond that is dropped, so a long hitch (or a 10 s frame) is never
 * simulated as one giant step. Returns the number of fixed steps run.
 *
 * Pin targets are sampled once per call and interpolated in time across the steps it runs: each
 * step sees exactly the motion of its own time slice, however the frame and step lengths line up.
 *
 * In a threaded world the workers run the steps while this call waits (`Atomics.wait`; on a
 * browser's main thread, which may not block, a spin: use `beginClothStep` / `endClothStepAsync`
 * there).
 */
export function stepCloth(world: object, dt: number): number {
  const steps = openFrame(world, dt, true)
  endClothStep(world)
  return steps
}

/**
 * Starts a frame of `dt` seconds (see `stepCloth`) and returns how many fixed steps it runs. In a
 * threaded world the first step runs on the workers while this thread goes on (animation, AI,
 * rendering of the last frame); `endClothStep` (or `endClothStepAsync`) finishes the frame. Without
 * workers the step's substeps run in `endClothStep`: in every mode a frame's results (positions,
 * meshes, stats) appear, and its events are delivered, in `endClothStep`.
 *
 * Pins and colliders follow the Transforms as they are when this is called. Between the two calls
 * the game may write Transforms (they are read at the next begin) and read what finished steps
 * left (meshes, stats, events); changing cloths, pins, colliders or settings throws a ClothError.
 *
 * @example
 * animate(dt)                      // write the characters' Transforms
 * beginClothStep(world, dt)        // the workers start on this frame's step
 * updateGameLogic(dt)              // the main thread is free meanwhile
 * await endClothStepAsync(world)   // (or endClothStep, which blocks where a thread may block)
 * drawCloths()                     // getClothMesh: this frame's cloth
 */
export function beginClothStep(world: object, dt: number): number {
  return openFrame(world, dt, false)
}

/** Opens a frame (see `beginClothStep`); `blocking`: the caller waits for its end right away. */
function openFrame(world: object, dt: number, blocking: boolean): number {
  const state = getClothWorld(world)
  const f = state.frame
  if (f.open) throw new ClothError('world', world, 'is already stepping a frame (call endClothStep first)')
  refuseNestedStep(state, world)
  if (typeof dt !== 'number' || !Number.isFinite(dt) || dt < 0) {
    throw new ClothError('dt', dt, 'must be a finite number of seconds ≥ 0')
  }
  const k = state.kinematics
  const time = k.time
  const fixed = state.fixedTimeStep
  const d = Math.min(dt, state.maxStepsPerFrame * fixed)
  state.accumulator += d
  time[K_SINCE_SAMPLE] += d
  time[K_DROPPED] += dt - d // (its share of the motion is carried at the sample, not simulated)
  // the tolerance keeps 1/60-s frames from drifting into an alternating 0/2-step pattern
  let steps = Math.floor(state.accumulator / fixed + 1e-9)
  const overflow = steps > state.maxStepsPerFrame
  if (overflow) {
    steps = state.maxStepsPerFrame
    // (time kept from a frame refused at its sample): what the steps cannot take is dropped too
    const excess = state.accumulator - steps * fixed
    state.accumulator -= excess
    time[K_SINCE_SAMPLE] -= excess
    time[K_DROPPED] += excess
  }
  if (steps === 0) return 0
  k.framed = true
  f.steps = steps
  f.next = 1
  f.overflow = overflow
  try {
    startFrameStep(world, state, blocking)
  } catch (e) {
    abandonFrame(state)
    throw e
  }
  f.open = true
  return steps
}

/**
 * Finishes the frame `beginClothStep` started: waits for the workers (blocking; on a browser's main
 * thread, which may not block, it spins: prefer `endClothStepAsync` there), runs the frame's other
 * fixed steps, delivers the events (tear and reset listeners run here). Returns the fixed steps
 * the frame ran (0 when no frame was open).
 */
export function endClothStep(world: object): number {
  const state = getClothWorld(world)
  const f = state.frame
  if (!f.open) return 0
  if (f.ending) throw new ClothError('world', world, 'is finishing a frame in endClothStepAsync: await it instead')
  try {
    for (;;) {
      finishFixedStep(world)
      if (f.next > f.steps) break
      startFrameStep(world, state, true)
    }
  } catch (e) {
    abandonFrame(state)
    throw e
  }
  closeFrame(state)
  return f.steps
}

/**
 * `endClothStep` for a thread that may not block (a browser's main thread): resolves when the frame
 * is finished, its events delivered. Allocates a promise per call, and holds a timer while it waits (in
 * Node that keeps the process alive until the workers finish).
 */
export function endClothStepAsync(world: object): Promise<number> {
  // (a wrong world throws here, not in the promise)
  return finishFrameAsync(world, getClothWorld(world))
}

async function finishFrameAsync(world: object, state: ClothWorldState): Promise<number> {
  const f = state.frame
  if (!f.open || f.ending) return 0
  f.ending = true
  const th = state.threads
  try {
    for (;;) {
      if (th !== null && th.phase === 1) await waitForWorkersAsync(th.pool, th.step)
      finishFixedStep(world)
      if (f.next > f.steps) break
      startFrameStep(world, state, false)
    }
  } catch (e) {
    abandonFrame(state)
    throw e
  }
  closeFrame(state)
  return f.steps
}

/** Starts the frame's next fixed step: where it ends within the time since the last sample, then its first half. */
function startFrameStep(world: object, state: ClothWorldState, blocking: boolean): void {
  const f = state.frame
  const s = f.next++
  const time = state.kinematics.time
  const left = state.accumulator - state.fixedTimeStep
  // where this step ends within the time since the last sample (all of it when time is dropped)
  const since = time[K_SINCE_SAMPLE]
  time[K_STEP_FRACTION] = f.overflow ? s / f.steps : Math.min(1, (since - Math.max(0, left)) / since)
  startFixedStep(world, blocking)
  // (only a step that started spends its time: a frame refused at its sample keeps it for the next)
  state.accumulator = left
}

/**
 * A step threw (a host transform refused in the sync phase, a listener's error): the frame ends
 * there, and the next call starts a frame of its own and samples the transforms again.
 */
function abandonFrame(state: ClothWorldState): void {
  const f = state.frame
  landStores(state, false)
  landRemovals(state)
  f.open = false
  f.ending = false
  f.deferred = false
  state.kinematics.framed = false
  state.kinematics.newFrame = true
}

function closeFrame(state: ClothWorldState): void {
  const f = state.frame
  f.open = false
  f.ending = false
  const k = state.kinematics
  k.framed = false
  k.newFrame = true
  if (state.frame.overflow || state.accumulator < 0) state.accumulator = 0
  k.time[K_SINCE_SAMPLE] = 0
}

/**
 * Stops a threaded world's workers (they exit; a world garbage-collected without this call has
 * them terminated then, but only when the collector gets to it). A step in flight is finished
 * first (an open frame is ended: its listeners run). The world keeps working, its cloths stepped on the calling thread. Call it when you drop
 * a threaded world, or in tests; a world without workers is left as it is.
 */
export function disposeClothWorld(world: object): void {
  const state = getClothWorld(world)
  if (state.frame.ending) throw new ClothError('world', world, 'is finishing a frame in endClothStepAsync: await it first')
  // (from a listener it finished the frame inside the step being finished: one step counted twice)
  if (state.frame.delivering) throw new ClothError('world', world, "is calling a step's listeners: dispose of it after the frame")
  if (state.frame.open) endClothStep(world)
  const th = state.threads
  if (th === null) return
  stopThreads(th)
  state.threads = null
}
