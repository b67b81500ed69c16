import { multiplyQuatAt, normalizeQuatAt, rotateVecAt } from '../../core/math'
import { applyJump, readPoseInto, trackEntity, untrackEntity } from '../../world/kinematics'
import type { ClothState, ClothWorldState } from '../../world/state'
import { adoptAnchor, releaseAnchor } from '../budget/freeze'
import { pinOffsetAhead } from '../pins/step'
import { bindRigid, currentReference, restNormals, trackedPose } from './reference'
import { FROM_CLOTH, M_BIND, M_POSE, M_PRIMED, M_REF_VALID, S_FRAME_EXPLICIT, type ClothCharacter } from './types'

/**
 * A character cloth's frame: which entity it is (given, or the default: the first pin's target, the
 * first skin bone, the world), and moving the cloth's reference onto a new frame without moving it.
 */

/** The target of the cloth's first pin that has one (but `except`), else its first skin bone, else 0 (the world). */
export function defaultFrame(state: ClothWorldState, c: ClothState, except = -1): number {
  const P = state.components.Pin
  for (const pin of c.pins.list) if (pin !== except && P.target[pin] !== 0) return P.target[pin]
  const skin = c.character?.skin
  if (skin) { for (const bone of skin.bones) if (bone !== 0) return bone }
  return 0
}

/** The frame back to its default, no longer one given explicitly. */
export function useDefaultFrame(state: ClothWorldState, c: ClothState, ch: ClothCharacter): void {
  ch.settings[S_FRAME_EXPLICIT] = 0
  setFrame(state, c, ch, defaultFrame(state, c))
}

/**
 * Called when a pin is added (before it joins the cloth's list): a character cloth whose frame is
 * its default and that had no pin with a target takes the new pin's target as its frame; a rigid
 * reference whose frame the new pin holds it to is fitted to its pins on that frame, the new one
 * with them. So pins added or moved after the character settings give what pinning first gives:
 * left as it was, the reference of a cape equipped from 5 m away stayed where the cape was made
 * (11,249 % stretch for good), and a collar re-pinned 10 cm higher stayed 10 cm off (215 %).
 */
export function adoptPinFrame(state: ClothWorldState, pin: number): void {
  const P = state.components.Pin
  const c = state.components.Cloth.state[P.cloth[pin]]
  const ch = c?.character
  const eid = P.target[pin]
  if (!ch || eid === 0) return
  // (the observer runs before pinParticle lists the pin: it is listed here for the fit, and unlisted after)
  const list = c.pins.list
  list.push(pin)
  let adopt = ch.settings[S_FRAME_EXPLICIT] === 0
  for (let q = 0; q < list.length - 1; q++) if (P.target[list[q]] !== 0) adopt = false
  if (adopt && eid !== ch.frame) setFrame(state, c, ch, eid)
  else if (eid === ch.frame && ch.frameSlot >= 0 && ch.skin === null) {
    trackedPose(state, ch.frameSlot, ch.motion, M_BIND)
    fitToPins(state, c, ch, eid)
  }
  list.pop()
}

/**
 * A rigid reference bound anew to the cloth as created, fitted to its pins on its frame `eid`
 * (`attachPose`, from the frame's pose now at motion[M_BIND..]).
 */
function fitToPins(state: ClothWorldState, c: ClothState, ch: ClothCharacter, eid: number): void {
  restAsCreated(c, ch)
  attachPose(state, c, eid, ch.motion, M_BIND)
  ch.motion[M_REF_VALID] = 0
  bindRigid(c, ch)
}

/**
 * Called when a pin goes away (before or after it leaves the cloth's list): a character cloth whose frame is
 * its default and was this pin's target takes the default without it (another pin's target, the
 * first skin bone, the world), its reference staying where it is. A cape whose pins were all
 * removed had kept its character as its frame: dropped, it walked 3 m along with the character
 * (and was carried 10 m by its teleport), where making the settings after the unpin gave a cape
 * lying still: setup order decided.
 */
export function dropPinFrame(state: ClothWorldState, pin: number): void {
  const P = state.components.Pin
  const c = state.components.Cloth.state[P.cloth[pin]]
  const ch = c?.character
  if (!ch || ch.settings[S_FRAME_EXPLICIT] !== 0 || P.target[pin] === 0 || P.target[pin] !== ch.frame) return
  setFrame(state, c, ch, defaultFrame(state, c, pin))
}

/**
 * Makes `eid` (0: the world) the cloth's frame. A rigid reference is rebound so that it stays
 * where it is now (`rebind`), carried by the new frame from here on; the frame's motion history
 * restarts. Without `rebind` (nothing is bound yet) the rest shape is bound exactly: to the frame's
 * pose when the cloth's first pin on it was made (`attachPose`), else to its pose now.
 */
export function setFrame(state: ClothWorldState, c: ClothState, ch: ClothCharacter, eid: number, rebind = true): void {
  if (eid === ch.frame && (eid === 0 || ch.frameSlot >= 0)) return
  // a frame that the cloth's pins hold it to binds the cloth as created to them, as the first
  // setting does: kept where it stood, a reference that drifted meanwhile (the world as the frame
  // for a moment while the character walked) stayed 5 cm off the pins for good (16 % stretch)
  const onPins = rebind && ch.skin === null && eid !== 0 && pinnedTo(state, c, eid)
  if (!onPins && ch.skin === null && rebind) rebindRest(state, c, ch)
  const oldFrame = ch.frame, oldSlot = ch.frameSlot
  const slot = eid !== 0 ? trackEntity(state, eid) : -1
  if (slot >= 0) backdate(state, slot, eid, oldSlot, oldFrame)
  ch.frame = eid
  ch.frameSlot = slot
  // a frozen cloth carried by the old frame is carried by it until now, then by the new one
  // (released before the new frame was in, it was carried by nothing: 30 m/s at its thaw)
  if (oldSlot >= 0) {
    releaseAnchor(state, c, oldSlot)
    untrackEntity(state, oldFrame)
  }
  adoptAnchor(state, c)
  const m = ch.motion
  if (ch.frameSlot >= 0) trackedPose(state, ch.frameSlot, m, M_POSE)
  // (the world, or a frame gone: the last pose stays)
  m.copyWithin(M_BIND, M_POSE, M_POSE + 10)
  // a new frame entity has no motion history: its first step asks the cloth's motion whether the
  // frame stood still until now (see `frameFromCloth`; the world as the frame stands still anyway)
  m[M_PRIMED] = ch.frameSlot >= 0 ? FROM_CLOTH : 0
  if (onPins) fitToPins(state, c, ch, eid)
  else {
    if (!rebind && ch.skin === null) attachPose(state, c, eid, m, M_BIND)
    m[M_REF_VALID] = 0
    if (ch.skin === null) bindRigid(c, ch)
  }
}

/** The character's rest shape back to the cloth as created, with its normals. */
export function restAsCreated(c: ClothState, ch: ClothCharacter): void {
  ch.rest.set(c.guard.rest.subarray(0, 3 * c.count))
  restNormals(c, ch.rest, ch.restNormal)
}

/** Whether a pin of the cloth holds it to `eid`. */
function pinnedTo(state: ClothWorldState, c: ClothState, eid: number): boolean {
  const P = state.components.Pin
  for (const pin of c.pins.list) if (P.target[pin] === eid) return true
  return false
}

/**
 * The pose to bind the rest shape (the cloth as created) to, so that the reference puts the pinned
 * particles where their pins on `eid` hold them, into out[o..o+9]; left alone when no pin of the
 * cloth targets it. A pin records its target's pose when made (`PinStore.pose`) and holds its
 * particle where it was then: for pins made while the cloth was where it was created (as pinning
 * at creation does), the first pin's pose is that (bound to the pose at the call instead, a cape
 * configured after a 3 m walk had its reference 3.3 m off). Pins made after the cloth moved (re-
 * pinned after a walk, or given offsets elsewhere) hold particles where the rest shape does not
 * put them at that pose: the rest shape is then fitted to the pins, the rigid motion that best
 * takes their rest positions onto their offsets in the target's frame (`fitRigid`), with the
 * first pin's scale (re-pinned after a walk and a turn, the reference lay 3.3 m off its pins).
 */
function attachPose(state: ClothWorldState, c: ClothState, eid: number, out: Float64Array, o: number): void {
  const P = state.components.Pin
  const ch = c.character!
  let first = -1, off = 0
  for (const pin of c.pins.list) {
    if (P.target[pin] !== eid) continue
    if (first < 0) {
      first = pin
      for (let j = 0; j < 10; j++) out[o + j] = P.pose[10 * pin + j]
    }
    // where the rest shape puts the pin's particle at that pose, against where the pin holds it
    const i = 3 * P.particle[pin]
    pinOffsetAhead(P, pin, glideAhead, fit, 0)
    fit[0] *= out[o + 7]
    fit[1] *= out[o + 8]
    fit[2] *= out[o + 9]
    rotateVecAt(out, o + 3, fit, 0, fit, 0)
    off = Math.max(
      off,
      Math.hypot(out[o] + fit[0] - ch.rest[i], out[o + 1] + fit[1] - ch.rest[i + 1], out[o + 2] + fit[2] - ch.rest[i + 2]),
    )
  }
  if (first < 0 || !(off > 1e-6)) return
  fitRigid(state, c, eid, out, o)
}

/** Scratch of `attachPose` and `fitRigid`: a vector (0..2), centroids (3..8), S (9..17), N (18..33), an offset (34..36). */
const fit = new Float64Array(37)

/** How far ahead (seconds) of their glides' state now the fit takes the pins' offsets (`pinOffsetAhead`); −1: their end offsets. */
const glideAhead = new Float64Array([-1])

/**
 * Sync phase, before the step's reference: a rigid reference whose frame holds pins that glide
 * (`blendTime`: re-pinned with offsets, or a budget's thaw) is fitted to where they will hold their
 * particles at the step's end, as the settings fit it to pins (`fitToPins`), so the limits follow
 * the glide. (Fitted to the pins' end offsets at once, a constrained cape re-pinned onto a second
 * character 0.8 m away was held there while its collar glided: 1629 % stretch, 64 m/s.) Its last
 * step fits the end offsets themselves, what a pin that snaps gives.
 */
export function followPinGlides(state: ClothWorldState, c: ClothState, ch: ClothCharacter): void {
  if (ch.skin !== null || ch.frameSlot < 0) return
  const P = state.components.Pin
  const pins = c.pins.list
  let gliding = false
  for (let q = 0; q < pins.length && !gliding; q++) gliding = P.target[pins[q]] === ch.frame && P.blendLeft[pins[q]] > 0
  if (!gliding) return
  glideAhead[0] = c.h * c.substeps
  fitToPins(state, c, ch, ch.frame)
  glideAhead[0] = -1
}

/**
 * The rigid motion (rotation about and position of out[o..o+6], the scale at out[o+7..o+9] kept)
 * that best takes the pins' offsets on `eid` (scaled) onto their particles' rest positions, in
 * the least-squares sense (Horn's quaternion method: the eigenvector of the largest eigenvalue of
 * the 4×4 matrix N built from the cross-covariance S, by power iteration from the pose's own
 * rotation, so that a turn the pins leave open (one pin, or a row of them) stays as that pose has
 * it).
 */
function fitRigid(state: ClothWorldState, c: ClothState, eid: number, out: Float64Array, o: number): void {
  const P = state.components.Pin
  const rest = c.character!.rest
  const s0 = out[o + 7], s1 = out[o + 8], s2 = out[o + 9]
  const f = fit
  f.fill(0, 3, 18)
  let n = 0
  for (const pin of c.pins.list) {
    if (P.target[pin] !== eid) continue
    const i = 3 * P.particle[pin]
    pinOffsetAhead(P, pin, glideAhead, f, 34)
    f[3] += s0 * f[34]
    f[4] += s1 * f[35]
    f[5] += s2 * f[36]
    for (let a = 0; a < 3; a++) f[6 + a] += rest[i + a]
    n++
  }
  for (let a = 3; a < 9; a++) f[a] /= n
  for (const pin of c.pins.list) {
    if (P.target[pin] !== eid) continue
    const i = 3 * P.particle[pin]
    pinOffsetAhead(P, pin, glideAhead, f, 34)
    const ax = s0 * f[34] - f[3], ay = s1 * f[35] - f[4], az = s2 * f[36] - f[5]
    const bx = rest[i] - f[6], by = rest[i + 1] - f[7], bz = rest[i + 2] - f[8]
    f[9] += ax * bx
    f[10] += ax * by
    f[11] += ax * bz
    f[12] += ay * bx
    f[13] += ay * by
    f[14] += ay * bz
    f[15] += az * bx
    f[16] += az * by
    f[17] += az * bz
  }
  const xx = f[9], xy = f[10], xz = f[11], yx = f[12], yy = f[13], yz = f[14], zx = f[15], zy = f[16], zz = f[17]
  // N (symmetric, row-major), in quaternion order w, x, y, z, at f[18..33] (no array per fit: a
  // glide refits every step)
  const N = 18
  f[N] = xx + yy + zz
  f[N + 1] = f[N + 4] = yz - zy
  f[N + 2] = f[N + 8] = zx - xz
  f[N + 3] = f[N + 12] = xy - yx
  f[N + 5] = xx - yy - zz
  f[N + 6] = f[N + 9] = xy + yx
  f[N + 7] = f[N + 13] = zx + xz
  f[N + 10] = -xx + yy - zz
  f[N + 11] = f[N + 14] = yz + zy
  f[N + 15] = -xx - yy + zz
  let norm = 0
  for (let a = N; a < N + 16; a++) norm += f[a] * f[a]
  norm = Math.sqrt(norm)
  // from the pose's rotation (w, x, y, z); shifted by ‖N‖ so the largest eigenvalue dominates
  let qw = out[o + 6], qx = out[o + 3], qy = out[o + 4], qz = out[o + 5]
  if (norm > 1e-12) {
    for (let it = 0; it < 200; it++) {
      const w = (f[N] + norm) * qw + f[N + 1] * qx + f[N + 2] * qy + f[N + 3] * qz
      const x = f[N + 4] * qw + (f[N + 5] + norm) * qx + f[N + 6] * qy + f[N + 7] * qz
      const y = f[N + 8] * qw + f[N + 9] * qx + (f[N + 10] + norm) * qy + f[N + 11] * qz
      const z = f[N + 12] * qw + f[N + 13] * qx + f[N + 14] * qy + (f[N + 15] + norm) * qz
      const l = Math.hypot(w, x, y, z)
      qw = w / l
      qx = x / l
      qy = y / l
      qz = z / l
    }
  }
  out[o + 3] = qx
  out[o + 4] = qy
  out[o + 5] = qz
  out[o + 6] = qw
  // the position: the rest centroid less the turned offset centroid
  f[0] = f[3]
  f[1] = f[4]
  f[2] = f[5]
  rotateVecAt(out, o + 3, f, 0, f, 0)
  out[o] = f[6] - f[0]
  out[o + 1] = f[7] - f[1]
  out[o + 2] = f[8] - f[2]
}

/**
 * An entity tracked just now for the first time (slot `slot`, `eid`) has no history: its slot
 * starts at its Transform now, which the game may already have moved for the coming step, while
 * the cloth's reference is where the last step left it (so a frame or bone bound there was off by
 * that motion for good: a running cape's held rows stretched 74 % from its new frame's pinned row).
 * It takes the history of the entity the cloth follows (`via`, slot `viaSlot`, −1: none), offset
 * as the two are now: as if it had moved rigidly with it.
 */
export function backdate(state: ClothWorldState, slot: number, eid: number, viaSlot: number, via: number): void {
  const k = state.kinematics
  if (viaSlot < 0 || viaSlot === slot || k.refs[slot] !== 1) return
  const t = backdateScratch
  readPoseInto(state, via, t) // via now: t[0..6]
  readPoseInto(state, eid, t.subarray(7, 14)) // it now: t[7..13]
  // its pose relative to via's: q = q_via⁻¹·q, p = q_via⁻¹·(p − p_via)
  t[3] = -t[3]
  t[4] = -t[4]
  t[5] = -t[5]
  multiplyQuatAt(t, 3, t, 10, t, 17)
  for (let a = 0; a < 3; a++) t[21 + a] = t[7 + a] - t[a]
  rotateVecAt(t, 3, t, 21, t, 14)
  // via's history, moved by that offset: p = p_via + q_via·p_rel, q = q_via·q_rel
  for (const poses of [k.sampleFrom, k.sampleTo, k.stepFrom, k.stepTo]) {
    const o = 7 * viaSlot, d = 7 * slot
    rotateVecAt(poses, o + 3, t, 14, t, 21)
    for (let a = 0; a < 3; a++) poses[d + a] = poses[o + a] + t[21 + a]
    multiplyQuatAt(poses, o + 3, t, 17, poses, d + 3)
  }
}

/** Scratch of `backdate`: via's pose, the entity's pose, the relative position and rotation, a vector. */
const backdateScratch = new Float64Array(24)

/**
 * rest ← the reference as it stands now (and its normals), so a rebind does not move it. A rigid
 * reference whose frame is still at its bind pose (the world always is) is the rest shape: it is
 * left exact, where the reference computed from the float32 bind would round it (and setup orders
 * would part ways).
 */
export function rebindRest(state: ClothWorldState, c: ClothState, ch: ClothCharacter): void {
  const m = ch.motion
  if (ch.frameSlot >= 0) trackedPose(state, ch.frameSlot, m, M_POSE)
  let still = ch.skin === null
  for (let j = 0; j < 10 && still; j++) still = m[M_POSE + j] === m[M_BIND + j]
  if (!still) {
    const now = new Float64Array(ch.rest.length)
    currentReference(state, c, ch, now)
    ch.rest.set(now)
    restNormals(c, ch.rest, ch.restNormal)
  }
  m.copyWithin(M_BIND, M_POSE, M_POSE + 10)
}

/**
 * `teleportCloth`'s part for character cloth, after the cloth moved by the rigid motion at
 * motion[0..9] (a record of `moveClothBy`): a cloth whose frame is the world (no frame entity, or
 * one that went away) and whose reference is rigid takes its reference along, the world frame's
 * pose moving as the cloth did. (Its motion constraints held it where it had been: 44× stretched
 * between the moved world pins and the old reference.) A frame entity or bones keep the reference
 * where they are.
 */
export function carryWorldFrame(c: ClothState, motion: Float64Array): void {
  const ch = c.character
  if (ch === null || ch.frameSlot >= 0 || ch.skin !== null) return
  applyJump(motion, 0, ch.motion, M_POSE)
  normalizeQuatAt(ch.motion, M_POSE + 3)
  ch.motion[M_REF_VALID] = 0
}
