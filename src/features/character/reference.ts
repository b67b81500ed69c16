import { multiplyQuatAt, normalizeQuatAt, quatToMatrix, relativeRotationAt, rotateVecAt } from '../../core/math'
import { skinReference } from '../../kernels/skin'
import type { ClothState, ClothWorldState } from '../../world/state'
import { BLEND, RIGID, W_T, W_T0 } from '../../kernels/motion'
import { P_STEP_FRACTION, P_STEP_START } from '../../kernels/params'
import {
  BLEND_BOTH,
  BLEND_END,
  M_BIND,
  M_POSE,
  M_REF_VALID,
  W_BLEND,
  W_FROM,
  W_RT,
  W_TF,
  W_TO,
  W_TT,
  type ClothCharacter,
  type ClothSkin,
} from './types'

/**
 * The reference pose of a character cloth: its rest positions carried by the frame's transform
 * (pose · bind pose⁻¹), or blended from its bones' transforms when skinned. Poses here are
 * px py pz qx qy qz qw sx sy sz (stride 10).
 */

/** Scratch: two rotation matrices (9 each). */
const rot = new Float64Array(18)

/**
 * Writes a tracked entity's pose at the end of the current step (its `stepTo` and `scaleStepTo`:
 * sampled at the frame's start and interpolated, as pin targets' are, so a Transform written
 * between `beginClothStep` and `endClothStep` waits for the next frame) into out[o..o+9].
 */
export function trackedPose(state: ClothWorldState, slot: number, out: Float64Array, o: number): void {
  const k = state.kinematics
  for (let j = 0; j < 7; j++) out[o + j] = k.stepTo[7 * slot + j]
  for (let j = 0; j < 3; j++) out[o + 7 + j] = k.scaleStepTo[3 * slot + j]
}

/** Like `trackedPose`, at the start of the current step (`stepFrom`, `scaleStepFrom`). */
export function trackedStartPose(state: ClothWorldState, slot: number, out: Float64Array, o: number): void {
  const k = state.kinematics
  for (let j = 0; j < 7; j++) out[o + j] = k.stepFrom[7 * slot + j]
  for (let j = 0; j < 3; j++) out[o + 7 + j] = k.scaleStepFrom[3 * slot + j]
}

/** The identity pose into out[o..o+9]. */
export function identityPose(out: Float64Array, o: number): void {
  for (let j = 0; j < 10; j++) out[o + j] = j === 6 || j >= 7 ? 1 : 0
}

/**
 * The 3×4 matrix taking a point at bind pose `bind` to pose `now` (now · bind⁻¹):
 * A = R_now·diag(s_now / s_bind)·R_bindᵀ, t = p_now − A·p_bind, into out[oo..oo+11] (the layout
 * of `kernels/skin.ts`).
 */
export function poseMatrix(now: Float64Array, no: number, bind: Float64Array, bo: number, out: Float64Array, oo: number): void {
  quatToMatrix(now, no + 3, rot, 0)
  quatToMatrix(bind, bo + 3, rot, 9)
  const s0 = now[no + 7] / bind[bo + 7], s1 = now[no + 8] / bind[bo + 8], s2 = now[no + 9] / bind[bo + 9]
  for (let i = 0; i < 3; i++) {
    const a = rot[3 * i] * s0, b = rot[3 * i + 1] * s1, c = rot[3 * i + 2] * s2
    for (let j = 0; j < 3; j++) out[oo + 3 * i + j] = a * rot[9 + 3 * j] + b * rot[9 + 3 * j + 1] + c * rot[9 + 3 * j + 2]
  }
  const px = bind[bo], py = bind[bo + 1], pz = bind[bo + 2]
  for (let i = 0; i < 3; i++) {
    out[oo + 9 + i] = now[no + i] - (out[oo + 3 * i] * px + out[oo + 3 * i + 1] * py + out[oo + 3 * i + 2] * pz)
  }
}

/**
 * The frame's transform [R·diag(s) | p] of the pose at pose[po..] into out[oo..oo+11] (the 3×4
 * layout of `kernels/skin.ts`).
 */
export function poseTransform(pose: Float64Array, po: number, out: Float64Array, oo: number): void {
  quatToMatrix(pose, po + 3, rot, 0)
  for (let i = 0; i < 3; i++) for (let j = 0; j < 3; j++) out[oo + 3 * i + j] = rot[3 * i + j] * pose[po + 7 + j]
  out[oo + 9] = pose[po]
  out[oo + 10] = pose[po + 1]
  out[oo + 11] = pose[po + 2]
}

/**
 * A rigid reference's data (configuration time): each rest position and normal in the frame's
 * bind coordinates, l = diag(1/s)·Rᵀ·(rest − p) and Rᵀ·normal, into `bind` (RIGID values each).
 */
export function bindRigid(c: ClothState, ch: ClothCharacter): void {
  const m = ch.motion
  quatToMatrix(m, M_BIND + 3, rot, 0)
  const px = m[M_BIND], py = m[M_BIND + 1], pz = m[M_BIND + 2]
  for (let i = 0; i < c.count; i++) {
    const j = 3 * i, o = RIGID * i
    const dx = ch.rest[j] - px, dy = ch.rest[j + 1] - py, dz = ch.rest[j + 2] - pz
    const nx = ch.restNormal[j], ny = ch.restNormal[j + 1], nz = ch.restNormal[j + 2]
    for (let a = 0; a < 3; a++) {
      ch.bind[o + a] = (rot[a] * dx + rot[3 + a] * dy + rot[6 + a] * dz) / m[M_BIND + 7 + a]
      ch.bind[o + 3 + a] = rot[a] * nx + rot[3 + a] * ny + rot[6 + a] * nz
    }
  }
  m[M_REF_VALID] = 0
}

/** Scratch of bone poses at the end of a step (grown to the largest skeleton at configuration time). */
let boneScratch = new Float64Array(10 * 8)

/** Makes the bone-pose scratch hold `bones` poses (configuration time only). */
export function reserveBoneScratch(bones: number): void {
  if (boneScratch.length < 10 * bones) boneScratch = new Float64Array(10 * bones)
}

/** The bones' skinning matrices at the poses `bonePoses` (stride 10) into `mats` (stride 12). */
function boneMatrices(skin: ClothSkin, bonePoses: Float64Array, mats: Float64Array): void {
  for (let b = 0; b < skin.bones.length; b++) poseMatrix(bonePoses, 10 * b, skin.bind, 10 * b, mats, 12 * b)
}

/**
 * Sync phase, for a cloth with motion constraints: the frame's part of this step's reference. A
 * rigid reference needs the frame's transforms at the step's start and end (and its rotation at
 * the end, for normals), from which `blendReference` writes it per particle at the step's first
 * substep (both ends, every step: no continuity to keep track of). A skinned one is blended per
 * particle (`ref`, BLEND values, offsets from the frame's origin at the step's start and end) by
 * `blendReference` at the step's first substep, from the bones' matrices computed here: the start is last step's end while the
 * reference is continuous (the same origin); otherwise it is blended from the poses at the step's
 * start (the bones' last poses). Bones then remember their poses at the step's end.
 */
export function updateReference(state: ClothWorldState, ch: ClothCharacter): void {
  const w = ch.work
  const skin = ch.skin
  if (skin === null) {
    poseTransform(w, W_FROM, w, W_TF)
    poseTransform(w, W_TO, w, W_TT)
    quatToMatrix(w, W_TO + 3, w, W_RT)
    w[W_BLEND] = BLEND_BOTH
    return
  }
  const m = ch.motion
  if (m[M_REF_VALID] === 1) w[W_BLEND] = BLEND_END
  else {
    boneMatrices(skin, skin.pose, skin.matricesFrom)
    w[W_BLEND] = BLEND_BOTH
    m[M_REF_VALID] = 1
  }
  bonePosesAtEnd(state, skin, boneScratch, w)
  boneMatrices(skin, boneScratch, skin.matrices)
  for (let j = 0; j < skin.pose.length; j++) skin.pose[j] = boneScratch[j]
}

/**
 * Sync phase, for a skinned cloth whose reference is not in use (no motion constraints, no reset):
 * its bones' last poses follow them, and the next reference starts afresh. Left behind, the first
 * step after constraints came on blended from the bones' poses when the skin was set (or the
 * constraints last ran), and pulled the cape along its character's whole path since in one step:
 * 51 % stretch, 30 frames after the skin was set on a running character.
 */
export function followBones(state: ClothWorldState, ch: ClothCharacter): void {
  const skin = ch.skin
  if (skin === null) return
  bonePosesAtEnd(state, skin, skin.pose, ch.work)
  ch.motion[M_REF_VALID] = 0
}

/**
 * Predict phase, at the cloth's first substep (or the sync phase, before a reset puts the cloth on
 * its reference): the per-particle reference of the step that `updateReference` set up, skinned
 * or rigid.
 */
export function blendReference(c: ClothState, ch: ClothCharacter): void {
  const w = ch.work
  const mode = w[W_BLEND]
  if (mode === 0) return
  w[W_BLEND] = 0
  const skin = ch.skin
  if (skin === null) {
    rigidReference(ch.bind, w, ch.ref, c.count)
    return
  }
  const ref = ch.ref
  if (mode === BLEND_END) {
    for (let o = 0; o < BLEND * c.count; o += BLEND) {
      ref[o] = ref[o + 3]
      ref[o + 1] = ref[o + 4]
      ref[o + 2] = ref[o + 5]
    }
  } else skinReference(skin.matricesFrom, skin.joints, skin.weights, ch.rest, ch.restNormal, w, W_FROM, ref, 0, 6, BLEND, c.count)
  skinReference(skin.matrices, skin.joints, skin.weights, ch.rest, ch.restNormal, w, W_TO, ref, 3, 6, BLEND, c.count)
}

/**
 * A rigid reference's step: each particle's bind coordinates l carried by the frame's transforms
 * at the step's start and end, as offsets A·l from the frame's origin then, and its bind normal
 * turned by the frame's rotation at the end, into `ref` (BLEND values each).
 */
function rigidReference(bind: Float32Array, w: Float64Array, ref: Float32Array, count: number): void {
  const s00 = w[W_TF], s01 = w[W_TF + 1], s02 = w[W_TF + 2], s10 = w[W_TF + 3], s11 = w[W_TF + 4], s12 = w[W_TF + 5]
  const s20 = w[W_TF + 6], s21 = w[W_TF + 7], s22 = w[W_TF + 8]
  const e00 = w[W_TT], e01 = w[W_TT + 1], e02 = w[W_TT + 2], e10 = w[W_TT + 3], e11 = w[W_TT + 4], e12 = w[W_TT + 5]
  const e20 = w[W_TT + 6], e21 = w[W_TT + 7], e22 = w[W_TT + 8]
  const n00 = w[W_RT], n01 = w[W_RT + 1], n02 = w[W_RT + 2], n10 = w[W_RT + 3], n11 = w[W_RT + 4], n12 = w[W_RT + 5]
  const n20 = w[W_RT + 6], n21 = w[W_RT + 7], n22 = w[W_RT + 8]
  for (let i = 0, o = 0, r = 0; i < count; i++, o += RIGID, r += BLEND) {
    const lx = bind[o], ly = bind[o + 1], lz = bind[o + 2]
    const nx = bind[o + 3], ny = bind[o + 4], nz = bind[o + 5]
    ref[r] = s00 * lx + s01 * ly + s02 * lz
    ref[r + 1] = s10 * lx + s11 * ly + s12 * lz
    ref[r + 2] = s20 * lx + s21 * ly + s22 * lz
    ref[r + 3] = e00 * lx + e01 * ly + e02 * lz
    ref[r + 4] = e10 * lx + e11 * ly + e12 * lz
    ref[r + 5] = e20 * lx + e21 * ly + e22 * lz
    ref[r + 6] = n00 * nx + n01 * ny + n02 * nz
    ref[r + 7] = n10 * nx + n11 * ny + n12 * nz
    ref[r + 8] = n20 * nx + n21 * ny + n22 * nz
  }
}

/**
 * The frame's part of the reference for local substep k of n (`ch.refParams`, see REF_PARAMS in
 * kernels/motion.ts: the frame's origin at the substep's end and start), with P_STEP_START and
 * P_STEP_FRACTION set to k/n and (k + 1)/n; k = −1 gives the reference at the step's start.
 */
export function referenceSubstep(c: ClothState, ch: ClothCharacter, k: number, n: number): void {
  const p = c.params
  const f = (k + 1) / n, f0 = k / n
  p[P_STEP_START] = f0
  p[P_STEP_FRACTION] = f
  const w = ch.work, r = ch.refParams
  for (let q = 0; q < 3; q++) {
    r[W_T + q] = w[W_FROM + q] + (w[W_TO + q] - w[W_FROM + q]) * f
    r[W_T0 + q] = w[W_FROM + q] + (w[W_TO + q] - w[W_FROM + q]) * f0
  }
}

/**
 * Each bone's pose at the end of the step into out (stride 10). A removed bone keeps its last pose
 * in the cloth's frame: with `w` (a step's work, its frame's poses at the step's start and end) it
 * is carried by the frame's motion over the step; without (configuration time) it stays. (Left in
 * the world where it went, the part of a running character's cape weighted on it was held there:
 * 2174 % stretch within a second.)
 */
function bonePosesAtEnd(state: ClothWorldState, skin: ClothSkin, out: Float64Array, w: Float64Array | null): void {
  if (w !== null) relativeRotationAt(w, W_TO + 3, w, W_FROM + 3, carry, 0)
  for (let b = 0; b < skin.bones.length; b++) {
    const slot = skin.slots[b], o = 10 * b
    if (slot >= 0) {
      trackedPose(state, slot, out, o)
      continue
    }
    for (let j = 0; j < 10; j++) out[o + j] = skin.pose[o + j]
    if (w !== null) carryPose(out, o, w, W_FROM, w, W_TO, carry, 0)
  }
}

/** The pose at pose[o..o+6] carried rigidly with a frame from its pose `from[fo..]` to `to[to0..]`, `turn[tu..tu+3]` the turn between them. */
export function carryPose(
  pose: Float64Array,
  o: number,
  from: Float64Array,
  fo: number,
  to: Float64Array,
  to0: number,
  turn: Float64Array,
  tu: number,
): void {
  for (let j = 0; j < 3; j++) carry[4 + j] = pose[o + j] - from[fo + j]
  rotateVecAt(turn, tu, carry, 4, carry, 4)
  for (let j = 0; j < 3; j++) pose[o + j] = to[to0 + j] + carry[4 + j]
  multiplyQuatAt(turn, tu, pose, o + 3, pose, o + 3)
  normalizeQuatAt(pose, o + 3)
}

/** Scratch of `bonePosesAtEnd` and `carryPose`: the frame's turn over the step (quaternion), a vector. */
const carry = new Float64Array(7)

/**
 * The reference positions (xyz per particle, world) at the frame pose `pose[0..9]` and, for a
 * skinned cloth, the bone poses `bones` (stride 10), into `out` (configuration time and queries).
 */
function referencePositions(c: ClothState, ch: ClothCharacter, pose: Float64Array, bones: Float64Array, out: Float64Array): void {
  const skin = ch.skin
  if (skin === null) {
    const t = new Float64Array(12)
    poseTransform(pose, 0, t, 0)
    for (let i = 0; i < c.count; i++) {
      const o = RIGID * i
      for (let a = 0; a < 3; a++)
        out[3 * i + a] = t[3 * a] * ch.bind[o] + t[3 * a + 1] * ch.bind[o + 1] + t[3 * a + 2] * ch.bind[o + 2] + t[9 + a]
    }
    return
  }
  const both = new Float32Array(6 * c.count) // positions (offsets from the frame's origin) and normals
  const mats = new Float64Array(12 * skin.bones.length) // (not the step's: a query may come between its phases)
  boneMatrices(skin, bones, mats)
  skinReference(mats, skin.joints, skin.weights, ch.rest, ch.restNormal, pose, 0, both, 0, 3, 6, c.count)
  for (let i = 0; i < c.count; i++) for (let d = 0; d < 3; d++) out[3 * i + d] = pose[d] + both[6 * i + d]
}

/**
 * The reference as it stands now (the frame's and bones' current tracked poses) into `out`
 * (configuration time: rebinding to another frame or skeleton keeps the reference where it is).
 */
export function currentReference(state: ClothWorldState, c: ClothState, ch: ClothCharacter, out: Float64Array): void {
  const pose = new Float64Array(10)
  if (ch.frameSlot >= 0) trackedPose(state, ch.frameSlot, pose, 0)
  else pose.set(ch.motion.subarray(M_POSE, M_POSE + 10))
  const skin = ch.skin
  const bones = new Float64Array(skin === null ? 0 : 10 * skin.bones.length)
  if (skin !== null) bonePosesAtEnd(state, skin, bones, null)
  referencePositions(c, ch, pose, bones, out)
}

/** The reference at the end of the cloth's last step into `out` (queries). */
export function lastReference(c: ClothState, ch: ClothCharacter, out: Float64Array): void {
  referencePositions(c, ch, ch.motion.subarray(M_POSE, M_POSE + 10), ch.skin === null ? new Float64Array(0) : ch.skin.pose, out)
}

/**
 * Area-weighted vertex normals of the rest positions (unnormalised triangle normals summed, then
 * normalised; +z when degenerate), into `out` (configuration time, and each step of a pin's glide).
 */
export function restNormals(c: ClothState, rest: Float64Array, out: Float64Array): void {
  const t = c.topology
  const tris = t.triangles
  out.fill(0, 0, 3 * c.count)
  for (let k = 0; k < t.triangleCount; k++) {
    const a = 3 * tris[3 * k], b = 3 * tris[3 * k + 1], d = 3 * tris[3 * k + 2]
    const ux = rest[b] - rest[a], uy = rest[b + 1] - rest[a + 1], uz = rest[b + 2] - rest[a + 2]
    const vx = rest[d] - rest[a], vy = rest[d + 1] - rest[a + 1], vz = rest[d + 2] - rest[a + 2]
    const nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx
    out[a] += nx
    out[a + 1] += ny
    out[a + 2] += nz
    out[b] += nx
    out[b + 1] += ny
    out[b + 2] += nz
    out[d] += nx
    out[d + 1] += ny
    out[d + 2] += nz
  }
  for (let j = 0; j < 3 * c.count; j += 3) {
    const l = Math.hypot(out[j], out[j + 1], out[j + 2])
    if (l > 1e-15) {
      out[j] /= l
      out[j + 1] /= l
      out[j + 2] /= l
    } else {
      out[j] = 0
      out[j + 1] = 0
      out[j + 2] = 1
    }
  }
}
