import { CARRY_PART, CARRY_WHOLE, K_CARRIED, K_DROPPED, applyJump, readPoseInto } from '../../world/kinematics'
import { rotateVecAt } from '../../core/math'
import type { ClothState, ClothWorldState } from '../../world/state'

/** `Kinematics.carry`: CARRY_WITH + f, carried by slot f's jump after the sample (`carryWithFrames`). */
const CARRY_WITH = 3

/**
 * Sync phase, before a frame sample after dropped frame time (a hitch longer than the steps a frame
 * may run): how each tracked entity's motion in that time is taken (`Kinematics.carry`, read by
 * `sampleFrame`). Entities that cloths tie together (the pins, frame and bones of one cloth; two
 * cloths sharing one) form a group. A group also tied to the world (a pin in place, a skinned or
 * constrained cloth with the world as its frame) sweeps its whole motion (CARRY_PART): carried,
 * its cloths would be torn between the carried and the uncarried (a sheet pinned to the world and to
 * a turning corner was swung 0.7 rad about the corner: 39 % stretch). Any other group is carried by
 * one member's share of the motion, its root (the first skinned cloth's frame, else the first
 * cloth's first entity: CARRY_WHOLE), the rest by the root's jump (CARRY_WITH, `carryWithFrames`),
 * sweeping only their motion against it, so every cloth of the group is carried by one jump (a
 * skinned cape with each bone swept whole changed speed by 13 m/s in a frame after a 0.25 s hitch
 * at 4 m/s, 39 % stretch; an apron framed by the cape's hip bone, carried by the hip's own share
 * while its other bone swept, 133 %). An entity no cloth follows, a collider's body, is carried by
 * its own share (a leg on its own entity, swept while the cape was carried, ran through it: 347 %).
 * Returns whether some slot is carried with a root.
 */
export function markCarriedSlots(state: ClothWorldState): boolean {
  const k = state.kinematics
  // (the test alone, run every frame: in a function this small it is optimized at once; in the
  // long one below it stayed interpreted past a 3000-frame warm-up and boxed the double it read)
  return k.framed && k.time[K_DROPPED] > 0 && markGroups(state)
}

/** `markCarriedSlots` after dropped time. */
function markGroups(state: ClothWorldState): boolean {
  const k = state.kinematics
  k.carry.fill(0, 0, k.count)
  if (group.length < k.count) {
    group = new Int32Array(Math.max(k.count, 2 * group.length))
    root = new Int32Array(group.length)
    pinned = new Uint8Array(group.length)
  }
  for (let s = 0; s < k.count; s++) {
    group[s] = s
    root[s] = -1
    pinned[s] = 0
  }
  const cloths = state.cloths
  // the groups (k.carry marks the entities cloths follow, and CARRY_PART the groups tied to the world)
  for (let ci = 0; ci < cloths.length; ci++) tie(state, cloths[ci])
  for (let s = 0; s < k.count; s++) if (k.carry[s] === CARRY_PART) k.carry[find(s)] = CARRY_PART
  // each group's root: a skinned cloth's frame first
  for (let pass = 0; pass < 2; pass++) {
    for (let ci = 0; ci < cloths.length; ci++) {
      const ch = cloths[ci].character
      const skinned = ch !== null && ch.skin !== null && ch.frameSlot >= 0
      if (pass === 0 && !skinned) continue
      const s = skinned ? ch!.frameSlot : firstSlot(state, cloths[ci])
      if (s >= 0 && root[find(s)] < 0) root[find(s)] = s
    }
  }
  const live = k.live
  // a pin target that moved against its root since the last sample (two carriers circling with
  // unturned Transforms): no one jump carries the group, which sweeps as a whole (carried with the
  // root, the other swept twice its own motion, 27 m/s against 15 swept). Not a bone: a cloth
  // follows its bones' motion against the frame through its reference, which sweeps it well (a
  // crouch of 30 cm in a 1 s hitch, the whole group swept: 132 % against 25 %)
  for (let q = 0; q < live.length; q++) {
    const s = live[q], g = pinned[s] === 1 ? find(s) : -1
    if (g >= 0 && k.carry[g] !== CARRY_PART && root[g] >= 0 && root[g] !== s && !movesWith(state, s, root[g])) k.carry[g] = CARRY_PART
  }
  let any = false
  for (let q = 0; q < live.length; q++) {
    const s = live[q]
    if (k.carry[s] === 0) continue // followed by no cloth: its own share
    const g = find(s)
    if (k.carry[g] === CARRY_PART) k.carry[s] = CARRY_PART
    else if (root[g] === s) k.carry[s] = CARRY_WHOLE
    else {
      k.carry[s] = CARRY_WITH + root[g]
      any = true
    }
  }
  return any
}

/** How far (m) a member may move against its group's root, in the root's frame, and still be carried with it. */
const WITH_TOLERANCE = 0.25

/**
 * Whether slot `s` kept its place in the frame of slot `r` between their last samples and their
 * Transforms now, within WITH_TOLERANCE (a bone on its skeleton: its turn against it is free).
 */
function movesWith(state: ClothWorldState, s: number, r: number): boolean {
  const k = state.kinematics, t = rigid
  for (let when = 0; when < 2; when++) {
    const o = 10 * when
    if (when === 0) {
      for (let j = 0; j < 7; j++) {
        t[20 + j] = k.sampleTo[7 * s + j]
        t[30 + j] = k.sampleTo[7 * r + j]
      }
    } else {
      readPoseInto(state, k.eid[s], pose)
      t.set(pose, 20)
      readPoseInto(state, k.eid[r], pose)
      t.set(pose, 30)
    }
    // the offset turned into the root's frame: conj(q_r)·(p_s − p_r)
    for (let a = 0; a < 3; a++) t[40 + a] = t[20 + a] - t[30 + a]
    t[43] = -t[33]
    t[44] = -t[34]
    t[45] = -t[35]
    t[46] = t[36]
    rotateVecAt(t, 43, t, 40, t, o)
  }
  const dx = t[10] - t[0], dy = t[11] - t[1], dz = t[12] - t[2]
  return dx * dx + dy * dy + dz * dz <= WITH_TOLERANCE * WITH_TOLERANCE
}

/** Scratch of `movesWith`: the offsets then and now (0..2, 10..12), two poses (20.., 30..), a vector and a rotation (40..46). */
const rigid = new Float64Array(47)
const pose = new Float64Array(7)

/** Union-find over tracked slots: each slot's parent (`find` gives the group). */
let group = new Int32Array(64)
/** Per slot: 1 when a pin holds a cloth to it. */
let pinned = new Uint8Array(64)
/** Per group (at its representative), the slot whose share carries it, or −1. */
let root = new Int32Array(64)

function find(s: number): number {
  while (group[s] !== s) {
    group[s] = group[group[s]]
    s = group[s]
  }
  return s
}

function join(a: number, b: number): void {
  a = find(a)
  b = find(b)
  if (a !== b) group[b] = a
}

/** Ties the entities the cloth follows into one group, marked followed (CARRY_WHOLE) or tied to the world (CARRY_PART). */
function tie(state: ClothWorldState, c: ClothState): void {
  const k = state.kinematics, P = state.components.Pin
  const first = firstSlot(state, c)
  let world = false
  const pins = c.pins.list
  for (let q = 0; q < pins.length; q++) {
    const s = P.slot[pins[q]]
    if (P.target[pins[q]] === 0 || s < 0) world = true
    else {
      follow(k.carry, first, s)
      pinned[s] = 1
    }
  }
  const ch = c.character
  if (ch !== null) {
    if (ch.frameSlot >= 0) follow(k.carry, first, ch.frameSlot)
    else if (ch.skin !== null || ch.constrained) world = true
    if (ch.skin !== null) {
      for (let b = 0; b < ch.skin.slots.length; b++) if (ch.skin.slots[b] >= 0) follow(k.carry, first, ch.skin.slots[b])
    }
  }
  if (world && first >= 0) k.carry[first] = CARRY_PART
}

function follow(carry: Int32Array, first: number, s: number): void {
  if (carry[s] === 0) carry[s] = CARRY_WHOLE
  join(first, s)
}

/** The first entity the cloth follows (a pin's target, its frame, a bone), or −1. */
function firstSlot(state: ClothWorldState, c: ClothState): number {
  const P = state.components.Pin
  const pins = c.pins.list
  for (let q = 0; q < pins.length; q++) if (P.target[pins[q]] !== 0 && P.slot[pins[q]] >= 0) return P.slot[pins[q]]
  const ch = c.character
  if (ch === null) return -1
  if (ch.frameSlot >= 0) return ch.frameSlot
  if (ch.skin !== null) { for (let b = 0; b < ch.skin.slots.length; b++) if (ch.skin.slots[b] >= 0) return ch.skin.slots[b] }
  return -1
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
