/**
 * Marks a cloth entity. Its particle state (positions, previous positions, velocities, inverse
 * masses in flat typed arrays) and its shared rest data live in one `ClothState` per cloth;
 * particles are indices into those arrays, not entities. Create cloths with `createCloth` or
 * `createClothFromMesh`, and read them with `getClothState` / `getClothMesh`.
 *
 * The store is generic in the state it holds so that it needs nothing from the library above it;
 * the plugin's world state types it as `ClothStore<ClothState>`.
 */
export interface ClothStore<State = object> {
  /** Per-entity cloth state (undefined for entities without the component). */
  state: (State | undefined)[]
}

/** Creates the Cloth component store. Called by `installClothPlugin`. */
export function createClothStore<State = object>(): ClothStore<State> {
  return { state: [] }
}
