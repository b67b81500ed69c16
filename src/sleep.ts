import { ClothError, checkNonNegative, checkPositive } from './errors'
import { clothLayersMatch, colliderLayersMatch, colliderReaches } from './collision'
import { P_MAX_V2 } from './kernels/params'
import { particleBounds } from './kernels/mesh'
import { getCloth } from './pins'
import { getClothWorld, type ClothState, type ClothWorldState } from './state'
import { windReaches } from './wind'

/**
 * Sleeping. A cloth whose particles all stayed slower than a threshold for a while (default
 * 1 cm/s for 1 s) falls asleep: its velocities are zeroed and every phase skips it, so it costs a
 * few checks per step instead of a simulation. It wakes, at the start of a step, when
 * - a pin target of it moves or jumps;
 * - a collider whose layers match moves (or appears, or goes away) within reach of its bounds;
 * - a wind zone reaches its bounds (a cloth in the wind never falls asleep either);
 * - a self-colliding cloth it can collide with comes within reach;
 * - the world's gravity changes;
 * - the API changes it (pins, teleport, quality, tethers, collision settings, tearing, self-collision,
 *   a restored snapshot) or `wakeCloth` is called (after editing its arrays directly).
 */

/** Options of `setClothSleep` and of the plugin's `sleep` option. */
export interface ClothSleepOptions {
  /** Whether the cloth may fall asleep. Default true. */
  enabled?: boolean
  /** Speed every particle must stay below, m/s. Default 0.01. */
  speed?: number
  /** How long the cloth must stay that slow before it sleeps, s. Default 1. */
  delay?: number
}

/** Slots of `ClothState.sleep`. */
export const SL_STILL = 0
export const SL_SPEED2 = 1
export const SL_DELAY = 2
export const SL_ENABLED = 3
export const SLEEP_SLOTS = 4

/** Resolved sleep settings (world defaults). */
export interface SleepSettings {
  enabled: boolean
  speed: number
  delay: number
}

/** Per-world sleep bookkeeping (`ClothWorldState.sleep`). */
export interface SleepWorld {
  /** Settings new cloths start with. */
  defaults: SleepSettings
  /** Cloths asleep now. */
  count: number
  /** Gravity when the last cloth fell asleep (a change wakes every sleeper). */
  gravity: Float64Array
}

export const DEFAULT_SLEEP: Readonly<SleepSettings> = { enabled: true, speed: 0.01, delay: 1 }

/** Resolves the plugin's `sleep` option (boolean or options) into settings. */
export function resolveSleepOptions(o: boolean | ClothSleepOptions | undefined, base: SleepSettings, arg: string): SleepSettings {
  if (o === undefined) return { ...base }
  if (typeof o === 'boolean') return { ...base, enabled: o }
  if (typeof o !== 'object' || o === null) throw new ClothError(arg, o, 'must be a boolean or { enabled?, speed?, delay? }')
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

/** A cloth's sleep block from settings. */
export function createClothSleep(s: SleepSettings): Float64Array {
  const b = new Float64Array(SLEEP_SLOTS)
  writeSettings(b, s)
  return b
}

function writeSettings(b: Float64Array, s: SleepSettings): void {
  b[SL_SPEED2] = s.speed * s.speed
  b[SL_DELAY] = s.delay
  b[SL_ENABLED] = s.enabled ? 1 : 0
}

/**
 * Sets whether and when a cloth may sleep (`true`/`false`, or options: left-out ones keep their
 * values). Turning it off wakes the cloth.
 *
 * @example setClothSleep(world, flag, false) // a flag that must keep fluttering in still air
 */
export function setClothSleep(world: object, cloth: number, options: boolean | ClothSleepOptions): void {
  const state = getClothWorld(world)
  const c = getCloth(state, cloth)
  const b = c.sleep
  const now: SleepSettings = { enabled: b[SL_ENABLED] === 1, speed: Math.sqrt(b[SL_SPEED2]), delay: b[SL_DELAY] }
  const s = resolveSleepOptions(options, now, 'options')
  writeSettings(b, s)
  wakeClothState(state, c)
}

/** Wakes a sleeping cloth (call it after writing a cloth's arrays directly). */
export function wakeCloth(world: object, cloth: number): void {
  const state = getClothWorld(world)
  wakeClothState(state, getCloth(state, cloth))
}

/** Whether the cloth is asleep. */
export function isClothSleeping(world: object, cloth: number): boolean {
  const state = getClothWorld(world)
  return getCloth(state, cloth).sleeping
}

/** Wakes `c` (if asleep) and restarts its stillness timer. Used by every API call that changes a cloth. */
export function wakeClothState(state: ClothWorldState, c: ClothState): void {
  c.sleep[SL_STILL] = 0
  if (!c.sleeping) return
  c.sleeping = false
  state.sleep.count--
  state.stats.wakes++
}

/**
 * Writeback phase, after a cloth's last substep: advances its stillness timer from the fastest
 * particle of the substep (`params[P_MAX_V2]`) and puts it to sleep once it was still long enough.
 */
export function updateSleep(state: ClothWorldState, c: ClothState): void {
  const s = c.sleep
  if (s[SL_ENABLED] === 0) return
  if (!(c.params[P_MAX_V2] <= s[SL_SPEED2])) {
    s[SL_STILL] = 0
    return
  }
  s[SL_STILL] += c.h * c.substeps // the cloth's step (longer when it steps every n-th)
  if (s[SL_STILL] < s[SL_DELAY]) return
  s[SL_STILL] = 0
  // the box it would sleep in (what the wake tests look at)
  particleBounds(c.pos, c.count, c.sleepBounds, 0)
  // still in a steady wind: the wind may change any time, so stay awake (and test again after
  // another delay)
  if (state.wind.zones.length > 0 && windReaches(state, c.sleepBounds)) return
  c.sleeping = true
  state.sleep.count++
  c.vel.fill(0, 0, 3 * c.count)
  const g = state.gravity
  state.sleep.gravity[0] = g[0]
  state.sleep.gravity[1] = g[1]
  state.sleep.gravity[2] = g[2]
}

/**
 * Sync phase, after the transforms, collider sweeps and wind zones of the step are known: wakes
 * every sleeping cloth that something now disturbs. Nothing to do (one comparison) while no cloth
 * sleeps.
 */
export function wakeSleepers(state: ClothWorldState): void {
  const sw = state.sleep
  if (sw.count === 0) return
  const cloths = state.cloths
  const g = state.gravity, sg = sw.gravity
  const gravityChanged = g[0] !== sg[0] || g[1] !== sg[1] || g[2] !== sg[2]
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    if (c.sleeping && (gravityChanged || disturbed(state, c))) wakeClothState(state, c)
  }
}

function disturbed(state: ClothWorldState, c: ClothState): boolean {
  const k = state.kinematics
  const P = state.components.Pin
  const pins = c.pins
  for (let q = 0; q < pins.length; q++) {
    const pin = pins[q]
    const slot = P.slot[pin]
    if ((slot >= 0 && k.moved[slot] === 1) || P.blendLeft[pin] > 0) return true
  }
  const b = c.sleepBounds
  const cw = state.collision
  const colliders = cw.colliders
  if (colliders.length > 0) {
    const C = cw.Collider
    const cc = c.collision!
    for (let q = 0; q < colliders.length; q++) {
      const e = colliders[q]
      if (k.moved[C.slot[e]] === 1 && colliderLayersMatch(C, e, cc) && colliderReaches(C, e, b, c)) return true
    }
  }
  if (state.wind.zones.length > 0 && windReaches(state, b)) return true
  const self = c.collision!.self
  if (self !== null) {
    const group = cw.selfCloths
    const ca = c.collision!
    for (let q = 0; q < group.length; q++) {
      const o = group[q]
      if (o === c || o.sleeping || o.lod.frozen) continue
      const cb = o.collision!
      if (!clothLayersMatch(ca, cb)) continue
      const ob = cb.bounds
      const D = self.thickness + cb.self!.thickness
      if (ob[0] > b[3] + D || b[0] > ob[3] + D || ob[1] > b[4] + D || b[1] > ob[4] + D || ob[2] > b[5] + D || b[2] > ob[5] + D) continue
      return true
    }
  }
  return false
}

/**
 * Wakes the sleeping cloths whose bounds collider `e`'s last swept bounds reach: called when a
 * collider appears (after its first sweep) or goes away (a cloth resting on it must fall).
 */
export function wakeAroundCollider(state: ClothWorldState, e: number): void {
  if (state.sleep.count === 0) return
  const C = state.collision.Collider
  const cloths = state.cloths
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    if (c.sleeping && colliderLayersMatch(C, e, c.collision!) && colliderReaches(C, e, c.sleepBounds, c)) wakeClothState(state, c)
  }
}
