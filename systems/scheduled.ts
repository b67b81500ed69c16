import { ClothError } from '../src/core/errors'
import { getClothWorld } from '../src/world/access'
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
 * particles and a phase run here would race them.
 */
function outsideFrame(world: object): void {
  const f = getClothWorld(world).frame
  if (f.open && !f.delivering) {
    throw new ClothError(
      'world',
      world,
      'is between beginClothStep and endClothStep: run the phase systems outside a frame (after endClothStep)',
    )
  }
}

export function clothSync<W extends object>(world: W): W {
  outsideFrame(world)
  return sync(world)
}

export function clothForces<W extends object>(world: W): W {
  outsideFrame(world)
  return forces(world)
}

export function clothPredict<W extends object>(world: W): W {
  outsideFrame(world)
  return predict(world)
}

export function clothSolve<W extends object>(world: W): W {
  outsideFrame(world)
  return solve(world)
}

export function clothCollide<W extends object>(world: W): W {
  outsideFrame(world)
  return collide(world)
}

export function clothTear<W extends object>(world: W): W {
  outsideFrame(world)
  return tear(world)
}

export function clothWriteback<W extends object>(world: W): W {
  outsideFrame(world)
  return writeback(world)
}

export function clothGuard<W extends object>(world: W): W {
  outsideFrame(world)
  return guard(world)
}

export function clothEvents<W extends object>(world: W): W {
  outsideFrame(world)
  return events(world)
}

/**
 * The per-substep phases in the pipeline's order (see `pipeline.ts`), for engines that schedule
 * systems themselves: such an engine runs `clothSync`, then each phase once per
 * `clothSubstepCount(world)` with `setClothSubstep(world, s)` before each round, then `clothGuard`
 * and `clothEvents`, or simply calls `clothFixedStep`.
 */
export const clothPhases = [clothForces, clothPredict, clothSolve, clothCollide, clothTear, clothWriteback] as const
