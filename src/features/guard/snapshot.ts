import { allFinite, copyInto, fit64 } from '../../core/arrays'
import { ClothError } from '../../core/errors'
import type { ClothState } from '../../world/state'
import { applyGuardSettings } from './api'
import type { GuardSettings } from './types'
import { newArray } from '../../core/shared'

/** The explosion guard's section of a snapshot. */
export interface GuardSnapshot {
  /** The last good pose, and safeCount, sinceSafe, failStreak. */
  guardSafe: Float64Array
  guardCounters: Float64Array
  guardSettings: GuardSettings
}

export function saveGuard(c: ClothState, s: GuardSnapshot): void {
  const g = c.guard
  s.guardSafe = copyInto(s.guardSafe, g.safe, 3 * g.safeCount)
  s.guardCounters = fit64(s.guardCounters, 3)
  s.guardCounters[0] = g.safeCount
  s.guardCounters[1] = g.sinceSafe
  s.guardCounters[2] = g.failStreak
  s.guardSettings = s.guardSettings ?? { ...g.settings }
  copySettings(g.settings, s.guardSettings)
}

/** Throws ClothError unless the guard section is complete and its settings valid. */
export function checkGuard(s: GuardSnapshot, arg: string): void {
  if (!(s.guardSafe instanceof Float64Array) || !allFinite(s.guardSafe)) throw new ClothError(arg, s, 'holds a non-finite number')
  const g = s.guardSettings
  if (
    typeof g !== 'object' || g === null || typeof g.enabled !== 'boolean' || typeof g.finite !== 'boolean' ||
    !(g.bounds === false || (g.bounds > 0 && g.bounds < Infinity)) || !(g.speed === false || (g.speed > 0 && g.speed < Infinity)) ||
    !Number.isInteger(g.snapshotInterval) || g.snapshotInterval < 1
  ) {
    throw new ClothError(`${arg}.guardSettings`, g, 'must be guard settings as saved by saveClothState')
  }
}

export function restoreGuard(c: ClothState, s: GuardSnapshot): void {
  const g = c.guard
  if (g.safe.length < s.guardSafe.length) g.safe = newArray(Float64Array, c.pos.length)
  g.safe.set(s.guardSafe)
  g.safeCount = s.guardCounters[0] | 0
  g.sinceSafe = s.guardCounters[1] | 0
  g.failStreak = s.guardCounters[2] | 0
  copySettings(s.guardSettings, g.settings)
  applyGuardSettings(g)
}

function copySettings(from: GuardSettings, to: GuardSettings): void {
  to.enabled = from.enabled
  to.finite = from.finite
  to.bounds = from.bounds
  to.speed = from.speed
  to.snapshotInterval = from.snapshotInterval
}
