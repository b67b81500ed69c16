import { CARRY_PART, CARRY_WHOLE, K_CARRIED, K_DROPPED, applyJump } from '../../world/kinematics'
import type { ClothState, ClothWorldState } from '../../world/state'

/** `Kinematics.carry`: CARRY_WITH + f, carried by slot f's jump after the sample (`carryWithFrames`). */
const CARRY_WITH = 3

/**
 * Sync phase, before a frame sample after dropped frame time (a hitch longer than the steps a frame
 * may run): which tracked entities' motion in that time is swept rather than carried
 * (`Kinematics.carry`, read by `sampleFrame`): those a cloth follows only in part (pins on it and
 * on the world or another entity). Carried, such a cloth would be torn between the carried and the
 * uncarried (a sheet pinned to the world and to a turning corner was swung 0.7 rad about the
 * corner: 39 % stretch). Every other entity is carried: one a cloth follows as a whole (every pin
 * on it, its character frame it or none) with the cloth, and a collider's body with it (a leg on
 * its own entity, swept while the cape was carried, ran through it: 347 %). A skinned cloth with a
 * frame follows the frame as a whole: its bones (and pins on them) are carried by the frame's jump
 * (`carryWithFrames`), and sweep only their motion against it (each bone swept whole, a skinned
 * cape after a 0.25 s hitch at 4 m/s changed speed by 13 m/s in a frame, with 39 % stretch).
 * Returns whether some slot is carried with a frame.
 */
export function markCarriedSlots(state: ClothWorldState): boolean {
  const k = state.kinematics
  if (!k.framed || !(k.time[K_DROPPED] > 0)) return false
  k.carry.fill(0, 0, k.count)
  const P = state.components.Pin
  const cloths = state.cloths
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    const whole = wholeSlot(state, c)
    const pins = c.pins.list
    for (let q = 0; q < pins.length; q++) if (P.target[pins[q]] !== 0) mark(k.carry, P.slot[pins[q]], whole)
    const ch = c.character
    if (ch === null) continue
    mark(k.carry, ch.frameSlot, whole)
    if (ch.skin !== null) { for (let b = 0; b < ch.skin.slots.length; b++) mark(k.carry, ch.skin.slots[b], whole) }
  }
  // carried with a frame that is itself swept or carried with another: swept
  let any = false
  const live = k.live
  for (let q = 0; q < live.length; q++) {
    const slot = live[q], f = k.carry[slot] - CARRY_WITH
    if (f < 0) continue
    if (k.carry[f] !== CARRY_WHOLE) k.carry[slot] = CARRY_PART
    else any = true
  }
  return any
}

/**
 * Sync phase, right after `sampleFrame` when `markCarriedSlots` returned true: each slot carried
 * with a frame takes the frame's jump for the dropped time's share (when the frame moved and the
 * slot did not jump itself), on its history as `sampleFrame` moves a carried slot's (its previous
 * sample is now `sampleFrom`), so it sweeps only its motion against the frame.
 */
export function carryWithFrames(state: ClothWorldState): void {
  const k = state.kinematics
  const live = k.live
  for (let q = 0; q < live.length; q++) {
    const slot = live[q], f = k.carry[slot] - CARRY_WITH
    if (f < 0 || k.jumped[slot] !== 0 || k.jumped[f] !== K_CARRIED) continue
    const j = 10 * slot, o = 7 * slot
    k.jump.copyWithin(j, 10 * f, 10 * f + 10)
    applyJump(k.jump, j, k.sampleFrom, o)
    applyJump(k.jump, j, k.stepTo, o)
    applyJump(k.jump, j, k.stepFrom, o)
    k.jumped[slot] = K_CARRIED
  }
}

/**
 * A slot a cloth follows: carried if it is the one the cloth follows as a whole (`whole`), carried
 * with `whole` if it is another of a skinned cloth's (a bone, or a pin on one), unless another
 * cloth follows it otherwise (a slot one cloth follows as a whole can be carried with a frame: any
 * rigid jump of it carries that cloth along).
 */
function mark(carry: Int32Array, slot: number, whole: number): void {
  if (slot < 0) return
  const want = slot === whole ? CARRY_WHOLE : whole >= 0 ? CARRY_WITH + whole : CARRY_PART
  const had = carry[slot]
  if (had === 0 || had === want || (had === CARRY_WHOLE && want >= CARRY_WITH)) carry[slot] = want
  else if (!(had >= CARRY_WITH && want === CARRY_WHOLE)) carry[slot] = CARRY_PART
}

/**
 * The slot the cloth follows as a whole (all its pins, and its character frame), or −1. A skinned
 * cloth's pins on its bones count as on its frame; with the world as its frame, it has none.
 */
function wholeSlot(state: ClothWorldState, c: ClothState): number {
  const P = state.components.Pin
  const ch = c.character, skin = ch === null ? null : ch.skin
  let slot = -1
  const pins = c.pins.list
  for (let q = 0; q < pins.length; q++) {
    const pin = pins[q], s = P.slot[pin]
    if (P.target[pin] === 0 || s < 0) return -1 // held by the world too
    if (skin !== null && ch!.frameSlot >= 0 && skin.slots.indexOf(s) >= 0) continue // a bone: carried with the frame
    if (slot < 0) slot = s
    else if (s !== slot) return -1
  }
  if (ch !== null) {
    if (skin !== null && ch.frameSlot < 0) return -1
    if (slot < 0) slot = ch.frameSlot
    else if (ch.frameSlot !== slot && (ch.frameSlot >= 0 || ch.constrained)) return -1
  }
  return slot
}
