/**
 * Tear phase, on each cloth's last substep of a step, after collisions: breaks over-strained edges
 * of tearable cloths. (Tearing arrives with the tearing feature; until then this phase does no
 * work.)
 */
export function clothTear<W extends object>(world: W): W {
  return world
}
