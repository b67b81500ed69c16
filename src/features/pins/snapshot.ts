import { entityExists, hasComponent, removeEntity } from 'bitecs'
import { allFinite, fit32, fit64 } from '../../core/arrays'
import { ClothError, MAX_COORDINATE, MAX_SCALE } from '../../core/errors'
import {
  SLOT_DATA,
  SLOT_SCALE_DATA,
  generationChanged,
  restoreSlot,
  restoreSlotScale,
  saveSlot,
  saveSlotScale,
  scalesInRange,
  transformGeneration,
} from '../../world/kinematics'
import type { ClothState, ClothWorldState } from '../../world/state'
import { pinParticle } from './api'

/** The pins' section of a snapshot (see `saveClothState`). */
export interface PinsSnapshot {
  pinCount: Uint16Array
  /** Per pin, in order: entity, particle, target (0 = world point). */
  pins: Int32Array
  /** Per pin: ox, oy, oz, blendFrom xyz, blendLeft, blendTime. */
  pinData: Float64Array
  /**
   * Per pin: its target's pose when it was made (10: position, rotation, scale; see `PinStore.pose`).
   * Absent in older snapshots: the restored pins keep the poses they have (a pin created again by
   * the restore: its target's pose then).
   */
  pinPoses?: Float64Array
  /** Distinct target entities of the pins. */
  targets: Int32Array
  /** Per target: sampleFrom, sampleTo, stepFrom, stepTo (7 each), jump (10), jumped, forceJump. */
  targetData: Float64Array
  /**
   * Per target: its scale at the same four times (3 each). Absent in snapshots from versions that
   * did not track scale: the targets' scales are then taken as they are at the restore.
   */
  targetScales?: Float64Array
  /**
   * Per target: how many times an entity with its id had lost its transform when saved (see
   * `Kinematics.generation`); a restore refuses a target that lost it since, even if the id names
   * an entity with a transform again. Absent in older snapshots: not checked.
   */
  targetGenerations?: Uint32Array
}

const PIN_DATA = 8
const POSE = 10

/** Saves the cloth's pins and the motion history of their targets. */
export function savePins(state: ClothWorldState, c: ClothState, s: PinsSnapshot): void {
  const n = c.count
  const P = state.components.Pin
  const k = state.kinematics
  const pins = c.pins.list
  const np = pins.length
  // distinct targets, in pin order
  let nt = 0
  for (let q = 0; q < np; q++) {
    const t = P.target[pins[q]]
    if (t !== 0 && firstTargetIndex(P, pins, q, t)) nt++
  }
  s.pinCount = s.pinCount && s.pinCount.length === n ? s.pinCount : new Uint16Array(n)
  for (let i = 0; i < n; i++) s.pinCount[i] = c.pinCount[i]
  s.pins = fit32(s.pins, 3 * np)
  s.pinData = fit64(s.pinData, PIN_DATA * np)
  s.pinPoses = fit64(s.pinPoses, POSE * np)
  s.targets = fit32(s.targets, nt)
  s.targetData = fit64(s.targetData, SLOT_DATA * nt)
  s.targetScales = fit64(s.targetScales, SLOT_SCALE_DATA * nt)
  s.targetGenerations = s.targetGenerations && s.targetGenerations.length === nt ? s.targetGenerations : new Uint32Array(nt)
  let t = 0
  for (let q = 0; q < np; q++) {
    const pin = pins[q]
    const target = P.target[pin]
    s.pins[3 * q] = pin
    s.pins[3 * q + 1] = P.particle[pin]
    s.pins[3 * q + 2] = target
    const d = PIN_DATA * q
    s.pinData[d] = P.ox[pin]
    s.pinData[d + 1] = P.oy[pin]
    s.pinData[d + 2] = P.oz[pin]
    s.pinData[d + 3] = P.blendFrom[3 * pin]
    s.pinData[d + 4] = P.blendFrom[3 * pin + 1]
    s.pinData[d + 5] = P.blendFrom[3 * pin + 2]
    s.pinData[d + 6] = P.blendLeft[pin]
    s.pinData[d + 7] = P.blendTime[pin]
    for (let j = 0; j < POSE; j++) s.pinPoses[POSE * q + j] = P.pose[POSE * pin + j]
    if (target === 0 || !firstTargetIndex(P, pins, q, target)) continue
    s.targets[t] = target
    saveSlot(k, k.slotOf[target], s.targetData, SLOT_DATA * t)
    saveSlotScale(k, k.slotOf[target], s.targetScales, SLOT_SCALE_DATA * t)
    s.targetGenerations[t] = transformGeneration(k, target)
    t++
  }
}

/** Throws ClothError unless the pins' section is complete and usable in `world` for `n` particles. */
export function checkPins(world: object, state: ClothWorldState, s: PinsSnapshot, arg: string, n: number): void {
  if (
    !(s.pinCount instanceof Uint16Array) || s.pinCount.length !== n || !(s.pins instanceof Int32Array) || s.pins.length % 3 !== 0 ||
    !(s.pinData instanceof Float64Array) || s.pinData.length !== (PIN_DATA * s.pins.length) / 3 ||
    !(s.targets instanceof Int32Array) || !(s.targetData instanceof Float64Array) || s.targetData.length !== SLOT_DATA * s.targets.length
  ) {
    throw new ClothError(arg, s, 'is not a complete snapshot (array sizes do not match)')
  }
  if (
    s.targetScales !== undefined &&
    (!(s.targetScales instanceof Float64Array) || s.targetScales.length !== SLOT_SCALE_DATA * s.targets.length)
  ) {
    throw new ClothError(arg, s, 'is not a complete snapshot (array sizes do not match)')
  }
  if (s.pinPoses !== undefined && (!(s.pinPoses instanceof Float64Array) || s.pinPoses.length !== (POSE * s.pins.length) / 3)) {
    throw new ClothError(arg, s, 'is not a complete snapshot (array sizes do not match)')
  }
  if (
    !allFinite(s.pinData) || !allFinite(s.targetData) || (s.targetScales !== undefined && !allFinite(s.targetScales)) ||
    (s.pinPoses !== undefined && !allFinite(s.pinPoses))
  ) {
    throw new ClothError(arg, s, 'holds a non-finite number')
  }
  if (s.targetScales !== undefined && !scalesInRange(s.targetScales)) {
    throw new ClothError(`${arg}.targetScales`, s.targetScales, `must hold scales in (0, ${MAX_SCALE}], as a Transform's`)
  }
  const gens = s.targetGenerations
  if (gens !== undefined && (!(gens instanceof Uint32Array) || gens.length !== s.targets.length)) {
    throw new ClothError(arg, s, 'is not a complete snapshot (array sizes do not match)')
  }
  const np = s.pins.length / 3
  for (let q = 0; q < np; q++) {
    const target = s.pins[3 * q + 2]
    if (target !== 0 && (!entityExists(world as never, target) || !hasComponent(world as never, target, state.transforms.component))) {
      throw new ClothError(arg, s, `pins entity ${target}, which no longer exists or has no Transform`)
    }
    if (target !== 0 && gens !== undefined) {
      const t = s.targets.indexOf(target)
      if (t >= 0 && generationChanged(state.kinematics, gens[t], target)) {
        throw new ClothError(
          arg,
          s,
          `pins entity ${target}, which lost its Transform (was removed) after the save: the id now names another entity`,
        )
      }
    }
    if (!(s.pins[3 * q + 1] >= 0 && s.pins[3 * q + 1] < n)) throw new ClothError(arg, s, 'holds a pin on a particle out of range')
    if (target !== 0 && s.pinPoses !== undefined && !isPose(s.pinPoses, POSE * q)) {
      throw new ClothError(
        arg,
        s,
        'holds a pin pose no Transform gives (a position beyond ±1e9 m, a rotation not of unit length, or a scale not in (0, 1e6])',
      )
    }
  }
}

/**
 * Makes the cloth's pins those of the snapshot (same particles, targets, order): pins added since
 * are removed, pins removed since are created again, and the pins still there keep their entities,
 * so the game's handles to them still hold (made all anew, the pins got their recycled ids back in
 * another order: a replay releasing "the left corner" by its handle released the right one). Runs
 * before the particles are restored.
 */
export function restorePinEntities(world: object, state: ClothWorldState, c: ClothState, s: PinsSnapshot): void {
  const P = state.components.Pin
  const np = s.pins.length / 3
  const pins = c.pins.list
  let same = pins.length === np
  for (let q = 0; same && q < np; q++) same = pins[q] === s.pins[3 * q] && savedAs(P, pins[q], s, q)
  if (same) return
  // the saved pins still held as saved, by their entity; the rest go
  const kept = new Int32Array(np).fill(-1)
  for (let q = 0; q < np; q++) {
    const pin = s.pins[3 * q]
    if (pins.includes(pin) && savedAs(P, pin, s, q)) kept[q] = pin
  }
  for (let q = pins.length - 1; q >= 0; q--) {
    const pin = pins[q]
    if (!kept.includes(pin) && entityExists(world as never, pin)) removeEntity(world as never, pin)
  }
  for (let q = 0; q < np; q++) {
    if (kept[q] >= 0) continue
    const target = s.pins[3 * q + 2]
    const d = PIN_DATA * q
    const offset = [s.pinData[d], s.pinData[d + 1], s.pinData[d + 2]]
    kept[q] = pinParticle(world, c.eid, s.pins[3 * q + 1], target === 0 ? null : target, offset, { blendTime: 0 })
  }
  // in the saved order (what the pins' data and the steps follow)
  pins.length = 0
  for (let q = 0; q < np; q++) pins.push(kept[q])
}

/** Whether pin entity `pin` holds the particle and target the snapshot's q-th pin held. */
function savedAs(P: ClothWorldState['components']['Pin'], pin: number, s: PinsSnapshot, q: number): boolean {
  return P.particle[pin] === s.pins[3 * q + 1] && P.target[pin] === s.pins[3 * q + 2]
}

/** Restores the pins' data, the particles' pin counts and the targets' motion history. */
export function restorePins(state: ClothWorldState, c: ClothState, s: PinsSnapshot): void {
  const P = state.components.Pin
  const pins = c.pins.list
  c.pins.fresh = false // (its particles are the simulation's, as saved)
  c.pins.backdate[10] = 0
  c.pinCount.set(s.pinCount)
  for (let q = 0; q < pins.length; q++) {
    const pin = pins[q]
    const d = PIN_DATA * q
    P.ox[pin] = s.pinData[d]
    P.oy[pin] = s.pinData[d + 1]
    P.oz[pin] = s.pinData[d + 2]
    P.blendFrom[3 * pin] = s.pinData[d + 3]
    P.blendFrom[3 * pin + 1] = s.pinData[d + 4]
    P.blendFrom[3 * pin + 2] = s.pinData[d + 5]
    P.blendLeft[pin] = s.pinData[d + 6]
    P.blendTime[pin] = s.pinData[d + 7]
    if (s.pinPoses !== undefined) { for (let j = 0; j < POSE; j++) P.pose[POSE * pin + j] = s.pinPoses[POSE * q + j] }
  }
  const k = state.kinematics
  for (let t = 0; t < s.targets.length; t++) {
    const slot = k.slotOf[s.targets[t]]
    restoreSlot(k, slot, s.targetData, SLOT_DATA * t)
    restoreSlotScale(state, slot, s.targetScales ?? null, SLOT_SCALE_DATA * t)
  }
}

/** Whether p[o..o+9] is a pose a Transform can have: position, unit rotation, scale. */
function isPose(p: Float64Array, o: number): boolean {
  const q2 = p[o + 3] * p[o + 3] + p[o + 4] * p[o + 4] + p[o + 5] * p[o + 5] + p[o + 6] * p[o + 6]
  let ok = Math.abs(q2 - 1) < 1e-3
  for (let a = 0; a < 3; a++) ok &&= Math.abs(p[o + a]) <= MAX_COORDINATE && p[o + 7 + a] > 0 && p[o + 7 + a] <= MAX_SCALE
  return ok
}

function firstTargetIndex(P: { target: Uint32Array }, pins: number[], q: number, t: number): boolean {
  for (let r = 0; r < q; r++) if (P.target[pins[r]] === t) return false
  return true
}
