import { ClothError, checkInteger } from '../src/core/errors'
import { getClothWorld } from '../src/world/access'
import type { ClothWorldState } from '../src/world/state'
import { clothGuard } from './clothGuard'
import { collideOfCloth } from './clothCollide'
import { forcesOfCloth } from './clothForces'
import { predictOfCloth } from './clothPredict'
import { solveOfCloth } from './clothSolve'
import { tearOfCloth } from './clothTear'
import { writebackOfCloth } from './clothWriteback'
import { collideSelfColliding } from '../src/features/collision/step'
import { orderTearEvents } from '../src/features/tearing/events'
import { guardCheck } from '../src/features/guard/step'
import { setGuardAnchor } from '../src/features/character/step'
import { IO_HEALTH, OUT_EVENTS, OUT_MS, OUT_SLEPT, OUT_TEARS, writeClothHandoff } from '../src/threads/handoff'
import { EV } from '../src/features/tearing/types'
import { takeStats } from '../src/world/stats'
import type { WorkerWorld } from '../src/threads/mirror'
import { clothSync } from './clothSync'
import { clothEvents } from './clothEvents'
import { Q_MEASURED, Q_T0 } from '../src/features/budget/types'
import { waitForWorkers } from '../src/threads/pool'
import { collectClothStep, dispatchClothStep } from './threaded'
import { refreshFrameMeshes } from '../src/mesh'
import { refreshFrameProxies } from '../src/proxy'
import { deliverResets } from '../src/features/guard/step'
import { landRemovals, landStores } from '../src/world/flight'

/**
 * The phase order, written once. Per fixed step:
 *
 *   sync                      read pin targets and colliders once, so every substep sees one
 *                             consistent motion; wake sleeping cloths that this motion disturbs
 *   for each substep:
 *     forces                  external accelerations first: predict integrates them
 *     predict                 x* = x + v·h + a·h², pinned particles placed on their (interpolated) targets
 *     solve                   constraints project x*; pins are fixed points (inverse mass 0)
 *     collide                 after the solve, so no constraint pushes a particle back into a collider
 *     tear                    after collide, on the last substep, so strain is measured on the final pose
 *     writeback               last: a character cloth's motion constraints (max distance, backstop,
 *                             drive around its reference pose: the last position change, so the
 *                             limits hold at every substep's end), then velocities from the motion,
 *                             including collision, tear and constraint changes; after a cloth's last
 *                             substep, the sleep test (on the final velocities)
 *   guard                     once, after the last substep: a cloth that went non-finite, out of
 *                             reach of its pins or into runaway speed goes back to a safe pose
 *                             before the renderer, the listeners or the next step read it
 *   events                    after the step: tear listeners see a finished step and may change the world
 *
 * `clothPhases` (`scheduled.ts`) lists the per-substep phases in that order for engines that
 * schedule systems themselves, each checking that no frame is open. The pipeline itself runs them
 * cloth by cloth (`runSubsteps`): the same numbers in the same order for each cloth, so the same
 * bytes as the phase systems run by hand.
 */

/** Runs one fixed step of every cloth: sync, then all substeps of all phases, then the guard. */
export function clothFixedStep<W extends object>(world: W): W {
  const state = getClothWorld(world)
  if (state.frame.open) throw new ClothError('world', world, 'is between beginClothStep and endClothStep (call endClothStep first)')
  refuseNestedStep(state, world)
  startFixedStep(world, true)
  finishFixedStep(world)
  return world
}

/** Throws a ClothError when called from a listener of a step (they may change the world, not step it). */
export function refuseNestedStep(state: ClothWorldState, world: object): void {
  if (state.frame.delivering) {
    throw new ClothError('world', world, "is calling a step's listeners: they may change the world but not step it")
  }
}

/**
 * First half of a fixed step: the sync phase (the only one that reads transforms), then the
 * substeps and the guard go to the workers, or wait for `finishFixedStep` and run there on this
 * thread: in every mode the step's results appear, and its listeners run, at its finish. In a
 * threaded world, `blocking` (the caller finishes the step right away) keeps a step too small to
 * pay for the handoff on this thread; otherwise (`beginClothStep`, and `endClothStepAsync` between
 * steps) the game may read meshes before the finish, so the meshes read before are brought up to
 * date first (the last finished step's, see `refreshFrameMeshes`).
 */
export function startFixedStep(world: object, blocking: boolean): void {
  const state = getClothWorld(world)
  clothSync(world)
  state.scheduledWritebacks = -1 // (a step of its own: the phase systems' count is not kept)
  if (!blocking) {
    refreshFrameMeshes(state)
    refreshFrameProxies(state)
  }
  // removals from here to the step's results wait for them (world/flight.ts)
  state.frame.inFlight = true
  if (state.threads !== null && dispatchClothStep(state, state.threads, blocking)) return
  state.frame.deferred = true
}

/**
 * The substeps of a fixed step, for every cloth of the world (on this thread, or a worker's
 * share): forces, predict, solve, collide, tear, writeback at each substep, in the order above.
 *
 * A cloth's substeps touch only that cloth and what the sync phase fixed for the step (pin
 * targets, collider frames, wind), so each cloth runs all its substeps before the next cloth
 * starts: its particles stay in the core's cache from one phase and substep to the next instead of
 * every phase streaming the whole world through it (the 64-cape crowd: see the budget benchmark).
 * Cloths that collide with themselves or each other (`selfCloths`) are joined within a substep by
 * their contacts: they run after the others, together, phase by phase (and the step's tear events
 * are put back in cloth order). Either way each cloth computes the same numbers in the same order:
 * the results are the same bytes as the phase systems run by hand.
 */
function runSubsteps(world: object): void {
  const state = getClothWorld(world)
  const n = state.substepCount
  const cloths = state.cloths
  const group = state.collision.selfCloths
  const tornFrom = state.tearing.pendingCount // (the step's events follow)
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    if (c.collision.self !== null) continue // (with its group, below)
    for (let s = 0; s < n; s++) {
      state.substep = s
      forcesOfCloth(state, c)
      predictOfCloth(state, c)
      solveOfCloth(state, c)
      collideOfCloth(state, c)
      tearOfCloth(state, c)
      writebackOfCloth(state, c)
    }
  }
  if (group.length > 0) {
    const tornBefore = state.tearing.pendingCount
    for (let s = 0; s < n; s++) {
      state.substep = s
      for (let q = 0; q < group.length; q++) forcesOfCloth(state, group[q])
      for (let q = 0; q < group.length; q++) predictOfCloth(state, group[q])
      for (let q = 0; q < group.length; q++) solveOfCloth(state, group[q])
      collideSelfColliding(state)
      for (let q = 0; q < group.length; q++) tearOfCloth(state, group[q])
      for (let q = 0; q < group.length; q++) writebackOfCloth(state, group[q])
    }
    if (tornBefore > tornFrom && state.tearing.pendingCount > tornBefore) orderTearEvents(state, tornFrom)
  }
  if (n > 0) state.substep = n - 1 // (where the loop by phases leaves it)
}

/** The substeps of every cloth here on this thread, then the guard (timed when the budget asks). */
function runStep(world: object): void {
  const state = getClothWorld(world)
  const timing = state.budget.timing
  // a time budget that adapts times one step before each allocation (the sync phase decides)
  const timed = state.budget.timeNext
  if (timed) timing[Q_T0] = performance.now()
  runSubsteps(world)
  clothGuard(world)
  if (timed) timing[Q_MEASURED] = performance.now() - timing[Q_T0]
}

/**
 * Second half: waits for the workers if they have the step and takes their results (the guard's
 * resets, tear events), or runs the substeps and the guard here; then delivers the guard's resets,
 * counts the substeps and delivers the tear events. In every mode the listeners run here, with a
 * frame (`stepCloth`'s too) still open: they may change the world, as between frames, but not step it.
 */
export function finishFixedStep(world: object): void {
  const state = getClothWorld(world)
  const th = state.threads
  const f = state.frame
  if (th !== null && th.phase === 1) waitForWorkers(th.pool, th.step)
  // the step is done: listeners (guard resets, tears) may change the world
  f.delivering = true
  try {
    const threaded = th !== null && th.phase === 1
    try {
      landStores(state, threaded)
      if (threaded) collectClothStep(state, th)
      else if (f.deferred) {
        f.deferred = false
        runStep(world) // (its guard leaves the reset listeners to deliverResets below)
      }
    } finally {
      // entities removed while the step was in flight go now, at the same point in every mode,
      // before any listener (their cloths' events of this step are dropped with them)
      landRemovals(state)
    }
    f.stepping = false // (the workers ran the guard)
    deliverResets(state) // (the step's resets, from the workers or from its guard here)
    clothEvents(world)
  } finally {
    f.delivering = false
  }
}

/** Number of global substeps in the current fixed step (set by `clothSync`). */
export function clothSubstepCount(world: object): number {
  return getClothWorld(world).substepCount
}

/** Selects the global substep the per-substep phases work on next. */
export function setClothSubstep(world: object, s: number): void {
  const state = getClothWorld(world)
  state.substep = checkInteger('s', s, 0, Math.max(0, state.substepCount - 1))
}

/**
 * Worker: runs the step for the cloths of `ww` (read in by `readStepInputs`): every substep's
 * phases, then the guard's check of each cloth; writes the cloths' handoff blocks and the worker's
 * output block (`out`).
 */
export function runWorkerStep(ww: WorkerWorld, list: Int32Array, out: Float64Array): void {
  // the clock only for the budget's timed steps (performance.now allocates)
  const timed = ww.state.budget.timeNext
  const t0 = timed ? performance.now() : 0
  const world = ww.world
  const state = ww.state
  state.sleep.count = 0
  state.tearing.pendingCount = 0
  runSubsteps(world)
  const n = list[0]
  for (let i = 1; i <= n; i++) {
    const io = ww.ios[list[i]]!
    const c = ww.cloths[list[i]]!
    if (c.subIndex >= 0) setGuardAnchor(c)
    io[IO_HEALTH] = guardCheck(state, c)
  }
  for (let i = 1; i <= n; i++) writeClothHandoff(ww.cloths[list[i]]!, ww.ios[list[i]]!)
  takeStats(state.stats, out, 0)
  out[OUT_SLEPT] = state.sleep.count
  const tw = state.tearing
  const events = Math.min(tw.pendingCount, ((out.length - OUT_EVENTS) / EV) | 0)
  out[OUT_TEARS] = events
  for (let i = 0; i < events * EV; i++) out[OUT_EVENTS + i] = tw.pending[i]
  out[OUT_MS] = timed ? performance.now() - t0 : 0
}
