import { multiplyQuatAt, relativeRotationAt, rotateVecAt } from '../../core/math'
import { G_ANCHOR, clearGuardAnchor } from '../../kernels/guard'
import { predictPositions, updateVelocities } from '../../kernels/integrate'
import {
  anyLimit,
  BLEND,
  constrainAndUpdateVelocities,
  driveTowardReference,
  placeOnReference,
  predictInFrame,
  releaseLimitHolds,
} from '../../kernels/motion'
import { K_DROPPED, K_LAST_SPAN, K_SINCE_SAMPLE, applyJump, jumpTest, landsBeyond, readPoseInto } from '../../world/kinematics'
import { carryGrabTargetsBy, moveClothBy } from '../../world/rigid'
import type { ClothState, ClothWorldState, Kinematics } from '../../world/state'
import { wakeClothState } from '../../world/wake'
import { beginFrameStep, frameSubstep } from './frame'
import { followPinGlides } from './frames'
import { blendReference, carryPose, followBones, referenceSubstep, trackedPose, trackedStartPose, updateReference } from './reference'
import {
  M_GAP,
  M_POSE,
  M_PRIMED,
  M_REF_VALID,
  M_V,
  M_VC,
  M_W,
  M_WC,
  S_EVERY,
  S_TELEPORT_ANGLE,
  S_TELEPORT_DISTANCE,
  S_TELEPORT_MODE,
  W_FROM,
  W_TO,
  W_V,
  W_LIMITED,
  W_SKIN_JUMPED,
  W_BONE_LEAPT,
  W_RESUME,
  W_W,
  type ClothCharacter,
  type ClothSkin,
} from './types'

/** Pose and quaternion scratch of the teleport test. */
const pose = new Float64Array(7)
const turn = new Float64Array(4)

/**
 * The orientation a frame turning steadily would have `ratio` steps after its last sample: the
 * turn from `from` to `to` (its last step), scaled by `ratio` about the same axis, after `at` (all
 * unit quaternions at offset o), into out[0..3].
 */
function predictTurn(to: Float64Array, from: Float64Array, at: Float64Array, o: number, out: Float64Array): void {
  const ratio = jumpTest[0] // (the span, in `jumpTest` as the teleport test reads it: a double passed to a call is boxed)
  relativeRotationAt(to, o, from, o, out, 0)
  let x = out[0], y = out[1], z = out[2], w = out[3]
  if (w < 0) {
    x = -x
    y = -y
    z = -z
    w = -w
  }
  const sin = Math.sqrt(x * x + y * y + z * z)
  if (sin > 1e-12) {
    const half = Math.atan2(sin, w) * ratio, s = Math.sin(half) / sin
    out[0] = x * s
    out[1] = y * s
    out[2] = z * s
    out[3] = Math.cos(half)
  } else {
    out[0] = 0
    out[1] = 0
    out[2] = 0
    out[3] = 1
  }
  multiplyQuatAt(out, 0, at, o, out, 0)
}

/**
 * Sync phase, before the frame sample: a frame about to arrive farther than its cloth's teleport
 * distance from where its velocity would have taken it, or turned by more than its teleport angle,
 * is marked to jump (`forceJump`), as are the bones of a skinned cloth with it, so that the sample
 * records a jump instead of interpolating across the gap. A pending `teleportCloth` marks the
 * frame too (the cloth was moved by hand; its frame must not sweep across the gap either).
 */
export function markFrameTeleports(state: ClothWorldState): void {
  const k = state.kinematics
  const cloths = state.cloths
  // (the frame's whole span: dropped time too, as `sampleFrame` takes it)
  const ratio = (k.framed ? k.time[K_SINCE_SAMPLE] + k.time[K_DROPPED] : state.fixedTimeStep) / state.fixedTimeStep
  const reach = state.maxSpeed * state.fixedTimeStep * ratio
  jumpTest[2] = reach * reach
  jumpTest[4] = ratio / k.time[K_LAST_SPAN] // (`sampleFrame`, after this, records this frame's)
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    const ch = c.character
    if (ch === null) continue
    ch.work[W_BONE_LEAPT] = 0
    const slot = jumpSlot(ch), o = 7 * slot
    if (slot < 0) continue
    readPoseInto(state, slot === ch.frameSlot ? ch.frame : boneAt(ch, slot), pose)
    // the cloth's own distance, tested as `sampleFrame` tests the world's
    jumpTest[0] = ratio
    jumpTest[1] = ch.settings[S_TELEPORT_DISTANCE] * ch.settings[S_TELEPORT_DISTANCE]
    jumpTest[3] = k.jumped[slot]
    const moved = landsBeyond(k, o, pose, jumpTest)
    // the rotation too: the last step's turn, scaled to the span, after the last sample (not also
    // against the last sample, as the distance is: a turn wraps round, and a steady turn through a
    // hitch snapped 180° came out at 0.9 rad)
    const angle = ch.settings[S_TELEPORT_ANGLE]
    predictTurn(k.stepTo, k.stepFrom, k.sampleTo, o + 3, turn)
    let dot = pose[3] * turn[0] + pose[4] * turn[1] + pose[5] * turn[2] + pose[6] * turn[3]
    if (dot < 0) dot = -dot
    const turned = 2 * Math.acos(dot > 1 ? 1 : dot) > angle
    const skin = ch.skin
    if (!c.pins.skipTeleport && !moved && !turned) {
      if (skin !== null) markBoneLeaps(state, ch, skin)
      continue
    }
    k.forceJump[slot] = 1
    if (skin !== null) { for (let b = 0; b < skin.slots.length; b++) if (skin.slots[b] >= 0) k.forceJump[skin.slots[b]] = 1 }
  }
}

/**
 * A bone of a skinned cloth that lands beyond the cloth's teleport distance or angle on its own
 * (posed a frame before or after its root around a teleport) is marked as a leap for this cloth
 * (`W_BONE_LEAPT`): only such a sample lets `skinJumped` rest the limits (a bone swung fast against its frame is
 * motion, and its cloth held to it: tested as motion, a strip at max distance 0 on an arm swinging
 * at 4 m/s let go 0.42 m with a teleport distance of 5 cm).
 */
function markBoneLeaps(state: ClothWorldState, ch: ClothCharacter, skin: ClothSkin): void {
  const k = state.kinematics
  // (the span and the cloth's distance as `markFrameTeleports` left them in `jumpTest`: doubles
  // passed to a call are boxed)
  const angle = ch.settings[S_TELEPORT_ANGLE]
  for (let b = 0; b < skin.slots.length; b++) {
    const bs = skin.slots[b], o = 7 * bs
    if (bs < 0 || bs === ch.frameSlot) continue
    readPoseInto(state, skin.bones[b], pose)
    jumpTest[3] = k.jumped[bs]
    predictTurn(k.stepTo, k.stepFrom, k.sampleTo, o + 3, turn)
    let dot = pose[3] * turn[0] + pose[4] * turn[1] + pose[5] * turn[2] + pose[6] * turn[3]
    if (dot < 0) dot = -dot
    if (landsBeyond(k, o, pose, jumpTest) || 2 * Math.acos(dot > 1 ? 1 : dot) > angle) ch.work[W_BONE_LEAPT] = 1
  }
}

/**
 * Whose jumps are the cloth's teleports: its frame's, or with the world as its frame, its first
 * skin bone's still there (the skin jumping with its character carries the cloth along: left in
 * the world, a skinned cape was dragged 10 m by its limits, at 27 m/s and 12 % stretch). −1: none.
 */
function jumpSlot(ch: ClothCharacter): number {
  if (ch.frameSlot >= 0 || ch.frame !== 0 || ch.skin === null) return ch.frameSlot
  const slots = ch.skin.slots
  for (let b = 0; b < slots.length; b++) if (slots[b] >= 0) return slots[b]
  return -1
}

/** The entity of the skin bone at kinematic slot `slot`. */
function boneAt(ch: ClothCharacter, slot: number): number {
  const skin = ch.skin!
  return skin.bones[skin.slots.indexOf(slot)]
}

/**
 * Sync phase, when some cloth sleeps: wakes sleeping cloths whose frame or bones move this step
 * (the sleep feature knows only pins, colliders and wind).
 */
export function wakeMovedCharacters(state: ClothWorldState): void {
  if (state.sleep.count === 0) return
  const moved = state.kinematics.moved
  const cloths = state.cloths
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    const ch = c.character
    if (ch === null || !c.sleep.asleep) continue
    let wake = ch.frameSlot >= 0 && moved[ch.frameSlot] === 1
    const skin = ch.skin
    if (skin !== null) { for (let b = 0; b < skin.slots.length && !wake; b++) wake = skin.slots[b] >= 0 && moved[skin.slots[b]] === 1 }
    if (wake) wakeClothState(state, c)
  }
}

/** Whether the cloth's frame or one of its bones jumped at this frame's sample. */
export function characterJumped(state: ClothWorldState, c: ClothState): boolean {
  const ch = c.character
  if (ch === null) return false
  const jumped = state.kinematics.jumped
  if (ch.frameSlot >= 0 && jumped[ch.frameSlot] !== 0) return true
  const skin = ch.skin
  if (skin === null) return false
  for (let b = 0; b < skin.slots.length; b++) if (skin.slots[b] >= 0 && jumped[skin.slots[b]] !== 0) return true
  return false
}

/**
 * Sync phase, for a cloth that sits this step out: asleep or frozen, it misses its frame's motion
 * meanwhile, so its next step starts from the frame's pose then (a cloth stepping every n-th step
 * does not: its step spans the steps it skips).
 */
export function noteIdle(c: ClothState): void {
  if (c.character !== null && (c.sleep.asleep || c.budget.frozen)) c.character.motion[M_GAP] = 1
}

/** How the pins' teleport handling left the cloth this step (`followTargetJumps`). */
export const JUMP_NONE = 0
export const JUMP_CARRIED = 1
export const JUMP_EXPLICIT = 2

/**
 * Sync phase, per running cloth with character state: handles a jump of its frame (carry the
 * cloth along, 'keep', unless a pin target's jump already did; or put it on its reference pose,
 * 'reset'), then this step's frame motion and reference pose.
 */
export function beginCharacterStep(state: ClothWorldState, c: ClothState, frameStart: boolean, pinJump: number): void {
  const ch = c.character!
  const k = state.kinematics
  const m = ch.motion
  const slot = jumpSlot(ch)
  const jumped = frameStart && slot >= 0 && k.jumped[slot] !== 0
  const teleported = jumped && k.jumped[slot] === 1 // (2: the carried motion of dropped time)
  // (tested at every frame, hot: its first run was interpreted code, which boxes its doubles. It holds
  // for the frame's every step, where the bones glide on toward the late pose: rested for the first
  // alone, a cape at 30 Hz was dragged across a 10 m teleport, 16,954 %)
  const skinJump = frameStart ? m[M_GAP] !== 1 && skinJumped(state, ch, slot) && leapt(k, ch, slot) : ch.work[W_SKIN_JUMPED] === 1
  ch.work[W_SKIN_JUMPED] = skinJump ? 1 : 0
  if (frameStart || m[M_GAP] === 1) resyncBones(state, ch, m[M_GAP] === 1)
  const gap = m[M_GAP] === 1
  if (jumped || gap) {
    // start from the frame's pose now (a jump moved the tracked poses; a gap left them behind).
    // The frame's last velocities stay: they are what the cloth's own velocities were carried with
    // (a sleeping cloth's are zero, like its frame's; a frozen cloth kept both), turned as the
    // frame turned meanwhile, as the thaw's carry turned the cloth's (kept as they were, the first
    // step felt a 90° turn while frozen as the frame's whole change of velocity: 2.4 m/s)
    if (ch.frameSlot >= 0) {
      if (gap) {
        trackedStartPose(state, ch.frameSlot, gapPose, 0)
        relativeRotationAt(gapPose, 3, m, M_POSE + 3, gapPose, 10)
        turnVelocities(m, gapPose, 10)
        // a removed bone's kept pose rides the frame over the gap, as it does step by step (left
        // where the frame was at the freeze, the part weighted on it was held there: 2720 % for good)
        const skin = ch.skin
        if (skin !== null) {
          for (let b = 0; b < skin.slots.length; b++)
            if (skin.slots[b] < 0)
              carryPose(skin.pose, 10 * b, m, M_POSE, gapPose, 0, gapPose, 10)
        }
      }
      trackedStartPose(state, ch.frameSlot, m, M_POSE)
    }
    m[M_REF_VALID] = 0
    m[M_GAP] = 0
    if (gap && ch.constrained) ch.work[W_RESUME] = 1
  }
  // a jump turned the cloth's velocities (carried along) or replaced them (reset): the frame's too
  // (after a gap, the turn since its last step holds the jump's)
  if (jumped && !gap) {
    turnVelocities(m, k.jump, 10 * slot + 3)
    // a removed bone's kept pose jumps with the frame too (left behind: 16,954 % after a 10 m teleport)
    const skin = ch.skin
    if (skin !== null) {
      for (let b = 0; b < skin.slots.length; b++)
        if (skin.slots[b] < 0)
          applyJump(k.jump, 10 * slot, skin.pose, 10 * b)
    }
  }
  // (onto a skeleton a frame behind or ahead of its frame, a reset put the cape where the frame was not: it is carried)
  const reset = teleported && ch.settings[S_TELEPORT_MODE] === 1 && pinJump !== JUMP_EXPLICIT && !skinJump
  if (reset) m[M_PRIMED] = 0
  if (jumped && pinJump === JUMP_NONE) {
    if (!reset) {
      moveClothBy(c, k.jump, 10 * slot)
      if (teleported) state.stats.teleports++
    } else {
      // the cloth goes onto its reference below; the hands holding it jumped with the frame (their
      // targets swept the 10 m gap in one step: 47 % stretch)
      carryGrabTargetsBy(c, k.jump, 10 * slot)
    }
  }
  followPinGlides(state, c, ch)
  beginFrameStep(state, c, ch)
  if (ch.constrained || reset) updateReference(state, ch)
  else followBones(state, ch)
  // (limits that limit nothing cost nothing: a max distance of Infinity everywhere, say a reach
  // slider at its top, ran the constrained writeback over every particle for the same bytes, 1.11×)
  if (ch.constrained) ch.work[W_LIMITED] = anyLimit(ch.lim, c.count) ? 1 : 0
  if (reset) {
    resetToReference(c, ch)
    if (pinJump === JUMP_NONE) state.stats.teleports++ // (else the pins counted it, carrying the cloth first)
    if (!ch.constrained) m[M_REF_VALID] = 0 // kept only while constraints use it
  }
}

/** The frame's pose at the step's start after a gap (10 values), then its turn since its pose before (4). */
const gapPose = new Float64Array(14)

/**
 * Sync phase, before the bones and the frame move on: whether a bone of a skinned cloth moved
 * against the entity whose jumps are the cloth's teleports (tracked at `slot`) by more than the
 * teleport distance or angle since the cloth's last step. Game code that poses the skeleton a frame
 * after (or before) its root gives that for one step around a teleport: the cloth is carried with
 * its frame while its reference stays with the bones, and its limits dragged it across the gap
 * (21,961 % stretch after a 10 m jump). The limits rest for such a step; the bones' poses are
 * followed as usual, so the next step holds the cloth to them where they then are.
 */
function skinJumped(state: ClothWorldState, ch: ClothCharacter, slot: number): boolean {
  const skin = ch.skin
  if (skin === null || slot < 0) return false
  const m = ch.motion, s = skinScratch
  const limit = ch.settings[S_TELEPORT_DISTANCE], angle = ch.settings[S_TELEPORT_ANGLE]
  // the entity's last pose (the frame's, or the first bone's with the world as frame) and its pose now
  const first = slot === ch.frameSlot ? -1 : skin.slots.indexOf(slot)
  for (let j = 0; j < 7; j++) s[j] = first < 0 ? m[M_POSE + j] : skin.pose[10 * first + j]
  trackedPose(state, slot, s, 7)
  relativeRotationAt(s, 10, s, 3, s, 17) // its turn since
  s[3] = -s[3]
  s[4] = -s[4]
  s[5] = -s[5]
  s[10] = -s[10]
  s[11] = -s[11]
  s[12] = -s[12]
  for (let b = 0; b < skin.slots.length; b++) {
    const bs = skin.slots[b], o = 10 * b
    if (bs < 0) continue
    trackedPose(state, bs, s, 21)
    // the bone's place in the entity's frame, last step and now
    for (let a = 0; a < 3; a++) {
      s[31 + a] = skin.pose[o + a] - s[a]
      s[34 + a] = s[21 + a] - s[7 + a]
    }
    rotateVecAt(s, 3, s, 31, s, 31)
    rotateVecAt(s, 10, s, 34, s, 34)
    const dx = s[34] - s[31], dy = s[35] - s[32], dz = s[36] - s[33]
    if (dx * dx + dy * dy + dz * dz > limit * limit) return true
    if (angle === Infinity) continue
    // its turn against the entity's: the angle of (its turn)·(the entity's turn)⁻¹
    relativeRotationAt(s, 24, skin.pose, o + 3, s, 37)
    relativeRotationAt(s, 37, s, 17, s, 37)
    const w = Math.abs(s[40])
    if (2 * Math.acos(w > 1 ? 1 : w) > angle) return true
  }
  return false
}

/** Whether the entity at `slot` or a bone of the cloth's skin was sampled as a jump this frame, or a bone leapt for this cloth (`markBoneLeaps`). */
function leapt(k: Kinematics, ch: ClothCharacter, slot: number): boolean {
  if (ch.work[W_BONE_LEAPT] === 1 || (slot >= 0 && k.jumped[slot] !== 0)) return true
  const skin = ch.skin
  if (skin === null) return false
  for (let b = 0; b < skin.slots.length; b++) if (skin.slots[b] >= 0 && k.jumped[skin.slots[b]] !== 0) return true
  return false
}

/** Scratch of `skinJumped`: the entity's poses (0..13), its turn (17..20), a bone's pose (21..30), two offsets (31..36), a turn (37..40). */
const skinScratch = new Float64Array(41)

/** The frame's velocity history turned by the unit quaternion at q[qo..qo+3]. */
function turnVelocities(m: Float64Array, q: Float64Array, qo: number): void {
  rotateVecAt(q, qo, m, M_V, m, M_V)
  rotateVecAt(q, qo, m, M_W, m, M_W)
  rotateVecAt(q, qo, m, M_VC, m, M_VC)
  rotateVecAt(q, qo, m, M_WC, m, M_WC)
}

/**
 * Bones that jumped at this frame sample continue from their new place; after a gap (the cloth sat
 * steps out asleep or frozen, and was carried) every bone does.
 */
function resyncBones(state: ClothWorldState, ch: ClothCharacter, all: boolean): void {
  const skin = ch.skin
  if (skin === null) return
  const jumped = state.kinematics.jumped
  for (let b = 0; b < skin.slots.length; b++) {
    const slot = skin.slots[b]
    if (slot < 0 || (!all && jumped[slot] === 0)) continue
    trackedStartPose(state, slot, skin.pose, 10 * b)
    ch.motion[M_REF_VALID] = 0
  }
}

/**
 * Teleport 'reset': every particle on its reference at the step's start, at rest in the frame
 * (with the world as the frame, moving as its reference does over the step: the skin's motion; at
 * rest in the world, a cape reset onto a walking skeleton was left behind and swung up to 7 m/s);
 * pieces a tear freed from the character (`ClothState.detached`) stay where they lie, as they do
 * in a carry.
 */
function resetToReference(c: ClothState, ch: ClothCharacter): void {
  blendReference(c, ch)
  referenceSubstep(c, ch, -1, c.substeps) // (the reference at the step's start)
  const detached = c.detached
  if (detached[0] > 0) swapDetached(c, detached, true)
  placeOnReference(c.pos, null, c.count, ch.ref, ch.refParams, c.params, null)
  const w = ch.work
  const { pos, prev, vel } = c
  const vx = w[W_V], vy = w[W_V + 1], vz = w[W_V + 2], ox = w[W_FROM], oy = w[W_FROM + 1], oz = w[W_FROM + 2]
  const ax = w[W_W], ay = w[W_W + 1], az = w[W_W + 2]
  for (let j = 0; j < 3 * c.count; j += 3) {
    prev[j] = pos[j]
    prev[j + 1] = pos[j + 1]
    prev[j + 2] = pos[j + 2]
    // the frame's velocity at the particle: V + ω × r
    const rx = pos[j] - ox, ry = pos[j + 1] - oy, rz = pos[j + 2] - oz
    vel[j] = vx + ay * rz - az * ry
    vel[j + 1] = vy + az * rx - ax * rz
    vel[j + 2] = vz + ax * ry - ay * rx
  }
  if (ch.frameSlot < 0) referenceVelocities(c, ch)
  if (detached[0] > 0) swapDetached(c, detached, false) // (their positions and velocities back)
  c.version++
}

/** Each particle's velocity: its reference's over the step (start to end, see kernels/motion.ts `BLEND`). */
function referenceVelocities(c: ClothState, ch: ClothCharacter): void {
  const w = ch.work, ref = ch.ref, vel = c.vel
  const inv = 1 / (c.h * c.substeps)
  for (let i = 0; i < c.count; i++) {
    const j = 3 * i, o = BLEND * i
    for (let a = 0; a < 3; a++) vel[j + a] = (w[W_TO + a] + ref[o + 3 + a] - w[W_FROM + a] - ref[o + a]) * inv
  }
}

/**
 * Predict phase, for a cloth with character state: a skinned reference's blend at the first
 * substep, the reference for this substep (when motion constraints use it), then the predict in
 * the frame (inertia shares, frame-relative damping) when inertia is on, then held particles onto
 * their reference. Returns false when the world-space predict must run instead (it runs before
 * the held particles are placed: see `placeHeld`).
 */
export function predictCharacter(c: ClothState, k: number): boolean {
  const ch = c.character!
  if (k === 0) blendReference(c, ch)
  // where each particle starts the substep, for the limits' velocity bound: only where they run
  const start = ch.constrained && limitsRun(c, ch, k) ? ch.start : null
  if (ch.constrained) referenceSubstep(c, ch, k, c.substeps)
  const inFrame = ch.inertia
  // (the predict in the frame records it as it goes; otherwise one memmove, cheaper than a loop
  // over the live particles at the same capacity)
  if (start !== null && !inFrame) start.set(c.pos)
  if (inFrame) {
    frameSubstep(c, ch, k, c.substeps)
    const detached = c.detached
    if (detached[0] > 0) swapDetached(c, detached, true)
    predictInFrame(c.pos, c.prev, start, c.vel, c.invMass, c.accel, c.params, ch.frameParams, c.count)
    if (detached[0] > 0) {
      // pieces a tear freed from the character move in the world, not in its frame
      swapDetached(c, detached, false)
      predictPositions(c.pos, c.prev, c.vel, c.invMass, c.accel, c.params, c.count, detached)
    }
  }
  return inFrame
}

/** Positions and velocities of a cloth's detached particles before the predict (grown on a tear, rarely). */
let detachedScratch = new Float64Array(0)

/** Keeps (`keep`) the listed particles' positions and velocities, or puts them back. */
function swapDetached(c: ClothState, list: Int32Array, keep: boolean): void {
  const n = list[0]
  if (detachedScratch.length < 6 * n) detachedScratch = new Float64Array(6 * Math.max(n, c.pos.length / 3))
  const s = detachedScratch, pos = c.pos, vel = c.vel
  for (let q = 1; q <= n; q++) {
    const j = 3 * list[q], o = 6 * (q - 1)
    for (let a = 0; a < 3; a++) {
      if (keep) {
        s[o + a] = pos[j + a]
        s[o + 3 + a] = vel[j + a]
      } else {
        pos[j + a] = s[o + a]
        vel[j + a] = s[o + 3 + a]
      }
    }
  }
}

/** Predict phase, after the predict: held particles onto their reference at the substep's end. */
export function placeHeld(c: ClothState): void {
  const ch = c.character!
  if (ch.work[W_SKIN_JUMPED] === 1) return
  placeOnReference(c.pos, ch.heldList, ch.heldCount, ch.ref, ch.refParams, c.params, c.pinCount)
}

/** `since` for the limits after a gap: their corrections enter the velocity at 1/2²⁰ (see `constrainAndUpdateVelocities`). */
const RESUME_SINCE = 1 << 20

/**
 * Whether the motion constraints run at local substep k: every `every`-th substep and the step's
 * last (every substep with a drive), and never when no particle has a limit or a drive.
 */
function limitsRun(c: ClothState, ch: ClothCharacter, k: number): boolean {
  if (ch.work[W_SKIN_JUMPED] === 1) return false
  if (ch.drive !== null) return true
  if (ch.work[W_LIMITED] === 0) return false
  const every = runEvery(c, ch)
  return every === 1 || (k + 1) % every === 0 || k === c.substeps - 1
}

/**
 * The substeps between limit runs: `every`, but at most one less than the step's substeps, so that
 * the step's last run is never its only one. Run once, at the last substep, the whole step's drift
 * was taken back after the last solve, and the frame showed the particles put back one by one:
 * a walking skirt's edges 28 % stretched at the median (80 % at worst), a cape knocked over 323 %,
 * against 7–8 % and 54 % with a run one substep before it.
 */
function runEvery(c: ClothState, ch: ClothCharacter): number {
  const every = ch.settings[S_EVERY]
  return every < c.substeps ? every : c.substeps > 1 ? c.substeps - 1 : 1
}

/**
 * Writeback phase: max distance, backstop and drive at the end of the substep, then the
 * velocities (the reference for the substep was set up by the predict phase). With `every` n > 1
 * and no drive, the constraints run at every n-th substep and the step's last; the others get
 * the plain velocity update.
 */
export function writebackCharacter(c: ClothState): void {
  const ch = c.character!
  releaseLimitHolds(c.invMass, c.invMass3, ch.limitHeld)
  const k = c.subIndex, every = runEvery(c, ch)
  if (!limitsRun(c, ch, k)) {
    updateVelocities(c.pos, c.prev, c.vel, c.params, c.count)
    return
  }
  if (ch.drive !== null) driveTowardReference(c.pos, c.prev, c.invMass, ch.ref, ch.refParams, ch.drive, c.params, c.count)
  // the substeps since the last check: `every` (the step's last substep may come sooner); 1 with a
  // drive. In the step after a gap, a correction is a placement, without velocity: the cloth was
  // carried rigidly by one pin target while its reference moved on (a skinned cape frozen while its
  // back bone leaned thawed with the backstop inside it, pushed out at 24 m/s)
  const resume = ch.work[W_RESUME] === 1
  if (resume && k === c.substeps - 1) ch.work[W_RESUME] = 0
  const since = resume ? RESUME_SINCE : ch.drive !== null ? 1 : (k % every) + 1
  constrainAndUpdateVelocities(
    c.pos,
    c.prev,
    ch.start,
    c.vel,
    c.invMass,
    c.invMass3,
    ch.limitHeld,
    ch.ref,
    ch.lim,
    ch.refParams,
    c.params,
    since,
    c.count,
  )
}

/**
 * Guard phase, after a reset: held particles back on their reference at the step's end (the
 * guard restores the pinned particles through the pins, and knows nothing of these).
 */
export function placeHeldAfterReset(c: ClothState): void {
  const ch = c.character!
  if (ch.heldCount === 0 || ch.work[W_SKIN_JUMPED] === 1) return
  referenceSubstep(c, ch, c.substeps - 1, c.substeps)
  placeOnReference(c.pos, ch.heldList, ch.heldCount, ch.ref, ch.refParams, c.params, c.pinCount)
  for (let q = 0; q < ch.heldCount; q++) {
    const j = 3 * ch.heldList[q]
    c.prev[j] = c.pos[j]
    c.prev[j + 1] = c.pos[j + 1]
    c.prev[j + 2] = c.pos[j + 2]
  }
}

/**
 * Guard phase, before the check: the box around a constrained cloth's reference pose at the
 * step's end, as the guard's anchor box (`G_ANCHOR`, with the pins): its motion constraints hold
 * it there, so a cloth that follows its reference (a character scaled up, bones far apart) is not
 * taken for one flying off. Empty for a cloth without motion constraints.
 */
export function setGuardAnchor(c: ClothState): void {
  const g = c.guard.params
  const ch = c.character
  clearGuardAnchor(g)
  if (ch === null || !ch.constrained) return
  const ref = ch.ref, w = ch.work
  let minX = Infinity, minY = Infinity, minZ = Infinity
  let maxX = -Infinity, maxY = -Infinity, maxZ = -Infinity
  for (let o = 0; o < BLEND * c.count; o += BLEND) {
    const x = ref[o + 3], y = ref[o + 4], z = ref[o + 5]
    if (x < minX) minX = x
    if (x > maxX) maxX = x
    if (y < minY) minY = y
    if (y > maxY) maxY = y
    if (z < minZ) minZ = z
    if (z > maxZ) maxZ = z
  }
  if (!(minX <= maxX)) return
  g[G_ANCHOR] = w[W_TO] + minX
  g[G_ANCHOR + 1] = w[W_TO + 1] + minY
  g[G_ANCHOR + 2] = w[W_TO + 2] + minZ
  g[G_ANCHOR + 3] = w[W_TO] + maxX
  g[G_ANCHOR + 4] = w[W_TO + 1] + maxY
  g[G_ANCHOR + 5] = w[W_TO + 2] + maxZ
}
