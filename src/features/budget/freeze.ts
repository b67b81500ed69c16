import { particleBounds } from '../../kernels/mesh'
import { carryFrozen } from '../../world/rigid'
import { applyJump } from '../../world/kinematics'
import { normalizeQuatAt } from '../../core/math'
import { glideThawingPins } from '../pins/api'
import type { ClothState, ClothWorldState } from '../../world/state'
import { wakeClothState } from '../../world/wake'

/**
 * Freezing. A frozen cloth keeps its state (velocities too) and is skipped by every phase. It
 * hangs from its pins all the same: it is carried rigidly by the motion of one of them (the
 * reference pin) since the freeze, when it thaws or before its pins change (`carryFrozen`), so a
 * cape on a character that walked on meanwhile is not yanked. Only a live pin counts: when the
 * reference pin goes (unpinned, or its target removed, whose id another entity may then reuse),
 * the cloth is carried by the motion until then (it hung from that target until then) and another
 * pin with a target becomes the reference, from its target's pose now; with none left the cloth
 * stays where it was let go, and a pin added later becomes the reference. A character cloth
 * without a pin with a target (held by its motion constraints) is carried the same way by its
 * character frame, or its first skin bone (`ANCHOR_REF`); when that entity goes, by its motion
 * until then.
 */

/** `refPin` of a frozen cloth carried by its character frame or first bone instead of a pin. */
export const ANCHOR_REF = -2

/** The kinematic slot of a character cloth's frame, else of its first tracked skin bone (other than slot `skip`); −1 without. */
export function anchorSlot(c: ClothState, skip = -1): number {
  const ch = c.character
  if (ch === null) return -1
  if (ch.frameSlot >= 0 && ch.frameSlot !== skip) return ch.frameSlot
  const skin = ch.skin
  if (skin !== null) { for (let b = 0; b < skin.slots.length; b++) if (skin.slots[b] >= 0 && skin.slots[b] !== skip) return skin.slots[b] }
  return -1
}

/**
 * Sync phase: freezes a cloth, taking its first pin with a target as the reference, at its
 * target's pose at the step's start (`stepFrom`: where the cloth's last step left it, the step
 * about to run the first it misses). When the step took a frame sample (`sampled`) at which the
 * target jumped (a teleport, or dropped frame time carried), that pose has jumped already while
 * the cloth, frozen before it followed, has not: the pose before the jump is taken (from after it,
 * a cape frozen in a 0.5 s frame of a hero running at 4 m/s thawed 1.71 m behind its pins). A
 * cloth `teleportCloth` moved for that jump was moved by hand instead (`ClothPins.hand`): that
 * pose moved as the cloth was, and the hand move is no longer pending (as `teleportCloth` does for
 * a frozen cloth; left pending and the jump undone, a cape moved with its hero by 10 m thawed
 * 9.9 m off its pins).
 */
export function freezeCloth(state: ClothWorldState, c: ClothState, sampled: boolean): void {
  const lod = c.budget
  const k = state.kinematics
  lod.frozen = true
  lod.frozenCentre.set(lod.centre)
  pickReference(state, c, -1, -1, k.stepFrom)
  const slot = lod.refSlot, hand = c.pins.hand
  if (!sampled || slot < 0 || k.jumped[slot] === 0) return
  if (c.pins.skipTeleport && hand[10] !== 1) return // (moved by a motion not known: as it jumped)
  undoJump(k.jump, 10 * slot, lod.refPose)
  if (!c.pins.skipTeleport) return
  applyJump(hand, 0, lod.refPose, 0)
  normalizeQuatAt(lod.refPose, 3)
  c.pins.skipTeleport = false
  hand[10] = 0
}

/** Moves the pose at pose[0..6] back by the jump at `j`: `applyJump` by its inverse record (centre + d, R⁻¹, −d). */
function undoJump(jump: Float64Array, j: number, pose: Float64Array): void {
  for (let a = 0; a < 3; a++) {
    back[a] = jump[j + a] + jump[j + 7 + a]
    back[3 + a] = -jump[j + 3 + a]
    back[7 + a] = -jump[j + 7 + a]
  }
  back[6] = jump[j + 6]
  applyJump(back, 0, pose, 0)
  normalizeQuatAt(pose, 3)
}

/** Scratch of `undoJump`: the inverse jump record. */
const back = new Float64Array(10)

/**
 * Thaws a frozen cloth, carried rigidly by its reference pin's target since the freeze, to the
 * target's pose in `poses`: `stepFrom` in the sync phase (where the pins start this step from),
 * `stepTo` between steps (the simulation's now).
 */
export function thaw(state: ClothWorldState, c: ClothState, poses: Float64Array): void {
  const lod = c.budget
  if (carryFrozen(c, poses)) wakeClothState(state, c)
  const k = state.kinematics
  glideThawingPins(state, c, poses, poses === k.stepFrom ? k.scaleStepFrom : k.scaleStepTo)
  lod.frozen = false
  lod.phase = lod.stepEvery - 1 // a far cloth steps at once: where it was carried to is this step's start
  lod.dueNow = true // (at whatever level this allocation gives it: a phase alone was undone by a new level's, and a cape thawed into a far level sat out 3 steps, drawn 3 m off its character)
  lod.waited = 0 // (so its step is one fixed step long)
  lod.refPin = -1
  lod.refSlot = -1
  lod.shownSlot = -1 // (carried to `poses`: drawn from there until it steps, not from before the freeze)
}

/** Called when a pin is added: a frozen cloth without a reference takes it (when it has a target). */
export function adoptReference(state: ClothWorldState, pin: number): void {
  const c = state.components.Cloth.state[state.components.Pin.cloth[pin]]
  if (!c || !c.budget.frozen || c.budget.refSlot >= 0) return
  const slot = state.components.Pin.slot[pin]
  if (slot >= 0) setReference(c, pin, slot, state.kinematics.stepTo)
}

/**
 * Called when a pin goes away (after the pins feature has released it): if it was a frozen cloth's
 * reference, the cloth is carried by its target's motion until now and another pin takes over.
 */
export function releaseReference(state: ClothWorldState, pin: number): void {
  const c = state.components.Cloth.state[state.components.Pin.cloth[pin]]
  if (!c || !c.budget.frozen || c.budget.refPin !== pin) return
  // between steps: the target's pose at the end of the last step (its slot may just have been
  // freed, with the pose still in it)
  if (carryFrozen(c, state.kinematics.stepTo)) {
    particleBounds(c.pos, c.count, c.budget.measure, 0, c.topology.unused)
    for (let a = 0; a < 3; a++) c.budget.frozenCentre[a] = 0.5 * (c.budget.measure[a] + c.budget.measure[a + 3])
  }
  pickReference(state, c, pin, -1, state.kinematics.stepTo)
}

/**
 * Called when a character cloth's frame or bone is about to go (before its slot is freed): if the
 * frozen cloth was carried by it, it is carried by its motion until now and another reference
 * takes over (`skip`: the slot going).
 */
export function releaseAnchor(state: ClothWorldState, c: ClothState, skip: number): void {
  const lod = c.budget
  if (!lod.frozen || lod.refPin !== ANCHOR_REF || lod.refSlot !== skip) return
  if (carryFrozen(c, state.kinematics.stepTo)) {
    particleBounds(c.pos, c.count, lod.measure, 0, c.topology.unused)
    for (let a = 0; a < 3; a++) lod.frozenCentre[a] = 0.5 * (lod.measure[a] + lod.measure[a + 3])
  }
  pickReference(state, c, -1, skip, state.kinematics.stepTo)
}

/**
 * The cloth's first pin with a target (other than `except`) becomes the reference, from its
 * target's pose in `poses`; without one, its character anchor (other than slot `skip`).
 */
function pickReference(state: ClothWorldState, c: ClothState, except: number, skip: number, poses: Float64Array): void {
  c.budget.refPin = -1
  c.budget.refSlot = -1
  const P = state.components.Pin
  const pins = c.pins.list
  for (let q = 0; q < pins.length; q++) {
    const slot = P.slot[pins[q]]
    if (slot < 0 || pins[q] === except) continue
    setReference(c, pins[q], slot, poses)
    return
  }
  // (past the one going, to the next frame or bone: a frame or first bone going took the anchor
  // with it, and a frozen cape re-framed thawed at 30 m/s)
  const slot = anchorSlot(c, skip)
  if (slot >= 0) setReference(c, ANCHOR_REF, slot, poses)
}

/**
 * `teleportCloth`'s part for a frozen cloth, after it moved by the rigid motion at motion[0..9] (a
 * record of `moveClothBy`): the pose it is carried from moves with it, so that the thaw carries it
 * only by its reference's motion since, not by the teleport a second time (a cape frozen on a
 * standing character moved with it by 10.6 m thawed 10.6 m beyond its pins: 10,304 % stretch).
 */
export function carryFrozenReference(c: ClothState, motion: Float64Array): void {
  const lod = c.budget
  if (lod.refSlot >= 0) {
    applyJump(motion, 0, lod.refPose, 0)
    normalizeQuatAt(lod.refPose, 3)
  }
  particleBounds(c.pos, c.count, lod.measure, 0, c.topology.unused)
  for (let a = 0; a < 3; a++) lod.frozenCentre[a] = 0.5 * (lod.measure[a] + lod.measure[a + 3])
}

/**
 * Called when a character cloth's frame changed: a frozen cloth that nothing carries (its frame
 * was the world) is carried by its new anchor from the anchor's pose now.
 */
export function adoptAnchor(state: ClothWorldState, c: ClothState): void {
  if (c.budget.frozen && c.budget.refPin === -1) pickReference(state, c, -1, -1, state.kinematics.stepTo)
}

function setReference(c: ClothState, pin: number, slot: number, poses: Float64Array): void {
  const lod = c.budget
  lod.refPin = pin
  lod.refSlot = slot
  for (let j = 0; j < 7; j++) lod.refPose[j] = poses[7 * slot + j]
}
