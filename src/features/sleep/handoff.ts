import type { ClothState } from '../../world/state'

/** The sleep section of a cloth's per-step handoff (see `src/threads/handoff.ts`). */
export const SLEEP_HANDOFF = 5

export function writeSleepHandoff(c: ClothState, io: Float64Array, o: number): void {
  const s = c.sleep
  io[o] = s.asleep ? 1 : 0
  io[o + 1] = s.enabled ? 1 : 0
  io[o + 2] = s.speed2
  io[o + 3] = s.delay
  io[o + 4] = s.still
}

export function readSleepHandoff(io: Float64Array, o: number, c: ClothState): void {
  const s = c.sleep
  s.asleep = io[o] === 1
  s.enabled = io[o + 1] === 1
  s.speed2 = io[o + 2]
  s.delay = io[o + 3]
  s.still = io[o + 4]
}
