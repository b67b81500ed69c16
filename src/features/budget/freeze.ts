import { relativeRotationAt } from '../../core/math'
import { moveClothRigidly } from '../../world/rigid'
import type { ClothState, ClothWorldState } from '../../world/state'
import { wakeClothState } from '../../world/wake'

/**
 * Freezes a cloth: it keeps its state (velocities too) and is skipped by every phase. The pose of
 * its first pin target is remembered, to carry the cloth along when it thaws.
 */
export function freezeCloth(state: ClothWorldState, c: ClothState): void {
  const lod = c.budget
  lod.frozen = true
  lod.refSlot = -1
  lod.refEntity = -1
  lod.frozenCentre.set(lod.centre)
  const P = state.components.Pin
  const k = state.kinematics
  const pins = c.pins.list
  for (let q = 0; q < pins.length; q++) {
    const slot = P.slot[pins[q]]
    if (slot < 0) continue
    lod.refSlot = slot
    lod.refEntity = k.eid[slot]
    for (let j = 0; j < 7; j++) lod.refPose[j] = k.stepTo[7 * slot + j]
    break
  }
}

/** Thaws a frozen cloth, carried rigidly by its reference target's motion since the freeze. */
export function thaw(state: ClothWorldState, c: ClothState): void {
  const lod = c.budget
  lod.frozen = false
  lod.phase = 0
  const k = state.kinematics
  const slot = lod.refSlot
  lod.refSlot = -1
  if (slot < 0 || k.eid[slot] !== lod.refEntity) return
  const ref = lod.refPose
  const o = 7 * slot
  // R = q_now · q_ref⁻¹ about the old position, then to the new one (the pose the pins start from)
  const r = lod.measure
  relativeRotationAt(k.stepFrom, o + 3, ref, 3, r, 0)
  const rx = r[0], ry = r[1], rz = r[2], rw = r[3]
  const dx = k.stepFrom[o] - ref[0], dy = k.stepFrom[o + 1] - ref[1], dz = k.stepFrom[o + 2] - ref[2]
  if (dx === 0 && dy === 0 && dz === 0 && rx === 0 && ry === 0 && rz === 0) return
  moveClothRigidly(c, ref[0], ref[1], ref[2], rx, ry, rz, rw, k.stepFrom[o], k.stepFrom[o + 1], k.stepFrom[o + 2])
  wakeClothState(state, c)
}
