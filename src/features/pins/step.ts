import { rotateVecAt } from '../../core/math'
import { P_H, P_STEP_FRACTION } from '../../kernels/params'
import { interpolatePose, interpolateScale } from '../../world/kinematics'
import { moveClothBy } from '../../world/rigid'
import type { ClothState, ClothWorldState } from '../../world/state'

/** Pose and scale scratch of placePins: the target's pose and scale at the substep's fraction of the step. */
const pose = new Float64Array(7)
const scale = new Float64Array(3)

/**
 * A pin's offset in its target's frame into out[o..o+2], `ahead[0]` seconds after its glide's state
 * now (`blendTime`: smoothstep from `blendFrom` to its offset, as `placePins` glides it); −1: its
 * end offset. (Seconds in an array: a double passed to a call is boxed.)
 */
export function pinOffsetAhead(
  P: ClothWorldState['components']['Pin'],
  pin: number,
  ahead: Float64Array,
  out: Float64Array,
  o: number,
): void {
  let lx = P.ox[pin], ly = P.oy[pin], lz = P.oz[pin]
  const left = P.blendLeft[pin] - ahead[0]
  if (ahead[0] >= 0 && left > 0) {
    const u = 1 - left / P.blendTime[pin], s = u * u * (3 - 2 * u), b = 3 * pin
    lx = P.blendFrom[b] + (lx - P.blendFrom[b]) * s
    ly = P.blendFrom[b + 1] + (ly - P.blendFrom[b + 1]) * s
    lz = P.blendFrom[b + 2] + (lz - P.blendFrom[b + 2]) * s
  }
  out[o] = lx
  out[o + 1] = ly
  out[o + 2] = lz
}

/**
 * Whether every anchor of the cloth's tethers follows one and the same thing, so that they keep
 * their rest distances from each other: all its pins on one target (or all on the world), and the
 * particles its motion constraints hold (max distance 0) on the same frame without a skin.
 * Otherwise the tether solve lets tethers lengthen as their anchors move apart (`solveTethers`).
 */
export function anchorsMoveTogether(state: ClothWorldState, c: ClothState): boolean {
  const P = state.components.Pin
  const pins = c.pins.list
  let target = -1
  for (let q = 0; q < pins.length; q++) {
    const t = P.target[pins[q]]
    if (target < 0) target = t
    else if (t !== target) return false
  }
  const ch = c.character
  return ch === null || ch.heldCount === 0 || (ch.skin === null && (target < 0 || ch.frame === target))
}

/** The slot of the first of the cloth's pin targets that jumped at this frame's sample, or −1. */
export function jumpedPinTarget(state: ClothWorldState, c: ClothState): number {
  const jumped = state.kinematics.jumped
  const P = state.components.Pin
  const pins = c.pins.list
  for (let q = 0; q < pins.length; q++) {
    const slot = P.slot[pins[q]]
    if (slot >= 0 && jumped[slot] !== 0) return slot
  }
  return -1
}

/**
 * At a frame sample: if one of the cloth's pin targets jumped (teleported), carry the whole cloth
 * along by the same rigid transform, keeping its shape and (rotated) velocity. The kinematics
 * module has already moved the target's earlier poses, so the pins continue from the new place.
 * Returns 1 when it carried the cloth, 2 when `teleportCloth` had moved it by hand (nothing to
 * follow), else 0.
 */
export function followTargetJumps(state: ClothWorldState, c: ClothState): number {
  const k = state.kinematics
  if (c.pins.skipTeleport) {
    c.pins.skipTeleport = false
    replaceHandMove(state, c)
    return 2
  }
  const slot = jumpedPinTarget(state, c)
  if (slot < 0) return 0
  if (k.jumped[slot] === 1) state.stats.teleports++ // (not the carried motion of dropped time)
  moveClothBy(c, k.jump, 10 * slot)
  return 1
}

/**
 * A cloth `teleportCloth` moved by hand (`ClothPins.hand`, T) whose pins all hold it to one target:
 * the hand move is replaced by the target's jump at this sample (J: its motion beyond what its
 * velocity predicts, `sampleFrame`), as a detected teleport carries it, so the rest of the target's
 * motion is simulated as motion. A game that moves its character from A to B and the cloth by B − A
 * has given the frame's running motion as part of the teleport: the pins then interpolated that
 * part while the cloth had already been moved by it and kept its velocity (24 % stretch after a
 * 0.1 s frame at 4 m/s, against 5.6 % for the same teleport detected). A cloth held to several
 * targets, or to a target and the world, keeps the hand move.
 */
function replaceHandMove(state: ClothWorldState, c: ClothState): void {
  const hand = c.pins.hand
  if (hand[10] !== 1) return
  hand[10] = 0
  const P = state.components.Pin
  const pins = c.pins.list
  if (pins.length === 0) return
  const target = P.target[pins[0]]
  for (let q = 1; q < pins.length; q++) if (P.target[pins[q]] !== target) return
  const slot = P.slot[pins[0]]
  const k = state.kinematics
  if (target === 0 || slot < 0 || k.jumped[slot] !== 1) return
  moveClothBy(c, hand, 0, true) // T⁻¹
  moveClothBy(c, k.jump, 10 * slot) // J
}

/** A pin's offset, scaled and turned (scratch of `pinTravel`). */
const offset = new Float64Array(3)

/** Where the pins stand in this step's target poses (0 its start, 1 its end; below 0 before it). */
const pinFraction = new Float64Array(1)

/**
 * Places the pinned particles of a cloth for local substep k of n: the target's pose is
 * interpolated (position lerp, rotation slerp) to (k + 1)/n of the way through the step, so a fast
 * character drags its cloth smoothly instead of in one jerk per step. Scalars travel in typed
 * arrays: calling helpers with double arguments would box them (allocate) on every call.
 * `advance` false places them as they stand (the guard, after a reset): the blends of pins added
 * or moved at run time do not move on, and no pin update is counted.
 */
export function placePins(state: ClothWorldState, c: ClothState, k: number, n: number, advance = true): void {
  const P = state.components.Pin
  const h = c.params[P_H]
  const f = (k + 1) / n
  c.params[P_STEP_FRACTION] = f
  // a step that spans fixed steps the cloth sat out (stepping every n-th) moves its pins over the
  // whole span: from where they stand (where its last step left them) straight to where their
  // targets are at the step's end, an equal part per substep. (Over the last fixed step only, the
  // pinned particles took all the waited motion at the first substep; along this step's motion
  // extrapolated back, they went where their targets never were when a character started or
  // stopped walking: 3.1 m/s and 12 % stretch, against 1.5 m/s and 6.9 % never far-stepped)
  const span = Math.round((c.h * n) / state.fixedTimeStep)
  const rest = span > 1 ? 1 / (n - k) : 1 // (the share of what is left that this substep moves)
  pinFraction[0] = span > 1 ? 1 : f
  const pos = c.pos
  const K = state.kinematics
  const from = K.stepFrom, to = K.stepTo
  let poseSlot = -1 // the target whose pose and scale `pose` and `scale` hold (a pinned row shares one target)
  const pins = c.pins.list
  for (let q = 0; q < pins.length; q++) {
    const pin = pins[q]
    let lx = P.ox[pin], ly = P.oy[pin], lz = P.oz[pin]
    const left = P.blendLeft[pin]
    if (left > 0) {
      const total = P.blendTime[pin]
      const nextLeft = !advance ? left : left > h ? left - h : 0
      P.blendLeft[pin] = nextLeft
      const u = total > 0 ? 1 - nextLeft / total : 1
      const s = u * u * (3 - 2 * u) // smoothstep: no velocity kick at either end
      const b = 3 * pin
      lx = P.blendFrom[b] + (lx - P.blendFrom[b]) * s
      ly = P.blendFrom[b + 1] + (ly - P.blendFrom[b + 1]) * s
      lz = P.blendFrom[b + 2] + (lz - P.blendFrom[b + 2]) * s
    }
    const i = 3 * P.particle[pin]
    const tgt = P.target[pin]
    if (tgt === 0) {
      pos[i] = lx
      pos[i + 1] = ly
      pos[i + 2] = lz
      continue
    }
    // the target's pose and scale (k + 1)/n of the way through the step
    const slot = P.slot[pin]
    if (slot !== poseSlot) {
      interpolatePose(from, to, 7 * slot, pinFraction, 0, pose, 0)
      interpolateScale(K, 3 * slot, pinFraction, 0, scale, 0)
      poseSlot = slot
    }
    lx *= scale[0]
    ly *= scale[1]
    lz *= scale[2]
    const px = pose[0], py = pose[1], pz = pose[2], qx = pose[3], qy = pose[4], qz = pose[5], qw = pose[6]
    // v' = v + w·t + q × t, t = 2·q × v
    const tx = 2 * (qy * lz - qz * ly), ty = 2 * (qz * lx - qx * lz), tz = 2 * (qx * ly - qy * lx)
    const x = px + lx + qw * tx + (qy * tz - qz * ty)
    const y = py + ly + qw * ty + (qz * tx - qx * tz)
    const z = pz + lz + qw * tz + (qx * ty - qy * tx)
    if (rest === 1) {
      pos[i] = x
      pos[i + 1] = y
      pos[i + 2] = z
    } else {
      pos[i] += (x - pos[i]) * rest
      pos[i + 1] += (y - pos[i + 1]) * rest
      pos[i + 2] += (z - pos[i + 2]) * rest
    }
  }
  if (advance) state.stats.pinUpdates += pins.length
}

/**
 * Collision phase, at a step's first substep: the farthest any pinned particle of the cloth still
 * has to go this step, from where it stands to its target's pose at the step's end (with the
 * offset scaled and turned as at the end). The colliders a cloth is tested against must cover it:
 * a sheet yanked from rest at 18 m/s by its pins was dragged 25 mm into a ball its bounds did not
 * reach (they grew with its particles' speed alone). Into out[o] (a double returned from a call
 * V8 does not inline is boxed: an allocation per step).
 */
export function pinTravel(state: ClothWorldState, c: ClothState, out: Float64Array, o: number): void {
  const P = state.components.Pin
  const K = state.kinematics
  const to = K.stepTo, sc = K.scaleStepTo
  const pos = c.pos
  const pins = c.pins.list
  let far2 = 0
  for (let q = 0; q < pins.length; q++) {
    const pin = pins[q]
    const slot = P.slot[pin]
    if (P.target[pin] === 0 || slot < 0) continue
    const t = 7 * slot
    offset[0] = P.ox[pin] * sc[3 * slot]
    offset[1] = P.oy[pin] * sc[3 * slot + 1]
    offset[2] = P.oz[pin] * sc[3 * slot + 2]
    rotateVecAt(to, t + 3, offset, 0, offset, 0)
    const i = 3 * P.particle[pin]
    const dx = to[t] + offset[0] - pos[i], dy = to[t + 1] + offset[1] - pos[i + 1], dz = to[t + 2] + offset[2] - pos[i + 2]
    const d2 = dx * dx + dy * dy + dz * dz
    if (d2 > far2) far2 = d2
  }
  out[o] = Math.sqrt(far2)
}
