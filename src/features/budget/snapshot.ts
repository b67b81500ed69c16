import { allFinite, fit64 } from '../../core/arrays'
import { ClothError } from '../../core/errors'
import type { ClothState, ClothWorldState } from '../../world/state'
import { ANCHOR_REF, anchorSlot, thaw } from './freeze'
import { applyConfig } from './levels'
import { Q_FACTOR, Q_MEASURED, Q_PREDICTED } from './types'

/**
 * The budget's section of a snapshot: the world's allocation countdown and timing (world state,
 * like the step accumulator: rewound for the whole world) and the cloth's level-of-detail state:
 * the quality it wants (the quality target's choice), the controller's counters, its level, its
 * every-n-th-step phase, visibility, freeze and the freeze's reference. The settings (the world
 * budget, quality targets, cost numbers) are not in it: like colliders, they stay as they are.
 */
export interface BudgetSnapshot {
  /**
   * countdown, timing (factor, measured, predicted); wantSubsteps, wantIterations, stepEvery,
   * phase, frozen, visible, lowChecks, level, applied, distance, priority, centre (3), frozen
   * centre (3), the reference pin's index in the pins (−1: none), the reference pose (7), the
   * steps sat out since the cloth's last step and whether it freezes once caught up (0 in
   * snapshots of versions without them).
   * Absent in snapshots of versions without it: the cloth then wants the quality it runs.
   */
  budget?: Float64Array
}

const BUDGET_DATA = 31

export function saveBudget(state: ClothWorldState, c: ClothState, s: BudgetSnapshot): void {
  const q = state.budget
  const lod = c.budget
  const b = (s.budget = fit64(s.budget, BUDGET_DATA))
  b[0] = q.countdown
  b[1] = q.timing[Q_FACTOR]
  b[2] = q.timing[Q_MEASURED]
  b[3] = q.timing[Q_PREDICTED]
  b[4] = lod.wantSubsteps
  b[5] = lod.wantIterations
  b[6] = lod.stepEvery
  b[7] = lod.phase
  b[8] = lod.frozen ? 1 : 0
  b[9] = lod.visible ? 1 : 0
  b[10] = lod.lowChecks
  b[11] = lod.level
  b[12] = lod.applied
  b[13] = lod.distance
  b[14] = lod.priority
  for (let a = 0; a < 3; a++) {
    b[15 + a] = lod.centre[a]
    b[18 + a] = lod.frozenCentre[a]
  }
  b[21] = lod.refPin >= 0 ? c.pins.list.indexOf(lod.refPin) : lod.refPin === ANCHOR_REF && lod.refSlot >= 0 ? ANCHOR_REF : -1
  for (let j = 0; j < 7; j++) b[22 + j] = lod.refPose[j]
  b[29] = lod.waited
  b[30] = lod.freezing ? 1 : 0
}

/** Throws ClothError unless the budget section (when present) is complete and usable. */
export function checkBudget(s: BudgetSnapshot, arg: string, pinCount: number): void {
  const b = s.budget
  if (b === undefined) return
  if (!(b instanceof Float64Array) || b.length !== BUDGET_DATA || !allFinite(b))
    throw new ClothError(`${arg}.budget`, b, 'must be the budget state saved by saveClothState')
  const int = (v: number, min: number) => Number.isInteger(v) && v >= min
  if (
    !int(b[0], -1e9) || !(b[1] > 0) || !int(b[4], 1) || !int(b[5], 1) || !int(b[6], 1) || !int(b[7], 0) || !int(b[10], 0) ||
    !int(b[11], -1) || !int(b[12], -1) || !int(b[29], 0) || !int(b[21], ANCHOR_REF) || b[21] >= pinCount
  ) {
    throw new ClothError(`${arg}.budget`, b, 'must be the budget state saved by saveClothState (counts, levels, a pin index in range)')
  }
}

/**
 * Restores the budget's state (after the pins, whose order the reference pin's index refers to).
 * Without the section (an older snapshot) and without a world budget, the quality the restored
 * cloth runs (its substeps and iterations, in the core section) is also the quality it wants.
 */
export function restoreBudget(state: ClothWorldState, c: ClothState, s: BudgetSnapshot): void {
  const lod = c.budget
  const b = s.budget
  if (b === undefined) {
    if (state.budget.settings !== null) return
    lod.wantSubsteps = c.substeps
    lod.wantIterations = c.iterations
    return
  }
  const q = state.budget
  q.countdown = b[0] | 0
  q.timing[Q_FACTOR] = b[1]
  q.timing[Q_MEASURED] = b[2]
  q.timing[Q_PREDICTED] = b[3]
  // integers back as integers (| 0), so the fields keep their small-integer representation
  lod.wantSubsteps = b[4] | 0
  lod.wantIterations = b[5] | 0
  lod.stepEvery = b[6] | 0
  lod.phase = b[7] | 0
  lod.frozen = b[8] === 1 // (with no world budget, thawed below)
  lod.visible = b[9] === 1
  lod.lowChecks = b[10] | 0
  lod.level = b[11] | 0
  lod.applied = b[12] | 0
  lod.distance = b[13]
  lod.priority = b[14]
  for (let a = 0; a < 3; a++) {
    lod.centre[a] = b[15 + a]
    lod.frozenCentre[a] = b[18 + a]
  }
  const ref = b[21] | 0
  const pin = lod.frozen && ref >= 0 ? c.pins.list[ref] : -1
  const slot = pin >= 0 ? state.components.Pin.slot[pin] : -1
  lod.refPin = slot >= 0 ? pin : -1
  lod.refSlot = slot
  // carried by its character frame or bone: the saved one, which the character section (restored
  // before this one) tracks again
  const anchor = lod.frozen && ref === ANCHOR_REF ? anchorSlot(c) : -1
  if (anchor >= 0) {
    lod.refPin = ANCHOR_REF
    lod.refSlot = anchor
  }
  for (let j = 0; j < 7; j++) lod.refPose[j] = b[22 + j]
  lod.waited = b[29] | 0 // (the restored cloth lags its pins by them: its next step covers them)
  lod.freezing = b[30] === 1 && q.settings !== null
  if (q.settings === null) {
    // frozen by a budget gone since: only a world budget thaws a cloth, so it thaws now, carried
    // by its reference's motion since the freeze as `setClothBudget(null)` thaws it (left where it
    // froze, a cape whose character walked on was yanked at 111 m/s)
    if (lod.frozen) thaw(state, c, state.kinematics.stepTo)
    // the level the snapshot held is the budget's, gone since: the cloth runs its own quality (it
    // ran a far level for good, nothing setting it back)
    lod.level = lod.applied = -1
    applyConfig(state, c, lod.wantSubsteps, lod.wantIterations, 1)
  }
}
