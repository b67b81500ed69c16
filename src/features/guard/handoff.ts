import type { ClothState } from '../../world/state'

/** The guard section of a cloth's per-step handoff (see `src/threads/handoff.ts`): settings and counters. */
export const GUARD_HANDOFF = 9

export function writeGuardHandoff(c: ClothState, io: Float64Array, o: number): void {
  const g = c.guard
  const s = g.settings
  io[o] = s.enabled ? 1 : 0
  io[o + 1] = s.finite ? 1 : 0
  io[o + 2] = s.bounds === false ? -1 : s.bounds
  io[o + 3] = s.speed === false ? -1 : s.speed
  io[o + 4] = s.snapshotInterval
  io[o + 5] = g.size
  io[o + 6] = g.safeCount
  io[o + 7] = g.sinceSafe
  io[o + 8] = g.failStreak
}

export function readGuardHandoff(io: Float64Array, o: number, c: ClothState): void {
  const g = c.guard
  const s = g.settings
  s.enabled = io[o] === 1
  s.finite = io[o + 1] === 1
  s.bounds = io[o + 2] < 0 ? false : io[o + 2]
  s.speed = io[o + 3] < 0 ? false : io[o + 3]
  s.snapshotInterval = io[o + 4]
  g.size = io[o + 5]
  g.safeCount = io[o + 6]
  g.sinceSafe = io[o + 7]
  g.failStreak = io[o + 8]
}
