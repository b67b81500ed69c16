import { CARRY_PART, CARRY_WHOLE, K_DROPPED } from '../../world/kinematics'
import type { ClothState, ClothWorldState } from '../../world/state'

/**
 * Sync phase, before a frame sample after dropped frame time (a hitch longer than the steps a frame
 * may run): which tracked entities' motion in that time is swept rather than carried
 * (`Kinematics.carry`, read by `sampleFrame`): those a cloth follows only in part (pins on it and
 * on the world or another entity, or a skin). Carried, such a cloth would be torn between the
 * carried and the uncarried (a sheet pinned to the world and to a turning corner was swung 0.7 rad
 * about the corner: 39 % stretch). Every other entity is carried: one a cloth follows as a whole
 * (every pin on it, its character frame it or none, no skin) with the cloth, and a collider's body
 * with it (a leg on its own entity, swept while the cape was carried, ran through it: 347 %).
 */
export function markCarriedSlots(state: ClothWorldState): void {
  const k = state.kinematics
  if (!k.framed || !(k.time[K_DROPPED] > 0)) return
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
}

/** A slot a cloth follows: carried if it is the one the cloth follows as a whole (`whole`), unless another cloth follows it in part. */
function mark(carry: Uint8Array, slot: number, whole: number): void {
  if (slot < 0) return
  if (slot !== whole) carry[slot] = CARRY_PART
  else if (carry[slot] === 0) carry[slot] = CARRY_WHOLE
}

/** The slot the cloth follows as a whole (all its pins, and its character frame), or −1. */
function wholeSlot(state: ClothWorldState, c: ClothState): number {
  const P = state.components.Pin
  let slot = -1
  const pins = c.pins.list
  for (let q = 0; q < pins.length; q++) {
    const pin = pins[q]
    if (P.target[pin] === 0 || P.slot[pin] < 0) return -1 // held by the world too
    if (slot < 0) slot = P.slot[pin]
    else if (P.slot[pin] !== slot) return -1
  }
  const ch = c.character
  if (ch !== null) {
    if (ch.skin !== null) return -1
    if (slot < 0) slot = ch.frameSlot
    else if (ch.frameSlot !== slot && (ch.frameSlot >= 0 || ch.constrained)) return -1
  }
  return slot
}
