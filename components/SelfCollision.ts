/**
 * Marks a cloth entity whose particles keep apart from each other (self-collision) and from the
 * particles of other cloths that have it too. Structure of arrays indexed by the cloth entity;
 * add it with `enableSelfCollision`, remove it with `disableSelfCollision` (or removeComponent).
 * The spatial hash and pair lists live in the cloth's collision state.
 */
export interface SelfCollisionStore {
  /** Smallest distance between two particles, m. */
  thickness: Float64Array
  /** Kinetic friction between touching particles (cloth–cloth). */
  friction: Float64Array
  /** Static friction between touching particles. */
  staticFriction: Float64Array
}

/** Allocates a SelfCollision store for `capacity` entity ids. Called by `installClothPlugin`. */
export function createSelfCollisionStore(capacity: number): SelfCollisionStore {
  return {
    thickness: new Float64Array(capacity),
    friction: new Float64Array(capacity),
    staticFriction: new Float64Array(capacity),
  }
}
