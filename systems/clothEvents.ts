import { deliverToListeners, getClothWorld } from '../src/world/access'
import { dispatchTearEvents } from '../src/features/tearing/events'
import { noteShownAnchors } from '../src/draw'

/**
 * Events phase, once per fixed step after the substeps: counts the step's substeps
 * (`getClothStats`), notes where each cloth that ran the step
 * shows its anchor (for `getClothDrawTransform` while it sits steps out), then hands the step's
 * tear events to the `onClothTear` listeners and the `drainClothTears` queue. It runs outside the
 * solver, so a listener may change the world (remove a cloth, add a pin).
 */
export function clothEvents<W extends object>(world: W): W {
  const state = getClothWorld(world)
  state.stats.substeps += state.substepCount // (here, so that a step run phase by phase by hand counts too)
  noteShownAnchors(state)
  // listeners may change the world but not step it (a nested step overwrote the tear events being read)
  deliverToListeners(state, dispatchTearEvents)
  return world
}
