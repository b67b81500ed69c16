import type { ColliderStore } from '../../../components/Collider'
import { multiplyQuatAt, rotateVecAt } from '../../core/math'
import { SHAPE_PLANE } from '../../core/shapes'
import type { ClothState, ClothWorldState } from '../../world/state'
import { wakeClothState } from '../../world/wake'
import type { ClothCollision } from './types'
import { newArray } from '../../core/shared'
import { particleBounds } from '../../kernels/mesh'
import { liveColliders } from './list'

/** Which colliders reach which cloths: layers, swept bounds, per-cloth collider lists. */

/**
 * Whether collider `e`'s swept bounds come within the cloth's thickness of the box `b` (min xyz,
 * max xyz); a plane, whether the box's lowest point along the normal, at the step's start or end
 * pose, is no farther than the thickness.
 */
export function colliderReaches(C: ColliderStore, e: number, b: Float64Array, c: ClothState): boolean {
  return boundsReach(C.swept, 8 * e, C.shape[e] === SHAPE_PLANE, b, c)
}

/**
 * Whether collider `e` is a plane whose surface (normal and offset) is the same at the step's start
 * and end: moved only along itself or turned about its normal.
 */
export function planeUnchanged(C: ColliderStore, e: number): boolean {
  if (C.shape[e] !== SHAPE_PLANE) return false
  const sw = C.swept, o = 8 * e
  return sw[o] === sw[o + 4] && sw[o + 1] === sw[o + 5] && sw[o + 2] === sw[o + 6] && sw[o + 3] === sw[o + 7]
}

/**
 * Whether collider `e`, whose body jumped farther than the teleport distance at this frame's
 * sample, came within the cloth's thickness of the box `b` at its pose before the jump (the body's
 * previous frame sample). A jump does not sweep: the step's swept bounds start at the new place,
 * so without this a collider teleported out from under a sleeping cloth would never be seen to
 * leave it. False for a collider whose body did not jump.
 */
export function colliderReachedBeforeJump(state: ClothWorldState, e: number, b: Float64Array, c: ClothState): boolean {
  const k = state.kinematics
  const C = state.collision.Collider
  const slot = C.slot[e]
  if (slot < 0 || k.jumped[slot] === 0) return false
  const t = before
  // the body before the jump: sampleFrom is its previous sample moved by the jump (p' = pivot + t
  // + R(p − pivot), q' = R·q), and that sample's position is the jump's pivot
  const j = 10 * slot
  t[0] = k.jump[j]
  t[1] = k.jump[j + 1]
  t[2] = k.jump[j + 2]
  t[7] = -k.jump[j + 3]
  t[8] = -k.jump[j + 4]
  t[9] = -k.jump[j + 5]
  t[10] = k.jump[j + 6]
  multiplyQuatAt(t, 7, k.sampleFrom, 7 * slot + 3, t, 3) // q = R⁻¹·q'
  // the collider on it: p = pb + qb·(s ⊙ offset), q = qb·ql (the scale of that sample)
  const so = 3 * slot
  t[7] = C.offset[3 * e] * k.scaleSampleFrom[so]
  t[8] = C.offset[3 * e + 1] * k.scaleSampleFrom[so + 1]
  t[9] = C.offset[3 * e + 2] * k.scaleSampleFrom[so + 2]
  rotateVecAt(t, 3, t, 7, t, 11)
  t[0] += t[11]
  t[1] += t[12]
  t[2] += t[13]
  multiplyQuatAt(t, 3, C.rotation, 4 * e, t, 3)
  // its bounds there, in the layout of `Collider.swept` (the same pose at both ends)
  const plane = C.shape[e] === SHAPE_PLANE
  const r4 = 4 * e
  if (plane) {
    rotateVecAt(t, 3, C.size, r4, t, 11)
    const d = t[11] * t[0] + t[12] * t[1] + t[13] * t[2] + C.size[r4 + 3]
    for (let h = 0; h < 8; h += 4) {
      box[h] = t[11]
      box[h + 1] = t[12]
      box[h + 2] = t[13]
      box[h + 3] = d
    }
  } else {
    rotateVecAt(t, 3, C.bound, r4, t, 11)
    const rad = C.bound[r4 + 3]
    for (let a = 0; a < 3; a++) {
      box[a] = t[a] + t[11 + a] - rad
      box[3 + a] = t[a] + t[11 + a] + rad
    }
  }
  return boundsReach(box, 0, plane, b, c)
}

/** Pose scratch of `colliderReachedBeforeJump`: position, rotation, a vector, a rotated vector. */
const before = new Float64Array(14)
/** Bounds scratch of `colliderReachedBeforeJump`, laid out as `Collider.swept`. */
const box = new Float64Array(8)

/** How much farther than the thickness a plane still reaches a cloth (m): rounding of a resting contact. */
const PLANE_SLACK = 1e-6

/** The reach test of `colliderReaches` on bounds sw[o..o + 8) laid out as `Collider.swept`. */
function boundsReach(sw: Float64Array, o: number, plane: boolean, b: Float64Array, c: ClothState): boolean {
  const cc = c.collision
  const r = cc.thickness >= 0 ? cc.thickness : c.material.thickness
  if (plane) {
    const cx = 0.5 * (b[0] + b[3]), cy = 0.5 * (b[1] + b[4]), cz = 0.5 * (b[2] + b[5])
    const ex = 0.5 * (b[3] - b[0]), ey = 0.5 * (b[4] - b[1]), ez = 0.5 * (b[5] - b[2])
    const d0 = sw[o] * cx + sw[o + 1] * cy + sw[o + 2] * cz - Math.abs(sw[o]) * ex - Math.abs(sw[o + 1]) * ey - Math.abs(sw[o + 2]) * ez -
      sw[o + 3]
    const d1 = sw[o + 4] * cx + sw[o + 5] * cy + sw[o + 6] * cz - Math.abs(sw[o + 4]) * ex - Math.abs(sw[o + 5]) * ey -
      Math.abs(sw[o + 6]) * ez - sw[o + 7]
    // (touching counts, as for the other shapes: a cloth resting on a plane lies at the thickness,
    // to rounding, and must see the plane leave; asleep there, it stayed in the air)
    const reach = r + PLANE_SLACK
    return d0 <= reach || d1 <= reach
  }
  return !boxClear(sw, o, b, c)
}

/**
 * Whether the box sw[o..o + 6) (min xyz, max xyz) lies more than the cloth `c`'s collision
 * thickness from the box `b`: the test of a solid collider's swept bounds (`colliderReaches`), small
 * enough to be inlined where it runs per pair (the sleep phase's wake test). (The cloth, not its
 * thickness, is passed: a double passed to a call that is not inlined is boxed.)
 */
export function boxClear(sw: Float64Array, o: number, b: Float64Array, c: ClothState): boolean {
  const cc = c.collision
  const r = cc.thickness >= 0 ? cc.thickness : c.material.thickness
  return sw[o] > b[3] + r || sw[o + 3] < b[0] - r || sw[o + 1] > b[4] + r || sw[o + 4] < b[1] - r ||
    sw[o + 2] > b[5] + r || sw[o + 5] < b[2] - r
}

/** Whether cloth `cc` and collider `eid` may touch (each one's layer is in the other's mask). */
export function colliderLayersMatch(C: ColliderStore, eid: number, cc: ClothCollision): boolean {
  return (C.layer[eid] & cc.mask) !== 0 && (C.mask[eid] & cc.layer) !== 0
}

/** Whether two cloths' layers and masks let them collide with each other (both ways). */
export function clothLayersMatch(a: ClothCollision, b: ClothCollision): boolean {
  return (a.layer & b.mask) !== 0 && (b.layer & a.mask) !== 0
}

/** Takes collider `e` out of every cloth's list of colliders in range (it went away, maybe mid-step). */
export function dropActiveCollider(state: ClothWorldState, e: number): void {
  // (only e: emptying the lists took every collider away for the rest of a step run by hand, and a
  // sheet on the ground sank 55 mm through it before the next step's broadphase)
  for (let ci = 0; ci < state.cloths.length; ci++) {
    const cc = state.cloths[ci].collision
    let n = 0
    for (let a = 0; a < cc.activeCount; a++) if (cc.active[a] !== e) cc.active[n++] = cc.active[a]
    cc.activeCount = n
  }
}

/** Grows every cloth's collider list to hold all colliders (at collider creation, never in a step). */
export function reserveActiveColliders(state: ClothWorldState): void {
  const n = liveColliders(state.collision).length
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

/** Scratch of `selfReaches`: a box (6). */
const near = new Float64Array(6)

/**
 * Whether the self-colliding cloth `o`'s particles come within the two cloths' collision distances
 * of the sleeping self-colliding cloth `c`'s box (its `sleep.bounds`): read from the positions,
 * which snapshots save, not from the collision bounds made later in the step. (The cloths, not
 * numbers, are passed: a double passed to a call is boxed.)
 */
export function selfReaches(o: ClothState, c: ClothState): boolean {
  const b = c.sleep.bounds
  const reach = c.collision.self!.thickness + o.collision.self!.thickness
  particleBounds(o.pos, o.count, near, 0, o.topology.unused)
  return !(near[0] > b[3] + reach || b[0] > near[3] + reach || near[1] > b[4] + reach || b[1] > near[4] + reach || near[2] > b[5] + reach ||
    b[2] > near[5] + reach)
}
