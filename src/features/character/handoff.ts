import type { ClothState } from '../../world/state'

/**
 * The character section of a cloth's per-step handoff (see `src/threads/handoff.ts`): the plain
 * numbers the step reads. Its arrays (settings, the frame's motion and this step's poses and bone
 * matrices computed by the sync phase, the reference pose, limits, drive, held particles, skin) are
 * in shared memory; which of them the cloth holds (none without character state, a skin, a drive)
 * is its layout. A tear on a worker can hold a split particle (`heldCount`); the API changes the
 * rest between steps. The frame entity and its slot stay on the main thread (only the sync phase
 * reads them, and a removed entity clears them while the workers may be stepping).
 */
export const CHARACTER_HANDOFF = 3

export function writeCharacterHandoff(c: ClothState, io: Float64Array, o: number): void {
  const ch = c.character
  if (ch === null) return
  io[o] = ch.inertia ? 1 : 0
  io[o + 1] = ch.constrained ? 1 : 0
  io[o + 2] = ch.heldCount
}

export function readCharacterHandoff(io: Float64Array, o: number, c: ClothState): void {
  const ch = c.character
  if (ch === null) return
  ch.inertia = io[o] === 1
  ch.constrained = io[o + 1] === 1
  ch.heldCount = io[o + 2]
}
