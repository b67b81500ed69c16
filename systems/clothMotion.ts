import { getClothWorld } from '../src/world/access'
import { constrainCharacter } from '../src/features/character/step'

/**
 * Motion phase, every substep, after the collisions: character cloths with motion constraints
 * (`setClothMotionConstraints`) are held within their max distance of the reference pose, outside
 * their backstop and pulled by their drive. Last of the phases that move particles, so the limits
 * hold at the end of every substep. A cloth without them costs one null check.
 */
export function clothMotion<W extends object>(world: W): W {
  const state = getClothWorld(world)
  const cloths = state.cloths
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    if (c.subIndex < 0 || c.character === null || c.character.limits === null) continue
    constrainCharacter(c, c.subIndex)
  }
  return world
}
