import { getClothWorld } from '../src/world/access'
import { dispatchTearEvents } from '../src/features/tearing/events'

/**
 * Events phase, once per fixed step after the substeps: hands the step's tear events to the
 * `onClothTear` listeners and the `drainClothTears` queue. It runs outside the solver, so a
 * listener may change the world (remove a cloth, add a pin). Nothing to do without tears.
 */
export function clothEvents<W extends object>(world: W): W {
  dispatchTearEvents(getClothWorld(world))
  return world
}
