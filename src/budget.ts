import { addEntity, createWorld, hasComponent, observe, onRemove } from 'bitecs'
import { particleBounds } from './kernels/mesh'
import { createCloth } from './cloth'
import { addSphereCollider } from './colliders'
import { ClothError, checkInteger, checkObject, checkPositive } from './errors'
import { readPoseInto } from './kinematics'
import { maxEdgeStrain } from './kernels/mesh'
import { getCloth, pinRow, transformCloth } from './pins'
import { installClothPlugin } from './plugin'
import { wakeClothState } from './sleep'
import { getClothWorld, type ClothState, type ClothWorldState } from './state'
import { stepCloth } from './step'
import { checkEntity, setTransform } from './transform'

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
 * one rung per allocation, which keeps every change below the cloth's own motion (a cape on a
 * running character: 0.28 m/s largest velocity change at a level change against 0.87 m/s from
 * the running; see tests/budget.test.ts). A frozen cloth that thaws is first carried rigidly along
 * with its pin target's motion since it froze (like a teleport), so a cape on a character that
 * walked on meanwhile is not yanked.
 *
 * The cost model: time per fixed step of a cloth = substeps/stepEvery × (particles × a +
 * iterations × projections × b + tethers × 0.6 b + particles × colliders in range × c + d), where
 * projections counts distance constraints once, line-bending triples 0.8 and hinges 3 times (their
 * relative kernel costs), and a, b, c, d (ns per particle, per projection, per particle-collider
 * test, per cloth and substep) come from a calibration: one run of a few small scenes (once per
 * process, `calibrateClothCost`), or numbers you pass (so that machines in lockstep pick the same
 * levels).
 */

/** Substep counts the controllers choose from. */
export const SUBSTEP_LADDER: readonly number[] = [1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64]

/** Per-unit costs of the cost model, ns. */
export interface ClothCostCalibration {
  nsPerParticle: number
  nsPerProjection: number
  nsPerColliderTest: number
  nsPerClothSubstep: number
}

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

/** Slots of `ClothLod.values`. */
const V_DIST = 0
const V_CX = 1 // centre of the bounds (3)
const V_REF = 4 // reference pose of the freeze (7)
const V_STRAIN = 11
const V_STRETCH = 12 // target: max stretch (0 = none)
const V_MS = 13 // target: ms per step (0 = none)
const V_PRIO = 14
const V_FC = 15 // centre when it froze (3)
const V_BOX = 18 // the particles' bounds, min xyz and max xyz (6)
const V_COUNT = 24

/** Per-cloth level-of-detail state (`ClothState.lod`). */
export interface ClothLod {
  /** Quality asked for (by `setClothQuality`, creation or the target). */
  wantSubsteps: number
  wantIterations: number
  /** Runs every n-th fixed step; `phase` counts the steps since it last ran. */
  stepEvery: number
  phase: number
  frozen: boolean
  visible: boolean
  hasTarget: boolean
  minSubsteps: number
  maxSubsteps: number
  /** Checks in a row the stretch stayed well under the target. */
  lowChecks: number
  /** Level chosen by the allocation (see `levelConfig`), and the level applied last (−1: none yet). */
  level: number
  applied: number
  /** Entity and kinematic slot the freeze reference pose belongs to (−1: none). */
  refEntity: number
  refSlot: number
  values: Float64Array
}

interface BudgetSettings {
  msPerFrame: number
  adapt: boolean
  farStepEvery: number
  viewer: number
  near: number
  far: number
  cull: number
  freezeInvisible: boolean
  interval: number
}

/** Per-world budget state (`ClothWorldState.quality`). */
export interface QualityWorld {
  budget: BudgetSettings | null
  /** Cloths with a quality target. */
  targets: number
  /** Steps until the next allocation. */
  countdown: number
  /** nsPerParticle, nsPerProjection, nsPerColliderTest, nsPerClothSubstep. */
  calibration: Float64Array | null
  /** Viewer pose scratch, level configuration scratch (s, i, e, cost, logq). */
  pose: Float64Array
  cfg: Float64Array
  /** Time the next fixed step (set by the sync phase, read by `clothFixedStep`). */
  timeNext: boolean
  /** Timing: [Q_T0] start of the timed step, [Q_MEASURED] its ms, [Q_PREDICTED] the model's ns per step, [Q_FACTOR] correction. */
  timing: Float64Array
}

export const Q_T0 = 0
export const Q_MEASURED = 1
export const Q_PREDICTED = 2
export const Q_FACTOR = 3

export function createQualityWorld(): QualityWorld {
  return {
    budget: null,
    targets: 0,
    countdown: 0,
    calibration: null,
    pose: new Float64Array(7),
    cfg: new Float64Array(5),
    timeNext: false,
    timing: Float64Array.from([0, 0, 0, 1]),
  }
}

export function createClothLod(substeps: number, iterations: number): ClothLod {
  return {
    wantSubsteps: substeps,
    wantIterations: iterations,
    stepEvery: 1,
    phase: 0,
    frozen: false,
    visible: true,
    hasTarget: false,
    minSubsteps: 1,
    maxSubsteps: 32,
    lowChecks: 0,
    level: -1,
    applied: -1,
    refEntity: -1,
    refSlot: -1,
    values: new Float64Array(V_COUNT),
  }
}

// ---------------------------------------------------------------------------------------------
// Calibration

let processCalibration: Float64Array | null = null

/**
 * Measures the cost model's per-unit costs on this machine (a few small scenes, about 30 ms; the
 * result is kept for the process). Pass `force` to measure again.
 */
export function calibrateClothCost(force = false): ClothCostCalibration {
  if (processCalibration === null || force) processCalibration = measureCalibration()
  const c = processCalibration
  return { nsPerParticle: c[0], nsPerProjection: c[1], nsPerColliderTest: c[2], nsPerClothSubstep: c[3] }
}

function measureCalibration(): Float64Array {
  const api = { installClothPlugin, createWorld, createCloth, pinRow, addEntity, setTransform, addSphereCollider, stepCloth }
  const time = (res: number, iterations: number, colliders: boolean): { ms: number; particles: number; projections: number; tethers: number } => {
    const world = api.installClothPlugin(api.createWorld(), { sleep: false, guard: false })
    const cloth = api.createCloth(world, { width: 1, height: 1, resolution: res, position: [0, 2, 0], substeps: 4, iterations })
    api.pinRow(world, cloth, 0)
    if (colliders) {
      // two balls the sheet drapes over (contacts, as on a character), not ones it never nears
      for (let k = 0; k < 2; k++) {
        const e = api.addEntity(world)
        api.setTransform(world, e, [0.25 - 0.5 * k, 1.6 - 0.3 * k, 0.12])
        api.addSphereCollider(world, e, { radius: 0.2 })
      }
    }
    const c = getCloth(getClothWorld(world), cloth)
    const t = c.topology
    for (let f = 0; f < 20; f++) api.stepCloth(world, 1 / 60)
    let best = Infinity
    for (let r = 0; r < 3; r++) {
      const t0 = performance.now()
      for (let f = 0; f < 15; f++) api.stepCloth(world, 1 / 60)
      best = Math.min(best, (performance.now() - t0) / 15)
    }
    // (tethers: once per substep, 0.6 of a projection, as in the model)
    const projections = iterations * (t.distCount + t.compCount + 0.8 * t.lineCount + 3 * t.hingeCount) + 0.6 * c.tethers.count
    return { ms: best, particles: c.count, projections: projections / iterations, tethers: 0.6 * c.tethers.count }
  }
  const a = time(20, 1, false)
  const b = time(20, 5, false)
  const withColliders = time(20, 1, true)
  const tiny = time(3, 1, false)
  const sub = 4
  // a and b differ by 4 iterations of the constraints (not the tethers, which run once)
  const nsProj = Math.max(0.5, ((b.ms - a.ms) * 1e6) / (sub * 4 * (a.projections - a.tethers)))
  const nsCol = Math.max(0.5, ((withColliders.ms - a.ms) * 1e6) / (sub * 2 * a.particles))
  // the small and the tiny sheet give the per-particle cost and the per-cloth overhead
  const perA = (a.ms * 1e6) / sub - nsProj * a.projections
  const perTiny = (tiny.ms * 1e6) / sub - nsProj * tiny.projections
  const nsPart = Math.max(0.5, (perA - perTiny) / (a.particles - tiny.particles))
  const nsCloth = Math.max(0, perTiny - nsPart * tiny.particles)
  return Float64Array.from([nsPart, nsProj, nsCol, nsCloth])
}

function checkCalibration(c: ClothCostCalibration, arg: string): Float64Array {
  checkObject(arg, c)
  return Float64Array.from([
    checkPositive(`${arg}.nsPerParticle`, c.nsPerParticle),
    checkPositive(`${arg}.nsPerProjection`, c.nsPerProjection),
    checkPositive(`${arg}.nsPerColliderTest`, c.nsPerColliderTest),
    c.nsPerClothSubstep === 0 ? 0 : checkPositive(`${arg}.nsPerClothSubstep`, c.nsPerClothSubstep),
  ])
}

function calibration(q: QualityWorld): Float64Array {
  if (q.calibration === null) {
    calibrateClothCost()
    q.calibration = processCalibration
  }
  return q.calibration!
}

// ---------------------------------------------------------------------------------------------
// API

/**
 * Lets a cloth pick its own substeps: keep its largest edge stretch under `maxStretch` (checked
 * every 15 steps; substeps rise while it is exceeded and fall while it stays under 40 % of it),
 * and/or spend at most `msPerStep` per fixed step (by the cost model). `null` removes the target;
 * the cloth keeps the substeps it had.
 *
 * @example setClothQualityTarget(world, heroCape, { maxStretch: 0.02, msPerStep: 0.5 })
 */
export function setClothQualityTarget(world: object, cloth: number, target: ClothQualityTarget | null): void {
  const state = getClothWorld(world)
  const c = getCloth(state, cloth)
  const lod = c.lod
  const q = state.quality
  if (target === null) {
    if (lod.hasTarget) q.targets--
    lod.hasTarget = false
    return
  }
  checkObject('target', target)
  const stretch = target.maxStretch === undefined ? 0 : checkPositive('target.maxStretch', target.maxStretch)
  const ms = target.msPerStep === undefined ? 0 : checkPositive('target.msPerStep', target.msPerStep)
  if (stretch === 0 && ms === 0) throw new ClothError('target', target, 'must set maxStretch and/or msPerStep (or be null)')
  const min = target.minSubsteps === undefined ? 1 : checkInteger('target.minSubsteps', target.minSubsteps, 1, 256)
  const max = target.maxSubsteps === undefined ? Math.max(32, min) : checkInteger('target.maxSubsteps', target.maxSubsteps, min, 256)
  if (target.calibration !== undefined) q.calibration = checkCalibration(target.calibration, 'target.calibration')
  else if (ms > 0) calibration(q)
  if (!lod.hasTarget) q.targets++
  lod.hasTarget = true
  lod.values[V_STRETCH] = stretch
  lod.values[V_MS] = ms
  lod.minSubsteps = min
  lod.maxSubsteps = max
  lod.lowChecks = 0
  q.countdown = 0 // decide at the next step
  wakeClothState(state, c)
}

/**
 * Sets (or with `null` removes) the world's cloth budget: level of detail by distance from a
 * viewer, freezing of invisible or culled cloths, and optionally a time per fixed step shared by
 * all cloths. Levels are re-allocated every `interval` fixed steps. Removing the budget gives every
 * cloth its own quality back.
 *
 * @example setClothBudget(world, { msPerFrame: 4, viewer: camera, near: 8, far: 30, cull: 80 })
 */
export function setClothBudget(world: object, options: ClothBudgetOptions | null): void {
  const state = getClothWorld(world)
  const q = state.quality
  if (options === null) {
    q.budget = null
    for (let ci = 0; ci < state.cloths.length; ci++) {
      const c = state.cloths[ci]
      if (c.lod.frozen) thaw(state, c)
      c.lod.level = c.lod.applied = -1
      applyConfig(state, c, c.lod.wantSubsteps, c.lod.wantIterations, 1)
    }
    return
  }
  checkObject('options', options)
  const msPerFrame = options.msPerFrame === undefined ? 0 : checkPositive('options.msPerFrame', options.msPerFrame)
  let viewer = -1
  if (options.viewer !== undefined && options.viewer !== null) {
    viewer = checkEntity(world, 'options.viewer', options.viewer)
    if (!hasComponent(world as never, viewer, state.transforms.component)) throw new ClothError('options.viewer', viewer, 'must have a Transform (call setTransform)')
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
  if (options.adapt !== undefined && typeof options.adapt !== 'boolean') throw new ClothError('options.adapt', options.adapt, 'must be a boolean')
  const adapt = options.adapt ?? true
  const farStepEvery = options.farStepEvery === undefined ? 1 : options.farStepEvery
  if (farStepEvery !== 1 && farStepEvery !== 2 && farStepEvery !== 4) throw new ClothError('options.farStepEvery', farStepEvery, 'must be 1, 2 or 4')
  if (options.calibration !== undefined) q.calibration = checkCalibration(options.calibration, 'options.calibration')
  else if (msPerFrame > 0) calibration(q)
  q.timing[Q_FACTOR] = 1
  q.timing[Q_MEASURED] = 0
  q.budget = { msPerFrame, adapt, farStepEvery, viewer, near, far, cull, freezeInvisible: options.freezeInvisible ?? true, interval }
  q.countdown = 0
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
  if (c.lod.visible !== visible) state.quality.countdown = 0
  c.lod.visible = visible
}

/** A cloth's current level of detail (what the budget and its target chose). */
export function getClothLod(world: object, cloth: number): ClothLodInfo {
  const state = getClothWorld(world)
  const c = getCloth(state, cloth)
  const lod = c.lod
  const cal = state.quality.calibration
  let predictedMs = 0
  if (cal !== null) {
    configCost(c, c.substeps, c.iterations, lod.stepEvery, cal, state.quality.cfg)
    predictedMs = state.quality.cfg[3] * state.quality.timing[Q_FACTOR] * 1e-6
  }
  return {
    substeps: c.substeps,
    iterations: c.iterations,
    stepEvery: lod.stepEvery,
    frozen: lod.frozen,
    wantSubsteps: lod.wantSubsteps,
    wantIterations: lod.wantIterations,
    distance: lod.values[V_DIST],
    predictedMs,
  }
}

/** Called by `setClothQuality`: the cloth's own quality (the budget may still run it lower). */
export function setWantedQuality(state: ClothWorldState, c: ClothState, substeps: number, iterations: number): void {
  c.lod.wantSubsteps = substeps
  c.lod.wantIterations = iterations
  if (state.quality.budget === null) applyConfig(state, c, substeps, iterations, 1)
  else state.quality.countdown = 0
}

// ---------------------------------------------------------------------------------------------
// The allocation (sync phase)

/**
 * Sync phase: every `interval` steps, runs the cloths' quality targets and the world budget and
 * applies the chosen levels. Nothing (one comparison) without a budget or a target.
 */
export function updateQuality(state: ClothWorldState): void {
  const q = state.quality
  if (q.budget === null && q.targets === 0) return
  if (--q.countdown > 0) return
  const b = q.budget
  q.countdown = b !== null ? b.interval : 15
  const cloths = state.cloths
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    if (c.lod.hasTarget && !c.sleeping && !c.lod.frozen) runTarget(state, c)
  }
  if (b === null) {
    for (let ci = 0; ci < cloths.length; ci++) {
      const c = cloths[ci]
      applyConfig(state, c, c.lod.wantSubsteps, c.lod.wantIterations, 1)
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
  allocate(state, b)
}

/**
 * Sync phase, every step after `updateQuality`: whether `clothFixedStep` should time this step
 * (the step before an allocation, when a time budget adapts).
 */
export function wantStepTiming(state: ClothWorldState): void {
  const q = state.quality
  const b = q.budget
  q.timeNext = b !== null && b.adapt && b.msPerFrame > 0 && q.countdown === 1
}

/**
 * The world budget's last allocation: predicted and measured time per fixed step, and the
 * correction applied to the cost model.
 */
export function getClothBudgetStats(world: object): ClothBudgetStats {
  const q = getClothWorld(world).quality
  const t = q.timing
  return { predictedMs: t[Q_PREDICTED] * t[Q_FACTOR] * 1e-6, measuredMs: t[Q_MEASURED], correction: t[Q_FACTOR] }
}

/** The quality target's controller: moves the wanted substeps along the ladder. */
function runTarget(state: ClothWorldState, c: ClothState): void {
  const lod = c.lod
  const v = lod.values
  let s = lod.wantSubsteps
  const stretch = v[V_STRETCH]
  // judge the stretch only while the cloth runs what it wants (not cut back by the budget)
  if (stretch > 0 && c.substeps === s && lod.stepEvery === 1) {
    const t = c.topology
    maxEdgeStrain(c.pos, t.stretchIds, t.stretchRest, t.stretchCount, v, V_STRAIN)
    const strain = v[V_STRAIN]
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
  const ms = v[V_MS]
  if (ms > 0) {
    const cal = calibration(state.quality)
    const cfg = state.quality.cfg
    if (stretch === 0) s = lod.maxSubsteps // a time target alone: the most the time allows
    // the largest ladder count (or s itself) within the time
    while (s > lod.minSubsteps) {
      configCost(c, s, lod.wantIterations, 1, cal, cfg)
      if (cfg[3] * 1e-6 <= ms) break
      s = ladderBelow(s)
    }
  }
  if (s < lod.minSubsteps) s = lod.minSubsteps
  if (s > lod.maxSubsteps) s = lod.maxSubsteps
  lod.wantSubsteps = s
}

/** Smallest ladder count ≥ x (the last rung when none is). */
function ladderAtLeast(x: number): number {
  for (let k = 0; k < SUBSTEP_LADDER.length; k++) if (SUBSTEP_LADDER[k] >= x) return SUBSTEP_LADDER[k]
  return SUBSTEP_LADDER[SUBSTEP_LADDER.length - 1]
}

/** Largest ladder count < s (1 at the bottom). */
function ladderBelow(s: number): number {
  let best = 1
  for (let k = 0; k < SUBSTEP_LADDER.length; k++) if (SUBSTEP_LADDER[k] < s) best = SUBSTEP_LADDER[k]
  return best
}

/**
 * Levels of a cloth that wants S substeps and I iterations, from the top: level L (the top) is
 * S × I; down from there the ladder's substep counts below S; then, at one substep, iterations
 * halved down to 1; then, if the budget's `farStepEvery` allows it (never for self-colliding cloths),
 * stepping every 2nd and every 4th fixed step.
 * Writes s, i, e (stepEvery) to cfg[0..2].
 */
function levelConfig(c: ClothState, level: number, cfg: Float64Array): void {
  const S = c.lod.wantSubsteps, I = c.lod.wantIterations
  const below = substepsBelow(S) // ladder rungs below S
  const halvings = iterationHalvings(I)
  // level ≥ halvings + 2: substep rungs (the top one is S itself)
  const k = level - (halvings + 2)
  if (k >= 0) {
    cfg[0] = k < below ? SUBSTEP_LADDER[k] : S
    cfg[1] = I
    cfg[2] = 1
    return
  }
  cfg[0] = 1
  if (level >= 2) {
    // level 2 + h: iterations I >> (halvings − h)
    const h = level - 2
    const it = I >> (halvings - h)
    cfg[1] = it > 1 ? it : 1
    cfg[2] = 1
    return
  }
  cfg[1] = 1
  cfg[2] = level === 1 ? 2 : 4
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
function topLevel(c: ClothState): number {
  return iterationHalvings(c.lod.wantIterations) + 2 + substepsBelow(c.lod.wantSubsteps)
}

function bottomLevel(c: ClothState, b: BudgetSettings): number {
  // a self-colliding cloth keeps stepping every step: its contacts need the travel limits of one
  if (c.collision!.self !== null) return 2
  return b.farStepEvery === 4 ? 0 : b.farStepEvery === 2 ? 1 : 2
}

/** Cost of one fixed step at (s, i, e), ns, into cfg[3]; log quality into cfg[4]. */
function configCost(c: ClothState, s: number, i: number, e: number, cal: Float64Array, cfg: Float64Array): void {
  const t = c.topology
  const projections = t.distCount + t.compCount + 0.8 * t.lineCount + 3 * t.hingeCount
  const cc = c.collision!
  const colliderTests = c.count * (cc.activeCount + (cc.self !== null ? 2 : 0))
  const perSub = cal[0] * c.count + cal[1] * (i * projections + 0.6 * c.tethers.count) + cal[2] * colliderTests + cal[3]
  cfg[3] = (perSub * s) / e
  cfg[4] = 2 * Math.log(s) + Math.log(i) - 2 * Math.log(e)
}

function levelCost(c: ClothState, level: number, cal: Float64Array, cfg: Float64Array): void {
  levelConfig(c, level, cfg)
  configCost(c, cfg[0], cfg[1], cfg[2], cal, cfg)
}

/** The world budget: freezing, distance levels, then the time budget, then apply. */
function allocate(state: ClothWorldState, b: BudgetSettings): void {
  const q = state.quality
  const cloths = state.cloths
  const pose = q.pose
  const haveViewer = b.viewer >= 0 // (cleared when the viewer loses its Transform)
  if (haveViewer) readPoseInto(state, b.viewer, pose)
  const cfg = q.cfg
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    const lod = c.lod
    const v = lod.values
    measureCentre(state, c)
    let d = 0
    if (haveViewer) {
      const dx = v[V_CX] - pose[0], dy = v[V_CX + 1] - pose[1], dz = v[V_CX + 2] - pose[2]
      d = Math.sqrt(dx * dx + dy * dy + dz * dz)
    }
    v[V_DIST] = d
    v[V_PRIO] = 1 / (1 + (d / b.near) * (d / b.near))
    const freeze = (b.freezeInvisible && !lod.visible) || d > b.cull
    if (freeze && !lod.frozen) freezeCloth(state, c)
    else if (!freeze && lod.frozen) thaw(state, c)
    // distance: full quality within `near`, substeps scaled by near/d beyond, the floor past `far`
    const top = topLevel(c)
    let level = top
    if (d >= b.far) level = bottomLevel(c, b)
    else if (d > b.near) {
      const cap = lod.wantSubsteps * (b.near / d)
      while (level > halvingsTop(c)) {
        levelConfig(c, level, cfg)
        if (cfg[0] <= cap) break
        level--
      }
    }
    lod.level = level
  }
  if (b.msPerFrame > 0) fitBudget(state, b)
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    const lod = c.lod
    // up one level per allocation at most: a stiffer level pulls in the stretch the softer one let
    // build up, and a rung at a time spreads that over several allocations (down is free: a softer
    // level lets the cloth sag through its own motion)
    if (lod.applied >= 0 && lod.level > lod.applied + 1) lod.level = lod.applied + 1
    lod.applied = lod.level
    levelConfig(c, lod.level, cfg)
    applyConfig(state, c, cfg[0], cfg[1], cfg[2])
  }
  // the model's time per step at these levels, for the timing correction and the stats
  const cal = q.calibration
  let total = 0
  if (cal !== null) {
    for (let ci = 0; ci < cloths.length; ci++) {
      const c = cloths[ci]
      if (c.lod.frozen || c.sleeping) continue
      configCost(c, c.substeps, c.iterations, c.lod.stepEvery, cal, cfg)
      total += cfg[3]
    }
  }
  q.timing[Q_PREDICTED] = total
}

/** The lowest level that still runs one substep at full iterations. */
function halvingsTop(c: ClothState): number {
  return iterationHalvings(c.lod.wantIterations) + 2
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
  // few % from step to step (64 capes: measured 2 % over a prediction that filled the budget)
  const budget = (HEADROOM * b.msPerFrame * 1e6) / state.quality.timing[Q_FACTOR]
  const q = state.quality
  const cal = calibration(q)
  const cfg = q.cfg
  const cloths = state.cloths
  let total = 0
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    if (c.lod.frozen || c.sleeping) continue
    levelCost(c, c.lod.level, cal, cfg)
    total += cfg[3]
  }
  while (total > budget) {
    let best = -1
    let bestScore = Infinity
    let bestSaving = 0
    for (let ci = 0; ci < cloths.length; ci++) {
      const c = cloths[ci]
      const lod = c.lod
      if (lod.frozen || c.sleeping || lod.level <= bottomLevel(c, b)) continue
      levelCost(c, lod.level, cal, cfg)
      const cost = cfg[3], logq = cfg[4]
      levelCost(c, lod.level - 1, cal, cfg)
      const saving = cost - cfg[3]
      if (!(saving > 0)) continue
      const score = (lod.values[V_PRIO] * (logq - cfg[4])) / saving
      if (score < bestScore) {
        bestScore = score
        best = ci
        bestSaving = saving
      }
    }
    if (best < 0) break // everything at its floor
    cloths[best].lod.level--
    total -= bestSaving
  }
}

/** Centre of the cloth's particle bounds (a frozen cloth: moved along with its reference target). */
function measureCentre(state: ClothWorldState, c: ClothState): void {
  const v = c.lod.values
  if (c.lod.frozen) {
    const k = state.kinematics
    const slot = c.lod.refSlot
    if (slot >= 0 && k.eid[slot] === c.lod.refEntity) {
      const o = 7 * slot
      // centre moved by the target's translation since the freeze (rotation ignored: an estimate)
      v[V_CX] = v[V_FC] + k.stepTo[o] - v[V_REF]
      v[V_CX + 1] = v[V_FC + 1] + k.stepTo[o + 1] - v[V_REF + 1]
      v[V_CX + 2] = v[V_FC + 2] + k.stepTo[o + 2] - v[V_REF + 2]
    }
    return
  }
  particleBounds(c.pos, c.count, v, V_BOX)
  v[V_CX] = 0.5 * (v[V_BOX] + v[V_BOX + 3])
  v[V_CX + 1] = 0.5 * (v[V_BOX + 1] + v[V_BOX + 4])
  v[V_CX + 2] = 0.5 * (v[V_BOX + 2] + v[V_BOX + 5])
}

/** Sets the counts a cloth runs (and its substep length). */
function applyConfig(state: ClothWorldState, c: ClothState, s: number, i: number, e: number): void {
  const si = s | 0, ii = i | 0, ei = e | 0
  if (c.substeps === si && c.iterations === ii && c.lod.stepEvery === ei) return
  c.substeps = si
  c.iterations = ii
  if (c.lod.stepEvery !== ei) c.lod.phase = 0
  c.lod.stepEvery = ei
  c.h = (state.fixedTimeStep * ei) / si
}

/**
 * Freezes a cloth: it keeps its state (velocities too) and is skipped by every phase. The pose of
 * its first pin target is remembered, to carry the cloth along when it thaws.
 */
function freezeCloth(state: ClothWorldState, c: ClothState): void {
  const lod = c.lod
  lod.frozen = true
  lod.refSlot = -1
  lod.refEntity = -1
  const v = lod.values
  v[V_FC] = v[V_CX]
  v[V_FC + 1] = v[V_CX + 1]
  v[V_FC + 2] = v[V_CX + 2]
  const P = state.components.Pin
  const k = state.kinematics
  for (let q = 0; q < c.pins.length; q++) {
    const slot = P.slot[c.pins[q]]
    if (slot < 0) continue
    lod.refSlot = slot
    lod.refEntity = k.eid[slot]
    for (let j = 0; j < 7; j++) v[V_REF + j] = k.stepTo[7 * slot + j]
    break
  }
}

/** Thaws a frozen cloth, carried rigidly by its reference target's motion since the freeze. */
function thaw(state: ClothWorldState, c: ClothState): void {
  const lod = c.lod
  lod.frozen = false
  lod.phase = 0
  const k = state.kinematics
  const slot = lod.refSlot
  lod.refSlot = -1
  if (slot < 0 || k.eid[slot] !== lod.refEntity) return
  const v = lod.values
  const o = 7 * slot
  // R = q_now · q_ref⁻¹ about the old position, then to the new one (the pose the pins start from)
  const fx = -v[V_REF + 3], fy = -v[V_REF + 4], fz = -v[V_REF + 5], fw = v[V_REF + 6]
  const tx = k.stepFrom[o + 3], ty = k.stepFrom[o + 4], tz = k.stepFrom[o + 5], tw = k.stepFrom[o + 6]
  const rx = tw * fx + tx * fw + ty * fz - tz * fy
  const ry = tw * fy - tx * fz + ty * fw + tz * fx
  const rz = tw * fz + tx * fy - ty * fx + tz * fw
  const rw = tw * fw - tx * fx - ty * fy - tz * fz
  const dx = k.stepFrom[o] - v[V_REF], dy = k.stepFrom[o + 1] - v[V_REF + 1], dz = k.stepFrom[o + 2] - v[V_REF + 2]
  if (dx === 0 && dy === 0 && dz === 0 && rx === 0 && ry === 0 && rz === 0) return
  transformCloth(c, v[V_REF], v[V_REF + 1], v[V_REF + 2], rx, ry, rz, rw, k.stepFrom[o], k.stepFrom[o + 1], k.stepFrom[o + 2])
  wakeClothState(state, c)
}

/** Registers the budget's observer (called by `installClothPlugin`): a viewer that loses its Transform is dropped. */
export function installQuality(world: object, state: ClothWorldState): void {
  observe(world as never, onRemove(state.transforms.component), (eid: number) => {
    const b = state.quality.budget
    if (b !== null && b.viewer === eid) b.viewer = -1
  })
}
