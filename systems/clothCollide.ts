/**
 * Collide phase, every substep, after the constraint solve: pushes particles out of colliders and
 * applies friction. (Colliders arrive with the collision feature; until then this phase does no
 * work.)
 */
export function clothCollide<W extends object>(world: W): W {
  return world
}
