import { HEALTH_NONFINITE, HEALTH_OK, HEALTH_SPEED, checkClothHealth, checkPieceHealth } from '../../kernels/guard'
import { guardActive } from './api'
import type { ClothState, ClothWorldState } from '../../world/state'
import { placeRigidly } from './place'
import { EVENT_CAPACITY, REASONS } from './types'
import { newArray } from '../../core/shared'
import { nextListener } from '../../core/listeners'

/**
 * The health check of one cloth (a HEALTH_* code): one pass over its particles. A tearable cloth
 * in several pieces has its bounds measured per piece (`checkPieceHealth`): a piece torn off may
 * fall away from the pins it no longer hangs from, but must keep its own shape.
 */
export function checkGuardHealth(c: ClothState): number {
  const unused = c.topology.unused
  if (c.piece !== null && c.pieceCount > 1)
    return checkPieceHealth(c.pos, c.vel, c.invMass, c.count, c.piece, c.pieceCount, c.guard.pieceBox, c.guard.params, unused)
  return checkClothHealth(c.pos, c.vel, c.invMass, c.count, c.guard.params, unused)
}

/**
 * The guard's check of one cloth after a step (the guard phase, on whichever thread stepped it):
 * −1 when nothing was checked (guard off, or the cloth sat the step out), else the HEALTH_* code;
 * a healthy cloth's pose is kept as the next safe one.
 */
export function guardCheck(state: ClothWorldState, c: ClothState): number {
  if (!guardActive(c.guard) || c.subIndex < 0) return -1 // off, or asleep this step (a cloth that fell asleep in it still counts)
  state.stats.guardChecks++
  const health = checkGuardHealth(c)
  if (health === HEALTH_OK) keepSafePose(c)
  return health
}

/** A good step: count it and copy the pose when the snapshot interval is due. */
export function keepSafePose(c: ClothState): void {
  const g = c.guard
  g.failStreak = 0
  if (++g.sinceSafe < g.settings.snapshotInterval) return
  g.sinceSafe = 0
  if (g.safe.length !== c.pos.length) g.safe = newArray(Float64Array, c.pos.length) // the cloth grew (tearing)
  g.safe.set(c.pos)
  g.safeCount = c.count
}

/**
 * Puts a failed cloth into a safe pose and raises the event. `reason` is a HEALTH_* code.
 * The pose (the last good one, or the rest shape when the last good one failed too) is moved
 * rigidly so that its pinned particles best match where the pins hold them now (least squares,
 * Horn's quaternion method), velocities are cleared, pinned particles keep their exact places.
 */
export function restoreSafePose(state: ClothWorldState, c: ClothState, reason: number): void {
  const g = c.guard
  const particle = findOffender(c, reason)
  const useRest = g.failStreak > 0 || g.safeCount !== c.count
  const src = useRest ? g.rest : g.safe
  const srcCount = useRest ? c.count : g.safeCount
  g.failStreak++
  placeRigidly(state, c, src, srcCount)
  g.sinceSafe = 0
  c.version++
  state.stats.guardResets++
  c.sleep.still = 0 // a cloth that keeps failing is not at rest, however still it is after each reset

  const w = state.guard
  const slot = (w.evHead + w.evCount) % EVENT_CAPACITY
  if (w.evCount < EVENT_CAPACITY) w.evCount++
  else w.evHead = (w.evHead + 1) % EVENT_CAPACITY
  w.evCloth[slot] = c.eid
  w.evReason[slot] = reason
  w.evStep[slot] = state.stats.steps
  w.evParticle[slot] = particle
  w.evRest[slot] = useRest ? 1 : 0
  if (w.raised < EVENT_CAPACITY) w.raised++
}

/** Calls the reset listeners for the resets of this guard phase, oldest first. */
export function deliverResets(state: ClothWorldState): void {
  const w = state.guard
  const raised = w.raised
  w.raised = 0
  if (raised === 0 || w.listeners.length === 0) return
  const e = w.event
  for (let k = raised; k > 0; k--) {
    const slot = (w.evHead + w.evCount - k) % EVENT_CAPACITY
    for (let l = 0; l < w.listeners.length;) {
      if (w.evCloth[slot] < 0) break // its cloth was removed by a listener (forgetResetEvents)
      e.cloth = w.evCloth[slot]
      e.reason = REASONS[w.evReason[slot]]
      e.step = w.evStep[slot]
      e.particle = w.evParticle[slot]
      e.restoredTo = w.evRest[slot] === 1 ? 'rest' : 'snapshot'
      const listener = w.listeners[l]
      listener(e)
      l = nextListener(w.listeners, l, listener)
    }
  }
}

function findOffender(c: ClothState, reason: number): number {
  const pos = c.pos, vel = c.vel
  if (reason === HEALTH_NONFINITE) {
    for (let i = 0; i < c.count; i++) {
      const j = 3 * i
      if (!Number.isFinite(pos[j] + pos[j + 1] + pos[j + 2] + vel[j] + vel[j + 1] + vel[j + 2])) return i
    }
    return -1
  }
  // bounds: farthest from the centroid of the pinned particles (or of the cloth); speed: fastest
  // (vertices no triangle uses are no part of the cloth)
  const unused = c.topology.unused
  let cx = 0, cy = 0, cz = 0, m = 0
  for (let i = 0; i < c.count; i++) {
    if (unused !== null && unused[i] === 1) continue
    if (reason === HEALTH_SPEED || (c.invMass[i] === 0) === (c.pins.list.length > 0)) {
      const j = 3 * i
      cx += reason === HEALTH_SPEED ? vel[j] : pos[j]
      cy += reason === HEALTH_SPEED ? vel[j + 1] : pos[j + 1]
      cz += reason === HEALTH_SPEED ? vel[j + 2] : pos[j + 2]
      m++
    }
  }
  if (m > 0) {
    cx /= m
    cy /= m
    cz /= m
  }
  const a = reason === HEALTH_SPEED ? vel : pos
  let best = -1, bestD = -1
  for (let i = 0; i < c.count; i++) {
    if (unused !== null && unused[i] === 1) continue
    const j = 3 * i
    const d = (a[j] - cx) ** 2 + (a[j + 1] - cy) ** 2 + (a[j + 2] - cz) ** 2
    if (d > bestD) {
      bestD = d
      best = i
    }
  }
  return best
}
