import type { ClothState, ClothWorldState } from '../../world/state'
import type { BudgetSettings, LevelConfig } from './types'

/** Substep counts the controllers choose from. */
export const SUBSTEP_LADDER: readonly number[] = Object.freeze([1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64])

/** Smallest ladder count ≥ x (the last rung when none is). */
export function ladderAtLeast(x: number): number {
  for (let k = 0; k < SUBSTEP_LADDER.length; k++) if (SUBSTEP_LADDER[k] >= x) return SUBSTEP_LADDER[k]
  return SUBSTEP_LADDER[SUBSTEP_LADDER.length - 1]
}

/** Largest ladder count < s (1 at the bottom). */
export function ladderBelow(s: number): number {
  let best = 1
  for (let k = 0; k < SUBSTEP_LADDER.length; k++) if (SUBSTEP_LADDER[k] < s) best = SUBSTEP_LADDER[k]
  return best
}

/**
 * Levels of a cloth that wants S substeps and I iterations, from the top: level L (the top) is
 * S × I; down from there the ladder's substep counts below S; then, at one substep, iterations
 * halved down to 1; then, if the budget's `farStepEvery` allows it (never for self-colliding cloths),
 * stepping every 2nd and every 4th fixed step.
 * Writes substeps, iterations and stepEvery to `cfg`.
 */
export function levelConfig(c: ClothState, level: number, cfg: LevelConfig): void {
  const S = c.budget.wantSubsteps, I = c.budget.wantIterations
  const below = substepsBelow(S) // ladder rungs below S
  const halvings = iterationHalvings(I)
  // level ≥ halvings + 2: substep rungs (the top one is S itself)
  const k = level - (halvings + 2)
  if (k >= 0) {
    cfg.substeps = k < below ? SUBSTEP_LADDER[k] : S
    cfg.iterations = I
    cfg.stepEvery = 1
    return
  }
  cfg.substeps = 1
  if (level >= 2) {
    // level 2 + h: iterations I >> (halvings − h)
    const h = level - 2
    const it = I >> (halvings - h)
    cfg.iterations = it > 1 ? it : 1
    cfg.stepEvery = 1
    return
  }
  cfg.iterations = 1
  cfg.stepEvery = level === 1 ? 2 : 4
}

function substepsBelow(S: number): number {
  let n = 0
  while (n < SUBSTEP_LADDER.length && SUBSTEP_LADDER[n] < S) n++
  return n
}

function iterationHalvings(I: number): number {
  let h = 0
  while (I >> (h + 1) >= 1) h++
  return h
}

/** The top level of a cloth (its wanted quality), and its lowest. */
export function topLevel(c: ClothState): number {
  return iterationHalvings(c.budget.wantIterations) + 2 + substepsBelow(c.budget.wantSubsteps)
}

/** Ladder rung of the fewest substeps a self-colliding cloth runs under the budget (SUBSTEP_LADDER[4]: 6). */
const SELF_FLOOR_RUNG = 4

/** Ladder rung of the fewest substeps a cloth with `lineSolve` runs under the budget (SUBSTEP_LADDER[1]: 2). */
const LINES_FLOOR_RUNG = 1

export function bottomLevel(c: ClothState, b: BudgetSettings): number {
  // a self-colliding cloth keeps stepping every step, at 6 substeps or its own count when fewer:
  // its contacts need the travel limits of one step, and its stacked layers the substeps (a far
  // heap of folds at 1 × 1 was squashed to 60 % of its height and jittered at 0.3–0.5 m/s for
  // good, never still enough to sleep; still 0.09 m/s after 3 s at 4 substeps, settled at 6)
  if (c.collision.self !== null) return Math.min(topLevel(c), halvingsTop(c) + SELF_FLOOR_RUNG)
  // a cloth solving lines keeps 2 substeps or its own count when fewer: at one, a hanging sheet's
  // rows and columns kept it moving (0.19 m/s, 3 mm a frame) and it never slept
  if (c.lines !== null && c.tear === null) return Math.min(topLevel(c), halvingsTop(c) + LINES_FLOOR_RUNG)
  return b.farStepEvery === 4 ? 0 : b.farStepEvery === 2 ? 1 : 2
}

/** Cost of one fixed step at (s, i, e), ns, into cfg.cost; log quality into cfg.logQuality. */
export function configCost(c: ClothState, s: number, i: number, e: number, cal: Float64Array, cfg: LevelConfig): void {
  const t = c.topology
  const projections = t.distCount + t.compCount + 0.8 * t.lineCount + 3 * t.hingeCount
  const cc = c.collision
  const colliderTests = c.count * (cc.activeCount + (cc.self !== null ? 2 : 0))
  const aero = c.wind !== null && c.wind.active !== 0 ? t.triangleCount : 0 // (a zone reached it this step)
  const perSub = cal[0] * c.count + cal[1] * (i * projections + 0.6 * c.tethers.set.count) + cal[2] * colliderTests + cal[3] + cal[4] * aero
  cfg.cost = (perSub * s) / e
  cfg.logQuality = 2 * Math.log(s) + Math.log(i) - 2 * Math.log(e)
}

export function levelCost(c: ClothState, level: number, cal: Float64Array, cfg: LevelConfig): void {
  levelConfig(c, level, cfg)
  configCost(c, cfg.substeps, cfg.iterations, cfg.stepEvery, cal, cfg)
}

/** The lowest level that still runs one substep at full iterations. */
export function halvingsTop(c: ClothState): number {
  return iterationHalvings(c.budget.wantIterations) + 2
}

/** Sets the counts a cloth runs (and its substep length). */
export function applyConfig(state: ClothWorldState, c: ClothState, s: number, i: number, e: number): void {
  const si = s | 0, ii = i | 0, ei = e | 0
  if (c.substeps === si && c.iterations === ii && c.budget.stepEvery === ei) return
  c.substeps = si
  c.iterations = ii
  // the steps waited since the cloth's last step carry over (reset, a level changing more often than
  // it steps kept a far cloth from stepping at all, and undid a thaw's step at once)
  if (c.budget.phase > ei - 1) c.budget.phase = ei - 1
  c.budget.stepEvery = ei
  c.h = (state.fixedTimeStep * ei) / si
}
