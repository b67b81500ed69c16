import { allFinite, fit64 } from '../../core/arrays'
import { ClothError } from '../../core/errors'
import type { ClothState, ClothWorldState } from '../../world/state'

/** The sleep section of a snapshot. */
export interface SleepSnapshot {
  /** Asleep (1/0), stillness timer, bounds it sleeps in (6). Absent: awake. */
  sleep?: Float64Array
}

export function saveSleep(c: ClothState, s: SleepSnapshot): void {
  const sl = (s.sleep = fit64(s.sleep, 8))
  sl[0] = c.sleep.asleep ? 1 : 0
  sl[1] = c.sleep.still
  for (let j = 0; j < 6; j++) sl[2 + j] = c.sleep.bounds[j]
}

export function checkSleep(s: SleepSnapshot, arg: string): void {
  if (s.sleep !== undefined && (!(s.sleep instanceof Float64Array) || s.sleep.length !== 8 || !allFinite(s.sleep))) {
    throw new ClothError(arg, s, 'holds a non-finite number')
  }
}

export function restoreSleep(state: ClothWorldState, c: ClothState, s: SleepSnapshot): void {
  const sl = s.sleep
  const asleep = sl !== undefined && sl[0] === 1
  const sleep = c.sleep
  if (asleep !== sleep.asleep) {
    sleep.asleep = asleep
    state.sleep.count += asleep ? 1 : -1
  }
  sleep.still = sl !== undefined ? sl[1] : 0
  if (sl !== undefined) { for (let j = 0; j < 6; j++) sleep.bounds[j] = sl[2 + j] }
}
