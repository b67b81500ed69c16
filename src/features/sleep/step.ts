import { P_MAX_V2 } from '../../kernels/params'
import { SHAPE_PLANE } from '../../core/shapes'
import { particleBounds } from '../../kernels/mesh'
import type { ClothState, ClothWorldState } from '../../world/state'
import { wakeClothState } from '../../world/wake'
import {
  boxClear,
  clothLayersMatch,
  colliderLayersMatch,
  colliderReachedBeforeJump,
  colliderReaches,
  planeUnchanged,
  selfReaches,
} from '../collision/reach'
import { windReaches } from '../wind/step'
import { B_REFRESH } from '../collision/types'

/**
 * Writeback phase, after a cloth's last substep: advances its stillness timer from the fastest
 * particle of the substep (`params[P_MAX_V2]`) and puts it to sleep once it was still long enough.
 */
export function updateSleep(state: ClothWorldState, c: ClothState): void {
  const s = c.sleep
  if (!s.enabled) return
  if (!(c.params[P_MAX_V2] <= s.speed2)) {
    s.still = 0
    return
  }
  s.still += c.h * c.substeps // the cloth's step (longer when it steps every n-th)
  if (s.still < s.delay) return
  s.still = 0
  // the box it would sleep in (what the wake tests look at)
  particleBounds(c.pos, c.count, s.bounds, 0, c.topology.unused)
  // still in a steady wind: the wind may change any time, so stay awake (and test again after
  // another delay)
  if (state.wind.zones.length > 0 && windReaches(state, s.bounds)) return
  s.asleep = true
  state.sleep.count++
  c.vel.fill(0, 0, 3 * c.count)
  c.collision.bounds[B_REFRESH] = 1 // (its bounds and hash made again from where it sleeps)
  const g = state.gravity
  state.sleep.gravity[0] = g[0]
  state.sleep.gravity[1] = g[1]
  state.sleep.gravity[2] = g[2]
}

/**
 * Sync phase, after the transforms, collider sweeps and wind zones of the step are known: wakes
 * every sleeping cloth that something now disturbs. Nothing to do (one comparison) while no cloth
 * sleeps.
 */
export function wakeSleepers(state: ClothWorldState): void {
  const sw = state.sleep
  if (sw.count === 0) return
  const cloths = state.cloths
  const g = state.gravity, sg = sw.gravity
  const gravityChanged = g[0] !== sg[0] || g[1] !== sg[1] || g[2] !== sg[2]
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    if (c.sleep.asleep && (gravityChanged || disturbed(state, c))) wakeClothState(state, c)
  }
}

function disturbed(state: ClothWorldState, c: ClothState): boolean {
  const k = state.kinematics
  const P = state.components.Pin
  const pins = c.pins.list
  for (let q = 0; q < pins.length; q++) {
    const pin = pins[q]
    const slot = P.slot[pin]
    if ((slot >= 0 && k.moved[slot] === 1) || P.blendLeft[pin] > 0) return true
  }
  const b = c.sleep.bounds
  const cw = state.collision
  const colliders = cw.entries // (a removed one, not yet compacted, has slot −1: skipped below)
  if (colliders.length > 0) {
    const C = cw.Collider
    const cc = c.collision
    const sw = C.swept
    for (let q = 0; q < colliders.length; q++) {
      const e = colliders[q]
      const slot = C.slot[e]
      if (slot < 0 || k.moved[slot] !== 1) continue
      // a solid that did not jump and whose swept box stays clear of the cloth's disturbs nothing
      // (the box test first: with the full tests' calls for every pair, 500 sleeping cloths and 64
      // colliders moving far from them cost 2.3× a cape's step)
      if (k.jumped[slot] === 0 && C.shape[e] !== SHAPE_PLANE && boxClear(sw, 8 * e, b, c)) continue
      // a collider that jumped is tested where it was before the jump too (the jump does not sweep);
      // a plane that only slid or turned within itself (a ground carried by a running character)
      // is the same surface and disturbs nothing
      if (
        colliderLayersMatch(C, e, cc) &&
        ((colliderReaches(C, e, b, c) && !planeUnchanged(C, e)) || colliderReachedBeforeJump(state, e, b, c))
      ) return true
    }
  }
  if (state.wind.zones.length > 0 && windReaches(state, b)) return true
  return c.collision.self !== null && selfNeighbourMoves(state, c)
}

/**
 * Whether an awake self-colliding cloth that can touch the sleeper `c` moves (its last step was not
 * still by its own sleep speed: `still` 0) within reach of it (`selfReaches`). One still, like a
 * napkin settled on a sleeping one, disturbs nothing: woken by any awake neighbour in reach, two
 * settled napkins slept in turns, each waking the other, for good (every phase run, 100× the cost
 * of both asleep). The stillness timer and the positions are what snapshots save (restored into a
 * fresh world, a test of the collision bounds read zeros and a napkin stayed asleep).
 */
function selfNeighbourMoves(state: ClothWorldState, c: ClothState): boolean {
  const group = state.collision.selfCloths
  const ca = c.collision
  for (let q = 0; q < group.length; q++) {
    const o = group[q]
    if (o === c || o.sleep.asleep || o.budget.frozen || o.sleep.still > 0) continue
    if (clothLayersMatch(ca, o.collision) && selfReaches(o, c)) return true
  }
  return false
}
