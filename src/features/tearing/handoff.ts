import type { ClothState } from '../../world/state'

/** The tearing section of a cloth's per-step handoff (see `src/threads/handoff.ts`): capacities and the counts a tear changes. */
export const TEAR_HANDOFF = 19

export function writeTearHandoff(c: ClothState, io: Float64Array, o: number): void {
  const T = c.tear
  if (T === null) return
  io[o] = T.enabled ? 1 : 0
  io[o + 1] = T.particleCapacity
  io[o + 2] = T.stretch.count
  io[o + 3] = T.stretch.cap
  io[o + 4] = T.edges.count
  io[o + 5] = T.edges.cap
  io[o + 6] = T.dist.count
  io[o + 7] = T.dist.cap
  io[o + 8] = T.comp.count
  io[o + 9] = T.comp.cap
  io[o + 10] = T.lines.count
  io[o + 11] = T.hinges.count
  io[o + 12] = T.tethers.count
  io[o + 13] = T.scratch.kCap
  io[o + 14] = T.stepCount
  io[o + 15] = T.grewAt
  io[o + 16] = T.fanCount
  io[o + 17] = T.chainCount
  io[o + 18] = T.stamp
}

export function readTearHandoff(io: Float64Array, o: number, c: ClothState): void {
  const T = c.tear
  if (T === null) return
  T.enabled = io[o] === 1
  T.particleCapacity = io[o + 1]
  T.stretch.count = io[o + 2]
  T.stretch.cap = io[o + 3]
  T.edges.count = io[o + 4]
  T.edges.cap = io[o + 5]
  T.dist.count = io[o + 6]
  T.dist.cap = io[o + 7]
  T.comp.count = io[o + 8]
  T.comp.cap = io[o + 9]
  T.lines.count = io[o + 10]
  T.hinges.count = io[o + 11]
  T.tethers.count = io[o + 12]
  T.scratch.kCap = io[o + 13]
  T.stepCount = io[o + 14]
  T.grewAt = io[o + 15]
  T.fanCount = io[o + 16]
  T.chainCount = io[o + 17]
  T.stamp = io[o + 18]
}
