import type { ClothState } from '../../world/state'

/** The grab section of a cloth's per-step handoff (see `src/threads/handoff.ts`): how many grabs it has (their data is shared). */
export const GRAB_HANDOFF = 1

export function writeGrabHandoff(c: ClothState, io: Float64Array, o: number): void {
  io[o] = c.grab.count
}

export function readGrabHandoff(io: Float64Array, o: number, c: ClothState): void {
  c.grab.count = io[o]
}
