import { allFinite, fit64 } from '../../core/arrays'
import { ClothError } from '../../core/errors'
import type { ClothState, ClothWorldState } from '../../world/state'

/** The sleep section of a snapshot. */
export interface SleepSnapshot {
  /**
   * Asleep (1/0), stillness timer, bounds it sleeps in (6), then the world's gravity when a cloth
   * last fell asleep (3) and the cloth's settings: enabled (1/0), squared speed, delay (absent in
   * older snapshots). Absent: awake.
   */
  sleep?: Float64Array
}

/** Values of the sleep section (older snapshots: the first 8). */
const SLEEP = 14

export function saveSleep(state: ClothWorldState, c: ClothState, s: SleepSnapshot): void {
  const sl = (s.sleep = fit64(s.sleep, SLEEP))
  const sleep = c.sleep
  sl[0] = sleep.asleep ? 1 : 0
  sl[1] = sleep.still
  for (let j = 0; j < 6; j++) sl[2 + j] = sleep.bounds[j]
  sl.set(state.sleep.gravity, 8)
  sl[11] = sleep.enabled ? 1 : 0
  sl[12] = sleep.speed2
  sl[13] = sleep.delay
}

export function checkSleep(s: SleepSnapshot, arg: string): void {
  const sl = s.sleep
  if (sl !== undefined && (!(sl instanceof Float64Array) || (sl.length !== 8 && sl.length !== SLEEP) || !allFinite(sl))) {
    throw new ClothError(arg, s, 'holds a non-finite number')
  }
  if (sl !== undefined && sl.length === SLEEP && !(sl[12] >= 0 && sl[12] < 1e6 && sl[13] >= 0 && sl[13] < 1e9)) {
    throw new ClothError(arg, s, 'holds sleep settings setClothSleep refuses')
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
  if (sl === undefined || sl.length < SLEEP) return
  // the gravity it fell asleep under (world state, like the frame timing: a fresh world's [0, 0, 0]
  // read as a change of gravity, and woke every restored sleeper at the first step)
  if (asleep) state.sleep.gravity.set(sl.subarray(8, 11))
  sleep.enabled = sl[11] === 1
  sleep.speed2 = sl[12]
  sleep.delay = sl[13]
}
