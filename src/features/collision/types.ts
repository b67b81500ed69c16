import type { ColliderStore } from '../../../components/Collider'
import type { SelfCollisionStore } from '../../../components/SelfCollision'

/**
 * Per-world collision state: the Collider and SelfCollision stores, colliders and self-colliding
 * cloths in creation order (the solver never iterates in query order), and scratch blocks for
 * the kernels. Lives on `ClothWorldState.collision`, as `CollisionWorld<ClothState>` (generic here
 * so that this file needs nothing from the world layer above it).
 */
export interface CollisionWorld<Cloth = unknown> {
  Collider: ColliderStore
  SelfCollision: SelfCollisionStore
  /**
   * Collider entities in creation order, with those released since the last read still in place
   * (`released` of them): read it through `liveColliders`.
   */
  entries: number[]
  released: number
  /** The next collider's serial number (`Collider.serial`). */
  serials: number
  /** Cloths with self-collision, in creation order. */
  selfCloths: Cloth[]
  /** Kernel frame block (see `kernels/collide.ts`). */
  frame: Float64Array
  /** Kernel scratch block. */
  scratch: Float64Array
  /** Pose scratch (4 poses of 7) and substep fractions. */
  poses: Float64Array
  fractions: Float64Array
  /** Per-cloth measurement scratch (see `measureCloth`). */
  measure: Float64Array
  /** Parameter block of the particle–particle kernels (see `kernels/selfCollide.ts`). */
  selfParams: Float64Array
  /** The cloth–cloth broadphase's scratch (see `buildSelfCollisionPairs`). */
  sweep: SelfSweep
}

/**
 * Scratch of the broadphase between self-colliding cloths (`kernels/sweep.ts`), by index in
 * `selfCloths`: their extents along x, their order along it (a permutation of 0..count−1, kept
 * between steps), the overlapping pairs and each cloth's partners. Grown when the group or the
 * pairs outgrow it.
 */
export interface SelfSweep {
  count: number
  lo: Float64Array
  hi: Float64Array
  order: Int32Array
  head: Int32Array
  pairs: Int32Array
  list: Int32Array
}

/** Collision settings and per-step state of one cloth (`ClothState.collision`). */
export interface ClothCollision {
  /** Layer bits of the cloth. */
  layer: number
  /** Collider layers (and other cloths' layers) the cloth collides with. */
  mask: number
  /** Thickness override, m; < 0 means the material's. */
  thickness: number
  /** Kinetic friction override; < 0 means the material's. */
  friction: number
  /** Static friction override; < 0 means the same as the kinetic one. */
  staticFriction: number
  /**
   * This step's bounds of the particles (min xyz, max xyz), grown by how far they can travel in
   * the step; then mean velocity xyz and largest deviation from it, m/s (for self-collision).
   */
  bounds: Float64Array
  /** Colliders in range this step (entity ids, creation order). */
  active: Int32Array
  activeCount: number
  /** Self-collision state while enabled. */
  self: SelfCollisionState | null
}

/** Slots of `ClothCollision.bounds` after the bounds (0-5). */
export const B_MEAN_V = 6
export const B_MAX_DEV = 9
/**
 * 1: an idle cloth (asleep, frozen) measures its bounds and builds its self-collision hash at its
 * next step anyway, then keeps them. Set when it falls asleep (its velocities just zeroed) and when
 * it is restored, so that a sleeper's bounds and hash come from its saved positions alone: kept from
 * its last awake step, a cloth restored asleep into a fresh world had none, and a self-colliding
 * neighbour went through it. (In the shared array: a worker reads it.)
 */
export const B_REFRESH = 10

/** Self-collision state of one cloth (allocated when it is enabled, never in a step). */
export interface SelfCollisionState {
  /** Collision distance between two particles, m. */
  thickness: number
  friction: number
  staticFriction: number
  /** Hash table: buckets mask + 1 (a power of two). */
  mask: number
  start: Int32Array
  /** Per-bucket stamp of the last query that scanned it (plus the running stamp at the end). */
  visited: Int32Array
  entries: Int32Array
  /** Particles in the hash (the cloth's, less vertices no triangle uses). */
  hashed: number
  bucket: Int32Array
  /** Positions in hash order (xyz), refreshed with the hash each step. */
  sorted: Float64Array
  /** Self pairs found this step (2 particle indices each). */
  pairs: Int32Array
  capacity: number
  pairCount: number
  /** Pairs with later cloths this step, in blocks: partner index in `selfCloths`, first pair, count. */
  cross: Int32Array
  crossCapacity: number
  crossCount: number
  blocks: Int32Array
  blockCount: number
  /**
   * Per step: [0] hash cell size, m; [1] travel per rebuild interval, m; [2] rebuild intervals this
   * step; [3] travel over the step, m.
   */
  values: Float64Array
  /** 1 for particles that touched a collider in the last substep (set by the collider kernels). */
  touched: Uint8Array
}
