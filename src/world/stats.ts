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
