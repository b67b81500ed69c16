import { ClothError, checkNonNegative, checkPositive, checkKeys, keysOf } from '../../core/errors'
import { getCloth, getClothWorld, getClothWorldForChange } from '../../world/access'
import type { ClothSleep, ClothSleepOptions, SleepSettings, SleepWorld } from '../../world/state'
import { wakeClothState } from '../../world/wake'
import { newArray } from '../../core/shared'

/**
 * Sleeping. A cloth whose particles all stayed slower than a threshold for a while (default
 * 1 cm/s for 1 s) falls asleep: its velocities are zeroed and every phase skips it, so it costs a
 * few checks per step instead of a simulation. It wakes, at the start of a step, when
 * - a pin target of it moves, jumps or is scaled;
 * - a collider whose layers match moves (or appears, or goes away, or its body is scaled) within
 *   reach of its bounds, or jumps (teleports) from or to a place within reach;
 * - a wind zone reaches its bounds (a cloth in the wind never falls asleep either);
 * - a self-colliding cloth it can collide with comes within reach;
 * - the world's gravity changes;
 * - the API changes it (pins, teleport, quality, tethers, collision settings, tearing, self-collision,
 *   a restored snapshot) or `wakeCloth` is called (after editing its arrays directly).
 */

export const DEFAULT_SLEEP: Readonly<SleepSettings> = { enabled: true, speed: 0.01, delay: 1 }

const SLEEP_KEYS = keysOf<ClothSleepOptions>({ enabled: true, speed: true, delay: true })

/** Resolves the plugin's `sleep` option (boolean or options) into settings. */
export function resolveSleepOptions(o: boolean | ClothSleepOptions | undefined, base: SleepSettings, arg: string): SleepSettings {
  if (o === undefined) return { ...base }
  if (typeof o === 'boolean') return { ...base, enabled: o }
  if (typeof o !== 'object' || o === null) throw new ClothError(arg, o, 'must be a boolean or { enabled?, speed?, delay? }')
  checkKeys(arg, o, SLEEP_KEYS)
  if (o.enabled !== undefined && typeof o.enabled !== 'boolean') throw new ClothError(`${arg}.enabled`, o.enabled, 'must be a boolean')
  const speed = o.speed === undefined ? base.speed : checkPositive(`${arg}.speed`, o.speed)
  const delay = o.delay === undefined ? base.delay : checkNonNegative(`${arg}.delay`, o.delay)
  if (!(speed < 1e3)) throw new ClothError(`${arg}.speed`, speed, 'must be below 1000 m/s')
  if (!(delay < 1e9)) throw new ClothError(`${arg}.delay`, delay, 'must be finite')
  return { enabled: o.enabled ?? base.enabled, speed, delay }
}

export function createSleepWorld(defaults: SleepSettings): SleepWorld {
  return { defaults, count: 0, gravity: new Float64Array(3) }
}

/** A cloth's sleep state from settings: awake. */
export function createClothSleep(s: SleepSettings): ClothSleep {
  const sleep: ClothSleep = { asleep: false, enabled: true, speed2: 0, delay: 0, still: 0, bounds: newArray(Float64Array, 6) }
  writeSettings(sleep, s)
  return sleep
}

function writeSettings(sleep: ClothSleep, s: SleepSettings): void {
  sleep.speed2 = s.speed * s.speed
  sleep.delay = s.delay
  sleep.enabled = s.enabled
}

/**
 * Sets whether and when a cloth may sleep (`true`/`false`, or options: left-out ones keep their
 * values). Turning it off wakes the cloth.
 *
 * @example setClothSleep(world, flag, false) // a flag that must keep fluttering in still air
 */
export function setClothSleep(world: object, cloth: number, options: boolean | ClothSleepOptions): void {
  const state = getClothWorldForChange(world)
  const c = getCloth(state, cloth)
  const sleep = c.sleep
  const now: SleepSettings = { enabled: sleep.enabled, speed: Math.sqrt(sleep.speed2), delay: sleep.delay }
  writeSettings(sleep, resolveSleepOptions(options, now, 'options'))
  wakeClothState(state, c)
}

/**
 * Wakes a sleeping cloth (call it after writing a cloth's arrays directly). It also marks the
 * cloth's render data stale, so `getClothMesh` and the render helpers show the written positions
 * at once, before the next step.
 */
export function wakeCloth(world: object, cloth: number): void {
  const state = getClothWorldForChange(world)
  const c = getCloth(state, cloth)
  c.version++
  wakeClothState(state, c)
}

/** Whether the cloth is asleep. */
export function isClothSleeping(world: object, cloth: number): boolean {
  const state = getClothWorld(world)
  return getCloth(state, cloth).sleep.asleep
}
