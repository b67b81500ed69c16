import { updateVelocities } from '../src/kernels/integrate'
import { dampPairs } from '../src/kernels/damping'
import { P_STRETCH_DAMP } from '../src/kernels/params'
import { getClothWorld } from '../src/world/access'
import type { ClothState, ClothWorldState } from '../src/world/state'
import { updateSleep } from '../src/features/sleep/step'
import { writebackCharacter } from '../src/features/character/step'

/**
 * Writeback phase, every substep: reads velocities back from the substep's motion (v = Δx/h,
 * clamped to the world's speed limit), after holding a character cloth with motion constraints to
 * them (one pass for both). After a cloth's last substep of the step it damps stretch
 * vibration along structural edges (the material's `stretchDamping`), advances the sleep timer
 * (a cloth still long enough falls asleep) and marks the render mesh stale.
 */
export function clothWriteback<W extends object>(world: W): W {
  const state = getClothWorld(world)
  const cloths = state.cloths
  for (let ci = 0; ci < cloths.length; ci++) writebackOfCloth(state, cloths[ci])
  return world
}

/** The writeback phase of one cloth at the world's substep. */
export function writebackOfCloth(state: ClothWorldState, c: ClothState): void {
  const k = c.subIndex
  if (k < 0) return
  const ch = c.character
  if (ch !== null && ch.constrained) writebackCharacter(c)
  else updateVelocities(c.pos, c.prev, c.vel, c.params, c.count)
  if (k !== c.substeps - 1) return
  // once per step: damping the relative velocity along the edges once a step settles a stiff
  // sheet's buzz at a fraction of the cost of a pass per substep
  if (c.stretchDamping > 0) {
    const t = c.topology
    c.params[P_STRETCH_DAMP] = 1 - Math.exp(-c.stretchDamping * c.h * c.substeps) // the cloth's step (longer when it steps every n-th)
    dampPairs(c.pos, c.vel, c.invMass, t.stretchIds, t.stretchCount, c.params)
  }
  updateSleep(state, c)
  c.version++
}
