import { quatToMatrix } from '../../core/math'
import { rigidReference, skinReference } from '../../kernels/skin'
import type { ClothState, ClothWorldState } from '../../world/state'
import { REF, R_FROM, R_NORMAL, R_TO } from '../../kernels/motion'
import { M_BIND, M_POSE, M_REF_VALID, W_FROM, W_TO, type ClothCharacter, type ClothSkin } from './types'

/**
 * The reference pose of a character cloth: its rest positions carried by the frame's transform
 * (pose · bind pose⁻¹), or blended from its bones' transforms when skinned. Poses here are
 * px py pz qx qy qz qw sx sy sz (stride 10).
 */

/** Scratch: two rotation matrices (9 each). */
const rot = new Float64Array(18)

/**
 * Writes an entity's pose at the end of the current step (its tracked `stepTo`, with the
 * Transform's scale: used when finite and > 0, else 1) into out[o..o+9].
 */
export function trackedPose(state: ClothWorldState, slot: number, eid: number, out: Float64Array, o: number): void {
  const from = state.kinematics.stepTo
  for (let j = 0; j < 7; j++) out[o + j] = from[7 * slot + j]
  writeScale(state, eid, out, o)
}

/** Like `trackedPose`, at the start of the current step (`stepFrom`). */
export function trackedStartPose(state: ClothWorldState, slot: number, eid: number, out: Float64Array, o: number): void {
  const from = state.kinematics.stepFrom
  for (let j = 0; j < 7; j++) out[o + j] = from[7 * slot + j]
  writeScale(state, eid, out, o)
}

function writeScale(state: ClothWorldState, eid: number, out: Float64Array, o: number): void {
  const T = state.transforms
  const sx = T.sx ? T.sx[eid] : 1, sy = T.sy ? T.sy[eid] : 1, sz = T.sz ? T.sz[eid] : 1
  out[o + 7] = sx > 0 && sx < Infinity ? sx : 1
  out[o + 8] = sy > 0 && sy < Infinity ? sy : 1
  out[o + 9] = sz > 0 && sz < Infinity ? sz : 1
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

/** Scratch matrix of a rigid reference. */
const rigid = new Float64Array(12)

/**
 * The reference of every particle at the frame pose work[wo..] (rigid) or at the bones' poses
 * (skinned: `bonePoses` with stride 10): positions into out[o + stride·i ..], normals into
 * out[no + stride·i ..].
 */
function referenceAt(
  c: ClothState, ch: ClothCharacter, work: Float64Array, wo: number, bonePoses: Float64Array,
  out: Float32Array, o: number, no: number, stride: number,
): void {
  const skin = ch.skin
  // positions as offsets from the frame's origin at this pose (work[wo..wo+2])
  if (skin === null) {
    poseMatrix(work, wo, ch.motion, M_BIND, rigid, 0)
    rigidReference(rigid, 0, ch.rest, ch.restNormal, work, wo, out, o, no, stride, c.count)
    return
  }
  const nb = skin.bones.length
  for (let b = 0; b < nb; b++) poseMatrix(bonePoses, 10 * b, skin.bind, 10 * b, skin.matrices, 12 * b)
  skinReference(skin.matrices, skin.joints, skin.weights, ch.rest, ch.restNormal, work, wo, out, o, no, stride, c.count)
}

/** Scratch of bone poses at the end of a step (grown to the largest skeleton at configuration time). */
let boneScratch = new Float64Array(10 * 8)

/** Makes the bone-pose scratch hold `bones` poses (configuration time only). */
export function reserveBoneScratch(bones: number): void {
  if (boneScratch.length < 10 * bones) boneScratch = new Float64Array(10 * bones)
}

/**
 * Sync phase: the reference at the start and end of the cloth's step (`ref`, see R_* in
 * kernels/motion.ts), as offsets from the frame's origin at the step's start and end. The start is
 * last step's end while the reference is continuous (the same origin); otherwise it is computed
 * from the poses at the step's start (the frame's `work[W_FROM]`, the bones' last poses). Bones
 * then remember their poses at the step's end.
 */
export function updateReference(state: ClothWorldState, c: ClothState, ch: ClothCharacter): void {
  const m = ch.motion
  const skin = ch.skin
  const ref = ch.ref
  if (m[M_REF_VALID] === 1) {
    for (let o = 0; o < REF * c.count; o += REF) {
      ref[o] = ref[o + R_TO]
      ref[o + 1] = ref[o + R_TO + 1]
      ref[o + 2] = ref[o + R_TO + 2]
    }
  } else {
    referenceAt(c, ch, ch.work, W_FROM, skin === null ? boneScratch : skin.pose, ref, R_FROM, R_NORMAL, REF)
    m[M_REF_VALID] = 1
  }
  if (skin === null) {
    referenceAt(c, ch, ch.work, W_TO, boneScratch, ref, R_TO, R_NORMAL, REF)
    return
  }
  bonePosesAtEnd(state, skin, boneScratch)
  referenceAt(c, ch, ch.work, W_TO, boneScratch, ref, R_TO, R_NORMAL, REF)
  for (let j = 0; j < skin.pose.length; j++) skin.pose[j] = boneScratch[j]
}

/** Each bone's pose at the end of the step (a removed bone: its last pose) into out (stride 10). */
function bonePosesAtEnd(state: ClothWorldState, skin: ClothSkin, out: Float64Array): void {
  for (let b = 0; b < skin.bones.length; b++) {
    const slot = skin.slots[b]
    if (slot >= 0) trackedPose(state, slot, skin.bones[b], out, 10 * b)
    else for (let j = 0; j < 10; j++) out[10 * b + j] = skin.pose[10 * b + j]
  }
}

/**
 * The reference positions as they stand now (end of the last step: the frame's and bones' current
 * tracked poses) into `out` (xyz per particle; configuration time: rebinding to another frame or
 * skeleton keeps the reference where it is).
 */
export function currentReference(state: ClothWorldState, c: ClothState, ch: ClothCharacter, out: Float64Array): void {
  const pose = new Float64Array(10)
  if (ch.frameSlot >= 0) trackedPose(state, ch.frameSlot, ch.frame, pose, 0)
  else pose.set(ch.motion.subarray(M_POSE, M_POSE + 10))
  const skin = ch.skin
  const bones = new Float64Array(skin === null ? 0 : 10 * skin.bones.length)
  if (skin !== null) bonePosesAtEnd(state, skin, bones)
  const both = new Float32Array(6 * c.count) // positions (offsets from the frame's origin) and normals
  referenceAt(c, ch, pose, 0, bones, both, 0, 3, 6)
  for (let i = 0; i < c.count; i++) for (let d = 0; d < 3; d++) out[3 * i + d] = pose[d] + both[6 * i + d]
}

/**
 * Area-weighted vertex normals of the rest positions (unnormalised triangle normals summed, then
 * normalised; +z when degenerate), into `out` (configuration time).
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
    for (const p of [a, b, d]) {
      out[p] += nx
      out[p + 1] += ny
      out[p + 2] += nz
    }
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
