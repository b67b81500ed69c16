import { getClothWorld } from '../src/world/access'
import type { ClothState, ClothWorldState } from '../src/world/state'
import { tearStep } from '../src/features/tearing/step'

/**
 * Tear phase, on each cloth's last substep of a step, after collisions: measures the structural
 * edges of tearable cloths on their final pose and splits the mesh where an edge stayed
 * over-stretched (see `src/features/tearing/`). A cloth without `Tearable` costs one null check.
 */
export function clothTear<W extends object>(world: W): W {
  const state = getClothWorld(world)
  const cloths = state.cloths
  for (let ci = 0; ci < cloths.length; ci++) tearOfCloth(state, cloths[ci])
  return world
}

/** The tear phase of one cloth at the world's substep. */
export function tearOfCloth(state: ClothWorldState, c: ClothState): void {
  if (c.tear !== null && c.subIndex === c.substeps - 1) tearStep(state, c)
}
