import { entityExists, hasComponent } from 'bitecs'
import { checkOut } from './core/errors'
import { quatToMatrix } from './core/math'
import { getCloth, getClothWorld } from './world/access'
import { applyJump, readPoseInto } from './world/kinematics'
import type { ClothState, ClothWorldState } from './world/state'

/**
 * Drawing a cloth where its character is now. The cloth steps in fixed steps (1/60 s), so between
 * them, on a display faster than 60 Hz, or with uneven frame times, or pipelined by a frame, the
 * drawn cloth is where the last finished step left it while its character has moved on (up to one
 * step: 6.7 cm at 4 m/s). `getClothDrawTransform` gives the rigid motion of the cloth's anchor
 * since that step; drawn moved by it, the cloth's pinned edge is on its character every frame and
 * only the swing is up to a step old.
 */

/** Scratch: the anchor's pose now (0..6), the drawn step's (10..16), two rotations (20..37). */
const t = new Float64Array(38)

/**
 * The rigid motion, as a column-major 4×4 matrix into `out` (16 numbers; three.js `Matrix4.elements`
 * order), of the cloth's anchor from the step the cloth's mesh shows (`getClothMesh`: the last
 * finished step) to the anchor's Transform now: M = M_now · M_step⁻¹ with M = translation ·
 * rotation. A change of the anchor's scale is left out: it moves the pins, not the rest of the
 * cloth, which follows at the next step (drawn scaled with its anchor, a cape whose character grew
 * from 0.01 to 1 in half a second was drawn 3.9 m long). The anchor is the cloth's character
 * frame (`setClothInertia`), else the target
 * of its first pin that has one; without either (or once the anchor lost its Transform) the
 * identity. Draw the cloth's mesh with this as its world matrix (`updateClothDrawMatrix` in the
 * three.js entry does that). Exactly the identity while the anchor has not moved since that step
 * (at 60 Hz frames of whole steps). Allocates nothing.
 */
export function getClothDrawTransform<T extends { [i: number]: number; length: number }>(world: object, cloth: number, out: T): T {
  const state = getClothWorld(world)
  const c = getCloth(state, cloth)
  checkOut('out', out, 16)
  const slot = anchorSlot(state, c)
  const eid = slot < 0 ? -1 : state.kinematics.eid[slot]
  if (eid < 0 || !entityExists(world as never, eid) || !hasComponent(world as never, eid, state.transforms.component)) {
    for (let j = 0; j < 16; j++) out[j] = j % 5 === 0 ? 1 : 0
    return out
  }
  const k = state.kinematics
  // the step the mesh shows: while a frame runs, the one before it (its first step's start); a
  // frozen cloth, where it froze (the pose its thaw carries it from); a cloth sitting steps out
  // (the budget steps it every n-th), its own last step
  const lod = c.budget
  let poses = state.frame.open ? k.stepFrom : k.stepTo, po = 7 * slot
  if (lod.frozen && lod.refSlot === slot) {
    poses = lod.refPose
    po = 0
  } else if ((lod.shownStale || lod.shownCarried) && !lod.frozen && lod.shownSlot === slot) {
    // (whether it sat out the world's last step, not the step in flight while a frame is open: a
    // far cloth running that one was drawn 150 mm behind its pins every 4th step, found by a hunt)
    poses = lod.shownPose
    po = 0
  }
  readPoseInto(state, eid, t)
  let same = true
  for (let j = 0; j < 7; j++) {
    t[10 + j] = poses[po + j]
    same &&= t[10 + j] === t[j]
  }
  if (same) {
    for (let j = 0; j < 16; j++) out[j] = j % 5 === 0 ? 1 : 0
    return out
  }
  quatToMatrix(t, 3, t, 20) // R_now (row-major)
  quatToMatrix(t, 13, t, 29) // R_step
  // A = R_now · R_stepᵀ, b = p_now − A · p_step
  for (let r = 0; r < 3; r++) {
    for (let col = 0; col < 3; col++) {
      let a = 0
      for (let m = 0; m < 3; m++) a += t[20 + 3 * r + m] * t[29 + 3 * col + m]
      out[4 * col + r] = a
    }
    out[12 + r] = t[r] - (out[r] * t[10] + out[4 + r] * t[11] + out[8 + r] * t[12])
    out[3 + 4 * r] = 0
  }
  out[15] = 1
  return out
}

/**
 * After each fixed step: every cloth that ran it records its anchor's pose at the step's end (what
 * its mesh shows until it runs again). Drawn from the world's last step instead, a far cloth the
 * budget steps every 4th step was 15 cm off its pins at 3 m/s.
 */
export function noteShownAnchors(state: ClothWorldState): void {
  const cloths = state.cloths
  const to = state.kinematics.stepTo
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    c.budget.shownStale = c.idle
    if (c.idle) continue
    const slot = anchorSlot(state, c), lod = c.budget
    lod.shownSlot = slot
    lod.shownCarried = false
    if (slot >= 0) { for (let j = 0; j < 7; j++) lod.shownPose[j] = to[7 * slot + j] }
  }
}

/**
 * `teleportCloth` moved the cloth (by the rigid-motion record m[0..9], see `moveClothBy`) between
 * steps: the mesh now shows it moved, so the pose its anchor is drawn from moves too. (Measured
 * from the anchor's pose at the last step, a cape teleported with its character on a frame that
 * ran no step was drawn moved twice: 10 m off its pins for 2–3 frames at 144–240 Hz.)
 */
export function carryShownAnchor(state: ClothWorldState, c: ClothState, m: Float64Array): void {
  const slot = anchorSlot(state, c), lod = c.budget
  if (slot < 0 || lod.frozen) return
  const shown = (lod.shownStale || lod.shownCarried) && lod.shownSlot === slot
  if (!shown) { for (let j = 0; j < 7; j++) lod.shownPose[j] = state.kinematics.stepTo[7 * slot + j] }
  applyJump(m, 0, lod.shownPose, 0)
  lod.shownSlot = slot
  lod.shownCarried = true
}

/** The kinematic slot of the cloth's anchor: its character frame, else its first pin target; −1 when none. */
function anchorSlot(state: ClothWorldState, c: ClothState): number {
  const ch = c.character
  if (ch !== null && ch.frameSlot >= 0) return ch.frameSlot
  const P = state.components.Pin
  for (const pin of c.pins.list) if (P.target[pin] !== 0 && P.slot[pin] >= 0) return P.slot[pin]
  return -1
}
