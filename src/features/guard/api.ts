/**
 * Explosion guard. After every fixed step each cloth gets a cheap health check (one pass over its
 * particles, see `kernels/guard.ts`): finite numbers, particles within reach of their pins, no
 * runaway internal speed. A cloth that fails is put back into a safe pose at once: its last good
 * pose (copied every `snapshotInterval` steps), moved rigidly onto where its pins are now, or, when
 * that pose failed too, its rest shape placed the same way. Its velocities are cleared and a reset
 * event is raised (`onClothReset`, `drainClothResets`, `getClothStats().guardResets`). So NaN never
 * reaches `getClothMesh`, and a broken cloth recovers in the same frame instead of flying apart.
 */
import { ClothError, checkBoolean, checkInteger, checkPositive, checkKeys, keysOf } from '../../core/errors'
import { G_FINITE, G_REACH, G_SPEED2, GUARD_PARAM_COUNT, PIECE_STRIDE, clearGuardAnchor } from '../../kernels/guard'
import type { ClothTopology } from '../../model/topology'
import { grownArray } from '../../core/store'
import { getCloth, getClothWorld, getClothWorldForChange } from '../../world/access'
import type { ClothState } from '../../world/state'
import { restSize } from './size'
import {
  EVENT_CAPACITY,
  REASONS,
  type ClothGuardOptions,
  type ClothGuardState,
  type ClothResetEvent,
  type GuardSettings,
  type GuardWorld,
} from './types'
import { newArray, arrayOf } from '../../core/shared'

export function defaultGuardSettings(maxSpeed: number): GuardSettings {
  return { enabled: true, finite: true, bounds: 2, speed: 0.5 * maxSpeed, snapshotInterval: 1 }
}

const GUARD_KEYS = keysOf<ClothGuardOptions>({ enabled: true, finite: true, bounds: true, speed: true, snapshotInterval: true })

/** Merges user options over `base`, validating them. */
export function resolveGuardOptions(o: unknown, base: GuardSettings, arg: string): GuardSettings {
  const out = { ...base }
  if (o === undefined || o === true) return o === true ? { ...out, enabled: true } : out
  if (o === false) return { ...out, enabled: false }
  if (typeof o !== 'object' || o === null) throw new ClothError(arg, o, 'must be a boolean or guard options')
  const g = o as ClothGuardOptions
  checkKeys(arg, g, GUARD_KEYS)
  if (g.enabled !== undefined) out.enabled = checkBoolean(`${arg}.enabled`, g.enabled)
  if (g.finite !== undefined) out.finite = checkBoolean(`${arg}.finite`, g.finite)
  if (g.bounds !== undefined) out.bounds = g.bounds === false ? false : checkPositive(`${arg}.bounds`, g.bounds)
  if (g.speed !== undefined) out.speed = g.speed === false ? false : checkPositive(`${arg}.speed`, g.speed)
  if (g.snapshotInterval !== undefined) out.snapshotInterval = checkInteger(`${arg}.snapshotInterval`, g.snapshotInterval, 1, 1_000_000)
  return out
}

export function createGuardWorld(defaults: GuardSettings): GuardWorld {
  return {
    defaults,
    listeners: [],
    evCloth: new Int32Array(EVENT_CAPACITY),
    evReason: new Uint8Array(EVENT_CAPACITY),
    evStep: new Float64Array(EVENT_CAPACITY),
    evParticle: new Int32Array(EVENT_CAPACITY),
    evRest: new Uint8Array(EVENT_CAPACITY),
    evHead: 0,
    evCount: 0,
    raised: 0,
    event: { cloth: 0, reason: 'nonfinite', step: 0, particle: 0, restoredTo: 'snapshot' },
  }
}

/** The guard state of a new cloth; `pos` is its initial pose. */
export function createClothGuard(topology: ClothTopology, pos: Float64Array, settings: GuardSettings): ClothGuardState {
  const g: ClothGuardState = {
    settings,
    params: clearGuardAnchor(newArray(Float64Array, GUARD_PARAM_COUNT)),
    size: restSize(topology),
    safe: arrayOf(Float64Array, pos),
    safeCount: topology.particleCount,
    rest: arrayOf(Float64Array, pos),
    pieceBox: newArray(Float64Array, topology.pieces === null ? 0 : PIECE_STRIDE * topology.pieceCount),
    sinceSafe: 0,
    failStreak: 0,
  }
  applyGuardSettings(g)
  return g
}

/**
 * Grows the guard's per-particle copies to a capacity of `P` particles (a tearable cloth reserves
 * room for the particles its tears add), so keeping a torn cloth's pose allocates nothing.
 */
export function reserveGuard(c: ClothState, P: number): void {
  const g = c.guard
  g.rest = grownArray(g.rest, 3 * P)
  g.safe = grownArray(g.safe, 3 * P)
  if (g.pieceBox.length < PIECE_STRIDE * P) g.pieceBox = newArray(Float64Array, PIECE_STRIDE * P)
}

/**
 * A particle split off `from` (a tear) gets `from`'s rest pose: the guard's fallback after a
 * failed reset puts a torn cloth back in its rest layout, every piece in place.
 */
export function copyGuardParticle(c: ClothState, from: number, to: number): void {
  const rest = c.guard.rest
  rest[3 * to] = rest[3 * from]
  rest[3 * to + 1] = rest[3 * from + 1]
  rest[3 * to + 2] = rest[3 * from + 2]
}

/** Writes the settings into the kernel's threshold block. */
export function applyGuardSettings(g: ClothGuardState): void {
  const s = g.settings
  const p = g.params
  p[G_FINITE] = s.enabled && s.finite ? 1 : 0
  // a cloth of size 0 (all particles on one point) still gets a little room
  p[G_REACH] = s.enabled && s.bounds !== false ? s.bounds * Math.max(g.size, 1e-3) : 0
  p[G_SPEED2] = s.enabled && s.speed !== false ? s.speed * s.speed : 0
}

/** True when the guard has any test to run for this cloth. */
export function guardActive(g: ClothGuardState): boolean {
  const p = g.params
  return p[G_FINITE] !== 0 || p[G_REACH] !== 0 || p[G_SPEED2] !== 0
}

/**
 * Calls `listener` after every guard reset, at the end of the fixed step in which it happened
 * (after all cloths were checked). The event object is reused between calls: copy the fields you
 * keep. Do not step the world from a listener. Returns a function that removes the listener.
 *
 * @example
 * const off = onClothReset(world, (e) => console.warn(`cloth ${e.cloth} reset: ${e.reason}`))
 */
export function onClothReset(world: object, listener: (event: ClothResetEvent) => void): () => void {
  const w = getClothWorld(world).guard
  if (typeof listener !== 'function') throw new ClothError('listener', listener, 'must be a function')
  w.listeners.push(listener)
  return () => {
    const i = w.listeners.indexOf(listener)
    if (i >= 0) w.listeners.splice(i, 1)
  }
}

/**
 * The guard resets since the last call (at most the latest 64; `getClothStats().guardResets`
 * counts all), oldest first, as new objects; the queue is emptied.
 */
export function drainClothResets(world: object): ClothResetEvent[] {
  const w = getClothWorld(world).guard
  const out: ClothResetEvent[] = []
  for (let k = 0; k < w.evCount; k++) {
    const slot = (w.evHead + k) % EVENT_CAPACITY
    if (w.evCloth[slot] < 0) continue // its cloth was removed (see forgetResetEvents)
    out.push({
      cloth: w.evCloth[slot],
      reason: REASONS[w.evReason[slot]],
      step: w.evStep[slot],
      particle: w.evParticle[slot],
      restoredTo: w.evRest[slot] === 1 ? 'rest' : 'snapshot',
    })
  }
  w.evHead = 0
  w.evCount = 0
  return out
}

/**
 * Called when a cloth is removed: its reset events not yet delivered (to the listeners of the
 * current step, or to `drainClothResets`) are dropped, since its id may soon name another cloth.
 */
export function forgetResetEvents(w: GuardWorld, cloth: number): void {
  for (let k = 0; k < w.evCount; k++) {
    const slot = (w.evHead + k) % EVENT_CAPACITY
    if (w.evCloth[slot] === cloth) w.evCloth[slot] = -1
  }
}

/** Changes a cloth's guard settings (over its current ones); `false` turns its guard off. */
export function setClothGuard(world: object, cloth: number, options: boolean | ClothGuardOptions): void {
  const c = getCloth(getClothWorldForChange(world), cloth)
  if (typeof options !== 'boolean' && (typeof options !== 'object' || options === null)) {
    throw new ClothError('options', options, 'must be a boolean or guard options')
  }
  c.guard.settings = resolveGuardOptions(options, c.guard.settings, 'options')
  applyGuardSettings(c.guard)
}

/** A cloth's guard settings and its size (the reach unit of `bounds`), resolved. */
export function getClothGuard(world: object, cloth: number): Readonly<GuardSettings> & { size: number } {
  const g = getCloth(getClothWorld(world), cloth).guard
  return { ...g.settings, size: g.size }
}
