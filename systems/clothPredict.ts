import { predictPositions } from '../src/kernels/integrate'
import { setSubstepParams } from '../src/kernels/params'
import { placePins } from '../src/features/pins/step'
import { getClothWorld } from '../src/world/access'
import type { ClothState, ClothWorldState } from '../src/world/state'
import { clampSelfCollidingMotion } from '../src/features/collision/selfCollision'
import { placeHeld, predictCharacter } from '../src/features/character/step'

/**
 * Predict phase, every substep: fills the cloth's kernel parameters for the substep, integrates
 * free particles (gravity, extra acceleration, damping) to predicted positions (in its frame for a
 * cloth with inertia settings), then places particles held on a character cloth's reference and
 * pinned particles on their targets, interpolated through the step, and clamps a self-colliding
 * cloth's predicted relative motion to what its pair list covers.
 */
export function clothPredict<W extends object>(world: W): W {
  const state = getClothWorld(world)
  const cloths = state.cloths
  for (let ci = 0; ci < cloths.length; ci++) predictOfCloth(state, cloths[ci])
  return world
}

/** The predict phase of one cloth at the world's substep. */
export function predictOfCloth(state: ClothWorldState, c: ClothState): void {
  const k = c.subIndex
  if (k < 0) return
  setSubstepParams(c.params, c.h, c.damping, state.gravity, state.maxSpeed)
  const ch = c.character
  if (ch === null || !predictCharacter(c, k)) predictPositions(c.pos, c.prev, c.vel, c.invMass, c.accel, c.params, c.count)
  if (ch !== null && ch.heldCount > 0) placeHeld(c)
  state.stats.particlesIntegrated += c.count
  if (c.pins.list.length > 0) placePins(state, c, k, c.substeps)
  if (c.collision.self !== null) clampSelfCollidingMotion(state, c)
}
