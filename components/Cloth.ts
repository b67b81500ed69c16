import type { ClothState } from '../src/state'

/**
 * Marks a cloth entity. Its particle state (positions, previous positions, velocities, inverse
 * masses in flat typed arrays) and its shared rest data live in one `ClothState` per cloth;
 * particles are indices into those arrays, not entities. Create cloths with `createCloth` or
 * `createClothFromMesh`, and read them with `getClothState` / `getClothMesh`.
 */
export interface ClothStore {
  /** Per-entity cloth state (undefined for entities without the component). */
  state: (ClothState | undefined)[]
}

/** Creates the Cloth component store. Called by `installClothPlugin`. */
export function createClothStore(): ClothStore {
  return { state: [] }
}
