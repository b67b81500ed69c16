import type { ColliderStore } from '../../../components/Collider'
import { SHAPE_PLANE } from '../../core/shapes'
import type { ClothState, ClothWorldState } from '../../world/state'
import { wakeClothState } from '../../world/wake'
import type { ClothCollision } from './types'
import { newArray } from '../../core/shared'

/** Which colliders reach which cloths: layers, swept bounds, per-cloth collider lists. */

/**
 * Whether collider `e`'s swept bounds come within the cloth's thickness of the box `b` (min xyz,
 * max xyz); a plane, whether the box's lowest point along the normal, at the step's start or end
 * pose, is nearer than the thickness.
 */
export function colliderReaches(C: ColliderStore, e: number, b: Float64Array, c: ClothState): boolean {
  const cc = c.collision
  const r = cc.thickness > 0 ? cc.thickness : c.material.thickness
  const o = 8 * e
  const sw = C.swept
  if (C.shape[e] === SHAPE_PLANE) {
    const cx = 0.5 * (b[0] + b[3]), cy = 0.5 * (b[1] + b[4]), cz = 0.5 * (b[2] + b[5])
    const ex = 0.5 * (b[3] - b[0]), ey = 0.5 * (b[4] - b[1]), ez = 0.5 * (b[5] - b[2])
    const d0 = sw[o] * cx + sw[o + 1] * cy + sw[o + 2] * cz - Math.abs(sw[o]) * ex - Math.abs(sw[o + 1]) * ey - Math.abs(sw[o + 2]) * ez -
      sw[o + 3]
    const d1 = sw[o + 4] * cx + sw[o + 5] * cy + sw[o + 6] * cz - Math.abs(sw[o + 4]) * ex - Math.abs(sw[o + 5]) * ey -
      Math.abs(sw[o + 6]) * ez - sw[o + 7]
    return d0 < r || d1 < r
  }
  return !(
    sw[o] > b[3] + r || sw[o + 3] < b[0] - r ||
    sw[o + 1] > b[4] + r || sw[o + 4] < b[1] - r ||
    sw[o + 2] > b[5] + r || sw[o + 5] < b[2] - r
  )
}

/** Whether cloth `cc` and collider `eid` may touch (each one's layer is in the other's mask). */
export function colliderLayersMatch(C: ColliderStore, eid: number, cc: ClothCollision): boolean {
  return (C.layer[eid] & cc.mask) !== 0 && (C.mask[eid] & cc.layer) !== 0
}

/** Whether two cloths' layers and masks let them collide with each other (both ways). */
export function clothLayersMatch(a: ClothCollision, b: ClothCollision): boolean {
  return (a.layer & b.mask) !== 0 && (b.layer & a.mask) !== 0
}

/** Resets every cloth's collider list (a collider went away mid-step; the next step rebuilds them). */
export function clearActiveColliders(state: ClothWorldState): void {
  for (let ci = 0; ci < state.cloths.length; ci++) state.cloths[ci].collision.activeCount = 0
}

/** Grows every cloth's collider list to hold all colliders (at collider creation, never in a step). */
export function reserveActiveColliders(state: ClothWorldState): void {
  const n = state.collision.colliders.length
  for (let ci = 0; ci < state.cloths.length; ci++) {
    const cc = state.cloths[ci].collision!
    if (cc.active.length < n) {
      const grown = newArray(Int32Array, Math.max(n, 2 * cc.active.length))
      grown.set(cc.active)
      cc.active = grown
    }
  }
}

/**
 * Wakes the sleeping cloths whose bounds collider `e`'s last swept bounds reach: called when a
 * collider appears (after its first sweep) or goes away (a cloth resting on it must fall).
 */
export function wakeAroundCollider(state: ClothWorldState, e: number): void {
  if (state.sleep.count === 0) return
  const C = state.collision.Collider
  const cloths = state.cloths
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    if (c.sleep.asleep && colliderLayersMatch(C, e, c.collision) && colliderReaches(C, e, c.sleep.bounds, c)) wakeClothState(state, c)
  }
}
