import { deliverResets, guardCheck, restoreSafePose } from '../src/features/guard/step'
import { HEALTH_OK } from '../src/kernels/guard'
import { deliverToListeners, getClothWorld } from '../src/world/access'
import { placeHeldAfterReset, setGuardAnchor } from '../src/features/character/step'

/**
 * Guard phase, once per fixed step after the last substep: checks each cloth's health (finite,
 * within reach of its pins and a character cloth's reference pose, no runaway speed; one pass over
 * its particles) and puts a failing
 * cloth back into a safe pose with its velocities cleared, raising a reset event. Good steps copy
 * the pose as the next safe one (a character cloth's held particles go back onto their reference
 * pose after a reset). Listeners (`onClothReset`) are called at the end, after every cloth was
 * checked (for a step in flight, by `finishFixedStep`). A cloth whose guard is off, or that
 * sleeps, costs nothing here.
 */
export function clothGuard<W extends object>(world: W): W {
  const state = getClothWorld(world)
  const cloths = state.cloths
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    if (c.subIndex >= 0) setGuardAnchor(c)
    const health = guardCheck(state, c)
    if (health > HEALTH_OK) {
      restoreSafePose(state, c, health)
      if (c.character !== null) placeHeldAfterReset(c)
    }
  }
  state.frame.stepping = false
  // (a step started by `startFixedStep` has its listeners called by `finishFixedStep`, after what
  // was removed while it ran: the same moment as for the workers' resets)
  if (!state.frame.inFlight) deliverToListeners(state, deliverResets)
  return world
}
