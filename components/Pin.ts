import { newArray } from '../src/core/shared'
/**
 * A pin is an entity that holds one cloth particle at a point: on a target entity's Transform
 * (offset given in the target's local frame, so rotation and scale apply) or, with no target, at a
 * fixed world position. Structure of arrays indexed by the pin's entity id.
 */
export interface PinStore {
  /** Cloth entity the pinned particle belongs to. */
  cloth: Uint32Array
  /** Particle index in that cloth. */
  particle: Uint32Array
  /** Target entity, 0 = none (the offset is then a world position). */
  target: Uint32Array
  /** The target's kinematic slot (see `src/kinematics.ts`), −1 with no target. */
  slot: Int32Array
  /** Local offset x in the target frame (world x with no target), m. */
  ox: Float64Array
  /** Local offset y, m. */
  oy: Float64Array
  /** Local offset z, m. */
  oz: Float64Array
  /** Offset the pin blends from after pinning at a new offset, xyz per pin (stride 3), m. */
  blendFrom: Float64Array
  /** Blend time left, s (0 = at the offset). */
  blendLeft: Float64Array
  /** Total blend time, s. */
  blendTime: Float64Array
  /**
   * The target's pose when the pin was made, 10 per pin (position, rotation xyzw, scale; zero with
   * no target): where the cloth was attached to it, which a character reference bound later starts
   * from (features/character/frames.ts).
   */
  pose: Float64Array
}

/** Allocates a Pin store for `capacity` entity ids. Called by `installClothPlugin`. */
export function createPinStore(capacity: number): PinStore {
  return {
    cloth: newArray(Uint32Array, capacity),
    particle: newArray(Uint32Array, capacity),
    target: newArray(Uint32Array, capacity),
    slot: newArray(Int32Array, capacity),
    ox: newArray(Float64Array, capacity),
    oy: newArray(Float64Array, capacity),
    oz: newArray(Float64Array, capacity),
    blendFrom: newArray(Float64Array, 3 * capacity),
    blendLeft: newArray(Float64Array, capacity),
    blendTime: newArray(Float64Array, capacity),
    pose: newArray(Float64Array, 10 * capacity),
  }
}
