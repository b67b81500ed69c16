import { newArray } from '../src/core/shared'
/**
 * Marks a cloth entity as tearable: an edge that stays stretched beyond `strain` for `hysteresis`
 * consecutive steps breaks, and the mesh splits there. Structure of arrays indexed by the cloth's
 * entity id. Add it with `makeTearable` (which also reserves the cloth's capacity and gives it its
 * own copy of the rest data); the arrays of the split mesh live in the cloth's `ClothState.tear`.
 */
export interface TearableStore {
  /** Engineering strain at which an edge breaks (0.3 = 30 % longer than rest). */
  strain: Float64Array
  /** Most tears per cloth per fixed step. */
  maxTearsPerStep: Uint16Array
  /** Consecutive steps an edge must stay over the threshold before it breaks. */
  hysteresis: Uint8Array
  /** Smallest piece, in triangles, a tear may cut free (a split that would cut off less is not made). */
  minPiece: Uint16Array
  /** Tears so far (particles added by splits). */
  tears: Uint32Array
}

/** Allocates a Tearable store for `capacity` entity ids. Called by `installClothPlugin`. */
export function createTearableStore(capacity: number): TearableStore {
  return {
    strain: newArray(Float64Array, capacity),
    maxTearsPerStep: newArray(Uint16Array, capacity),
    hysteresis: newArray(Uint8Array, capacity),
    minPiece: newArray(Uint16Array, capacity),
    tears: newArray(Uint32Array, capacity),
  }
}
