import { rebuildTethers } from '../src/cloth'
import { beginKinematicStep, sampleFrame } from '../src/kinematics'
import { followTargetJumps } from '../src/pins'
import { getClothWorld } from '../src/state'
import { advanceWind } from '../src/wind'

/**
 * Sync phase, once per fixed step before the substeps: picks the step's substep count, advances
 * the tracked transforms (pin targets) to this step's time slice, taking a new frame sample on a
 * frame's first step and carrying cloths along when their targets jumped, and rebuilds tethers of
 * cloths whose pins changed. This is the only phase that reads transforms.
 */
export function clothSync<W extends object>(world: W): W {
  const state = getClothWorld(world)
  const k = state.kinematics
  const frameStart = !k.framed || k.newFrame
  if (frameStart) {
    sampleFrame(state)
    k.newFrame = false
  }
  beginKinematicStep(k)
  let total = 0
  const cloths = state.cloths
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    if (c.substeps > total) total = c.substeps
    if (frameStart) followTargetJumps(state, c)
    if (c.tethersDirty) rebuildTethers(state, c)
  }
  state.substepCount = total
  state.substep = 0
  state.stats.steps++
  advanceWind(state) // wind time, gusts and zone poses for this step (nothing without zones)
  return world
}
