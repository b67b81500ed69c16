import { ClothError } from '../core/errors'
import { $cloth, type ClothState, type ClothWorldState } from './state'

/** Returns the plugin state of a world; throws ClothError if the plugin is not installed. */
export function getClothWorld(world: object): ClothWorldState {
  const state = typeof world === 'object' && world !== null ? (world as { [$cloth]?: ClothWorldState })[$cloth] : undefined
  if (!state) throw new ClothError('world', world, 'must be a bitECS world with the cloth plugin installed (call installClothPlugin first)')
  return state
}

/** Returns the plugin state of a world, or undefined. */
export function findClothWorld(world: object): ClothWorldState | undefined {
  return (world as { [$cloth]?: ClothWorldState })[$cloth]
}

/** Looks up a cloth's state, or throws ClothError. */
export function getCloth(state: ClothWorldState, cloth: number): ClothState {
  const c = typeof cloth === 'number' ? state.components.Cloth.state[cloth] : undefined
  if (!c) throw new ClothError('cloth', cloth, 'must be a cloth entity of this world')
  return c
}

/**
 * Calls a step's listeners through `deliver` (a module-level function: nothing is allocated) with
 * the world marked as delivering: they may change the world but not step it.
 */
export function deliverToListeners(state: ClothWorldState, deliver: (state: ClothWorldState) => void): void {
  const f = state.frame
  const was = f.delivering
  f.delivering = true
  try {
    deliver(state)
  } finally {
    f.delivering = was
  }
}

/**
 * The plugin state of a world whose particles are about to be read (`what`, the reader); throws
 * ClothError between `beginClothStep` and `endClothStep`, while the step in flight moves them (in
 * every mode, as changes are refused). Between a fixed step's phases run by hand, the step is
 * the caller's own: allowed.
 */
export function getClothWorldForRead(world: object, what: string): ClothWorldState {
  const state = getClothWorld(world)
  refuseOpenFrame(state, world, `, where the step in flight moves the particles: call ${what} after endClothStep`)
  return state
}

/** A ClothError naming the world (its message: the frame, then `rest`) while a frame is open, outside the step's listeners. */
function refuseOpenFrame(state: ClothWorldState, world: object, rest: string): void {
  const f = state.frame
  if (f.open && !f.delivering) throw new ClothError('world', world, `is between beginClothStep and endClothStep${rest}`)
}

/**
 * The plugin state of a world about to be changed; throws ClothError between `beginClothStep` and
 * `endClothStep`, while the workers may be reading and writing the cloths (in every mode, so that a
 * game behaves the same with and without workers), and between a fixed step's `clothSync` and its
 * `clothGuard` (phases run by hand). Listeners the step calls may change the world.
 */
export function getClothWorldForChange(world: object): ClothWorldState {
  const state = getClothWorld(world)
  refuseOpenFrame(state, world, ': change cloths, pins, colliders and settings after endClothStep')
  const f = state.frame
  if (f.stepping && !f.delivering) {
    // (motion constraints switched on there ran against a reference the sync had not set up: 491 %
    // stretch; a pin made there took the target's pose at the step's end for its start)
    throw new ClothError(
      'world',
      world,
      'is inside a fixed step (between clothSync and clothGuard): change cloths, pins, colliders and settings before clothSync or after clothGuard',
    )
  }
  return state
}
