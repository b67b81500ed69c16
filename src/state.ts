import type { ClothStore } from '../components/Cloth'
import type { ClothCollision, CollisionWorld } from './collision'
import type { PinStore } from '../components/Pin'
import type { TransformStore } from '../components/Transform'
import type { WindZoneStore } from '../components/WindZone'
import type { TearableStore } from '../components/Tearable'
import { ClothError } from './errors'
import type { ClothGuardOptions, ClothGuardState, GuardWorld } from './guard'
import type { Kinematics } from './kinematics'
import type { ClothMaterialSpec } from './materials'
import type { TetherMode, TetherSet } from './tethers'
import type { ClothTopology } from './topology'
import type { ClothWind, WindWorld } from './wind'
import type { ClothSleepOptions, SleepWorld } from './sleep'
import type { ClothLod, QualityWorld } from './budget'
import type { ClothTear, TearWorld } from './tearing'

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
   * this many steps is dropped, so a 10 s hitch never becomes one giant step). Default 4.
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

/** Everything one cloth instance owns: particle state in flat typed arrays plus shared rest data. */
export interface ClothState {
  /** The cloth's entity. */
  eid: number
  /** Creation sequence number; the solver visits cloths in this order, never in query order. */
  seq: number
  /** Rest data (shared, read-only). */
  topology: ClothTopology
  material: ClothMaterialSpec
  /** Live particles. */
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
  /** Number of pins holding each particle. */
  pinCount: Uint16Array
  /** Extra per-particle acceleration for this substep (wind), or null when nothing writes it. */
  accel: Float64Array | null
  /** XPBD multipliers, one per constraint. */
  distLambda: Float64Array
  compLambda: Float64Array
  lineLambda: Float64Array
  hingeLambda: Float64Array
  /** Long-range attachments, rebuilt when pins change. */
  tethers: TetherSet
  useTethers: boolean
  tetherMode: TetherMode
  tetherSlack: number
  tethersPerParticle: number
  tethersDirty: boolean
  /** Pin entities holding this cloth, in creation order. */
  pins: number[]
  /** Substeps per fixed step. */
  substeps: number
  /** Solver iterations per substep. */
  iterations: number
  /** 'xpbd' accumulates multipliers (stiffness independent of iterations); 'pbd' does not. */
  solver: 'xpbd' | 'pbd'
  /** Velocity damping, 1/s. */
  damping: number
  /** Stretch damping, 1/s (see ClothMaterialSpec.stretchDamping). */
  stretchDamping: number
  /** Local substep index this global substep, or −1 when the cloth sits this one out. */
  subIndex: number
  /** Substep length for this cloth, s. */
  h: number
  /** Kernel parameters for the current substep (see `kernels/params.ts`). */
  params: Float64Array
  /** Do not follow a pin target's jump at the next frame sample (set by `teleportCloth`). */
  skipTeleport: boolean
  /** Bumped at the end of every step; the render mesh is refreshed when it lags. */
  version: number
  renderedVersion: number
  /** Render buffers (float32), sized for the particle/triangle capacity. */
  renderPos: Float32Array
  renderNormal: Float32Array
  renderIndex: Uint32Array
  /** Cached views handed out by getClothMesh (sized to the live counts). */
  mesh: ClothMesh | null
  /** Aerodynamics buffers, allocated when a wind zone exists (see `src/wind.ts`), else null. */
  wind: ClothWind | null
  /** Tearing state of a tearable cloth (own rest data with reserved capacity), else null. */
  tear: ClothTear | null
  /** Explosion guard: settings, thresholds, last good pose, rest pose (see `src/guard.ts`). */
  guard: ClothGuardState
  /** Collision settings and per-step collision state (set when the cloth is created). */
  collision?: ClothCollision
  /** Asleep: every phase skips the cloth until something wakes it (see `src/sleep.ts`). */
  sleeping: boolean
  /** Stillness timer and sleep settings (slots in `src/sleep.ts`). */
  sleep: Float64Array
  /** Particle bounds when it fell asleep (min xyz, max xyz), for the wake tests. */
  sleepBounds: Float64Array
  /** Sits this fixed step out: asleep, frozen, or between the steps of a cloth stepping every n-th. */
  idle: boolean
  /** Level of detail: wanted quality, quality target, stepping rate, freezing (see `src/budget.ts`). */
  lod: ClothLod
}

/** GPU-ready mesh of a cloth: views sized to the live particles and triangles. */
export interface ClothMesh {
  /** xyz per particle, m. */
  positions: Float32Array
  /** Unit normal per particle (area-weighted). */
  normals: Float32Array
  /** 3 particle indices per triangle. */
  indices: Uint32Array
  vertexCount: number
  triangleCount: number
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
  components: { Transform: TransformStore; Cloth: ClothStore; Pin: PinStore; WindZone: WindZoneStore; Tearable: TearableStore }
  /** Where transforms are read from (the plugin's Transform unless the host gave its own). */
  transforms: TransformSource
  /** Capacity of the entity-indexed stores. */
  capacity: number
  /** Cloths in creation order. */
  cloths: ClothState[]
  nextSeq: number
  /** Tracked transforms (pin targets, colliders), interpolated across steps and substeps. */
  kinematics: Kinematics
  /** Global substep index within the current fixed step, and how many there are. */
  substep: number
  substepCount: number
  stats: ClothStats
  /** Wind zones and air (see `src/wind.ts`). */
  wind: WindWorld
  /** Tear events and tearable-cloth bookkeeping (see `src/tearing.ts`). */
  tearing: TearWorld
  /** Explosion guard defaults, reset events and listeners. */
  guard: GuardWorld
  /** Colliders and self-collision (see `src/collision.ts`). */
  collision: CollisionWorld
  /** Sleep defaults and bookkeeping (see `src/sleep.ts`). */
  sleep: SleepWorld
  /** Quality targets and the world budget (see `src/budget.ts`). */
  quality: QualityWorld
}

/** Symbol under which the plugin keeps its state on a world. */
export const $cloth = Symbol.for('bitecs-cloth')

/** Returns the plugin state of a world; throws ClothError if the plugin is not installed. */
export function getClothWorld(world: object): ClothWorldState {
  const state = (world as { [$cloth]?: ClothWorldState })[$cloth]
  if (!state) throw new ClothError('world', world, 'has no cloth plugin installed (call installClothPlugin first)')
  return state
}

/** Returns the plugin state of a world, or undefined. */
export function findClothWorld(world: object): ClothWorldState | undefined {
  return (world as { [$cloth]?: ClothWorldState })[$cloth]
}

export function createStats(): ClothStats {
  return {
    steps: 0,
    substeps: 0,
    particlesIntegrated: 0,
    distanceProjections: 0,
    dihedralProjections: 0,
    lineProjections: 0,
    tetherProjections: 0,
    pinUpdates: 0,
    tetherRebuilds: 0,
    teleports: 0,
    windTriangles: 0,
    strainChecks: 0,
    colliderTests: 0,
    selfCollisionTests: 0,
    tears: 0,
    guardChecks: 0,
    guardResets: 0,
    sleepingSteps: 0,
    wakes: 0,
    lodSkippedSteps: 0,
  }
}

/**
 * The local substep a cloth runs during global substep `s` of `total`, or −1. A cloth with n ≤
 * total substeps runs on n of them, spread evenly, so cloths with different substep counts stay
 * aligned in time (which matters once cloths collide with each other).
 */
export function localSubstep(n: number, s: number, total: number): number {
  const a = Math.floor((s * n) / total)
  const b = Math.floor(((s + 1) * n) / total)
  return b > a ? a : -1
}
