import { addComponent, addEntity, entityExists, hasComponent, removeEntity } from 'bitecs'
import type { vec3 } from 'gl-matrix'
import {
  ClothError,
  MAX_COORDINATE,
  checkIndex,
  checkInteger,
  checkNonNegative,
  checkObject,
  checkPoint,
  checkKeys,
  keysOf,
} from '../../core/errors'
import { relativeRotationAt, rotateVec3 } from '../../core/math'
import { getCloth, getClothWorld, getClothWorldForChange } from '../../world/access'
import { growStores } from '../../world/capacity'
import { readPoseInto, trackEntity, untrackEntity } from '../../world/kinematics'
import { carryFrozen, listLoosePieces, moveClothBy } from '../../world/rigid'
import type { ClothState, ClothWorldState } from '../../world/state'
import { checkEntity } from '../../world/transform'
import { pinOffsetAhead } from './step'
import { wakeClothState } from '../../world/wake'
import { touchLayout } from '../../core/shared'

/** Options of `pinParticle`. */
export interface PinOptions {
  /**
   * When an explicit offset puts the pin away from where the particle is, the particle glides to
   * it over this many seconds instead of jumping. Default 0.25 s; 0 snaps.
   */
  blendTime?: number
}

const PIN_KEYS = keysOf<PinOptions>({ blendTime: true })

const tmp = new Float64Array(16)
/** `pinOffsetAhead`'s time ahead: the glides' state now. */
const NOW = new Float64Array(1)
const _IDENTITY = [0, 0, 0, 1]

/**
 * Pins one particle. With a `target` entity (which must have a Transform), the particle follows
 * the target every substep at `offset` in the target's local frame (rotation and scale applied).
 * Without a target it stays at `offset` in world space. When `offset` is omitted the particle is
 * held where it is now, so pinning at runtime causes no jump; an explicit offset is blended in
 * over `blendTime`. Returns the pin entity (remove it, or call `unpin`, to release the particle).
 */
export function pinParticle(
  world: object,
  cloth: number,
  index: number,
  target?: number | null,
  offset?: Readonly<vec3> | ArrayLike<number>,
  options: PinOptions = {},
): number {
  const state = getClothWorldForChange(world)
  const c = getCloth(state, cloth)
  checkIndex('index', index, c.count)
  const tgt = target ?? 0
  if (tgt !== 0) {
    checkEntity(world, 'target', tgt)
    if (!hasComponent(world as never, tgt, state.transforms.component)) {
      throw new ClothError('target', tgt, 'must have a Transform (call setTransform first)')
    }
  }
  if (offset !== undefined) checkPoint('offset', offset)
  checkObject('options', options)
  checkKeys('options', options, PIN_KEYS)
  const blendTime = options.blendTime === undefined ? 0.25 : checkNonNegative('options.blendTime', options.blendTime)

  // a frozen cloth is first brought to where its pins have carried it (the particle is held there)
  carryFrozen(c, state.kinematics.stepTo)
  // the pin continues from the target's pose at the end of the last step (the simulation's now)
  const slot = tgt !== 0 ? trackEntity(state, tgt) : -1
  const k = state.kinematics
  // (with character settings bound to the cloth where the move left it, the move stays: undone
  // under them, a collar held at max distance 0 was pulled 83 mm off its pins for good)
  const bd = c.pins.backdate, bare = c.pins.list.length === 0
  if (bd[10] > 0 && c.character === null && (bare || slot !== bd[10] - 1)) undoBackdate(state, c)
  // (again after every pin went: a cape unpinned and pinned again was moved back twice, 167 mm)
  if (slot >= 0 && bare && bd[10] === 0 && c.pins.fresh && c.character === null) backdateNewCloth(state, c, slot, tgt)
  if (slot >= 0) { for (let j = 0; j < 7; j++) tmp[8 + j] = k.stepTo[7 * slot + j] }
  // where the particle is now, in the target's frame
  toLocal(state, slot, tmp, 8, c.pos[3 * index], c.pos[3 * index + 1], c.pos[3 * index + 2], tmp, 0)
  if (!(Math.abs(tmp[0]) <= MAX_COORDINATE && Math.abs(tmp[1]) <= MAX_COORDINATE && Math.abs(tmp[2]) <= MAX_COORDINATE)) {
    if (slot >= 0) untrackEntity(state, tgt)
    throw new ClothError('target', tgt, `is scaled so small that the particle would lie beyond ±${MAX_COORDINATE} m in its frame`)
  }

  const pin = addEntity(world as never)
  growStores(state, pin)
  const P = state.components.Pin
  P.cloth[pin] = cloth
  P.particle[pin] = index
  P.target[pin] = tgt
  P.slot[pin] = slot
  P.blendFrom[3 * pin] = tmp[0]
  P.blendFrom[3 * pin + 1] = tmp[1]
  P.blendFrom[3 * pin + 2] = tmp[2]
  if (offset === undefined) {
    P.ox[pin] = tmp[0]
    P.oy[pin] = tmp[1]
    P.oz[pin] = tmp[2]
    P.blendLeft[pin] = 0
  } else {
    P.ox[pin] = offset[0]
    P.oy[pin] = offset[1]
    P.oz[pin] = offset[2]
    P.blendLeft[pin] = blendTime
  }
  P.blendTime[pin] = blendTime
  // the target's pose now (as the offset took it), where the cloth was attached to it
  for (let j = 0; j < 10; j++) P.pose[10 * pin + j] = slot < 0 ? 0 : j < 7 ? k.stepTo[7 * slot + j] : k.scaleStepTo[3 * slot + j - 7]

  addComponent(world as never, pin, P)
  c.pins.list.push(pin)
  listLoosePieces(state, c)
  touchLayout()
  wakeClothState(state, c)
  if (c.pinCount[index]++ === 0) {
    c.invMass[index] = 0
    c.tethers.dirty = true
    c.tethers.loosen = true
  }
  return pin
}

/**
 * The first pin of a cloth that never stepped (`ClothPins.fresh`) and has no character settings
 * yet, when it is on an entity: its particles were placed where the game's Transforms are now, which
 * run ahead of the simulation's now (the last step) by the motion since, when the game animates
 * before it spawns (or draws above 60 Hz). The cloth is moved rigidly back by the target's motion
 * since its last step, so the pin holds it as it was placed (taken against the last step's pose
 * instead, a cape spawned on a tracked hero running at 5 m/s sat 83 mm off its shoulders for good,
 * 111 mm at 144 Hz), and its mesh is drawn from that pose until it steps (`getClothDrawTransform`;
 * drawn from the world's later steps, a cape spawned at a far level was 83–167 mm off before its
 * first step). Character settings given later bind to the cloth where it now is; ones given before
 * bound it at the last step (no move, as before).
 */
function backdateNewCloth(state: ClothWorldState, c: ClothState, slot: number, eid: number): void {
  const to = state.kinematics.stepTo, o = 7 * slot
  const lod = c.budget
  lod.shownSlot = slot
  for (let j = 0; j < 7; j++) lod.shownPose[j] = to[o + j]
  readPoseInto(state, eid, tmp)
  let moved = false
  for (let j = 0; j < 7; j++) moved ||= tmp[j] !== to[o + j]
  if (!moved) return
  const bd = c.pins.backdate
  // x' = to + R·(x − now): the record of `moveClothBy` (centre, rotation, translation)
  bd[0] = tmp[0]
  bd[1] = tmp[1]
  bd[2] = tmp[2]
  relativeRotationAt(to, o + 3, tmp, 3, bd, 3)
  bd[7] = to[o] - tmp[0]
  bd[8] = to[o + 1] - tmp[1]
  bd[9] = to[o + 2] - tmp[2]
  moveClothBy(c, bd, 0)
  bd[10] = slot + 1
  bd[11] = c.version
}

/**
 * Character settings that bind a cloth that never stepped and has no pins and no settings yet to
 * entity `eid` (an explicit frame, or its first skin bone): the cloth is taken as placed against
 * the entity's Transform now, as by a first pin (`backdateNewCloth`). Bound at the last step's
 * pose instead, a cape held by max distance 0 at its collar, spawned on a hero running at 5 m/s,
 * sat 83 mm off for good, its collar 31 mm inside the torso.
 */
export function placeNewCloth(state: ClothWorldState, c: ClothState, eid: number): void {
  const k = state.kinematics
  const slot = eid > 0 && eid < k.slotOf.length ? k.slotOf[eid] : -1
  if (slot < 0 || !c.pins.fresh || c.pins.list.length > 0 || c.character !== null || c.pins.backdate[10] > 0) return
  backdateNewCloth(state, c, slot, eid)
  const bd = c.pins.backdate
  if (bd[10] === 0) return
  // the rest shape as created, which the settings bind to the entity's last-step pose, moves too
  const rest = c.guard.rest
  for (let j = 0; j < 3 * c.count; j += 3) {
    rotateVec3(bd[3], bd[4], bd[5], bd[6], rest[j] - bd[0], rest[j + 1] - bd[1], rest[j + 2] - bd[2], tmp, 0)
    rest[j] = bd[0] + bd[7] + tmp[0]
    rest[j + 1] = bd[1] + bd[8] + tmp[1]
    rest[j + 2] = bd[2] + bd[9] + tmp[2]
  }
}

/**
 * A pin on another entity or in place, on a cloth `backdateNewCloth` moved for its first target
 * (or one moved since): no one rigid motion places it for both, so it goes back where the game
 * placed it and its pins so far are measured there against their targets' last step, as every pin
 * is (pinned elsewhere as well, a running hero's cape held a world pin, or one on a standing
 * character, 83 mm off where it was placed).
 */
function undoBackdate(state: ClothWorldState, c: ClothState): void {
  const bd = c.pins.backdate
  bd[10] = 0
  if (!c.pins.fresh || bd[11] !== c.version) return // (stepped or moved since: it stands)
  moveClothBy(c, bd, 0, true)
  c.budget.shownSlot = -1
  const P = state.components.Pin, k = state.kinematics
  for (let q = 0; q < c.pins.list.length; q++) {
    const pin = c.pins.list[q], slot = P.slot[pin], i = 3 * P.particle[pin]
    if (slot < 0) continue
    toLocal(state, slot, k.stepTo, 7 * slot, c.pos[i], c.pos[i + 1], c.pos[i + 2], tmp, 0)
    const b = 3 * pin
    // (a pin given no offset holds the particle where it was: its offset is that place)
    const plain = P.ox[pin] === P.blendFrom[b] && P.oy[pin] === P.blendFrom[b + 1] && P.oz[pin] === P.blendFrom[b + 2]
    for (let a = 0; a < 3; a++) P.blendFrom[b + a] = tmp[a]
    if (plain) {
      P.ox[pin] = tmp[0]
      P.oy[pin] = tmp[1]
      P.oz[pin] = tmp[2]
    }
  }
}

/**
 * Pins every particle of one grid row (row 0 is the top edge) to `target`, or in place when no
 * target is given. Each particle keeps its current position relative to the target. Returns the
 * pin entities, left to right.
 */
export function pinRow(world: object, cloth: number, row: number, target?: number | null): number[] {
  const state = getClothWorld(world)
  const c = getCloth(state, cloth)
  const { columns, rows } = c.topology
  if (rows === 0) throw new ClothError('cloth', cloth, 'was not built as a grid (pinRow needs createCloth)')
  checkInteger('row', row, 0, rows - 1)
  const pins: number[] = []
  for (let col = 0; col < columns; col++) pins.push(pinParticle(world, cloth, row * columns + col, target))
  return pins
}

/** Releases a pin (removes its entity). The particle keeps its current velocity: no pop. */
export function unpin(world: object, pin: number): void {
  const state = getClothWorldForChange(world)
  if (typeof pin !== 'number' || !entityExists(world as never, pin) || !hasComponent(world as never, pin, state.components.Pin)) {
    throw new ClothError('pin', pin, 'must be a pin entity of this world')
  }
  removeEntity(world as never, pin)
}

/** The pin entities holding a cloth, in creation order (a copy). */
export function getPins(world: object, cloth: number): number[] {
  return getCloth(getClothWorld(world), cloth).pins.list.slice()
}

/** Called when a Pin component goes away: frees the particle and forgets the pin. */
export function releasePin(state: ClothWorldState, pin: number): void {
  const P = state.components.Pin
  const c = state.components.Cloth.state[P.cloth[pin]]
  if (!c) return
  const list = c.pins.list
  const k = list.indexOf(pin)
  if (k < 0) return
  list.splice(k, 1)
  listLoosePieces(state, c)
  touchLayout()
  wakeClothState(state, c)
  if (P.slot[pin] >= 0) untrackEntity(state, P.target[pin])
  P.slot[pin] = -1
  const i = P.particle[pin]
  if (--c.pinCount[i] === 0) {
    c.invMass[i] = c.baseInvMass[i]
    c.tethers.dirty = true
    c.tethers.loosen = true
  }
}

/**
 * Writes the coordinates of world point (x, y, z) in the frame of the target tracked in `slot`
 * (pose at pose[po..], scale at the end of the last step) into out[o..o+2]; with no target
 * (slot −1), the point itself.
 */
function toLocal(
  state: ClothWorldState,
  slot: number,
  pose: Float64Array,
  po: number,
  x: number,
  y: number,
  z: number,
  out: Float64Array,
  o: number,
  scales: Float64Array = state.kinematics.scaleStepTo,
): void {
  if (slot < 0) {
    out[o] = x
    out[o + 1] = y
    out[o + 2] = z
    return
  }
  // inverse rotation: conjugate quaternion
  rotateVec3(-pose[po + 3], -pose[po + 4], -pose[po + 5], pose[po + 6], x - pose[po], y - pose[po + 1], z - pose[po + 2], out, o)
  out[o] /= scales[3 * slot]
  out[o + 1] /= scales[3 * slot + 1]
  out[o + 2] /= scales[3 * slot + 2]
}

/**
 * A frozen cloth thawing (features/budget): it was carried rigidly by one pin's target, so a pin
 * whose target moved otherwise meanwhile (scaled, or another target moving apart from it) holds
 * its particle elsewhere now. Such a pin glides from where its particle is, in its target's frame
 * at `poses`/`scales` (`stepFrom` or `stepTo`, with their scales), to its offset over its
 * `blendTime` (0: it snaps), as a pin given an offset does. (Snapped, a cape whose character
 * shrank to 0.6 while it was frozen thawed at 36 % stretch and 30 m/s; 2.3 % when it watched.)
 */
export function glideThawingPins(state: ClothWorldState, c: ClothState, poses: Float64Array, scales: Float64Array): void {
  const P = state.components.Pin
  const pins = c.pins.list
  for (let q = 0; q < pins.length; q++) {
    const pin = pins[q]
    const slot = P.slot[pin]
    if (slot < 0 || !(P.blendTime[pin] > 0)) continue
    const i = 3 * P.particle[pin]
    toLocal(state, slot, poses, 7 * slot, c.pos[i], c.pos[i + 1], c.pos[i + 2], tmp, 0, scales)
    // where the pin holds it now, in the target's frame (mid-glide: where the glide has got to)
    pinOffsetAhead(P, pin, NOW, tmp, 3)
    const so = 3 * slot
    const off = Math.hypot((tmp[0] - tmp[3]) * scales[so], (tmp[1] - tmp[4]) * scales[so + 1], (tmp[2] - tmp[5]) * scales[so + 2])
    if (!(off > 1e-4)) continue
    P.blendFrom[3 * pin] = tmp[0]
    P.blendFrom[3 * pin + 1] = tmp[1]
    P.blendFrom[3 * pin + 2] = tmp[2]
    P.blendLeft[pin] = P.blendTime[pin]
  }
}

/**
 * `teleportCloth`'s part for pins, after the cloth moved by the rigid motion at motion[0..9] (a
 * record of `moveClothBy`: centre, unit quaternion, translation): world-space pins move with it,
 * pins on targets start the next step at their targets' pose then (a jump, without the automatic
 * teleport test), and the motion is kept for that jump (`replaceHandMove` in step.ts).
 */
export function carryPins(state: ClothWorldState, c: ClothState, motion: Float64Array): void {
  const P = state.components.Pin
  const cx = motion[0], cy = motion[1], cz = motion[2], rx = motion[3], ry = motion[4], rz = motion[5], rw = motion[6]
  const tx = cx + motion[7], ty = cy + motion[8], tz = cz + motion[9]
  for (const pin of c.pins.list) {
    if (P.target[pin] !== 0) continue
    rotateVec3(rx, ry, rz, rw, P.ox[pin] - cx, P.oy[pin] - cy, P.oz[pin] - cz, tmp, 0)
    P.ox[pin] = tx + tmp[0]
    P.oy[pin] = ty + tmp[1]
    P.oz[pin] = tz + tmp[2]
    const b = 3 * pin
    rotateVec3(rx, ry, rz, rw, P.blendFrom[b] - cx, P.blendFrom[b + 1] - cy, P.blendFrom[b + 2] - cz, tmp, 0)
    P.blendFrom[b] = tx + tmp[0]
    P.blendFrom[b + 1] = ty + tmp[1]
    P.blendFrom[b + 2] = tz + tmp[2]
  }
  // the targets' next sample is a jump (whatever its size): the pins start from the new place
  const k = state.kinematics
  for (const pin of c.pins.list) if (P.slot[pin] >= 0) k.forceJump[P.slot[pin]] = 1
  c.pins.skipTeleport = true
  c.pins.hand.set(motion.subarray(0, 10))
  c.pins.hand[10] = 1
}
