import { rebuildTethers } from '../src/cloth'
import { samplePinTargets } from '../src/pins'
import { getClothWorld } from '../src/state'

/**
 * Sync phase, once per fixed step before the substeps: picks the step's substep count, rebuilds
 * tethers of cloths whose pins changed, and samples every pin target's Transform (detecting
 * teleports). This is the only phase that reads transforms for pins.
 */
export function clothSync<W extends object>(world: W): W {
  const state = getClothWorld(world)
  let total = 0
  for (const c of state.cloths) {
    if (c.substeps > total) total = c.substeps
    if (c.tethersDirty) rebuildTethers(state, c)
    samplePinTargets(state, c)
  }
  state.substepCount = total
  state.substep = 0
  state.stats.steps++
  return world
}
