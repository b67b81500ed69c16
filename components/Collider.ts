export { SHAPE_SPHERE, SHAPE_CAPSULE, SHAPE_BOX, SHAPE_HULL, SHAPE_PLANE, type ConvexHull } from '../src/core/shapes'
import type { ConvexHull } from '../src/core/shapes'
import { newArray } from '../src/core/shared'

/**
 * A collider: a rigid shape that pushes cloth particles out and applies friction. Structure of
 * arrays indexed by the collider's entity id.
 *
 * The collider's pose is the Transform of its `body` entity (the collider's own entity by default,
 * or another one: a character, a bone) composed with a local offset and rotation. An entity carries
 * one Collider; a character with several colliders uses one small entity per collider, each with
 * `body` = the character (see `addCapsuleCollider`).
 */
export interface ColliderStore {
  /** SHAPE_SPHERE, SHAPE_CAPSULE, SHAPE_BOX, SHAPE_HULL or SHAPE_PLANE. */
  shape: Uint8Array
  /** Entity whose Transform the collider follows. */
  body: Uint32Array
  /** The body's kinematic slot (see `src/kinematics.ts`). */
  slot: Int32Array
  /** Local offset in the body's frame (scaled by the body's scale), xyz per collider (stride 3), m. */
  offset: Float64Array
  /** Local rotation relative to the body, xyzw per collider (stride 4). */
  rotation: Float64Array
  /**
   * Shape dimensions (stride 4), m: sphere [radius]; capsule [radius, half-height] (axis = local y);
   * box [half-x, half-y, half-z]; plane [normal x, y, z (local, unit), distance along the normal].
   */
  size: Float64Array
  /** Local bounding sphere: centre xyz, radius (stride 4), m. */
  bound: Float64Array
  /**
   * How deep the shape's innermost point lies below its surface (sphere and capsule radius, box
   * smallest half-extent, hull inradius about its centroid; Infinity for planes), m. A particle
   * moving less than about half of this per substep cannot pass through; faster ones are swept.
   */
  depth: Float64Array
  /** Kinetic friction coefficient; < 0 means "use the cloth's". */
  friction: Float64Array
  /** Static friction coefficient; < 0 means "same as the kinetic one". */
  staticFriction: Float64Array
  /** Collision layer bits: the cloths whose mask has one of these bits collide with it. */
  layer: Uint32Array
  /** The cloth layers this collider collides with. */
  mask: Uint32Array
  /**
   * World bounds swept over the current fixed step (stride 8): min xyz, max xyz for solid shapes;
   * for planes the world normal and plane constant at the step's start (4) and end (4).
   */
  swept: Float64Array
  /**
   * The body's pose (7) and scale (3) at the step's end when `swept` was last computed, then 1 when
   * it was computed from a body at rest over its step (stride 11; 0 until then): a collider at rest
   * at that pose keeps its bounds (see `sweepColliders`).
   */
  sweptAt: Float64Array
  /**
   * Creation order: the collider's serial number, increasing along `CollisionWorld.entries` (a
   * removal finds its place there by binary search).
   */
  serial: Float64Array
  /**
   * The colliders following each body, as a list threaded through entity ids + 1 (0 ends it):
   * `firstOnBody[body]`, then `nextOnBody[collider]` (removing a body's Transform removes its
   * colliders without a pass over all of them).
   */
  firstOnBody: Uint32Array
  nextOnBody: Uint32Array
  /** Convex hull data of SHAPE_HULL colliders. */
  hulls: (ConvexHull | undefined)[]
}

/** Allocates a Collider store for `capacity` entity ids. Called by `installClothPlugin`. */
export function createColliderStore(capacity: number): ColliderStore {
  return {
    shape: newArray(Uint8Array, capacity),
    body: newArray(Uint32Array, capacity),
    slot: newArray(Int32Array, capacity),
    offset: newArray(Float64Array, 3 * capacity),
    rotation: newArray(Float64Array, 4 * capacity),
    size: newArray(Float64Array, 4 * capacity),
    bound: newArray(Float64Array, 4 * capacity),
    depth: newArray(Float64Array, capacity),
    friction: newArray(Float64Array, capacity),
    staticFriction: newArray(Float64Array, capacity),
    layer: newArray(Uint32Array, capacity),
    mask: newArray(Uint32Array, capacity),
    swept: newArray(Float64Array, 8 * capacity),
    sweptAt: newArray(Float64Array, 11 * capacity),
    serial: newArray(Float64Array, capacity),
    firstOnBody: newArray(Uint32Array, capacity),
    nextOnBody: newArray(Uint32Array, capacity),
    hulls: [],
  }
}
