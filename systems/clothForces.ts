import { getClothWorld } from '../src/world/access'
import type { ClothState, ClothWorldState } from '../src/world/state'
import { localSubstep } from '../src/world/stats'
import { applyWind } from '../src/features/wind/step'

/**
 * Forces phase, every substep: fills each cloth's extra per-particle acceleration (aerodynamics
 * from wind zones). Gravity needs no array: the predict kernel adds it directly. A cloth nothing
 * pushes keeps `accel` null and the predict kernel skips the term, so a scene without wind pays
 * nothing here. It also picks which cloths run this substep (`subIndex`; a cloth idle this step, asleep or held back by its level of detail, runs none).
 */
export function clothForces<W extends object>(world: W): W {
  const state = getClothWorld(world)
  const cloths = state.cloths
  for (let ci = 0; ci < cloths.length; ci++) forcesOfCloth(state, cloths[ci])
  return world
}

/** The forces phase of one cloth at the world's substep `state.substep`. */
export function forcesOfCloth(state: ClothWorldState, c: ClothState): void {
  c.subIndex = c.idle ? -1 : localSubstep(c.substeps, state.substep, state.substepCount)
  if (c.subIndex >= 0 && c.wind !== null) applyWind(state, c)
}
