import type { ClothState, ClothWorldState } from './state'

/**
 * Wakes `c` (if asleep) and restarts its stillness timer. Every API call that changes a cloth calls
 * it, whatever feature it belongs to; the sleep feature decides when a cloth falls asleep.
 */
export function wakeClothState(state: ClothWorldState, c: ClothState): void {
  const s = c.sleep
  s.still = 0
  if (!s.asleep) return
  s.asleep = false
  state.sleep.count--
  state.stats.wakes++
}
