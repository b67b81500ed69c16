import { maxEdgeStrain, particleBounds } from '../../kernels/mesh'
import { readPoseInto } from '../../world/kinematics'
import type { ClothState, ClothWorldState } from '../../world/state'
import { freezeCloth, thaw } from './freeze'
import { applyConfig, bottomLevel, configCost, halvingsTop, ladderAtLeast, ladderBelow, levelConfig, levelCost, topLevel } from './levels'
import { Q_FACTOR, Q_MEASURED, Q_PREDICTED, type BudgetSettings } from './types'

/** Slot of `ClothBudget.measure` that holds the largest edge strain (after the bounds). */
const M_STRAIN = 6

/**
 * Sync phase: every `interval` steps, runs the cloths' quality targets and the world budget and
 * applies the chosen levels. Nothing (one comparison) without a budget or a target. `sampled`: the
 * step took a frame sample (its targets' jumps are this step's).
 */
export function updateBudget(state: ClothWorldState, sampled: boolean): void {
  const q = state.budget
  if (q.settings === null && q.targets === 0) return
  if (q.settings !== null) freezeCaughtUp(state, sampled)
  if (--q.countdown > 0) return
  const b = q.settings
  q.countdown = b !== null ? b.interval : 15
  const cloths = state.cloths
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    if (c.budget.hasTarget && !c.sleep.asleep && !c.budget.frozen) runTarget(state, c)
  }
  if (b === null) {
    for (let ci = 0; ci < cloths.length; ci++) {
      const c = cloths[ci]
      applyConfig(state, c, c.budget.wantSubsteps, c.budget.wantIterations, 1)
    }
    return
  }
  const t = q.timing
  if (b.adapt && b.msPerFrame > 0 && t[Q_MEASURED] > 0 && t[Q_PREDICTED] > 0) {
    // the measured step against the model (clamped: one noisy sample moves it at most 2×)
    let r = (t[Q_MEASURED] * 1e6) / (t[Q_PREDICTED] * t[Q_FACTOR])
    r = r < 0.5 ? 0.5 : r > 2 ? 2 : r
    t[Q_FACTOR] *= 1 + 0.3 * (r - 1)
  }
  allocate(state, b, sampled)
}

/**
 * Sync phase, every step after `updateQuality`: whether `clothFixedStep` should time this step
 * (the step before an allocation, when a time budget adapts).
 */
export function wantStepTiming(state: ClothWorldState): void {
  const q = state.budget
  const b = q.settings
  q.timeNext = b !== null && b.adapt && b.msPerFrame > 0 && q.countdown === 1
}

/** The quality target's controller: moves the wanted substeps along the ladder. */
function runTarget(state: ClothWorldState, c: ClothState): void {
  const lod = c.budget
  let s = lod.wantSubsteps
  const stretch = lod.maxStretch
  // judge the stretch only while the cloth runs what it wants (not cut back by the budget)
  if (stretch > 0 && c.substeps === s && lod.stepEvery === 1) {
    const t = c.topology
    maxEdgeStrain(c.pos, t.stretchIds, t.stretchRest, t.stretchCount, lod.measure, M_STRAIN)
    const strain = lod.measure[M_STRAIN]
    if (strain > stretch) {
      // stretch error falls about as 1/substeps²: aim straight for the count that should do
      const aim = s * Math.sqrt(strain / stretch) * 1.1
      s = ladderAtLeast(aim > s + 1 ? aim : s + 1)
      lod.lowChecks = 0
    } else if (strain < 0.4 * stretch) {
      if (++lod.lowChecks >= 4) {
        s = ladderBelow(s)
        lod.lowChecks = 0
      }
    } else {
      lod.lowChecks = 0
    }
  }
  const ms = lod.msPerStep
  if (ms > 0) {
    const cal = state.budget.calibration!
    const cfg = state.budget.cfg
    if (stretch === 0) s = lod.maxSubsteps // a time target alone: the most the time allows
    // the largest ladder count (or s itself) within the time
    while (s > lod.minSubsteps) {
      configCost(c, s, lod.wantIterations, 1, cal, cfg)
      if (cfg.cost * 1e-6 <= ms) break
      s = ladderBelow(s)
    }
  }
  // (a cloth solving lines keeps 2 substeps at least: at one it never comes to rest, see levels.ts)
  const least = c.lines !== null && c.tear === null && lod.minSubsteps < 2 ? 2 : lod.minSubsteps
  if (s < least) s = least
  if (s > lod.maxSubsteps) s = lod.maxSubsteps
  lod.wantSubsteps = s
}

/** The world budget: freezing, distance levels, then the time budget, then apply. */
function allocate(state: ClothWorldState, b: BudgetSettings, sampled: boolean): void {
  const q = state.budget
  const cloths = state.cloths
  const pose = q.pose
  const haveViewer = b.viewer >= 0 // (cleared when the viewer loses its Transform)
  if (haveViewer) readPoseInto(state, b.viewer, pose)
  const cfg = q.cfg
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    const lod = c.budget
    measureCentre(state, c)
    let d = 0
    if (haveViewer) {
      const cx = lod.centre
      const dx = cx[0] - pose[0], dy = cx[1] - pose[1], dz = cx[2] - pose[2]
      d = Math.sqrt(dx * dx + dy * dy + dz * dz)
    }
    lod.distance = d
    lod.priority = 1 / (1 + (d / b.near) * (d / b.near))
    const freeze = (b.freezeInvisible && !lod.visible) || d > b.cull
    if (freeze && !lod.frozen) {
      // a far cloth that sat steps out lags its pins and frame by them: it takes its step now and
      // freezes at the next, where it is (frozen with the lag, it thawed with it undone at once:
      // 67 % stretch on a cape whose camera cut to it)
      if (lod.waited > 0 && !c.sleep.asleep) lod.freezing = true
      else freezeCloth(state, c, sampled)
    } else if (!freeze) {
      lod.freezing = false
      if (lod.frozen) thaw(state, c, state.kinematics.stepFrom)
    }
    // distance: full quality within `near`, substeps scaled by near/d beyond, the floor past `far`
    const top = topLevel(c)
    let level = top
    if (d >= b.far) level = bottomLevel(c, b)
    else if (d > b.near) {
      const cap = lod.wantSubsteps * (b.near / d)
      while (level > halvingsTop(c)) {
        levelConfig(c, level, cfg)
        if (cfg.substeps <= cap) break
        level--
      }
    }
    lod.level = level
  }
  if (b.msPerFrame > 0) fitBudget(state, b)
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    const lod = c.budget
    // up one level per allocation at most: a stiffer level pulls in the stretch the softer one let
    // build up, and a rung at a time spreads that over several allocations (down is free: a softer
    // level lets the cloth sag through its own motion)
    if (lod.applied >= 0 && lod.level > lod.applied + 1) lod.level = lod.applied + 1
    lod.applied = lod.level
    levelConfig(c, lod.level, cfg)
    applyConfig(state, c, cfg.substeps, cfg.iterations, cfg.stepEvery)
  }
  // the model's time per step at these levels, for the timing correction and the stats
  const cal = q.calibration
  let total = 0
  if (cal !== null) {
    for (let ci = 0; ci < cloths.length; ci++) {
      const c = cloths[ci]
      if (c.budget.frozen || c.sleep.asleep) continue
      configCost(c, c.substeps, c.iterations, c.budget.stepEvery, cal, cfg)
      total += cfg.cost
    }
  }
  q.timing[Q_PREDICTED] = total
}

/** Sync phase, every step with a world budget: freezes the cloths that took their catch-up step (`ClothBudget.freezing`). */
function freezeCaughtUp(state: ClothWorldState, sampled: boolean): void {
  const cloths = state.cloths
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    const lod = c.budget
    if (!lod.freezing || (lod.waited > 0 && !c.sleep.asleep)) continue
    lod.freezing = false
    freezeCloth(state, c, sampled)
  }
}

/** Share of `msPerFrame` the time budget plans to spend. */
const HEADROOM = 0.95

/**
 * Lowers levels until the predicted total fits `budget` ns: each round lowers the cloth whose
 * next level down loses the least quality (weighted by its priority, which falls with distance)
 * per nanosecond saved. Frozen and sleeping cloths cost nothing.
 */
function fitBudget(state: ClothWorldState, b: BudgetSettings): void {
  // in model nanoseconds, aiming HEADROOM under the budget: the corrected model still errs by a
  // few % from step to step
  const budget = (HEADROOM * b.msPerFrame * 1e6) / state.budget.timing[Q_FACTOR]
  const q = state.budget
  const cal = q.calibration!
  const cfg = q.cfg
  const cloths = state.cloths
  let total = 0
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    if (c.budget.frozen || c.sleep.asleep) continue
    levelCost(c, c.budget.level, cal, cfg)
    total += cfg.cost
  }
  while (total > budget) {
    let best = -1
    let bestScore = Infinity
    let bestSaving = 0
    for (let ci = 0; ci < cloths.length; ci++) {
      const c = cloths[ci]
      const lod = c.budget
      if (lod.frozen || c.sleep.asleep || lod.level <= bottomLevel(c, b)) continue
      levelCost(c, lod.level, cal, cfg)
      const cost = cfg.cost, logq = cfg.logQuality
      levelCost(c, lod.level - 1, cal, cfg)
      const saving = cost - cfg.cost
      if (!(saving > 0)) continue
      const score = (lod.priority * (logq - cfg.logQuality)) / saving
      if (score < bestScore) {
        bestScore = score
        best = ci
        bestSaving = saving
      }
    }
    if (best < 0) break // everything at its floor
    cloths[best].budget.level--
    total -= bestSaving
  }
}

/** Centre of the cloth's particle bounds (a frozen cloth: moved along with its reference target). */
function measureCentre(state: ClothWorldState, c: ClothState): void {
  const lod = c.budget
  const centre = lod.centre
  if (lod.frozen) {
    const k = state.kinematics
    const slot = lod.refSlot
    if (slot >= 0) {
      const o = 7 * slot
      // centre moved by the target's translation since the freeze (rotation ignored: an estimate)
      for (let a = 0; a < 3; a++) centre[a] = lod.frozenCentre[a] + k.stepTo[o + a] - lod.refPose[a]
    } else centre.set(lod.frozenCentre)
    return
  }
  const box = lod.measure
  particleBounds(c.pos, c.count, box, 0, c.topology.unused)
  for (let a = 0; a < 3; a++) centre[a] = 0.5 * (box[a] + box[a + 3])
}
