import { predictPositions } from '../src/kernels/integrate'
import { placePins } from '../src/pins'
import { getClothWorld } from '../src/state'

/**
 * Predict phase, every substep: integrates free particles (gravity, extra acceleration, damping)
 * to predicted positions, then places pinned particles on their targets, interpolated through the
 * step.
 */
export function clothPredict<W extends object>(world: W): W {
  const state = getClothWorld(world)
  const g = state.gravity
  for (const c of state.cloths) {
    const k = c.subIndex
    if (k < 0) continue
    const h = c.h
    const damp = Math.exp(-c.damping * h)
    predictPositions(c.pos, c.prev, c.vel, c.invMass, c.accel, g[0], g[1], g[2], h, damp, c.count)
    state.stats.particlesIntegrated += c.count
    if (c.pins.length > 0) placePins(state, c, k, c.substeps, h)
  }
  return world
}
