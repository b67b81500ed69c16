import { beginCollisionStep, collideSubstep } from '../src/features/collision/step'
import { getClothWorld } from '../src/world/access'

/**
 * Collide phase, every substep, after the constraint solve: particle–particle contacts of cloths
 * with self-collision, then each cloth against the colliders in range (pushed out to the surface
 * plus the cloth's thickness, with friction against the moving surface). On a step's first
 * substep it also runs the broadphase (swept collider bounds against cloth bounds, layers) and
 * builds the self-collision hashes. A world without colliders or self-collision does no work here.
 */
export function clothCollide<W extends object>(world: W): W {
  const state = getClothWorld(world)
  const cw = state.collision
  if (cw.colliders.length === 0 && cw.selfCloths.length === 0) return world
  if (state.substep === 0) beginCollisionStep(state)
  collideSubstep(state)
  return world
}
