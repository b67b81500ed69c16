import type { ClothStats } from './state'

/** Work counters, all zero. */
export function createStats(): ClothStats {
  return {
    steps: 0,
    substeps: 0,
    particlesIntegrated: 0,
    distanceProjections: 0,
    dihedralProjections: 0,
    lineProjections: 0,
    tetherProjections: 0,
    pinUpdates: 0,
    tetherRebuilds: 0,
    teleports: 0,
    windTriangles: 0,
    strainChecks: 0,
    colliderTests: 0,
    selfCollisionTests: 0,
    tears: 0,
    guardChecks: 0,
    guardResets: 0,
    sleepingSteps: 0,
    wakes: 0,
    lodSkippedSteps: 0,
  }
}

/** Number of counters in `ClothStats` (the order of `addStats` and `takeStats`). */
export const STAT_COUNT = 20

/**
 * Adds counters kept as doubles at from[o..o + STAT_COUNT) (a worker's, see `takeStats`). Each
 * field by name: a store through a computed key would box every double it writes.
 */
export function addStats(stats: ClothStats, from: Float64Array, o: number): void {
  stats.steps += from[o + 0]
  stats.substeps += from[o + 1]
  stats.particlesIntegrated += from[o + 2]
  stats.distanceProjections += from[o + 3]
  stats.dihedralProjections += from[o + 4]
  stats.lineProjections += from[o + 5]
  stats.tetherProjections += from[o + 6]
  stats.pinUpdates += from[o + 7]
  stats.tetherRebuilds += from[o + 8]
  stats.teleports += from[o + 9]
  stats.windTriangles += from[o + 10]
  stats.strainChecks += from[o + 11]
  stats.colliderTests += from[o + 12]
  stats.selfCollisionTests += from[o + 13]
  stats.tears += from[o + 14]
  stats.guardChecks += from[o + 15]
  stats.guardResets += from[o + 16]
  stats.sleepingSteps += from[o + 17]
  stats.wakes += from[o + 18]
  stats.lodSkippedSteps += from[o + 19]
}

/** Moves the counters into to[o..o + STAT_COUNT) and zeroes them (a worker, after its step). */
export function takeStats(stats: ClothStats, to: Float64Array, o: number): void {
  to[o + 0] = stats.steps
  stats.steps = 0
  to[o + 1] = stats.substeps
  stats.substeps = 0
  to[o + 2] = stats.particlesIntegrated
  stats.particlesIntegrated = 0
  to[o + 3] = stats.distanceProjections
  stats.distanceProjections = 0
  to[o + 4] = stats.dihedralProjections
  stats.dihedralProjections = 0
  to[o + 5] = stats.lineProjections
  stats.lineProjections = 0
  to[o + 6] = stats.tetherProjections
  stats.tetherProjections = 0
  to[o + 7] = stats.pinUpdates
  stats.pinUpdates = 0
  to[o + 8] = stats.tetherRebuilds
  stats.tetherRebuilds = 0
  to[o + 9] = stats.teleports
  stats.teleports = 0
  to[o + 10] = stats.windTriangles
  stats.windTriangles = 0
  to[o + 11] = stats.strainChecks
  stats.strainChecks = 0
  to[o + 12] = stats.colliderTests
  stats.colliderTests = 0
  to[o + 13] = stats.selfCollisionTests
  stats.selfCollisionTests = 0
  to[o + 14] = stats.tears
  stats.tears = 0
  to[o + 15] = stats.guardChecks
  stats.guardChecks = 0
  to[o + 16] = stats.guardResets
  stats.guardResets = 0
  to[o + 17] = stats.sleepingSteps
  stats.sleepingSteps = 0
  to[o + 18] = stats.wakes
  stats.wakes = 0
  to[o + 19] = stats.lodSkippedSteps
  stats.lodSkippedSteps = 0
}

/**
 * The local substep a cloth runs during global substep `s` of `total`, or −1. A cloth with n ≤
 * total substeps runs on n of them, spread evenly, so cloths with different substep counts stay
 * aligned in time (which matters once cloths collide with each other).
 */
export function localSubstep(n: number, s: number, total: number): number {
  const a = Math.floor((s * n) / total)
  const b = Math.floor(((s + 1) * n) / total)
  return b > a ? a : -1
}
