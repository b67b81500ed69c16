import type { ClothState } from '../../world/state'

/** The wind section of a cloth's per-step handoff (see `src/threads/handoff.ts`). */
export const WIND_HANDOFF = 1

export function writeWindHandoff(c: ClothState, io: Float64Array, o: number): void {
  io[o] = c.wind !== null ? c.wind.active : 0
}

export function readWindHandoff(io: Float64Array, o: number, c: ClothState): void {
  if (c.wind !== null) c.wind.active = io[o]
}
