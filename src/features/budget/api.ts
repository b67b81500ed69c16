import { hasComponent, observe, onAdd, onRemove } from 'bitecs'
import { ClothError, checkAtMost, checkInteger, checkObject, checkPositive, checkKeys, keysOf } from '../../core/errors'
import { getCloth, getClothWorld, getClothWorldForChange } from '../../world/access'
import type { ClothState, ClothWorldState } from '../../world/state'
import { checkEntity } from '../../world/transform'
import { wakeClothState } from '../../world/wake'
import { adoptReference, releaseReference, thaw } from './freeze'
import { applyConfig, configCost } from './levels'
import { Q_FACTOR, Q_MEASURED, Q_PREDICTED, type BudgetWorld, type ClothBudget } from './types'
import { deferrable } from '../../world/flight'

/**
 * Quality budgets and level of detail.
 *
 * A cloth's accuracy levers are its substeps and iterations. This module picks them for the user:
 *
 * - per cloth, from a target (`setClothQualityTarget`): a largest edge stretch, kept by a feedback
 *   controller that measures the stretch and moves the substeps up or down a ladder; and/or a time
 *   per step, met through the cost model below;
 * - per world (`setClothBudget`): a time per fixed step shared by all cloths, and level of detail
 *   by distance from a viewer entity (camera or listener): near cloths keep their quality, farther
 *   ones get fewer substeps down to one (optionally stepping only every 2nd or 4th fixed step),
 *   and cloths that are invisible (`setClothVisible`) or beyond the cull distance freeze.
 *
 * Substeps go first, iterations only once at one substep: per unit of time, substeps buy more
 * accuracy than iterations (XPBD with small steps; see the accuracy chart in the README). Quality
 * is ranked by q = substeps² × iterations / stepEvery²: the stretch of our sheets fell as 1/substeps².
 *
 * No pop: XPBD stiffness does not depend on the substep count, so a level change alters how
 * closely the cloth follows its material, never the material, and velocities carry over. What a
 * higher level does do is pull in the stretch the lower one let build up; levels therefore rise
 * one rung per allocation, which keeps every change below the cloth's own motion (measured in
 * tests/budget.test.ts). A frozen cloth that thaws is first carried rigidly along
 * with the motion of a pin target it still hangs from (like a teleport), so a cape on a character
 * that walked on meanwhile is not yanked (see `freeze.ts`).
 *
 * The cost model: time per fixed step of a cloth = substeps/stepEvery × (particles × a +
 * iterations × projections × b + tethers × 0.6 b + particles × colliders in range × c + d +
 * triangles × w while a wind zone reaches it), where projections counts distance constraints once,
 * line-bending triples 0.8 and hinges 3 times (their relative kernel costs), and a, b, c, d, w (ns
 * per particle, per projection, per particle-collider test, per cloth and substep, per triangle in
 * the wind) come from a calibration: one run of a few small scenes (once per
 * process, `calibrateClothCost` in src/calibrate.ts, which builds them through the public API),
 * or numbers you pass (so that machines in lockstep pick the same levels).
 */

/** Per-unit costs of the cost model, ns. */
export interface ClothCostCalibration {
  nsPerParticle: number
  nsPerProjection: number
  nsPerColliderTest: number
  nsPerClothSubstep: number
  /**
   * Per triangle and substep of a cloth a wind zone reaches (its aerodynamics). Left out of a
   * calibration you pass, it counts as 6 × `nsPerProjection`, about what calibrations here measure (60–70 ns against 10–11).
   */
  nsPerWindTriangle?: number
}

/** A calibration's wind cost when it gives none: its projection cost times this. */
export const WIND_PER_PROJECTION = 6

/** Options of `setClothQualityTarget`. */
export interface ClothQualityTarget {
  /** Largest edge stretch to keep (0.01 = 1 %): substeps rise while it is exceeded, fall while well under. */
  maxStretch?: number
  /** Time budget of this cloth per fixed step, ms (by the cost model). */
  msPerStep?: number
  /** Bounds of the substeps the target may pick. Default 1 and 32. */
  minSubsteps?: number
  maxSubsteps?: number
  /** Cost model numbers for the world (as in `setClothBudget`); default a calibration run once per process. */
  calibration?: ClothCostCalibration
}

/** Options of `setClothBudget`. */
export interface ClothBudgetOptions {
  /** Time for all cloths per fixed step, ms (by the cost model). Default: no time limit, distance rules only. */
  msPerFrame?: number
  /** Entity with a Transform (camera, listener) distances are measured from. Default none. */
  viewer?: number | null
  /** Full quality within this distance, m. Default 10. */
  near?: number
  /** Beyond this distance a cloth runs 1 substep and 1 iteration, m. Default 40. */
  far?: number
  /**
   * Beyond `far`, step a cloth only every n-th fixed step (with an n times longer step), and let
   * the time budget do the same: cheaper still, but the longer step makes the cloth softer, and it
   * springs back (visibly, on a sheet hanging from its corners) when it returns to full rate.
   * Default 1 (every step).
   */
  farStepEvery?: 1 | 2 | 4
  /** Beyond this distance a cloth freezes, m. Default Infinity (never). */
  cull?: number
  /** Freeze cloths marked invisible (`setClothVisible`). Default true. */
  freezeInvisible?: boolean
  /** Fixed steps between two re-allocations. Default 15. */
  interval?: number
  /** Cost model numbers; default a calibration run once per process. */
  calibration?: ClothCostCalibration
  /**
   * Correct the cost model by the measured time of the cloth work (one fixed step is timed before
   * each allocation; the ratio to the prediction is smoothed). It catches what small calibration
   * scenes miss (cache misses of many cloths, a busy core), and makes the chosen levels depend on
   * timing: turn it off, with a fixed `calibration`, for machines in lockstep. Default true.
   */
  adapt?: boolean
}

const CALIBRATION_KEYS = keysOf<ClothCostCalibration>({
  nsPerParticle: true,
  nsPerProjection: true,
  nsPerColliderTest: true,
  nsPerClothSubstep: true,
  nsPerWindTriangle: true,
})
const TARGET_KEYS = keysOf<ClothQualityTarget>({
  maxStretch: true,
  msPerStep: true,
  minSubsteps: true,
  maxSubsteps: true,
  calibration: true,
})
const BUDGET_KEYS = keysOf<ClothBudgetOptions>({
  msPerFrame: true,
  viewer: true,
  near: true,
  far: true,
  farStepEvery: true,
  cull: true,
  freezeInvisible: true,
  interval: true,
  calibration: true,
  adapt: true,
})

/** The budget's view of the last allocation (`getClothBudgetStats`). */
export interface ClothBudgetStats {
  /** Predicted time of all cloths per fixed step at the chosen levels, ms (corrected). */
  predictedMs: number
  /** Measured time of the last timed fixed step, ms (0 before the first). */
  measuredMs: number
  /** Measured / modelled time, smoothed (1 until measured, or with `adapt` off). */
  correction: number
}

/** Level of detail of one cloth (`getClothLod`). */
export interface ClothLodInfo {
  /** Substeps and iterations it runs now. */
  substeps: number
  iterations: number
  /** It steps every n-th fixed step (with an n times longer step). */
  stepEvery: number
  frozen: boolean
  /** What it would run without the budget (its own settings or its target's choice). */
  wantSubsteps: number
  wantIterations: number
  /** Distance from the viewer at the last allocation, m (0 without a viewer). */
  distance: number
  /** Predicted cost per fixed step at the current level, ms (the cost model, times the budget's correction). */
  predictedMs: number
}

/** The per-world budget state: no budget, no targets, no calibration yet. */
export function createBudgetWorld(): BudgetWorld {
  return {
    settings: null,
    targets: 0,
    countdown: 0,
    calibration: null,
    pose: new Float64Array(7),
    cfg: { substeps: 1, iterations: 1, stepEvery: 1, cost: 0.5, logQuality: 0.5 },
    timeNext: false,
    timing: Float64Array.from([0, 0, 0, 1]),
  }
}

/** A cloth's budget state: it wants the quality it was created with, no target, visible. */
export function createClothBudget(substeps: number, iterations: number): ClothBudget {
  return {
    wantSubsteps: substeps,
    wantIterations: iterations,
    stepEvery: 1,
    phase: 0,
    waited: 0,
    freezing: false,
    frozen: false,
    visible: true,
    hasTarget: false,
    minSubsteps: 1,
    maxSubsteps: 32,
    maxStretch: 0,
    msPerStep: 0,
    lowChecks: 0,
    level: -1,
    applied: -1,
    distance: 0,
    priority: 1,
    centre: new Float64Array(3),
    frozenCentre: new Float64Array(3),
    refPin: -1,
    refSlot: -1,
    refPose: new Float64Array(7),
    shownSlot: -1,
    shownPose: new Float64Array(7),
    shownCarried: false,
    shownStale: false,
    dueNow: false,
    measure: new Float64Array(7),
  }
}

/** Validates cost model numbers given at the API. */
export function checkCalibration(c: ClothCostCalibration, arg: string): Float64Array {
  checkObject(arg, c)
  checkKeys(arg, c, CALIBRATION_KEYS)
  // (a second per unit at most: beyond ~1e306 ns a cloth's predicted cost was Infinity)
  const ns = (key: keyof ClothCostCalibration) => checkAtMost(`${arg}.${key}`, checkPositive(`${arg}.${key}`, c[key]), 1e9, ' ns')
  return Float64Array.from([
    ns('nsPerParticle'),
    ns('nsPerProjection'),
    ns('nsPerColliderTest'),
    c.nsPerClothSubstep === 0 ? 0 : ns('nsPerClothSubstep'),
    c.nsPerWindTriangle === undefined ? WIND_PER_PROJECTION * c.nsPerProjection : c.nsPerWindTriangle === 0 ? 0 : ns('nsPerWindTriangle'),
  ])
}

/** `setClothQualityTarget`, with the calibration run it needs for a time target (`measure`) passed in. */
export function configureQualityTarget(world: object, cloth: number, target: ClothQualityTarget | null, measure: () => Float64Array): void {
  const state = getClothWorldForChange(world)
  const c = getCloth(state, cloth)
  const lod = c.budget
  const q = state.budget
  if (target === null) {
    if (lod.hasTarget) q.targets--
    lod.hasTarget = false
    return
  }
  checkObject('target', target)
  checkKeys('target', target, TARGET_KEYS)
  const stretch = target.maxStretch === undefined ? 0 : checkPositive('target.maxStretch', target.maxStretch)
  const ms = target.msPerStep === undefined ? 0 : checkPositive('target.msPerStep', target.msPerStep)
  if (stretch === 0 && ms === 0) throw new ClothError('target', target, 'must set maxStretch and/or msPerStep (or be null)')
  const min = target.minSubsteps === undefined ? 1 : checkInteger('target.minSubsteps', target.minSubsteps, 1, 256)
  const max = target.maxSubsteps === undefined ? Math.max(32, min) : checkInteger('target.maxSubsteps', target.maxSubsteps, min, 256)
  if (target.calibration !== undefined) q.calibration = checkCalibration(target.calibration, 'target.calibration')
  else if (ms > 0 && q.calibration === null) q.calibration = measure()
  if (!lod.hasTarget) q.targets++
  lod.hasTarget = true
  lod.maxStretch = stretch
  lod.msPerStep = ms
  lod.minSubsteps = min
  lod.maxSubsteps = max
  lod.lowChecks = 0
  q.countdown = 0 // decide at the next step
  wakeClothState(state, c)
}

/** `setClothBudget`, with the calibration run it needs for a time budget (`measure`) passed in. */
export function configureBudget(world: object, options: ClothBudgetOptions | null, measure: () => Float64Array): void {
  const state = getClothWorldForChange(world)
  const q = state.budget
  if (options === null) {
    q.settings = null
    for (let ci = 0; ci < state.cloths.length; ci++) {
      const c = state.cloths[ci]
      if (c.budget.frozen) thaw(state, c, state.kinematics.stepTo) // (between steps)
      c.budget.freezing = false
      c.budget.level = c.budget.applied = -1
      applyConfig(state, c, c.budget.wantSubsteps, c.budget.wantIterations, 1)
    }
    return
  }
  checkObject('options', options)
  checkKeys('options', options, BUDGET_KEYS)
  const msPerFrame = options.msPerFrame === undefined ? 0 : checkPositive('options.msPerFrame', options.msPerFrame)
  let viewer = -1
  if (options.viewer !== undefined && options.viewer !== null) {
    viewer = checkEntity(world, 'options.viewer', options.viewer)
    if (!hasComponent(world as never, viewer, state.transforms.component))
      throw new ClothError('options.viewer', viewer, 'must have a Transform (call setTransform)')
  }
  const near = options.near === undefined ? 10 : checkPositive('options.near', options.near)
  const far = options.far === undefined ? Math.max(40, near) : checkPositive('options.far', options.far)
  if (far < near) throw new ClothError('options.far', far, `must be ≥ near (${near})`)
  let cull = Infinity
  if (options.cull !== undefined && options.cull !== Infinity) cull = checkPositive('options.cull', options.cull)
  if (options.freezeInvisible !== undefined && typeof options.freezeInvisible !== 'boolean') {
    throw new ClothError('options.freezeInvisible', options.freezeInvisible, 'must be a boolean')
  }
  const interval = options.interval === undefined ? 15 : checkInteger('options.interval', options.interval, 1, 100000)
  if (options.adapt !== undefined && typeof options.adapt !== 'boolean')
    throw new ClothError('options.adapt', options.adapt, 'must be a boolean')
  const adapt = options.adapt ?? true
  const farStepEvery = options.farStepEvery === undefined ? 1 : options.farStepEvery
  if (farStepEvery !== 1 && farStepEvery !== 2 && farStepEvery !== 4)
    throw new ClothError('options.farStepEvery', farStepEvery, 'must be 1, 2 or 4')
  const freezeInvisible = options.freezeInvisible ?? true
  const cal = options.calibration === undefined ? null : checkCalibration(options.calibration, 'options.calibration')
  const was = q.settings
  // the budget it runs, set again: kept as it runs (its timing and countdown reset, a game setting
  // its options again after a restore replayed 2.19 m off from 9 frames on)
  if (
    was !== null && (cal === null || sameCalibration(cal, q.calibration)) && was.msPerFrame === msPerFrame && was.adapt === adapt
    && was.farStepEvery === farStepEvery && was.viewer === viewer && was.near === near && was.far === far && was.cull === cull
    && was.freezeInvisible === freezeInvisible && was.interval === interval
  ) return
  if (cal !== null) q.calibration = cal
  else if (msPerFrame > 0 && q.calibration === null) q.calibration = measure()
  q.timing[Q_FACTOR] = 1
  q.timing[Q_MEASURED] = 0
  q.settings = { msPerFrame, adapt, farStepEvery, viewer, near, far, cull, freezeInvisible, interval }
  q.countdown = 0
}

function sameCalibration(a: Float64Array, b: Float64Array | null): boolean {
  if (b === null || a.length !== b.length) return false
  for (let j = 0; j < a.length; j++) if (a[j] !== b[j]) return false
  return true
}

/**
 * Tells the budget whether a cloth is visible (e.g. from your frustum or occlusion culling). With
 * a budget whose `freezeInvisible` is on (the default), an invisible cloth freezes at the next
 * allocation and thaws when it becomes visible again.
 */
export function setClothVisible(world: object, cloth: number, visible: boolean): void {
  const state = getClothWorld(world)
  const c = getCloth(state, cloth)
  if (typeof visible !== 'boolean') throw new ClothError('visible', visible, 'must be a boolean')
  if (c.budget.visible !== visible) state.budget.countdown = 0
  c.budget.visible = visible
}

/** A cloth's current level of detail (what the budget and its target chose). */
export function getClothLod(world: object, cloth: number): ClothLodInfo {
  const state = getClothWorld(world)
  const c = getCloth(state, cloth)
  const lod = c.budget
  const cal = state.budget.calibration
  let predictedMs = 0
  if (cal !== null) {
    configCost(c, c.substeps, c.iterations, lod.stepEvery, cal, state.budget.cfg)
    predictedMs = state.budget.cfg.cost * state.budget.timing[Q_FACTOR] * 1e-6
  }
  return {
    substeps: c.substeps,
    iterations: c.iterations,
    stepEvery: lod.stepEvery,
    frozen: lod.frozen,
    wantSubsteps: lod.wantSubsteps,
    wantIterations: lod.wantIterations,
    distance: lod.distance,
    predictedMs,
  }
}

/** Called by `setClothQuality`: the cloth's own quality (the budget may still run it lower). */
export function setWantedQuality(state: ClothWorldState, c: ClothState, substeps: number, iterations: number): void {
  c.budget.wantSubsteps = substeps
  c.budget.wantIterations = iterations
  if (state.budget.settings === null) applyConfig(state, c, substeps, iterations, 1)
  else state.budget.countdown = 0
}

/**
 * The world budget's last allocation: predicted and measured time per fixed step, and the
 * correction applied to the cost model.
 */
export function getClothBudgetStats(world: object): ClothBudgetStats {
  const q = getClothWorld(world).budget
  const t = q.timing
  return { predictedMs: t[Q_PREDICTED] * t[Q_FACTOR] * 1e-6, measuredMs: t[Q_MEASURED], correction: t[Q_FACTOR] }
}

/**
 * Registers the budget's observers (called by `installClothPlugin`): a viewer that loses its
 * Transform is dropped; pins that come and go change what carries a frozen cloth (see `freeze.ts`).
 */
export function installBudget(world: object, state: ClothWorldState): void {
  observe(
    world as never,
    onRemove(state.transforms.component),
    deferrable(state, (eid: number) => {
      const b = state.budget.settings
      if (b !== null && b.viewer === eid) b.viewer = -1
    }),
  )
  observe(world as never, onAdd(state.components.Pin), (pin: number) => adoptReference(state, pin))
  observe(world as never, onRemove(state.components.Pin), deferrable(state, (pin: number) => releaseReference(state, pin)))
}
