import { ClothError } from '../src/core/errors'
import { getClothWorld } from '../src/world/access'
import { refuseNestedStep } from './pipeline'
import { clothCollide as collide } from './clothCollide'
import { clothEvents as events } from './clothEvents'
import { clothForces as forces } from './clothForces'
import { clothGuard as guard } from './clothGuard'
import { clothPredict as predict } from './clothPredict'
import { clothSolve as solve } from './clothSolve'
import { clothSync as sync } from './clothSync'
import { clothTear as tear } from './clothTear'
import { clothWriteback as writeback } from './clothWriteback'

/**
 * The phase systems as an engine with its own scheduler calls them (the package exports these;
 * the pipeline in `pipeline.ts` calls the unchecked ones): each first checks that the world is not
 * between `beginClothStep` and `endClothStep`, when the workers of a threaded world own the
 * particles and a phase run here would race them, nor calling a step's listeners (which may change
 * the world but not step it: a nested step overwrote the tear events being delivered).
 */
function outsideFrame(world: object): void {
  const state = getClothWorld(world)
  refuseNestedStep(state, world)
  const f = state.frame
  if (f.open) {
    throw new ClothError(
      'world',
      world,
      'is between beginClothStep and endClothStep: run the phase systems outside a frame (after endClothStep)',
    )
  }
}

/** `phase`, first checking that no frame is open; it keeps the phase's name (or takes `name`). */
function checked(phase: <W extends object>(world: W) => W, name = phase.name): <W extends object>(world: W) => W {
  const run = <W extends object>(world: W): W => {
    outsideFrame(world)
    return phase(world)
  }
  Object.defineProperty(run, 'name', { value: name })
  return run
}

/**
 * The sync phase, once per fixed step before the substeps (reads the Transforms). Throws a
 * ClothError between `beginClothStep` and `endClothStep`.
 */
export const clothSync = checked(<W extends object>(world: W): W => {
  sync(world)
  getClothWorld(world).scheduledWritebacks = 0
  return world
}, sync.name)
/** The forces phase of a substep (wind and other accelerations). Throws a ClothError between `beginClothStep` and `endClothStep`. */
export const clothForces = checked(forces)
/** The predict phase of a substep (integration; pinned and held particles placed). Throws a ClothError between `beginClothStep` and `endClothStep`. */
export const clothPredict = checked(predict)
/** The solve phase of a substep (bending, distance constraints, tethers). Throws a ClothError between `beginClothStep` and `endClothStep`. */
export const clothSolve = checked(solve)
/** The collide phase of a substep (colliders, self-collision). Throws a ClothError between `beginClothStep` and `endClothStep`. */
export const clothCollide = checked(collide)
/** The tear phase of a substep (overstretched edges split at the step's last substep). Throws a ClothError between `beginClothStep` and `endClothStep`. */
export const clothTear = checked(tear)
/** The writeback phase of a substep (motion constraints, velocities, sleep). Throws a ClothError between `beginClothStep` and `endClothStep`. */
export const clothWriteback = checked(<W extends object>(world: W): W => {
  writeback(world)
  const state = getClothWorld(world)
  if (state.scheduledWritebacks >= 0) state.scheduledWritebacks++
  return world
}, writeback.name)
/**
 * The guard phase, once after the substeps (explosion guard). Throws a ClothError between
 * `beginClothStep` and `endClothStep`, and when the substep phases ran fewer rounds since
 * `clothSync` than `clothSubstepCount(world)` (run once per fixed step, every cloth went at a
 * fraction of its speed: a falling sheet at 1/8 of g with 8 substeps).
 */
export const clothGuard = checked(<W extends object>(world: W): W => {
  const state = getClothWorld(world)
  const ran = state.scheduledWritebacks
  state.scheduledWritebacks = -1 // (the guard alone, after a step run otherwise, checks nothing here)
  if (ran >= 0 && ran < state.substepCount) {
    state.frame.stepping = false // (the step is abandoned: the world may change again)
    throw new ClothError(
      'world',
      world,
      `ran the substep phases ${ran} times since clothSync, for ${state.substepCount} substeps: run each of clothPhases once per clothSubstepCount(world) (setClothSubstep(world, s) before each round), or call clothFixedStep`,
    )
  }
  return guard(world)
}, guard.name)
/** The events phase, after the step (tear and reset listeners). Throws a ClothError between `beginClothStep` and `endClothStep`. */
export const clothEvents = checked(events)

/**
 * The per-substep phases in the pipeline's order (see `pipeline.ts`), for engines that schedule
 * systems themselves: such an engine runs `clothSync`, then each phase once per
 * `clothSubstepCount(world)` with `setClothSubstep(world, s)` before each round, then `clothGuard`
 * and `clothEvents`, or simply calls `clothFixedStep`.
 */
export const clothPhases = [clothForces, clothPredict, clothSolve, clothCollide, clothTear, clothWriteback] as const
