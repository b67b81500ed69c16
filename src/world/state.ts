import type { ClothStore } from '../../components/Cloth'
import type { PinStore } from '../../components/Pin'
import type { TransformStore } from '../../components/Transform'
import type { WindZoneStore } from '../../components/WindZone'
import type { TearableStore } from '../../components/Tearable'
import type { ClothMaterialSpec } from '../model/materials'
import type { TetherMode, TetherSet } from '../model/tethers'
import type { ClothLines } from '../model/lines'
import type { ClothTopology } from '../model/topology'
import type { ClothPins } from '../features/pins/types'
import type { ClothGrabs, GrabWorld } from '../features/grab/types'
import type { ClothWind, WindWorld } from '../features/wind/types'
import type { ClothCollision, CollisionWorld } from '../features/collision/types'
import type { BudgetWorld, ClothBudget } from '../features/budget/types'
import type { ClothGuardOptions, ClothGuardState, GuardWorld } from '../features/guard/types'
import type { ClothCharacter } from '../features/character/types'
import type { ClothTear, TearWorld } from '../features/tearing/types'

/**
 * The plugin's state types: one `ClothState` per cloth (particle arrays, shared rest data, solver
 * settings, then one sub-object per feature) and one `ClothWorldState` per world (settings,
 * stores, cloths in creation order, then one sub-object per feature). Feature state types live in
 * `src/features/<feature>/types.ts`; sleeping is the exception, declared here, because every
 * feature wakes cloths (`wakeClothState`).
 */

/**
 * Where the plugin reads world transforms from. The plugin's own `Transform` store fits this
 * shape; an engine with its own stores passes them here (any entity-indexed arrays), plus the
 * component whose presence marks an entity as having a transform.
 */
export interface TransformSource {
  /** The component that marks entities with a transform (checked with hasComponent). */
  component: object
  px: ArrayLike<number>
  py: ArrayLike<number>
  pz: ArrayLike<number>
  qx: ArrayLike<number>
  qy: ArrayLike<number>
  qz: ArrayLike<number>
  qw: ArrayLike<number>
  /** Optional scale; 1 when absent. */
  sx?: ArrayLike<number>
  sy?: ArrayLike<number>
  sz?: ArrayLike<number>
}

/** Options of `installClothPlugin`. */
export interface ClothPluginOptions {
  /** Gravity, m/s². Default [0, −9.81, 0]. */
  gravity?: ArrayLike<number>
  /** Fixed simulation step, s. Default 1/60. Each step runs each cloth's own substeps. */
  fixedTimeStep?: number
  /**
   * Most fixed steps one `stepCloth` call may run (the accumulator keeps the rest, and time beyond
   * this many steps is dropped, so a 10 s hitch never becomes one giant step). Default: the steps of
   * a 1/15 s frame, from 4 to 1000 (4 at the default 1/60 s step, 16 at 1/240 s). A machine that
   * cannot step the cloth as fast as time passes then runs that many steps every frame: set it
   * lower to keep the frame rate and let the cloth fall behind.
   */
  maxStepsPerFrame?: number
  /** Read transforms from the host engine's stores instead of the plugin's `Transform`. */
  transforms?: TransformSource
  /** A pin target moving farther than this in one fixed step counts as a teleport, m. Default 2. */
  teleportDistance?: number
  /** Particle speed limit, m/s (a runaway guard, not a physical limit). Default 250. */
  maxSpeed?: number
  /** Initial entity capacity of the plugin's stores; they grow on demand. Default 1024. */
  capacity?: number
  /** Density of the air for aerodynamics, kg/m³ (a wind zone may override it). Default 1.2. */
  airDensity?: number
  /**
   * Explosion guard defaults for the cloths of this world (see `ClothGuardOptions`); false turns it
   * off. Default on: finite, bounds 2 × the cloth's size, speed half of `maxSpeed`.
   */
  guard?: boolean | ClothGuardOptions
  /**
   * Sleeping defaults for the cloths of this world (see `ClothSleepOptions`); false turns it off.
   * Default on: a cloth whose particles all stay below 1 cm/s for 1 s sleeps until disturbed.
   */
  sleep?: boolean | ClothSleepOptions
  /**
   * Worker threads that step this world's cloths (Web Workers in browsers, `worker_threads` in
   * Node), the particle state in shared memory; 0 (default) steps on the calling thread. The
   * results are bitwise identical whatever the count. See `beginClothStep` / `endClothStep`.
   */
  threads?: number
  /**
   * The worker script: the package's `worker.js` (next to its `index.js`), or your bundle of
   * `bitecs-cloth/worker`. Default: `worker.js` beside the library file.
   */
  workerUrl?: string | { readonly href: string }
  /**
   * Without shared memory (a browser page that is not cross-origin isolated), `threads` cannot
   * work: true throws a ClothError; false (default) warns once and steps on the calling thread.
   */
  requireThreads?: boolean
  /**
   * A step the cost model predicts cheaper than this (ms) runs on the calling thread when
   * `stepCloth` waits for it anyway: the handoff to the workers costs tens of microseconds.
   * Default 0.2; 0 always hands steps to the workers. (`beginClothStep` always hands them over.)
   */
  threadMinStepMs?: number
}

/** Counters of the work each phase did, accumulated since install (or the last reset). */
export interface ClothStats {
  /** Fixed steps run. */
  steps: number
  /** Global substeps run (the largest substep count of the cloths in each step). */
  substeps: number
  /** Particle predictions (free particles integrated). */
  particlesIntegrated: number
  /** Distance constraint projections (stretch, shear, bend springs, compression-only). */
  distanceProjections: number
  /** Dihedral hinge projections. */
  dihedralProjections: number
  /** Line-bending (three-particle) projections. */
  lineProjections: number
  /** Tether projections (including inactive ones, which cost a distance test). */
  tetherProjections: number
  /** Pinned-particle placements. */
  pinUpdates: number
  /** Tether rebuilds after pin changes. */
  tetherRebuilds: number
  /** Cloths moved by a teleport (automatic or explicit). */
  teleports: number
  /** Triangles processed by the aerodynamics kernel. */
  windTriangles: number
  /** Edge strain checks by the tearing phase. */
  strainChecks: number
  /** Particle–collider tests. */
  colliderTests: number
  /** Particle pairs examined by self-collision. */
  selfCollisionTests: number
  /** Tears (particle splits) by the tearing phase. */
  tears: number
  /** Cloth health checks by the explosion guard (one per cloth per step). */
  guardChecks: number
  /** Cloths reset by the explosion guard. */
  guardResets: number
  /** Steps cloths spent asleep (one per sleeping cloth per step). */
  sleepingSteps: number
  /** Sleeping cloths woken. */
  wakes: number
  /** Steps cloths sat out by level of detail (frozen, or between the steps of a cloth stepping every n-th). */
  lodSkippedSteps: number
}

/** Long-range attachments of a cloth (`ClothState.tethers`): settings and the live set. */
export interface ClothTethers {
  /** The tethers the solver runs (rebuilt when pins change, or the cloth tears). */
  set: TetherSet
  enabled: boolean
  mode: TetherMode
  slack: number
  perParticle: number
  /** Rebuild at the next step (pins changed, settings changed, the cloth tore). */
  dirty: boolean
  /**
   * The rebuild follows a change of pins or settings: its tethers start no tighter than the cloth
   * is (`loosenTethers`). Not after tears alone.
   */
  loosen: boolean
}

/** Render buffers of a cloth (`ClothState.render`): float32, sized for the particle/triangle capacity. */
export interface ClothRender {
  positions: Float32Array
  normals: Float32Array
  indices: Uint32Array
  /**
   * Texture coordinates, u v per particle (see `model/uvs.ts` for the convention). Rest data of the
   * cloth's render mesh: written at creation, copied to the new particle when tearing splits one.
   */
  uvs: Float32Array
  /** The `ClothState.version` the buffers were written at (−1: stale). */
  version: number
  /** Cached views handed out by getClothMesh (sized to the live counts). */
  mesh: ClothMesh | null
}

/** Options of `setClothSleep` and of the plugin's `sleep` option. */
export interface ClothSleepOptions {
  /** Whether the cloth may fall asleep. Default true. */
  enabled?: boolean
  /** Speed every particle must stay below, m/s. Default 0.01. */
  speed?: number
  /** How long the cloth must stay that slow before it sleeps, s. Default 1. */
  delay?: number
}

/** Resolved sleep settings (world defaults). */
export interface SleepSettings {
  enabled: boolean
  speed: number
  delay: number
}

/** Sleep settings and state of one cloth (`ClothState.sleep`). */
export interface ClothSleep {
  /** Asleep: every phase skips the cloth until something wakes it. */
  asleep: boolean
  enabled: boolean
  /** Speed² every particle must stay below, (m/s)², and for how long, s. */
  speed2: number
  delay: number
  /** How long the cloth has been that slow, s. */
  still: number
  /** Particle bounds when it fell asleep (min xyz, max xyz), for the wake tests. */
  bounds: Float64Array
}

/** Per-world sleep bookkeeping (`ClothWorldState.sleep`). */
export interface SleepWorld {
  /** Settings new cloths start with. */
  defaults: SleepSettings
  /** Cloths asleep now. */
  count: number
  /** Gravity when the last cloth fell asleep (a change wakes every sleeper). */
  gravity: Float64Array
}

/** Everything one cloth instance owns: particle state in flat typed arrays plus shared rest data. */
export interface ClothState {
  /** The cloth's entity. */
  eid: number
  /** Creation sequence number; the solver visits cloths in this order, never in query order. */
  seq: number
  /** Rest data (shared, read-only; a tearable cloth has its own copy). */
  topology: ClothTopology
  material: ClothMaterialSpec

  /** Live particles (the arrays may hold room for more: a tearable cloth reserves it). */
  count: number
  /** Positions, xyz interleaved, m. */
  pos: Float64Array
  /** Positions at the start of the current substep, m. */
  prev: Float64Array
  /** Velocities, m/s. */
  vel: Float64Array
  /** Inverse masses, 1/kg; 0 while pinned. */
  invMass: Float64Array
  /** Inverse masses without pins, 1/kg. */
  baseInvMass: Float64Array
  /**
   * The distance loops' copy of `invMass`, spread to position offsets (`invMass3[3i]` =
   * `invMass[i]`). The solve phase refreshes it at the first substep of every step, so it follows
   * pins, unpins, tears and restores made between steps.
   */
  invMass3: Float64Array
  /** Number of pins holding each particle, plus 1 while character cloth holds it on its reference (max distance 0). */
  pinCount: Uint16Array
  /** Extra per-particle acceleration for this substep (wind), or null when nothing writes it. */
  accel: Float64Array | null
  /** Connected piece of each particle (numbered by their lowest particle), or null: one piece. */
  piece: Int32Array | null
  pieceCount: number
  /**
   * Particles of pieces nothing carries along ([0] = count, then particles; room for every
   * particle when the mesh has pieces): the automatic rigid carries (a pin target's or character
   * frame's jump, a hitch, a thaw) leave them where they are (`moveClothRigidly`). Of a character
   * cloth, the pieces neither its frame, bones nor held particles hold (`releaseDetachedPieces`);
   * of any other, the pieces no pin on an entity holds (`listLoosePieces`). Empty for one piece.
   */
  detached: Int32Array

  /** Substeps per fixed step. */
  substeps: number
  /** Solver iterations per substep. */
  iterations: number
  /** 'xpbd' accumulates multipliers (converged stiffness independent of iterations); 'pbd' does not. */
  solver: 'xpbd' | 'pbd'
  /** Velocity damping, 1/s. */
  damping: number
  /** Stretch damping, 1/s (see ClothMaterialSpec.stretchDamping). */
  stretchDamping: number
  /** Substep length for this cloth, s. */
  h: number
  /** Local substep index this global substep, or −1 when the cloth sits this one out. */
  subIndex: number
  /** Sits this fixed step out: asleep, frozen, or between the steps of a cloth stepping every n-th. */
  idle: boolean
  /** Kernel parameters for the current substep (see `kernels/params.ts`). */
  params: Float64Array
  /** XPBD multipliers, one per constraint (three per line-bending triple). */
  distLambda: Float64Array
  compLambda: Float64Array
  lineLambda: Float64Array
  hingeLambda: Float64Array
  /**
   * Lines of structural edges solved directly each substep (the option `lineSolve`), or null. Not
   * used while the cloth is tearable (a tear would leave a line joining what it split).
   */
  lines: ClothLines | null
  /** Bumped at the end of every step (and by anything that moves the particles); the render mesh follows it. */
  version: number

  tethers: ClothTethers
  render: ClothRender
  sleep: ClothSleep
  pins: ClothPins
  /** Grabs holding particles of the cloth (soft point constraints toward targets). */
  grab: ClothGrabs
  /** Aerodynamics buffers, allocated when a wind zone exists, else null. */
  wind: ClothWind | null
  collision: ClothCollision
  budget: ClothBudget
  /** Explosion guard: settings, thresholds, last good pose, rest pose. */
  guard: ClothGuardState
  /** Character cloth (inertia in a frame, motion constraints, skinned reference), else null. */
  character: ClothCharacter | null
  /** Tearing state of a tearable cloth (own rest data with reserved capacity), else null. */
  tear: ClothTear | null
}

/** GPU-ready mesh of a cloth: views sized to the live particles and triangles. */
export interface ClothMesh {
  /** xyz per particle, m. */
  positions: Float32Array
  /** Unit normal per particle (area-weighted). */
  normals: Float32Array
  /**
   * Texture coordinates, u v per particle: u left to right and v bottom to top seen from the front,
   * as on `THREE.PlaneGeometry` (grid cloths: u = column / (columns − 1), v = 1 − row / (rows − 1)).
   */
  uvs: Float32Array
  /** 3 particle indices per triangle. */
  indices: Uint32Array
  vertexCount: number
  triangleCount: number
}

/**
 * Kinematic tracking of entities whose Transform drives the simulation (pin targets now,
 * colliders later). Each tracked entity gets a slot; its pose is sampled once per frame and
 * interpolated in time across the fixed steps of that frame and across the substeps of each step.
 *
 * A frame of variable length runs 0, 1 or several fixed steps; interpolating by time gives every
 * step exactly the motion of its own time slice, so pins do not jerk at frame rate.
 *
 * Poses are px py pz qx qy qz qw (stride 7), scales sx sy sz (stride 3). Per slot:
 * - `sampleFrom`, `sampleTo`: the target's pose at the previous and at the current frame sample;
 * - `stepFrom`, `stepTo`: its pose at the start and end of the current fixed step;
 * - `scaleSampleFrom` … `scaleStepTo`: its scale at the same four times (interpolated linearly).
 */
export interface Kinematics {
  /** Slot of each entity id, −1 when untracked (grown on demand). */
  slotOf: Int32Array
  /**
   * Per entity id: how many times an entity with this id lost its transform (removed, or its
   * transform component taken away), grown on demand. bitECS reuses ids, so a snapshot compares it
   * to tell the pin target it saved from another entity that got the id since.
   */
  generation: Uint32Array
  /** The entity whose transform is being taken away while its pins go with it (−1 otherwise). */
  losing: number
  /**
   * True while a snapshot this world did not save is restored: generations are not compared
   * (`generationChanged`); another world's counts, however its ids were used before, say nothing
   * about this one's.
   */
  foreign: boolean
  /** Entity of each slot, −1 when free. */
  eid: Int32Array
  /** Pins/colliders using each slot. */
  refs: Int32Array
  /** Highest slot in use + 1. */
  count: number
  /** Free slots (reused last-in first-out, which keeps slot order deterministic). */
  free: number[]
  /**
   * Slots in use, in no particular order: the per-step loops walk these, not every slot below
   * `count` (a hero tracked after a level of 20,000 colliders kept the loops that long once the
   * level unloaded: 1.4× the step), and each slot's index in it.
   */
  live: number[]
  liveAt: number[]
  sampleFrom: Float64Array
  sampleTo: Float64Array
  stepFrom: Float64Array
  stepTo: Float64Array
  scaleSampleFrom: Float64Array
  scaleSampleTo: Float64Array
  scaleStepFrom: Float64Array
  scaleStepTo: Float64Array
  /**
   * 1 when the entity jumped (teleported) at the current frame sample; 2 (`K_CARRIED`) when the
   * motion of dropped frame time was carried as a jump (cloths follow it as they follow a teleport,
   * but it is no teleport: not counted, no teleport reset). 0 otherwise.
   */
  jumped: Uint8Array
  /**
   * Per slot, at a sample after dropped frame time: whether its motion in that time is swept
   * (CARRY_PART: a cloth follows it and something else) or carried (0: nothing follows it, a
   * collider's body; CARRY_WHOLE: cloths following it follow nothing else; CARRY_WITH + f: a bone
   * of a skinned cloth carried as a whole by its frame at slot f, moved by f's jump). Set by
   * `markCarriedSlots` (features/character) before the sample.
   */
  carry: Int32Array
  /** 1 when the entity's pose or scale changes during the current fixed step (or it jumped): wakes sleepers. */
  moved: Uint8Array
  /** 1 to treat the next sample as a jump whatever its distance (set by teleportCloth). */
  forceJump: Uint8Array
  /** The jump as a rigid transform: pivot xyz, rotation xyzw, translation xyz (stride 10). */
  jump: Float64Array
  /**
   * Timing scalars, in a typed array so passing them around never allocates:
   * [K_SINCE_SAMPLE] seconds since the last frame sample; [K_STEP_FRACTION] the fraction of that
   * span at which the current fixed step ends; [K_DROPPED] seconds of frame time since the last
   * sample that no step simulates (beyond `maxStepsPerFrame`): the motion of that share of the
   * span is carried rigidly at the sample (`sampleFrame`), not simulated.
   */
  time: Float64Array
  /** True when the next sync must take a new frame sample. */
  newFrame: boolean
  /** True while `stepCloth` runs a frame's steps; outside it, every fixed step samples anew. */
  framed: boolean
}

/** Slots of `Kinematics.time`. */
export const K_SINCE_SAMPLE = 0
export const K_STEP_FRACTION = 1
export const K_DROPPED = 2
/** `Kinematics.time`: the last frame sample's span, in fixed steps (what a leap repeated at the next frame is scaled by, `landsBeyond`). */
export const K_LAST_SPAN = 3

/**
 * `Kinematics.jumped`: the scale leapt at this frame sample (`markScaleLeaps`): the frame's steps
 * take the new scale at once, unswept; the jump record is the identity.
 */
export const K_SCALED = 3

/** The frame `beginClothStep` opened (`ClothWorldState.frame`). */
export interface ClothFrame {
  /** Between `beginClothStep` and `endClothStep`: cloths may not change. */
  open: boolean
  /** Fixed steps the frame runs, and the next one to start (1-based). */
  steps: number
  next: number
  /** Time beyond `maxStepsPerFrame` fixed steps was dropped this frame. */
  overflow: boolean
  /** The started fixed step's substeps wait for its finish (`beginClothStep` without workers). */
  deferred: boolean
  /** `endClothStepAsync` is finishing the frame. */
  ending: boolean
  /** A finished step's listeners are being called (they may change the world, not step it). */
  delivering: boolean
  /**
   * Between a fixed step's sync phase and its guard: the step's reference poses, pin poses and
   * substep plan are set up, so cloths may not change (a scheduler running the phases by hand).
   */
  stepping: boolean
  /**
   * A started fixed step runs on workers or waits for its finish on this thread: removal observers
   * queue their callbacks (`removals`, with the entity ids in `removed`) until its results are in
   * (see world/flight.ts).
   */
  inFlight: boolean
  removals: ((eid: number) => void)[]
  removed: number[]
  /**
   * The fields of the stores the workers write (Pin: blends; Tearable: tear counts) as the step in
   * flight was handed over, when the stores grew meanwhile (else null; see world/flight.ts).
   */
  stale: { Pin: Record<string, unknown>; Tearable: Record<string, unknown> } | null
}

/** Per-world plugin state, kept on the world object under a symbol. */
export interface ClothWorldState {
  gravity: Float64Array
  fixedTimeStep: number
  maxStepsPerFrame: number
  teleportDistance: number
  maxSpeed: number
  /** Time not yet simulated, s. */
  accumulator: number
  components: {
    Transform: TransformStore
    Cloth: ClothStore<ClothState>
    Pin: PinStore
    WindZone: WindZoneStore
    Tearable: TearableStore
  }
  /** Where transforms are read from (the plugin's Transform unless the host gave its own). */
  transforms: TransformSource
  /** Capacity of the entity-indexed stores (all of them, the collision stores included). */
  capacity: number
  /** Cloths in creation order. */
  cloths: ClothState[]
  nextSeq: number
  /** Tracked transforms (pin targets, collider bodies, wind zones), interpolated across steps and substeps. */
  kinematics: Kinematics
  /** Global substep index within the current fixed step, and how many there are. */
  substep: number
  substepCount: number
  /** Writeback phases the scheduled phase systems ran since their `clothSync` (−1: none since their last `clothGuard`; see systems/scheduled.ts). */
  scheduledWritebacks: number
  stats: ClothStats
  sleep: SleepWorld
  grab: GrabWorld
  wind: WindWorld
  collision: CollisionWorld<ClothState>
  budget: BudgetWorld
  guard: GuardWorld
  tearing: TearWorld
  /** The frame being stepped (`beginClothStep` / `endClothStep`). */
  frame: ClothFrame
  /** Workers stepping the cloths, or null (the calling thread steps them). */
  threads: ClothThreads | null
}

/** A worker as the plugin uses it (a Web Worker or a Node `worker_threads` Worker). */
export interface ClothWorker {
  postMessage(message: unknown): void
  terminate(): unknown
}

/** A cloth as the workers know it: its handoff block and the arrays it held when last sent. */
export interface ClothBinding {
  cloth: ClothState
  /** Index the workers know the cloth by. */
  slot: number
  /** The per-step handoff block (see `src/threads/handoff.ts`), shared with the workers. */
  io: Float64Array
  /** The cloth's arrays in a fixed order, as last sent (see `src/threads/layout.ts`). */
  layout: unknown[]
}

/** Per-world threading state (`ClothWorldState.threads`; null when the world steps on its own thread). */
export interface ClothThreads {
  /** The pool (src/threads/pool.ts): workers, control words, errors. */
  pool: { workers: ClothWorker[]; control: Int32Array; block: boolean; errors: string[]; exited: number }
  /** Per-step world values the workers read (see `src/threads/handoff.ts`). */
  worldIO: Float64Array
  /** Per worker: the slots of the cloths it steps this step ([0] = count). */
  lists: Int32Array[]
  /** Per worker: what it hands back (work counters, sleep count, time, tear events). */
  outputs: Float64Array[]
  /** Binding of each slot (null: free), and of each cloth. */
  slots: (ClothBinding | null)[]
  bindings: Map<ClothState, ClothBinding>
  /** Layout epoch (src/core/shared.ts) when the bindings were last checked; layout messages sent. */
  epoch: number
  layoutSeq: number
  /** The world's shared arrays as last sent. */
  worldLayout: unknown[]
  /** Step number of the last step handed to the workers. */
  step: number
  /** 0: idle; 1: a step is with the workers; 2: a step ran on this thread and waits to be finished. */
  phase: number
  /** Steps whose predicted cost (ns, the budget's cost model) is below this run on this thread. */
  inlineNs: number
  /** Partition scratch, per cloth: cost, group, the worker of a group (at its root), sort order; per worker: load. */
  cost: Float64Array
  group: Int32Array
  order: Int32Array
  sorted: Int32Array
  load: Float64Array
  /** The worker of each binding slot at the last step (−1: none yet). */
  assign: Int32Array
  /** Test hook: check every step that the layout did not change unannounced and the workers hold the same values. */
  verify: boolean
  /** In verify mode: the main thread's fingerprints of the cloths it handed over, by slot. */
  verifyBefore: Map<number, string[]>
  /** Per worker, in verify mode: its fingerprints of the cloths before and after the step (text in shared memory). */
  verifyText: Int32Array[]
  /** Shared copies of arrays found outside shared memory (see `src/threads/layout.ts`). */
  adopt: WeakMap<object, object>
  /**
   * What `getClothTearCount` and `getGrabForce` read while a step is with the workers (which write
   * the live ones): the tear counts and each grabbing cloth's grab data as the last finished step
   * left them, copied when the step is handed over (main thread only).
   */
  finishedTears: Uint32Array
  finishedGrabs: WeakMap<ClothState, Float64Array>
}

/** Symbol under which the plugin keeps its state on a world. */
export const $cloth = Symbol.for('bitecs-cloth')
