import { beginClothCollision, beginCollisionStep, collideClothColliders, collideSubstep } from '../src/features/collision/step'
import { getClothWorld } from '../src/world/access'
import type { ClothState, ClothWorldState } from '../src/world/state'

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
  // (entries not yet compacted count too: the step's broadphase reads the live ones)
  if (cw.entries.length === 0 && cw.selfCloths.length === 0) return world
  if (state.substep === 0) beginCollisionStep(state)
  collideSubstep(state)
  return world
}

/**
 * The collide phase of one cloth that collides with neither itself nor other cloths, at the world's
 * substep (the cloths that do run together: see `runSubsteps` in pipeline.ts).
 */
export function collideOfCloth(state: ClothWorldState, c: ClothState): void {
  if (state.collision.entries.length === 0) return
  if (state.substep === 0) beginClothCollision(state, c)
  collideClothColliders(state, c)
}
