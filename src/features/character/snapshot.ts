import { entityExists, hasComponent } from 'bitecs'
import { fit32, fit64, fit8 } from '../../core/arrays'
import { newArray, touchLayout } from '../../core/shared'
import { ClothError, MAX_SCALE } from '../../core/errors'
import { BLEND, LIMITS, RIGID } from '../../kernels/motion'
import {
  SLOT_DATA,
  SLOT_SCALE_DATA,
  restoreSlot,
  restoreSlotScale,
  saveSlot,
  saveSlotScale,
  scalesInRange,
  trackEntity,
  generationChanged,
  transformGeneration,
  untrackEntity,
} from '../../world/kinematics'
import type { ClothState, ClothWorldState } from '../../world/state'
import { listLoosePieces } from '../../world/rigid'
import { reserveBoneScratch } from './reference'
import { blankCharacter, blankSkin } from './state'
import { M_BIND, M_POSE, MOTION, SETTINGS, type ClothCharacter, type ClothSkin } from './types'

/**
 * Character cloth's section of a snapshot: its settings, the frame's motion history (and the
 * tracked history of the frame entity), the reference pose, the motion constraints, the held
 * particles and the skin (bones, bind poses, their tracked history, joints, weights). Empty arrays
 * when the cloth has no character state.
 */
export interface CharacterSnapshot {
  /**
   * Header (inertia, frame, frame tracked, constrained, skin, the frame's Transform generation),
   * settings, motion, then the frame's slot history and scale history when tracked. The generations (here and per
   * bone, see `Kinematics.generation`) let a restore refuse an entity that lost its Transform since
   * the save, even if its id now names another entity with one.
   */
  character: Float64Array
  /** Per particle: rest, rest normal, limits, then the reference data (RIGID values, or BLEND when skinned). */
  characterParticles: Float64Array
  /** Drive frequency per particle, or empty when no particle has a drive. */
  characterDrive: Float64Array
  characterHeld: Uint8Array
  /** Bone entities (0: removed), and per bone: bind pose, last pose (10 each), slot and scale history (when tracked), Transform generation. */
  characterBones: Int32Array
  characterBoneData: Float64Array
  characterJoints: Int32Array
  characterWeights: Float64Array
}

const H_INERTIA = 0, H_FRAME = 1, H_TRACKED = 2, H_CONSTRAINED = 3, H_SKIN = 4, H_GEN = 5, HEADER = 6
/** Values per particle of `characterParticles` before the reference data: rest, rest normal, limits. */
const PER = 6 + LIMITS
/** The frame's slot and scale history in the header, when tracked. */
const TRACK = SLOT_DATA + SLOT_SCALE_DATA
const BONE_GEN = 20 + TRACK, BONE = BONE_GEN + 1
/** Where the frame's pose and bind pose keep their scale in `motion`. */
const MOTION_POSE_SCALE = M_POSE + 7, MOTION_BIND_SCALE = M_BIND + 7

export function saveCharacter(state: ClothWorldState, c: ClothState, s: CharacterSnapshot): void {
  const ch = c.character
  const n = c.count
  if (ch === null) {
    s.character = fit64(s.character, 0)
    s.characterParticles = fit64(s.characterParticles, 0)
    s.characterDrive = fit64(s.characterDrive, 0)
    s.characterHeld = fit8(s.characterHeld, 0)
    s.characterBones = fit32(s.characterBones, 0)
    s.characterBoneData = fit64(s.characterBoneData, 0)
    s.characterJoints = fit32(s.characterJoints, 0)
    s.characterWeights = fit64(s.characterWeights, 0)
    return
  }
  const k = state.kinematics
  const tracked = ch.frameSlot >= 0
  const h = (s.character = fit64(s.character, HEADER + SETTINGS + MOTION + (tracked ? TRACK : 0)))
  h[H_INERTIA] = ch.inertia ? 1 : 0
  h[H_FRAME] = ch.frame
  h[H_TRACKED] = tracked ? 1 : 0
  h[H_CONSTRAINED] = ch.constrained ? 1 : 0
  h[H_SKIN] = ch.skin !== null ? 1 : 0
  h[H_GEN] = tracked ? transformGeneration(k, ch.frame) : 0
  h.set(ch.settings, HEADER)
  h.set(ch.motion, HEADER + SETTINGS)
  if (tracked) {
    saveSlot(k, ch.frameSlot, h, HEADER + SETTINGS + MOTION)
    saveSlotScale(k, ch.frameSlot, h, HEADER + SETTINGS + MOTION + SLOT_DATA)
  }
  const stride = PER + (ch.skin === null ? RIGID : BLEND)
  const refStride = stride - PER
  const ref = ch.skin === null ? ch.bind : ch.ref // (a rigid reference's step data is rebuilt from bind every step)
  const p = (s.characterParticles = fit64(s.characterParticles, stride * n))
  for (let i = 0; i < n; i++) {
    const o = stride * i
    for (let d = 0; d < 3; d++) {
      p[o + d] = ch.rest[3 * i + d]
      p[o + 3 + d] = ch.restNormal[3 * i + d]
      p[o + 6 + d] = ch.lim[LIMITS * i + d]
    }
    for (let k = 0; k < refStride; k++) p[o + PER + k] = ref[refStride * i + k]
  }
  s.characterDrive = fit64(s.characterDrive, ch.drive === null ? 0 : n)
  if (ch.drive !== null) { for (let i = 0; i < n; i++) s.characterDrive[i] = ch.drive[i] }
  s.characterHeld = fit8(s.characterHeld, n)
  for (let i = 0; i < n; i++) s.characterHeld[i] = ch.held[i]
  const skin = ch.skin
  const nb = skin === null ? 0 : skin.bones.length
  s.characterBones = fit32(s.characterBones, nb)
  s.characterBoneData = fit64(s.characterBoneData, BONE * nb)
  s.characterJoints = fit32(s.characterJoints, skin === null ? 0 : 4 * n)
  s.characterWeights = fit64(s.characterWeights, skin === null ? 0 : 4 * n)
  if (skin === null) return
  for (let b = 0; b < nb; b++) {
    s.characterBones[b] = skin.bones[b]
    s.characterBoneData[BONE * b + BONE_GEN] = skin.bones[b] !== 0 ? transformGeneration(k, skin.bones[b]) : 0
    const o = BONE * b
    for (let d = 0; d < 10; d++) {
      s.characterBoneData[o + d] = skin.bind[10 * b + d]
      s.characterBoneData[o + 10 + d] = skin.pose[10 * b + d]
    }
    if (skin.slots[b] >= 0) {
      saveSlot(k, skin.slots[b], s.characterBoneData, o + 20)
      saveSlotScale(k, skin.slots[b], s.characterBoneData, o + 20 + SLOT_DATA)
    }
  }
  for (let q = 0; q < 4 * n; q++) {
    s.characterJoints[q] = skin.joints[q]
    s.characterWeights[q] = skin.weights[q]
  }
}

/** Throws ClothError unless the section is complete, without NaN, for `n` particles, and its entities still have a Transform in `world`. */
export function checkCharacter(world: object, state: ClothWorldState, s: CharacterSnapshot, arg: string, n: number): void {
  const h = s.character
  if (
    !(h instanceof Float64Array) || !(s.characterParticles instanceof Float64Array) || !(s.characterHeld instanceof Uint8Array) ||
    !(s.characterBones instanceof Int32Array) || !(s.characterBoneData instanceof Float64Array) ||
    !(s.characterJoints instanceof Int32Array) ||
    !(s.characterWeights instanceof Float64Array) || !(s.characterDrive instanceof Float64Array)
  ) {
    throw new ClothError(arg, s, 'is not a complete snapshot (character cloth section missing)')
  }
  if (h.length === 0) return
  const tracked = h[H_TRACKED] === 1
  const nb = s.characterBones.length
  if (
    h.length !== HEADER + SETTINGS + MOTION + (tracked ? TRACK : 0) ||
    s.characterParticles.length !== (PER + (nb > 0 ? BLEND : RIGID)) * n || s.characterHeld.length !== n ||
    (s.characterDrive.length !== 0 && s.characterDrive.length !== n) ||
    (h[H_SKIN] === 1) !== nb > 0 || s.characterBoneData.length !== BONE * nb || s.characterJoints.length !== (nb > 0 ? 4 * n : 0) ||
    s.characterWeights.length !== s.characterJoints.length
  ) {
    throw new ClothError(arg, s, 'is not a complete snapshot (character cloth array sizes do not match)')
  }
  // settings and limits may hold Infinity (no limit); nothing may be NaN
  if (hasNaN(h) || hasNaN(s.characterParticles) || hasNaN(s.characterDrive) || hasNaN(s.characterBoneData) || hasNaN(s.characterWeights)) {
    throw new ClothError(arg, s, 'holds NaN in its character cloth section')
  }
  for (let q = 0; q < s.characterJoints.length; q++) {
    if (!(s.characterJoints[q] >= 0 && s.characterJoints[q] < nb)) throw new ClothError(arg, s, 'holds a skin joint out of range')
  }
  // scales as a Transform holds them: the frame's pose and bind pose, its tracked history, each bone's
  let scales = scalesInRange(h, HEADER + SETTINGS + MOTION_POSE_SCALE, 3) && scalesInRange(h, HEADER + SETTINGS + MOTION_BIND_SCALE, 3)
  if (tracked) scales &&= scalesInRange(h, HEADER + SETTINGS + MOTION + SLOT_DATA, SLOT_SCALE_DATA)
  for (let b = 0; b < nb && scales; b++) {
    scales = scalesInRange(s.characterBoneData, BONE * b + 7, 3) && scalesInRange(s.characterBoneData, BONE * b + 17, 3)
  }
  if (!scales) throw new ClothError(arg, s, `holds a frame or bone scale outside (0, ${MAX_SCALE}] (a Transform's)`)
  const k = state.kinematics
  const frame = h[H_FRAME]
  if (tracked && !live(world, state, frame))
    throw new ClothError(arg, s, `has entity ${frame} as the cloth's frame, which no longer exists or has no Transform`)
  if (tracked && generationChanged(k, h[H_GEN], frame)) {
    throw new ClothError(
      arg,
      s,
      `has entity ${frame} as the cloth's frame, which lost its Transform (was removed) after the save: the id now names another entity`,
    )
  }
  for (let b = 0; b < nb; b++) {
    const e = s.characterBones[b]
    if (e !== 0 && !live(world, state, e))
      throw new ClothError(arg, s, `has entity ${e} as a bone, which no longer exists or has no Transform`)
    if (e !== 0 && generationChanged(k, s.characterBoneData[BONE * b + BONE_GEN], e)) {
      throw new ClothError(
        arg,
        s,
        `has entity ${e} as a bone, which lost its Transform (was removed) after the save: the id now names another entity`,
      )
    }
  }
}

function hasNaN(a: Float64Array): boolean {
  for (let q = 0; q < a.length; q++) if (Number.isNaN(a[q])) return true
  return false
}

/** Whether entity e exists and has a Transform. */
function live(world: object, state: ClothWorldState, e: number): boolean {
  return e !== 0 && entityExists(world as never, e) && hasComponent(world as never, e, state.transforms.component)
}

/**
 * Puts the section back. Pin counts and inverse masses (which include the held particles) come
 * back with the pins and the core section, before this runs.
 */
export function restoreCharacter(state: ClothWorldState, c: ClothState, s: CharacterSnapshot): void {
  const h = s.character
  const n = c.count
  if (h.length === 0) {
    if (c.character !== null) {
      untrackAll(state, c.character)
      c.character = null
      listLoosePieces(state, c)
      touchLayout()
    }
    return
  }
  const ch = c.character ?? (c.character = blankCharacter(c.pos.length / 3))
  const k = state.kinematics
  const tracked = h[H_TRACKED] === 1
  const frame = h[H_FRAME]
  if (ch.frame !== frame || (ch.frameSlot >= 0) !== tracked) {
    if (ch.frameSlot >= 0) untrackEntity(state, ch.frame)
    ch.frame = frame
    ch.frameSlot = tracked ? trackEntity(state, frame) : -1
  }
  ch.inertia = h[H_INERTIA] === 1
  for (let q = 0; q < SETTINGS; q++) ch.settings[q] = h[HEADER + q]
  for (let q = 0; q < MOTION; q++) ch.motion[q] = h[HEADER + SETTINGS + q]
  if (tracked) {
    restoreSlot(k, ch.frameSlot, h, HEADER + SETTINGS + MOTION)
    restoreSlotScale(state, ch.frameSlot, h, HEADER + SETTINGS + MOTION + SLOT_DATA)
  }
  ch.constrained = h[H_CONSTRAINED] === 1
  const p = s.characterParticles
  const stride = PER + (h[H_SKIN] === 1 ? BLEND : RIGID)
  const refStride = stride - PER
  const ref = h[H_SKIN] === 1 ? ch.ref : ch.bind
  ch.heldCount = 0
  for (let i = 0; i < n; i++) {
    const o = stride * i
    for (let d = 0; d < 3; d++) {
      ch.rest[3 * i + d] = p[o + d]
      ch.restNormal[3 * i + d] = p[o + 3 + d]
      ch.lim[LIMITS * i + d] = p[o + 6 + d]
    }
    for (let k = 0; k < refStride; k++) ref[refStride * i + k] = p[o + PER + k]
    ch.held[i] = s.characterHeld[i]
    if (ch.held[i] === 1) ch.heldList[ch.heldCount++] = i
  }
  if (s.characterDrive.length === 0) {
    if (ch.drive !== null) touchLayout()
    ch.drive = null
  } else {
    if (ch.drive === null) ch.drive = newArray(Float64Array, ch.held.length)
    for (let i = 0; i < n; i++) ch.drive[i] = s.characterDrive[i]
  }
  restoreSkin(state, ch, s, n)
}

function restoreSkin(state: ClothWorldState, ch: ClothCharacter, s: CharacterSnapshot, n: number): void {
  const nb = s.characterBones.length
  let skin = ch.skin
  let same = skin !== null && skin.bones.length === nb
  for (let b = 0; same && b < nb; b++)
    same = skin!.bones[b] === s.characterBones[b] && (skin!.slots[b] >= 0) === (s.characterBones[b] !== 0)
  if (!same) {
    if (skin !== null) untrackBones(state, skin)
    skin = ch.skin = nb === 0 ? null : blankSkin(nb, ch.held.length)
    touchLayout()
    if (skin !== null) {
      for (let b = 0; b < nb; b++) {
        const e = s.characterBones[b]
        skin.bones[b] = e
        skin.slots[b] = e !== 0 ? trackEntity(state, e) : -1
      }
      reserveBoneScratch(nb)
    }
  }
  if (skin === null) return
  const k = state.kinematics
  for (let b = 0; b < nb; b++) {
    const o = BONE * b
    for (let d = 0; d < 10; d++) {
      skin.bind[10 * b + d] = s.characterBoneData[o + d]
      skin.pose[10 * b + d] = s.characterBoneData[o + 10 + d]
    }
    if (skin.slots[b] >= 0) {
      restoreSlot(k, skin.slots[b], s.characterBoneData, o + 20)
      restoreSlotScale(state, skin.slots[b], s.characterBoneData, o + 20 + SLOT_DATA)
    }
  }
  for (let q = 0; q < 4 * n; q++) {
    skin.joints[q] = s.characterJoints[q]
    skin.weights[q] = s.characterWeights[q]
  }
}

function untrackBones(state: ClothWorldState, skin: ClothSkin): void {
  for (let b = 0; b < skin.bones.length; b++) if (skin.slots[b] >= 0) untrackEntity(state, skin.bones[b])
}

function untrackAll(state: ClothWorldState, ch: ClothCharacter): void {
  if (ch.frameSlot >= 0) untrackEntity(state, ch.frame)
  if (ch.skin !== null) untrackBones(state, ch.skin)
}
