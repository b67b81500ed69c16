import { quatToMatrix, relativeRotationAt } from '../core/math'
import { GRAB_STRIDE, G_AT, G_FRAME, G_SAMPLE, G_STEP_FROM, G_STEP_TO } from '../kernels/grab'
import type { ClothState, ClothWorldState } from './state'

/** Scratch of moveClothRigidly: the rotation matrix in [0, 9), the quaternion in [9, 13). */
const ROTATION = new Float64Array(13)

/** The grab targets a rigid move carries: where each glides from (the target asked for stays). */
const CARRIED_TARGETS = [G_FRAME, G_STEP_FROM, G_STEP_TO, G_AT, G_SAMPLE] as const

/** The row-major rotation matrix of the unit quaternion (rx, ry, rz, rw) into ROTATION[0..8]. */
function rotation(rx: number, ry: number, rz: number, rw: number): Float64Array {
  const M = ROTATION
  M[9] = rx
  M[10] = ry
  M[11] = rz
  M[12] = rw
  quatToMatrix(M, 9, M, 0)
  return M
}

/**
 * Moves a cloth rigidly: x' = to + R·(x − from) for positions and previous positions, v' = R·v,
 * so the motion carries no velocity and the shape is kept exactly. Its grabs' targets so far (where
 * each glides from, not the target asked for last) move with it: a hand that follows the character
 * across a teleport does not drag the cloth back over the gap. Used by teleports (explicit and
 * detected), by a frozen cloth that thaws, and by the guard's rigid placement. Pieces nothing
 * carries along (`ClothState.detached`: torn off, or never held by a pin on an entity) stay where
 * they are: the motion is the character's or the pin target's (carried 10 m by its teleport, a
 * piece lying on the ground had jumped with it), unless `carryDetached` (`teleportCloth`: the game
 * moves the whole cloth).
 */
export function moveClothRigidly(
  c: ClothState,
  fromX: number,
  fromY: number,
  fromZ: number,
  rx: number,
  ry: number,
  rz: number,
  rw: number,
  toX: number,
  toY: number,
  toZ: number,
  carryDetached = false,
): void {
  const M = rotation(rx, ry, rz, rw)
  const m00 = M[0], m01 = M[1], m02 = M[2], m10 = M[3], m11 = M[4], m12 = M[5], m20 = M[6], m21 = M[7], m22 = M[8]
  const { pos, prev, vel } = c
  for (let i = 0; i < 3 * c.count; i += 3) {
    let x = pos[i] - fromX, y = pos[i + 1] - fromY, z = pos[i + 2] - fromZ
    pos[i] = toX + m00 * x + m01 * y + m02 * z
    pos[i + 1] = toY + m10 * x + m11 * y + m12 * z
    pos[i + 2] = toZ + m20 * x + m21 * y + m22 * z
    x = prev[i] - fromX
    y = prev[i + 1] - fromY
    z = prev[i + 2] - fromZ
    prev[i] = toX + m00 * x + m01 * y + m02 * z
    prev[i + 1] = toY + m10 * x + m11 * y + m12 * z
    prev[i + 2] = toZ + m20 * x + m21 * y + m22 * z
    x = vel[i]
    y = vel[i + 1]
    z = vel[i + 2]
    vel[i] = m00 * x + m01 * y + m02 * z
    vel[i + 1] = m10 * x + m11 * y + m12 * z
    vel[i + 2] = m20 * x + m21 * y + m22 * z
  }
  const loose = !carryDetached && c.detached[0] > 0
  carryGrabTargets(c, M, fromX, fromY, fromZ, toX, toY, toZ, loose)
  if (loose) putBack(c, c.detached, M, fromX, fromY, fromZ, toX, toY, toZ)
  c.version++
}

/**
 * A cloth without character settings whose mesh has pieces (torn, or built so): lists in
 * `c.detached` the particles of the pieces that no pin on an entity holds, which the automatic
 * rigid carries leave in place. A pin target's teleport had carried a flag's torn-off half lying
 * on the ground 10 m along with the pole. A cloth no pin on an entity holds at all has nothing to
 * carry it: the list stays empty. Runs after a tear and when pins come or go.
 */
export function listLoosePieces(state: ClothWorldState, c: ClothState): void {
  if (c.character !== null) return // (see `releaseDetachedPieces`)
  const list = c.detached
  list[0] = 0
  const label = c.piece
  if (label === null) return
  if (looseScratch.length < c.pieceCount) looseScratch = new Uint8Array(Math.max(2 * looseScratch.length, c.pieceCount))
  const held = looseScratch
  held.fill(0, 0, c.pieceCount)
  const P = state.components.Pin
  let any = false
  for (const pin of c.pins.list) {
    if (P.target[pin] === 0) continue
    held[label[P.particle[pin]]] = 1
    any = true
  }
  if (!any) return
  let n = 0
  for (let i = 0; i < c.count; i++) if (held[label[i]] === 0) list[++n] = i
  list[0] = n
}

/** Scratch of `listLoosePieces`: whether a pin on an entity holds each piece (grown on a tear, rarely). */
let looseScratch = new Uint8Array(64)

/**
 * The listed particles (list[1..list[0]]) moved back by the inverse of x' = to + M·(x − from):
 * pieces a tear freed from a character stay where they are when its motion carries its cloth.
 */
function putBack(
  c: ClothState,
  list: Int32Array,
  m: Float64Array,
  fx: number,
  fy: number,
  fz: number,
  tx: number,
  ty: number,
  tz: number,
): void {
  const { pos, prev, vel } = c
  for (let q = 1; q <= list[0]; q++) {
    const j = 3 * list[q]
    let x = pos[j] - tx, y = pos[j + 1] - ty, z = pos[j + 2] - tz
    pos[j] = fx + m[0] * x + m[3] * y + m[6] * z
    pos[j + 1] = fy + m[1] * x + m[4] * y + m[7] * z
    pos[j + 2] = fz + m[2] * x + m[5] * y + m[8] * z
    x = prev[j] - tx
    y = prev[j + 1] - ty
    z = prev[j + 2] - tz
    prev[j] = fx + m[0] * x + m[3] * y + m[6] * z
    prev[j + 1] = fy + m[1] * x + m[4] * y + m[7] * z
    prev[j + 2] = fz + m[2] * x + m[5] * y + m[8] * z
    x = vel[j]
    y = vel[j + 1]
    z = vel[j + 2]
    vel[j] = m[0] * x + m[3] * y + m[6] * z
    vel[j + 1] = m[1] * x + m[4] * y + m[7] * z
    vel[j + 2] = m[2] * x + m[5] * y + m[8] * z
  }
}

/**
 * Rigid motions kept as records of 10 (`Kinematics.jump`, `ClothPins.hand`): a centre, a unit
 * quaternion R and a translation d, x' = centre + R·(x − centre) + d.
 */

/** `moveClothRigidly` by the record at m[o..o+9], or by its inverse. */
export function moveClothBy(c: ClothState, m: Float64Array, o: number, inverse = false): void {
  const cx = m[o], cy = m[o + 1], cz = m[o + 2], tx = cx + m[o + 7], ty = cy + m[o + 8], tz = cz + m[o + 9]
  if (inverse) moveClothRigidly(c, tx, ty, tz, -m[o + 3], -m[o + 4], -m[o + 5], m[o + 6], cx, cy, cz)
  else moveClothRigidly(c, cx, cy, cz, m[o + 3], m[o + 4], m[o + 5], m[o + 6], tx, ty, tz)
}

/**
 * `carryGrabTargets` by the record at m[o..o+9] (see `moveClothBy`), for a teleport's reset: the
 * grabs on loose pieces, which the reset leaves where they are, stay too (a hand holding a piece
 * torn off dragged it at 17.5 m/s).
 */
export function carryGrabTargetsBy(c: ClothState, m: Float64Array, o: number): void {
  if (c.grab.count === 0) return
  const cx = m[o], cy = m[o + 1], cz = m[o + 2]
  const M = rotation(m[o + 3], m[o + 4], m[o + 5], m[o + 6])
  carryGrabTargets(c, M, cx, cy, cz, cx + m[o + 7], cy + m[o + 8], cz + m[o + 9], c.detached[0] > 0)
}

/**
 * Moves the grabs' targets so far (where each glides from, not the target asked for) by
 * x' = to + M·(x − from), M the row-major rotation at m[0..8]: `moveClothRigidly`'s, and a
 * teleport reset's (the cloth is put on its reference; the hands that followed the jump stay with it).
 */
function carryGrabTargets(
  c: ClothState,
  m: Float64Array,
  fromX: number,
  fromY: number,
  fromZ: number,
  toX: number,
  toY: number,
  toZ: number,
  skipLoose = false,
): void {
  const G = c.grab
  for (let g = 0; g < G.count; g++) {
    // a hand on a piece the carry leaves where it is stays with it (its glide started 10 m off: the
    // piece was dragged across at 18 m/s, 117 at a 60 N grip)
    if (skipLoose && listed(c.detached, G.particle[g])) continue
    for (let q = 0; q < CARRIED_TARGETS.length; q++) {
      const o = GRAB_STRIDE * g + CARRIED_TARGETS[q]
      const x = G.data[o] - fromX, y = G.data[o + 1] - fromY, z = G.data[o + 2] - fromZ
      G.data[o] = toX + m[0] * x + m[1] * y + m[2] * z
      G.data[o + 1] = toY + m[3] * x + m[4] * y + m[5] * z
      G.data[o + 2] = toZ + m[6] * x + m[7] * y + m[8] * z
    }
  }
}

/** Rotation scratch of carryFrozen. */
const CARRY = new Float64Array(4)

/**
 * A frozen cloth hangs from its pins all the same (see `features/budget/freeze.ts`): this brings it
 * to where its reference pin's target has carried it since the freeze (or the last carry), rigidly,
 * from the target's pose `refPose` to its pose in `poses` (`stepTo`: now, between steps;
 * `stepFrom`: the start of the step, in the sync phase), which becomes the new `refPose`. Called
 * before anything relies on where a frozen cloth is: a thaw, a pin added or removed, a teleport.
 * Returns whether the cloth moved.
 */
export function carryFrozen(c: ClothState, poses: Float64Array): boolean {
  const lod = c.budget
  if (!lod.frozen || lod.refSlot < 0) return false
  const ref = lod.refPose
  const o = 7 * lod.refSlot
  // R = q_now · q_ref⁻¹ about the old position, then to the new one
  relativeRotationAt(poses, o + 3, ref, 3, CARRY, 0)
  const rx = CARRY[0], ry = CARRY[1], rz = CARRY[2], rw = CARRY[3]
  const dx = poses[o] - ref[0], dy = poses[o + 1] - ref[1], dz = poses[o + 2] - ref[2]
  if (dx === 0 && dy === 0 && dz === 0 && rx === 0 && ry === 0 && rz === 0) return false
  moveClothRigidly(c, ref[0], ref[1], ref[2], rx, ry, rz, rw, poses[o], poses[o + 1], poses[o + 2])
  for (let j = 0; j < 7; j++) ref[j] = poses[o + j]
  return true
}

/** Whether particle i is in `list` ([0] = count, then particles). */
function listed(list: Int32Array, i: number): boolean {
  for (let q = 1; q <= list[0]; q++) if (list[q] === i) return true
  return false
}
