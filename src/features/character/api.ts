import { hasComponent } from 'bitecs'
import { ClothError, MAX_COORDINATE, checkKeys, checkObject, checkOneOf, isArrayLike, keysOf } from '../../core/errors'
import { newArray, touchLayout } from '../../core/shared'
import { grownArray } from '../../core/store'
import { getCloth, getClothWorld, getClothWorldForChange } from '../../world/access'
import { readPoseInto, readScaleInto, trackEntity, untrackEntity } from '../../world/kinematics'
import { listLoosePieces } from '../../world/rigid'
import type { ClothState, ClothWorldState } from '../../world/state'
import { checkEntity } from '../../world/transform'
import { wakeClothState } from '../../world/wake'
import { releaseAnchor } from '../budget/freeze'
import { placeNewCloth } from '../pins/api'
import { BLEND, LIMITS, L_BACK, L_MAX, L_RADIUS, RIGID } from '../../kernels/motion'
import { clampFeltVelocities } from './frame'
import { blankCharacter, blankSkin, unconstrained } from './state'
import { backdate, defaultFrame, rebindRest, restAsCreated, setFrame, useDefaultFrame } from './frames'
import { bindRigid, identityPose, lastReference, reserveBoneScratch, trackedPose } from './reference'
import {
  M_BIND,
  M_POSE,
  M_REF_VALID,
  S_ANGULAR,
  S_CENTRIFUGAL,
  S_EVERY,
  S_FRAME_EXPLICIT,
  S_LINEAR,
  S_MAX_ANGULAR,
  S_MAX_LINEAR,
  S_TELEPORT_ANGLE,
  S_TELEPORT_DISTANCE,
  S_TELEPORT_MODE,
  type ClothCharacter,
  type ClothInertiaOptions,
  type ClothMotionConstraints,
  type ClothSkinningOptions,
  type ClothTeleportOptions,
  type PerParticle,
} from './types'

/** The keys each options object may have (`checkKeys`). */
const INERTIA_KEYS = keysOf<ClothInertiaOptions>({
  frame: true,
  linear: true,
  angular: true,
  centrifugal: true,
  maxLinearSpeed: true,
  maxAngularSpeed: true,
  teleport: true,
})
const TELEPORT_KEYS = keysOf<ClothTeleportOptions>({ mode: true, distance: true, angle: true })
const CONSTRAINT_KEYS = keysOf<ClothMotionConstraints>({ maxDistance: true, backstop: true, drive: true, every: true })
/**
 * Character cloth, the public API: inertia in the character's frame (`setClothInertia`), motion
 * constraints around a reference pose (`setClothMotionConstraints`), a skinned reference pose
 * (`setClothSkinning`). Per-step work is in step.ts, the frame's motion in frame.ts, the
 * reference pose in reference.ts.
 */

/**
 * Simulates a cloth in the frame of a moving entity (a character), feeling only a share of that
 * frame's motion: `linear`, `angular`, `centrifugal` in [0, 1] (1, the default, is world space; 0
 * moves the cloth rigidly with the frame, as if it stood still), with the frame's speed and turn
 * rate the cloth can feel capped by `maxLinearSpeed` and `maxAngularSpeed`. The cloth's damping
 * then acts on its velocity relative to the frame's motion (in world space it is a drag toward
 * still air; here air drag comes from wind zones). `teleport` sets what happens when the frame
 * jumps. Each call replaces every setting (omitted ones take their defaults); `null` returns the
 * cloth to world space.
 *
 * @example
 * setClothInertia(world, cape, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5, teleport: { mode: 'reset', angle: Math.PI / 2 } })
 */
export function setClothInertia(world: object, cloth: number, options: ClothInertiaOptions | null): void {
  const state = getClothWorldForChange(world)
  const c = getCloth(state, cloth)
  if (options === null) {
    const ch = c.character
    if (ch === null) return
    ch.inertia = false
    dropIfUnused(state, c)
    if (c.character !== null) useDefaultFrame(state, c, ch) // (the frame was an inertia setting)
    wakeClothState(state, c)
    return
  }
  checkObject('options', options)
  checkKeys('options', options, INERTIA_KEYS)
  const frame = options.frame === undefined ? undefined
    : options.frame === null ? 0 : checkFrameEntity(world, state, c, 'options.frame', options.frame)
  const linear = share('options.linear', options.linear)
  const angular = share('options.angular', options.angular)
  const centrifugal = share('options.centrifugal', options.centrifugal)
  const maxLinear = speed('options.maxLinearSpeed', options.maxLinearSpeed)
  const maxAngular = speed('options.maxAngularSpeed', options.maxAngularSpeed)
  let mode = 0, distance = state.teleportDistance, angle = Infinity
  if (options.teleport !== undefined) {
    const t = options.teleport
    checkObject('options.teleport', t)
    checkKeys('options.teleport', t, TELEPORT_KEYS)
    if (t.mode !== undefined) mode = checkOneOf('options.teleport.mode', t.mode, ['keep', 'reset'] as const) === 'reset' ? 1 : 0
    if (t.distance !== undefined) {
      if (typeof t.distance !== 'number' || !(t.distance > 0))
        throw new ClothError('options.teleport.distance', t.distance, 'must be a distance in metres > 0 (Infinity: never)')
      distance = t.distance
    }
    if (t.angle !== undefined) {
      if (typeof t.angle !== 'number' || !(t.angle > 0) || (t.angle > Math.PI && t.angle !== Infinity)) {
        throw new ClothError('options.teleport.angle', t.angle, 'must be an angle in radians in (0, π] (Infinity: never)')
      }
      angle = t.angle
    }
  }
  if (frame !== undefined) placeNewCloth(state, c, frame) // (spawned mid-run: taken as placed)
  const ch = ensureCharacter(state, c)
  if (frame !== undefined) {
    setFrame(state, c, ch, frame)
    ch.settings[S_FRAME_EXPLICIT] = 1
  } else useDefaultFrame(state, c, ch) // (each call replaces every setting: the frame too)
  const s = ch.settings
  s[S_LINEAR] = linear
  s[S_ANGULAR] = angular
  s[S_CENTRIFUGAL] = centrifugal
  s[S_MAX_LINEAR] = maxLinear
  s[S_MAX_ANGULAR] = maxAngular
  s[S_TELEPORT_MODE] = mode
  s[S_TELEPORT_DISTANCE] = distance
  s[S_TELEPORT_ANGLE] = angle
  clampFeltVelocities(ch)
  ch.inertia = true
  wakeClothState(state, c)
}

/**
 * Holds each particle near its reference position: the cloth's rest shape carried by its frame
 * (see `setClothInertia`; default the target of its first pin), or its skinned position
 * (`setClothSkinning`). `maxDistance` (m; 0 = kinematic, Infinity = free) caps the distance from
 * it; `backstop` keeps the particle outside a sphere of `radius` whose surface lies `distance`
 * behind the reference, along the reversed reference normal (the side opposite the one the
 * counter-clockwise triangles face), so it cannot pass into the body where no collider is;
 * `drive` pulls it toward the reference (the fraction of the distance closed every 1/60 s). Each
 * takes one number or one value per particle (painted: 0 at the collar growing to the hem).
 * `null` removes them.
 *
 * @example
 * setClothMotionConstraints(world, cape, { maxDistance: rows.map((r) => 0.3 * r), backstop: { distance: 0.02, radius: 0.5 } })
 */
export function setClothMotionConstraints(world: object, cloth: number, constraints: ClothMotionConstraints | null): void {
  const state = getClothWorldForChange(world)
  const c = getCloth(state, cloth)
  if (constraints === null) {
    liftMotionConstraints(state, c)
    return
  }
  checkObject('constraints', constraints)
  checkKeys('constraints', constraints, CONSTRAINT_KEYS)
  const n = c.count
  const maxDistance = perParticle('constraints.maxDistance', constraints.maxDistance, n, Infinity, 0, Infinity)
  const drive = perParticle('constraints.drive', constraints.drive, n, 0, 0, 1)
  const every = constraints.every ?? 1
  if (!Number.isInteger(every) || every < 1 || every > 1e6) throw new ClothError('constraints.every', every, 'must be an integer ≥ 1')
  const bs = constraints.backstop
  let bsDistance: Float64Array | null = null, bsRadius: Float64Array | null = null
  if (bs !== undefined && bs !== null) {
    checkObject('constraints.backstop', bs)
    checkKeys('constraints.backstop', bs, ['distance', 'radius'])
    if (bs.radius === undefined) throw new ClothError('constraints.backstop.radius', bs.radius, 'must be given (m > 0)')
    bsDistance = perParticle('constraints.backstop.distance', bs.distance, n, 0, 0, 1e6)
    bsRadius = perParticle('constraints.backstop.radius', bs.radius, n, 0, 1e-9, 1e6)
  }
  const ch = ensureCharacter(state, c)
  const lim = ch.lim
  let anyDrive = false
  for (let i = 0; i < n; i++) {
    const l = LIMITS * i
    lim[l + L_MAX] = maxDistance[i]
    lim[l + L_BACK] = bsDistance === null ? 0 : bsDistance[i]
    lim[l + L_RADIUS] = bsRadius === null ? 0 : bsRadius[i]
    if (drive[i] > 0) anyDrive = true
  }
  if (anyDrive) {
    ch.drive = ch.drive ?? newArray(Float64Array, ch.held.length)
    for (let i = 0; i < n; i++) ch.drive[i] = driveFrequency(drive[i])
  } else if (ch.drive !== null) {
    ch.drive = null
    touchLayout()
  }
  ch.constrained = true
  ch.settings[S_EVERY] = every
  const unused = c.topology.unused
  for (let i = 0; i < n; i++) {
    // (a vertex no triangle uses is no part of the cloth: held, it was placed on a reference its
    // no weights give, 1000 m away, and kept moving at the speed cap)
    const hold = maxDistance[i] === 0 && (unused === null || unused[i] === 0)
    if (hold && ch.held[i] === 0) holdParticle(c, ch, i)
    else if (!hold && ch.held[i] === 1) release(c, ch, i)
  }
  wakeClothState(state, c)
}

const SKINNING_KEYS = keysOf<ClothSkinningOptions>({ bones: true, joints: true, weights: true })

/**
 * Makes the cloth's reference pose skinned: linear blend skinning of its rest shape by `bones`
 * (entities with a Transform), with 4 bone indices (`joints`) and 4 weights (summing to 1) per
 * particle. The bind pose is the bones' pose now, and the rest shape the reference as it stands
 * now (the cloth as created, or as its frame carries it). Max distance, backstop, drive and the
 * particles held by max distance 0 then follow the skinned pose. `null` returns to the rigid
 * reference carried by the frame, from where the skinned pose leaves it.
 */
export function setClothSkinning(world: object, cloth: number, skinning: ClothSkinningOptions | null): void {
  const state = getClothWorldForChange(world)
  const c = getCloth(state, cloth)
  if (skinning === null) {
    const ch = c.character
    if (ch === null || ch.skin === null) return
    rebindRest(state, c, ch) // the reference stays where the skin put it, now carried by the frame
    releaseBones(state, c, ch)
    ch.skin = null
    touchLayout()
    bindRigid(c, ch)
    dropIfUnused(state, c)
    wakeClothState(state, c)
    return
  }
  checkObject('skinning', skinning)
  checkKeys('skinning', skinning, SKINNING_KEYS)
  const n = c.count
  const { bones, joints, weights } = skinning
  if (!isArrayLike(bones) || bones.length === 0 || bones.length > 65535)
    throw new ClothError('skinning.bones', bones, 'must be an array of 1 to 65535 bone entities')
  for (let b = 0; b < bones.length; b++) checkFrameEntity(world, state, c, `skinning.bones[${b}]`, bones[b])
  if (!isArrayLike(joints) || joints.length !== 4 * n)
    throw new ClothError('skinning.joints', joints, `must hold 4 bone indices per particle (${4 * n} numbers)`)
  for (let k = 0; k < 4 * n; k++) {
    const j = joints[k]
    if (!Number.isInteger(j) || j < 0 || j >= bones.length)
      throw new ClothError(`skinning.joints[${k}]`, j, `must be a bone index in [0, ${bones.length - 1}]`)
  }
  if (!isArrayLike(weights) || weights.length !== 4 * n)
    throw new ClothError('skinning.weights', weights, `must hold 4 weights per particle (${4 * n} numbers)`)
  const unused = c.topology.unused
  for (let i = 0; i < n; i++) {
    let sum = 0
    for (let k = 4 * i; k < 4 * i + 4; k++) {
      const w = weights[k]
      // (the sum's tolerance either side: one weight a rounding above 1, as float32 exporters write
      // them, or a rounding below 0, as 1 − a − b gives: −5.55e-17 was refused)
      if (typeof w !== 'number' || !(w >= -1e-3) || !(w <= 1 + 1e-3))
        throw new ClothError(`skinning.weights[${k}]`, w, 'must be a weight in [0, 1]')
      sum += w
    }
    // (a vertex no triangle uses is no part of the cloth: it may have no weights, as exports leave it)
    if (!(Math.abs(sum - 1) <= 1e-3) && !(sum === 0 && unused !== null && unused[i] === 1))
      throw new ClothError('skinning.weights', weights, `of particle ${i} sum to ${sum}; each particle's 4 weights must sum to 1`)
  }
  placeNewCloth(state, c, bones[0]) // (its default frame; spawned mid-run: taken as placed)
  const ch = ensureCharacter(state, c)
  rebindRest(state, c, ch)
  releaseBones(state, c, ch)
  const B = bones.length
  const skin = blankSkin(B, ch.held.length)
  for (let b = 0; b < B; b++) {
    skin.bones[b] = bones[b]
    skin.slots[b] = trackEntity(state, skin.bones[b])
    backdate(state, skin.slots[b], skin.bones[b], ch.frameSlot, ch.frame)
    trackedPose(state, skin.slots[b], skin.bind, 10 * b)
  }
  skin.pose.set(skin.bind)
  for (let i = 0; i < n; i++) {
    let sum = 0
    for (let k = 4 * i; k < 4 * i + 4; k++) sum += weights[k]
    for (let k = 4 * i; k < 4 * i + 4; k++) {
      skin.joints[k] = joints[k]
      // exactly 1 in total (an unused vertex without weights: all on its first joint)
      skin.weights[k] = sum > 0 ? weights[k] / sum : k === 4 * i ? 1 : 0
    }
  }
  ch.skin = skin
  reserveBoneScratch(B)
  if (ch.settings[S_FRAME_EXPLICIT] === 0) setFrame(state, c, ch, defaultFrame(state, c))
  ch.motion[M_REF_VALID] = 0
  wakeClothState(state, c)
}

/**
 * The cloth's reference pose at the end of its last step (positions, xyz per particle, m) as a
 * copy, or null when it has none (no character-cloth settings, or no motion constraints: the
 * reference is kept only while constraints use it).
 */
export function getClothReference(world: object, cloth: number): Float64Array | null {
  const c = getCloth(getClothWorld(world), cloth)
  const ch = c.character
  if (ch === null || !ch.constrained) return null
  const out = new Float64Array(3 * c.count)
  lastReference(c, ch, out)
  return out
}

// ---------------------------------------------------------------------------------------------
// Lifetime: creation, the frame, held particles, removal

/** The cloth's character state, created (configuration time) when it has none. */
function ensureCharacter(state: ClothWorldState, c: ClothState): ClothCharacter {
  if (c.character !== null) return c.character
  const P = c.pos.length / 3 // capacity (a tearable cloth reserves room)
  const ch = blankCharacter(P)
  const settings = ch.settings
  settings[S_LINEAR] = 1
  settings[S_ANGULAR] = 1
  settings[S_CENTRIFUGAL] = 1
  settings[S_MAX_LINEAR] = Infinity
  settings[S_MAX_ANGULAR] = Infinity
  settings[S_TELEPORT_DISTANCE] = state.teleportDistance
  settings[S_TELEPORT_ANGLE] = Infinity
  settings[S_EVERY] = 1
  // the rest shape as created, bound to the frame's pose now (float64 until then: a bind is float32)
  restAsCreated(c, ch)
  // the world as the frame: still, its origin at the cloth's centre, since the reference is kept as
  // float32 offsets from the frame's origin (from the world's, a cape 10 km out was 0.4 mm off)
  identityPose(ch.motion, M_POSE)
  for (let i = 0; i < c.count; i++) for (let a = 0; a < 3; a++) ch.motion[M_POSE + a] += ch.rest[3 * i + a] / c.count
  ch.motion.copyWithin(M_BIND, M_POSE, M_POSE + 10)
  c.character = ch
  c.detached[0] = 0 // (whole until a tear frees a piece from the character: `releaseDetachedPieces`)
  const frame = defaultFrame(state, c)
  if (frame !== 0) setFrame(state, c, ch, frame, false)
  else bindRigid(c, ch)
  return ch
}

function releaseBones(state: ClothWorldState, c: ClothState, ch: ClothCharacter): void {
  const skin = ch.skin
  if (skin === null) return
  for (let b = 0; b < skin.bones.length; b++) {
    if (skin.slots[b] >= 0) {
      releaseAnchor(state, c, skin.slots[b])
      untrackEntity(state, skin.bones[b])
    }
    skin.slots[b] = -1
  }
}

/** The cloth's motion constraints gone (`setClothMotionConstraints(world, cloth, null)`), its character state with them when nothing else is set. */
export function liftMotionConstraints(state: ClothWorldState, c: ClothState): void {
  const ch = c.character
  if (ch === null || !ch.constrained) return
  for (let q = ch.heldCount - 1; q >= 0; q--) release(c, ch, ch.heldList[q])
  ch.constrained = false
  ch.drive = null
  touchLayout()
  unconstrained(ch.lim)
  dropIfUnused(state, c)
  wakeClothState(state, c)
}

/** Holds particle i on its reference (max distance 0): it counts as pinned (inverse mass 0, a tether anchor). */
function holdParticle(c: ClothState, ch: ClothCharacter, i: number): void {
  ch.held[i] = 1
  ch.heldList[ch.heldCount++] = i
  if (c.pinCount[i]++ === 0) {
    c.invMass[i] = 0
    c.tethers.dirty = true
  }
}

/** Releases a held particle. */
function release(c: ClothState, ch: ClothCharacter, i: number): void {
  ch.held[i] = 0
  const list = ch.heldList
  for (let q = 0; q < ch.heldCount; q++) {
    if (list[q] !== i) continue
    list.copyWithin(q, q + 1, ch.heldCount)
    ch.heldCount--
    break
  }
  if (--c.pinCount[i] === 0) {
    c.invMass[i] = c.baseInvMass[i]
    c.tethers.dirty = true
  }
}

/** Drops the character state once nothing uses it (the cloth pays nothing again). */
function dropIfUnused(state: ClothWorldState, c: ClothState): void {
  const ch = c.character
  if (ch === null || ch.inertia || ch.constrained || ch.skin !== null) return
  releaseCharacter(state, c)
}

/** Forgets a cloth's character state: stops tracking its frame and bones, releases held particles. */
export function releaseCharacter(state: ClothWorldState, c: ClothState): void {
  const ch = c.character
  if (ch === null) return
  for (let q = ch.heldCount - 1; q >= 0; q--) release(c, ch, ch.heldList[q])
  releaseBones(state, c, ch)
  if (ch.frameSlot >= 0) {
    releaseAnchor(state, c, ch.frameSlot)
    untrackEntity(state, ch.frame)
  }
  ch.frameSlot = -1
  c.character = null
  listLoosePieces(state, c) // (the pieces no pin holds, now that the character holds none)
  touchLayout()
}

// ---------------------------------------------------------------------------------------------
// Tearing: room for split particles, and their copies

/** Grows the per-particle arrays to a capacity of `P` particles (creation time). */
export function reserveCharacter(c: ClothState, P: number): void {
  const ch = c.character
  if (ch === null) return
  ch.rest = grownArray(ch.rest, 3 * P)
  ch.restNormal = grownArray(ch.restNormal, 3 * P)
  ch.ref = grownArray(ch.ref, BLEND * P)
  ch.bind = grownArray(ch.bind, RIGID * P)
  ch.limitHeld = grownArray(ch.limitHeld, P + 1)
  ch.start = grownArray(ch.start, 3 * P)
  if (ch.lim.length < LIMITS * P) {
    const lim = unconstrained(newArray(Float32Array, LIMITS * P))
    lim.set(ch.lim)
    ch.lim = lim
  }
  if (ch.drive !== null) ch.drive = grownArray(ch.drive, P)
  ch.held = grownArray(ch.held, P)
  ch.heldList = grownArray(ch.heldList, P)
  if (ch.skin !== null) {
    ch.skin.joints = grownArray(ch.skin.joints, 4 * P)
    ch.skin.weights = grownArray(ch.skin.weights, 4 * P)
  }
}

/** A particle split off `from` (a tear) gets `from`'s reference, limits and skin weights; it stays held if `from` is. */
export function copyCharacterParticle(c: ClothState, from: number, to: number): void {
  const ch = c.character
  if (ch === null) return
  copy3(ch.rest, from, to)
  copy3(ch.restNormal, from, to)
  for (let k = 0; k < BLEND; k++) ch.ref[BLEND * to + k] = ch.ref[BLEND * from + k]
  for (let k = 0; k < RIGID; k++) ch.bind[RIGID * to + k] = ch.bind[RIGID * from + k]
  for (let k = 0; k < LIMITS; k++) ch.lim[LIMITS * to + k] = ch.lim[LIMITS * from + k]
  if (ch.drive !== null) ch.drive[to] = ch.drive[from]
  const skin = ch.skin
  if (skin !== null) {
    for (let k = 0; k < 4; k++) {
      skin.joints[4 * to + k] = skin.joints[4 * from + k]
      skin.weights[4 * to + k] = skin.weights[4 * from + k]
    }
  }
  copy3(ch.start, from, to) // (where it started the substep: the limits' velocity bound reads it)
  if (ch.held[from] === 1) holdParticle(c, ch, to)
}

/**
 * After a tear split the cloth into pieces: a piece that neither a held particle (max distance 0)
 * nor a pin on the character (its frame entity, or a skin bone) holds is no longer part of the
 * garment, so its particles lose their motion constraints (max distance, backstop, drive). Kept,
 * they held a scrap torn off by a nail in the world to the running character: one triangle from
 * the nail to the hero at 34,657 % stretch. Such particles are listed in `ClothState.detached`: they are
 * predicted in world space and left out of the frame's carries (a piece lying on the ground swung
 * 4.4 m round its character turning on the spot, and jumped 10 m with its teleport). A cloth
 * nothing holds to the character at all (limits alone) keeps them everywhere.
 */
export function releaseDetachedPieces(state: ClothWorldState, c: ClothState): void {
  const ch = c.character
  if (ch === null || c.piece === null) return
  c.detached[0] = 0
  const label = c.piece, n = c.pieceCount
  if (attachedScratch.length < n) attachedScratch = new Uint8Array(Math.max(2 * attachedScratch.length, n))
  const attached = attachedScratch
  attached.fill(0, 0, n)
  let any = false
  for (let q = 0; q < ch.heldCount; q++) {
    attached[label[ch.heldList[q]]] = 1
    any = true
  }
  const P = state.components.Pin
  const bones = ch.skin?.bones
  for (const pin of c.pins.list) {
    const t = P.target[pin]
    if (t === 0 || (t !== ch.frame && (bones === undefined || bones.indexOf(t) < 0))) continue
    attached[label[P.particle[pin]]] = 1
    any = true
  }
  if (!any) return
  let n2 = 0
  for (let i = 0; i < c.count; i++) {
    if (attached[label[i]] === 1) continue
    c.detached[++n2] = i
    ch.lim[LIMITS * i + L_MAX] = Infinity
    ch.lim[LIMITS * i + L_RADIUS] = 0
    if (ch.drive !== null) ch.drive[i] = 0
  }
  c.detached[0] = n2
}

/** Scratch of `releaseDetachedPieces`: whether each piece is held (grown on a tear, rarely). */
let attachedScratch = new Uint8Array(64)

function copy3(a: Float64Array, from: number, to: number): void {
  a[3 * to] = a[3 * from]
  a[3 * to + 1] = a[3 * from + 1]
  a[3 * to + 2] = a[3 * from + 2]
}

/**
 * The frequency ω (rad/s) of the critically damped spring that closes the fraction `f` of an
 * offset in 1/60 s from rest: f = 1 − (1 + ωT)·e^(−ωT), T = 1/60 s, solved by bisection (the
 * right side grows with ω). 0 gives 0, 1 gives Infinity.
 */
function driveFrequency(f: number): number {
  if (f <= 0) return 0
  if (f >= 1) return Infinity
  let lo = 0, hi = 1
  while (1 - (1 + hi) * Math.exp(-hi) < f) hi *= 2
  for (let k = 0; k < 100; k++) {
    const u = 0.5 * (lo + hi)
    if (1 - (1 + u) * Math.exp(-u) < f) lo = u
    else hi = u
  }
  return 30 * (lo + hi) // (u / T, u the midpoint)
}

// ---------------------------------------------------------------------------------------------
// Input checks

function checkFrameEntity(world: object, state: ClothWorldState, c: ClothState, arg: string, eid: unknown): number {
  checkEntity(world, arg, eid)
  if (eid === 0 || !hasComponent(world as never, eid as number, state.transforms.component)) {
    throw new ClothError(arg, eid, 'must be an entity with a Transform (call setTransform first)')
  }
  // the cloth in the entity's frame (its rest shape and where it is now), as `pinParticle` checks a
  // target: bound at a scale of 1e-39, the float32 bind overflowed and the reference was NaN
  const pose = frameScratch
  readPoseInto(state, eid as number, pose)
  readScaleInto(state, eid as number, pose, 7)
  const s = Math.min(pose[7], pose[8], pose[9])
  let far = 0
  for (const xs of [c.pos, c.guard.rest]) {
    for (let j = 0; j < 3 * c.count; j += 3) far = Math.max(far, Math.hypot(xs[j] - pose[0], xs[j + 1] - pose[1], xs[j + 2] - pose[2]))
  }
  if (!(far / s <= MAX_COORDINATE)) {
    throw new ClothError(arg, eid, `is scaled so small that the cloth would lie beyond ±${MAX_COORDINATE} m in its frame`)
  }
  return eid as number
}

/** Scratch of `checkFrameEntity`: a pose and scale. */
const frameScratch = new Float64Array(10)

function share(arg: string, v: unknown): number {
  if (v === undefined) return 1
  if (typeof v !== 'number' || !(v >= 0 && v <= 1)) throw new ClothError(arg, v, 'must be a share in [0, 1]')
  return v
}

function speed(arg: string, v: unknown): number {
  if (v === undefined) return Infinity
  if (typeof v !== 'number' || !(v > 0)) throw new ClothError(arg, v, 'must be a speed > 0 (Infinity: no limit)')
  return v
}

/** One value per particle from a number or an array of `n`, each in [min, max] (NaN never). */
function perParticle(arg: string, v: PerParticle | undefined, n: number, fallback: number, min: number, max: number): Float64Array {
  const out = new Float64Array(n)
  if (v === undefined) return out.fill(fallback)
  const range = `in [${min}, ${max === Infinity ? 'Infinity' : max}]`
  if (typeof v === 'number') {
    if (!(v >= min && v <= max)) throw new ClothError(arg, v, `must be ${range}`)
    return out.fill(v)
  }
  if (!isArrayLike(v) || v.length !== n) throw new ClothError(arg, v, `must be a number or ${n} numbers (one per particle)`)
  for (let i = 0; i < n; i++) {
    const x = v[i]
    if (typeof x !== 'number' || !(x >= min && x <= max)) throw new ClothError(`${arg}[${i}]`, x, `must be ${range}`)
    out[i] = x
  }
  return out
}
