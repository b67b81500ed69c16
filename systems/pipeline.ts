import { ClothError, checkInteger } from '../src/core/errors'
import { getClothWorld } from '../src/world/access'
import type { ClothWorldState } from '../src/world/state'
import { clothCollide } from './clothCollide'
import { clothForces } from './clothForces'
import { clothGuard } from './clothGuard'
import { clothPredict } from './clothPredict'
import { clothSolve } from './clothSolve'
import { clothSync } from './clothSync'
import { clothTear } from './clothTear'
import { clothWriteback } from './clothWriteback'
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
 * schedule systems themselves, each checking that no frame is open.
 */

/** Runs one fixed step of every cloth: sync, then all substeps of all phases. */
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
  if (!blocking) {
    refreshFrameMeshes(state)
    refreshFrameProxies(state)
  }
  // removals from here to the step's results wait for them (world/flight.ts)
  state.frame.inFlight = true
  if (state.threads !== null && dispatchClothStep(state, state.threads, blocking)) return
  state.frame.deferred = true
}

/** The substeps of every cloth here on this thread, then the guard (timed when the budget asks). */
function runSubsteps(world: object): void {
  const state = getClothWorld(world)
  const timing = state.budget.timing
  // a time budget that adapts times one step before each allocation (the sync phase decides)
  const timed = state.budget.timeNext
  if (timed) timing[Q_T0] = performance.now()
  for (let s = 0; s < state.substepCount; s++) {
    state.substep = s
    clothForces(world)
    clothPredict(world)
    clothSolve(world)
    clothCollide(world)
    clothTear(world)
    clothWriteback(world)
  }
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
        runSubsteps(world) // (its guard leaves the reset listeners to deliverResets below)
      }
    } finally {
      // entities removed while the step was in flight go now, at the same point in every mode,
      // before any listener (their cloths' events of this step are dropped with them)
      landRemovals(state)
    }
    f.stepping = false // (the workers ran the guard)
    deliverResets(state) // (the step's resets, from the workers or from its guard here)
    state.stats.substeps += state.substepCount
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
