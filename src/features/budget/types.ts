/**
 * State of the budget feature: quality targets, the world budget and level of detail are one
 * mechanism (it picks each cloth's substeps and iterations), with one name: budget.
 */

/** World budget settings, resolved (see `ClothBudgetOptions`). */
export interface BudgetSettings {
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

/** A level's configuration and cost (scratch of the allocation, written by `levelConfig` and `configCost`). */
export interface LevelConfig {
  substeps: number
  iterations: number
  stepEvery: number
  /** Predicted cost of one fixed step at this configuration, ns. */
  cost: number
  /** log quality: 2 log substeps + log iterations − 2 log stepEvery. */
  logQuality: number
}

/** Per-world budget state (`ClothWorldState.budget`). */
export interface BudgetWorld {
  /** The world budget, or null when none is set. */
  settings: BudgetSettings | null
  /** Cloths with a quality target. */
  targets: number
  /** Steps until the next allocation. */
  countdown: number
  /** Cost model: nsPerParticle, nsPerProjection, nsPerColliderTest, nsPerClothSubstep. */
  calibration: Float64Array | null
  /** Viewer pose scratch, and the level configuration the level functions write. */
  pose: Float64Array
  cfg: LevelConfig
  /** Time the next fixed step (set by the sync phase, read by `clothFixedStep`). */
  timeNext: boolean
  /** Timing: [Q_T0] start of the timed step, [Q_MEASURED] its ms, [Q_PREDICTED] the model's ns per step, [Q_FACTOR] correction. */
  timing: Float64Array
}

/** Slots of `BudgetWorld.timing` (read around every timed step: a typed array never boxes). */
export const Q_T0 = 0
export const Q_MEASURED = 1
export const Q_PREDICTED = 2
export const Q_FACTOR = 3

/** Per-cloth budget state (`ClothState.budget`). */
export interface ClothBudget {
  /** Quality asked for (by `setClothQuality`, creation or the quality target). */
  wantSubsteps: number
  wantIterations: number
  /** Runs every n-th fixed step; `phase` counts the steps since it last ran. */
  stepEvery: number
  phase: number
  /**
   * Fixed steps the cloth sat out (stepping every n-th) since its last step: its next step covers
   * them too, whatever rate it then runs at (the sync phase sets the step's length from it).
   */
  waited: number
  /** Chosen to freeze while it sat steps out: it steps now to catch up, and freezes at the next step. */
  freezing: boolean
  frozen: boolean
  visible: boolean
  /** Quality target: on, its substep bounds, its largest stretch and time per step (0 = none). */
  hasTarget: boolean
  minSubsteps: number
  maxSubsteps: number
  maxStretch: number
  msPerStep: number
  /** Checks in a row the stretch stayed well under the target. */
  lowChecks: number
  /** Level chosen by the allocation (see `levelConfig`), and the level applied last (−1: none yet). */
  level: number
  applied: number
  /** Distance from the viewer at the last allocation, m, and the priority it gives. */
  distance: number
  priority: number
  /** Centre of the particles' bounds at the last allocation, and where it was when the cloth froze. */
  centre: Float64Array
  frozenCentre: Float64Array
  /**
   * While frozen: the reference pin (−1: none; `ANCHOR_REF`: the character frame or bone whose
   * slot is `refSlot`), its target's kinematic slot, and the target's pose (px py pz qx qy qz qw)
   * when it became the reference (see `freeze.ts`).
   */
  refPin: number
  refSlot: number
  refPose: Float64Array
  /**
   * The kinematic slot of the cloth's draw anchor (`src/draw.ts`) and its pose at the end of the
   * last step the cloth ran (−1: none yet): what its mesh shows while it sits steps out.
   */
  shownSlot: number
  shownPose: Float64Array
  /**
   * True while the mesh shows the cloth moved by `teleportCloth` since its last step: `shownPose`
   * is then its anchor's pose at that step moved by the teleport (see `carryShownAnchor`).
   */
  shownCarried: boolean
  /**
   * True when the cloth sat out the world's last step (asleep, frozen, or stepping every n-th): its
   * mesh shows an older step, whose anchor pose is `shownPose`.
   */
  shownStale: boolean
  /** True from a thaw to the sync's choice of the cloth's step: it steps at once, at whatever level it gets. */
  dueNow: boolean
  /** Measurement scratch: the particles' bounds (6), then the largest edge strain. */
  measure: Float64Array
}
