/**
 * Explosion guard. After every fixed step each cloth gets a cheap health check (one pass over its
 * particles, see `kernels/guard.ts`): finite numbers, particles within reach of their pins, no
 * runaway internal speed. A cloth that fails is put back into a safe pose at once: its last good
 * pose (copied every `snapshotInterval` steps), moved rigidly onto where its pins are now, or, when
 * that pose failed too, its rest shape placed the same way. Its velocities are cleared and a reset
 * event is raised (`onClothReset`, `drainClothResets`, `getClothStats().guardResets`). So NaN never
 * reaches `getClothMesh`, and a broken cloth recovers in the same frame instead of flying apart.
 */
import { ClothError, checkInteger, checkPositive } from './errors'
import {
  checkClothHealth,
  checkPieceHealth,
  G_FINITE,
  G_REACH,
  G_SPEED2,
  GUARD_PARAM_COUNT,
  HEALTH_NONFINITE,
  HEALTH_SPEED,
} from './kernels/guard'
import { getCloth, placePins } from './pins'
import { getClothWorld, type ClothState, type ClothWorldState } from './state'
import { SL_STILL } from './sleep'
import type { ClothTopology } from './topology'

/** Guard settings, per world (defaults for new cloths) or per cloth. */
export interface ClothGuardOptions {
  /** Master switch. Default true. */
  enabled?: boolean
  /** Reset a cloth whose positions or velocities are NaN or infinite. Default true. */
  finite?: boolean
  /**
   * Reset a cloth with a particle farther than `bounds` × its size from the box around its pinned
   * particles (a cloth without pins: wider than `bounds` × its size). The size is the longest
   * shortest path along the cloth's edges at rest. Default 2 (every edge at twice its length);
   * false turns the test off.
   */
  bounds?: number | false
  /**
   * Reset a cloth whose rms particle speed relative to its mean velocity exceeds this, m/s.
   * Default: half the world's `maxSpeed` (125 m/s). false turns the test off.
   */
  speed?: number | false
  /** Steps between copies of the last good pose (1 = every step, the default). */
  snapshotInterval?: number
}

/** Why the guard reset a cloth. */
export type ClothResetReason = 'nonfinite' | 'bounds' | 'speed'

/** One guard reset. */
export interface ClothResetEvent {
  /** The cloth entity. */
  cloth: number
  reason: ClothResetReason
  /** The world's step counter (`getClothStats(world).steps`) when it happened. */
  step: number
  /** The first non-finite particle, the one farthest out of bounds, or the fastest one. */
  particle: number
  /** 'snapshot': the last good pose was restored; 'rest': the rest shape (the snapshot failed too). */
  restoredTo: 'snapshot' | 'rest'
}

/** Resolved guard settings. */
export interface GuardSettings {
  enabled: boolean
  finite: boolean
  bounds: number | false
  speed: number | false
  snapshotInterval: number
}

/** Guard state of one cloth (allocated with the cloth). */
export interface ClothGuardState {
  settings: GuardSettings
  /** Thresholds for the check kernel (see `kernels/guard.ts`). */
  params: Float64Array
  /** Longest shortest path along the cloth's edges at rest, m. */
  size: number
  /** Positions at the last good step, and how many particles they cover. */
  safe: Float64Array
  safeCount: number
  /** Positions at creation (the rest shape as placed in the world; torn-off particles added as they appear). */
  rest: Float64Array
  /** Good steps since the last copy into `safe`. */
  sinceSafe: number
  /** Consecutive failed checks (0 after a good step). */
  failStreak: number
}

/** Per-world guard state. */
export interface GuardWorld {
  defaults: GuardSettings
  listeners: ((event: ClothResetEvent) => void)[]
  /** The last `EVENT_CAPACITY` resets, a ring buffer of plain fields. */
  evCloth: Int32Array
  evReason: Uint8Array
  evStep: Float64Array
  evParticle: Int32Array
  evRest: Uint8Array
  /** Ring start and fill. */
  evHead: number
  evCount: number
  /** Resets raised during the current guard phase (delivered to listeners at its end). */
  raised: number
  /** The object handed to listeners (reused: copy what you keep). */
  event: ClothResetEvent
}

export const EVENT_CAPACITY = 64
const REASONS: readonly ClothResetReason[] = ['nonfinite', 'nonfinite', 'bounds', 'speed']

// ---------------------------------------------------------------------------------------------
// Options

export function defaultGuardSettings(maxSpeed: number): GuardSettings {
  return { enabled: true, finite: true, bounds: 2, speed: 0.5 * maxSpeed, snapshotInterval: 1 }
}

/** Merges user options over `base`, validating them. */
export function resolveGuardOptions(o: unknown, base: GuardSettings, arg: string): GuardSettings {
  const out = { ...base }
  if (o === undefined || o === true) return o === true ? { ...out, enabled: true } : out
  if (o === false) return { ...out, enabled: false }
  if (typeof o !== 'object' || o === null) throw new ClothError(arg, o, 'must be a boolean or guard options')
  const g = o as ClothGuardOptions
  if (g.enabled !== undefined) out.enabled = checkBoolean(`${arg}.enabled`, g.enabled)
  if (g.finite !== undefined) out.finite = checkBoolean(`${arg}.finite`, g.finite)
  if (g.bounds !== undefined) out.bounds = g.bounds === false ? false : checkPositive(`${arg}.bounds`, g.bounds)
  if (g.speed !== undefined) out.speed = g.speed === false ? false : checkPositive(`${arg}.speed`, g.speed)
  if (g.snapshotInterval !== undefined) out.snapshotInterval = checkInteger(`${arg}.snapshotInterval`, g.snapshotInterval, 1, 1_000_000)
  return out
}

function checkBoolean(arg: string, v: unknown): boolean {
  if (typeof v !== 'boolean') throw new ClothError(arg, v, 'must be true or false')
  return v
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
    params: new Float64Array(GUARD_PARAM_COUNT),
    size: restSize(topology),
    safe: Float64Array.from(pos),
    safeCount: topology.particleCount,
    rest: Float64Array.from(pos),
    sinceSafe: 0,
    failStreak: 0,
  }
  applyGuardSettings(g)
  return g
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
 * Longest shortest path along the edges of the rest shape (the geodesic diameter), estimated by a
 * double sweep of Dijkstra per connected piece: from any particle to the farthest one, then from
 * there. Exact on grids and convex sheets; never less than half the true value.
 */
export function restSize(t: ClothTopology): number {
  const n = t.particleCount
  if (n === 0 || t.edgeCount === 0) return 0
  const start = new Int32Array(n + 1)
  for (let e = 0; e < t.edgeCount; e++) {
    start[t.edges[2 * e] + 1]++
    start[t.edges[2 * e + 1] + 1]++
  }
  for (let i = 0; i < n; i++) start[i + 1] += start[i]
  const adj = new Int32Array(start[n])
  const adjLen = new Float64Array(start[n])
  const fill = start.slice(0, n)
  for (let e = 0; e < t.edgeCount; e++) {
    const a = t.edges[2 * e], b = t.edges[2 * e + 1], L = t.edgeRest[e]
    adj[fill[a]] = b
    adjLen[fill[a]++] = L
    adj[fill[b]] = a
    adjLen[fill[b]++] = L
  }
  const dist = new Float64Array(n)
  const seen = new Uint8Array(n)
  const heap = new DistHeap(start[n] + n)
  let size = 0
  for (let s = 0; s < n; s++) {
    if (seen[s]) continue
    const far = sweep(s, n, start, adj, adjLen, dist, heap, seen)
    const d = dist[far]
    const back = sweep(far, n, start, adj, adjLen, dist, heap, null)
    size = Math.max(size, d, dist[back])
  }
  return size
}

/** Dijkstra from `s`; returns the farthest reached particle (distances left in `dist`). */
function sweep(
  s: number, n: number, start: Int32Array, adj: Int32Array, adjLen: Float64Array,
  dist: Float64Array, heap: DistHeap, seen: Uint8Array | null,
): number {
  dist.fill(Infinity)
  dist[s] = 0
  heap.clear()
  heap.push(0, s)
  let far = s
  while (heap.size > 0) {
    const d = heap.topKey()
    const i = heap.pop()
    if (d > dist[i]) continue
    if (seen) seen[i] = 1
    if (d > dist[far]) far = i
    for (let k = start[i]; k < start[i + 1]; k++) {
      const j = adj[k]
      const nd = d + adjLen[k]
      if (nd < dist[j]) {
        dist[j] = nd
        heap.push(nd, j)
      }
    }
  }
  return far
}

class DistHeap {
  keys: Float64Array
  vals: Int32Array
  size = 0
  constructor(capacity: number) {
    this.keys = new Float64Array(capacity)
    this.vals = new Int32Array(capacity)
  }
  clear(): void {
    this.size = 0
  }
  topKey(): number {
    return this.keys[0]
  }
  push(key: number, val: number): void {
    if (this.size === this.keys.length) {
      const k = new Float64Array(2 * this.size), v = new Int32Array(2 * this.size)
      k.set(this.keys)
      v.set(this.vals)
      this.keys = k
      this.vals = v
    }
    let i = this.size++
    while (i > 0) {
      const p = (i - 1) >> 1
      if (this.keys[p] <= key) break
      this.keys[i] = this.keys[p]
      this.vals[i] = this.vals[p]
      i = p
    }
    this.keys[i] = key
    this.vals[i] = val
  }
  pop(): number {
    const top = this.vals[0]
    const n = --this.size
    const key = this.keys[n], val = this.vals[n]
    let i = 0
    for (;;) {
      let c = 2 * i + 1
      if (c >= n) break
      if (c + 1 < n && this.keys[c + 1] < this.keys[c]) c++
      if (this.keys[c] >= key) break
      this.keys[i] = this.keys[c]
      this.vals[i] = this.vals[c]
      i = c
    }
    this.keys[i] = key
    this.vals[i] = val
    return top
  }
}

// ---------------------------------------------------------------------------------------------
// Per step (called by the guard phase)

/**
 * The health check of one cloth (a HEALTH_* code): one pass over its particles. A tearable cloth
 * in several pieces has its bounds measured per piece (`checkPieceHealth`): a piece torn off may
 * fall away from the pins it no longer hangs from, but must keep its own shape.
 */
export function checkGuardHealth(c: ClothState): number {
  const T = c.tear
  if (T !== null && T.pieceCount > 1) return checkPieceHealth(c.pos, c.vel, c.invMass, c.count, T.piece, T.pieceCount, T.pieceBox, c.guard.params)
  return checkClothHealth(c.pos, c.vel, c.invMass, c.count, c.guard.params)
}

/** A good step: count it and copy the pose when the snapshot interval is due. */
export function keepSafePose(c: ClothState): void {
  const g = c.guard
  g.failStreak = 0
  if (++g.sinceSafe < g.settings.snapshotInterval) return
  g.sinceSafe = 0
  if (g.safe.length !== c.pos.length) g.safe = new Float64Array(c.pos.length) // the cloth grew (tearing)
  g.safe.set(c.pos)
  g.safeCount = c.count
}

// scratch for the rigid fit: S (9), N (16), q (4), centroids (6), matrix product (16)
const fit = new Float64Array(56)
const F_S = 0, F_N = 9, F_Q = 25, F_CS = 29, F_CT = 32, F_M = 35

/**
 * Puts a failed cloth into a safe pose and raises the event. `reason` is a HEALTH_* code.
 * The pose (the last good one, or the rest shape when the last good one failed too) is moved
 * rigidly so that its pinned particles best match where the pins hold them now (least squares,
 * Horn's quaternion method), velocities are cleared, pinned particles keep their exact places.
 */
export function resetCloth(state: ClothWorldState, c: ClothState, reason: number): void {
  const g = c.guard
  const particle = findOffender(c, reason)
  const useRest = g.failStreak > 0 || g.safeCount !== c.count
  const src = useRest ? g.rest : g.safe
  const srcCount = useRest ? c.count : g.safeCount
  g.failStreak++
  placeRigidly(state, c, src, srcCount)
  g.sinceSafe = 0
  c.version++
  state.stats.guardResets++
  c.sleep[SL_STILL] = 0 // a cloth that keeps failing is not at rest, however still it is after each reset

  const w = state.guard
  const slot = (w.evHead + w.evCount) % EVENT_CAPACITY
  if (w.evCount < EVENT_CAPACITY) w.evCount++
  else w.evHead = (w.evHead + 1) % EVENT_CAPACITY
  w.evCloth[slot] = c.eid
  w.evReason[slot] = reason
  w.evStep[slot] = state.stats.steps
  w.evParticle[slot] = particle
  w.evRest[slot] = useRest ? 1 : 0
  if (w.raised < EVENT_CAPACITY) w.raised++
}

/** Calls the reset listeners for the resets of this guard phase, oldest first. */
export function deliverResets(state: ClothWorldState): void {
  const w = state.guard
  const raised = w.raised
  w.raised = 0
  if (raised === 0 || w.listeners.length === 0) return
  const e = w.event
  for (let k = raised; k > 0; k--) {
    const slot = (w.evHead + w.evCount - k) % EVENT_CAPACITY
    for (let l = 0; l < w.listeners.length; l++) {
      e.cloth = w.evCloth[slot]
      e.reason = REASONS[w.evReason[slot]]
      e.step = w.evStep[slot]
      e.particle = w.evParticle[slot]
      e.restoredTo = w.evRest[slot] === 1 ? 'rest' : 'snapshot'
      w.listeners[l](e)
    }
  }
}

function findOffender(c: ClothState, reason: number): number {
  const pos = c.pos, vel = c.vel
  if (reason === HEALTH_NONFINITE) {
    for (let i = 0; i < c.count; i++) {
      const j = 3 * i
      if (!Number.isFinite(pos[j] + pos[j + 1] + pos[j + 2] + vel[j] + vel[j + 1] + vel[j + 2])) return i
    }
    return -1
  }
  // bounds: farthest from the centroid of the pinned particles (or of the cloth); speed: fastest
  let cx = 0, cy = 0, cz = 0, m = 0
  for (let i = 0; i < c.count; i++) {
    if (reason === HEALTH_SPEED || (c.invMass[i] === 0) === (c.pins.length > 0)) {
      const j = 3 * i
      cx += reason === HEALTH_SPEED ? vel[j] : pos[j]
      cy += reason === HEALTH_SPEED ? vel[j + 1] : pos[j + 1]
      cz += reason === HEALTH_SPEED ? vel[j + 2] : pos[j + 2]
      m++
    }
  }
  if (m > 0) {
    cx /= m
    cy /= m
    cz /= m
  }
  const a = reason === HEALTH_SPEED ? vel : pos
  let best = -1, bestD = -1
  for (let i = 0; i < c.count; i++) {
    const j = 3 * i
    const d = (a[j] - cx) ** 2 + (a[j + 1] - cy) ** 2 + (a[j + 2] - cz) ** 2
    if (d > bestD) {
      bestD = d
      best = i
    }
  }
  return best
}

/**
 * pos ← R·(src − c_src) + c_now for every particle, with R, c_src, c_now fitted to the pinned
 * particles (their current positions are the targets); prev ← pos, vel ← 0.
 */
function placeRigidly(state: ClothWorldState, c: ClothState, src: Float64Array, srcCount: number): void {
  const P = state.components.Pin
  const pos = c.pos
  // where the pins hold their particles at the end of this step (a NaN may have reached pinned
  // particles too: 0 × NaN is NaN in the constraint updates): as on the last substep, blends as
  // they stand
  placePins(state, c, c.substeps - 1, c.substeps, false)
  const f = fit
  for (let k = 0; k < fit.length; k++) f[k] = 0
  let n = 0
  for (let q = 0; q < c.pins.length; q++) {
    const i = P.particle[c.pins[q]]
    if (i >= srcCount) continue
    const j = 3 * i
    f[F_CS] += src[j]
    f[F_CS + 1] += src[j + 1]
    f[F_CS + 2] += src[j + 2]
    f[F_CT] += pos[j]
    f[F_CT + 1] += pos[j + 1]
    f[F_CT + 2] += pos[j + 2]
    n++
  }
  f[F_Q + 3] = 1
  if (n > 0) {
    for (let k = 0; k < 3; k++) {
      f[F_CS + k] /= n
      f[F_CT + k] /= n
    }
    // cross-covariance S_ab = Σ (s − c_s)_a (t − c_t)_b
    for (let q = 0; q < c.pins.length; q++) {
      const i = P.particle[c.pins[q]]
      if (i >= srcCount) continue
      const j = 3 * i
      for (let a = 0; a < 3; a++) {
        const s = src[j + a] - f[F_CS + a]
        for (let b = 0; b < 3; b++) f[F_S + 3 * a + b] += s * (pos[j + b] - f[F_CT + b])
      }
    }
    hornRotation(f)
  }
  // (nothing pins the cloth: identity and c_src = c_now = 0, the pose goes back where it was)
  const qx = f[F_Q], qy = f[F_Q + 1], qz = f[F_Q + 2], qw = f[F_Q + 3]
  const csx = f[F_CS], csy = f[F_CS + 1], csz = f[F_CS + 2]
  const ctx = n > 0 ? f[F_CT] : csx, cty = n > 0 ? f[F_CT + 1] : csy, ctz = n > 0 ? f[F_CT + 2] : csz
  const prev = c.prev, vel = c.vel
  let mx = 0, my = 0, mz = 0
  for (let i = 0; i < c.count; i++) {
    const j = 3 * i
    vel[j] = 0
    vel[j + 1] = 0
    vel[j + 2] = 0
    if (i >= srcCount) continue
    if (c.pinCount[i] === 0) {
      const vx = src[j] - csx, vy = src[j + 1] - csy, vz = src[j + 2] - csz
      const tx = 2 * (qy * vz - qz * vy), ty = 2 * (qz * vx - qx * vz), tz = 2 * (qx * vy - qy * vx)
      pos[j] = ctx + vx + qw * tx + (qy * tz - qz * ty)
      pos[j + 1] = cty + vy + qw * ty + (qz * tx - qx * tz)
      pos[j + 2] = ctz + vz + qw * tz + (qx * ty - qy * tx)
    }
    mx += pos[j]
    my += pos[j + 1]
    mz += pos[j + 2]
  }
  // particles the copy does not cover (added by tearing since): kept if finite, else put on the
  // centroid of the restored ones
  const m = Math.min(srcCount, c.count)
  if (m > 0) {
    mx /= m
    my /= m
    mz /= m
  }
  for (let i = srcCount; i < c.count; i++) {
    const j = 3 * i
    if (c.pinCount[i] === 0 && !Number.isFinite(pos[j] + pos[j + 1] + pos[j + 2])) {
      pos[j] = mx
      pos[j + 1] = my
      pos[j + 2] = mz
    }
  }
  for (let j = 0; j < 3 * c.count; j++) prev[j] = pos[j]
}

/**
 * The rotation q (x, y, z, w into f[F_Q..]) that best maps the centred source points onto the
 * centred targets, from the cross-covariance S in f[F_S..]: the eigenvector of Horn's symmetric
 * 4×4 matrix with the largest eigenvalue, by shifted power iteration from the identity (so an
 * undetermined rotation, e.g. one pin, stays the identity).
 */
function hornRotation(f: Float64Array): void {
  const sxx = f[F_S], sxy = f[F_S + 1], sxz = f[F_S + 2]
  const syx = f[F_S + 3], syy = f[F_S + 4], syz = f[F_S + 5]
  const szx = f[F_S + 6], szy = f[F_S + 7], szz = f[F_S + 8]
  // order (w, x, y, z)
  const N = F_N
  f[N] = sxx + syy + szz
  f[N + 1] = syz - szy
  f[N + 2] = szx - sxz
  f[N + 3] = sxy - syx
  f[N + 5] = sxx - syy - szz
  f[N + 6] = sxy + syx
  f[N + 7] = szx + sxz
  f[N + 10] = -sxx + syy - szz
  f[N + 11] = syz + szy
  f[N + 15] = -sxx - syy + szz
  f[N + 4] = f[N + 1]
  f[N + 8] = f[N + 2]
  f[N + 12] = f[N + 3]
  f[N + 9] = f[N + 6]
  f[N + 13] = f[N + 7]
  f[N + 14] = f[N + 11]
  let shift = 0
  for (let k = 0; k < 9; k++) shift += Math.abs(f[F_S + k])
  if (!(shift > 0) || !Number.isFinite(shift)) return
  for (let k = 0; k < 4; k++) f[N + 5 * k] += shift // all eigenvalues ≥ 0 now
  // (N + shift)^(2^48), rescaled each time, is a multiple of the projector onto the top eigenspace
  const M = F_M
  for (let it = 0; it < 48; it++) {
    let big = 0
    for (let r = 0; r < 4; r++) {
      for (let col = 0; col < 4; col++) {
        let v = 0
        for (let k = 0; k < 4; k++) v += f[N + 4 * r + k] * f[N + 4 * k + col]
        f[M + 4 * r + col] = v
        if (Math.abs(v) > big) big = Math.abs(v)
      }
    }
    if (!(big > 0) || !Number.isFinite(big)) return
    for (let k = 0; k < 16; k++) f[N + k] = f[M + k] / big
  }
  // project the identity (column 0); if the best rotation is a half turn away from it, the
  // identity has no component there: take the strongest column instead
  let best = 0, bestL = 0, l0 = 0
  for (let col = 0; col < 4; col++) {
    const l = f[N + col] ** 2 + f[N + 4 + col] ** 2 + f[N + 8 + col] ** 2 + f[N + 12 + col] ** 2
    if (col === 0) l0 = l
    if (l > bestL) {
      best = col
      bestL = l
    }
  }
  if (l0 > 1e-12 * bestL) {
    best = 0
    bestL = l0
  }
  if (!(bestL > 0)) return
  const inv = 1 / Math.sqrt(bestL)
  const w = f[N + best] * inv, x = f[N + 4 + best] * inv, y = f[N + 8 + best] * inv, z = f[N + 12 + best] * inv
  f[F_Q] = x
  f[F_Q + 1] = y
  f[F_Q + 2] = z
  f[F_Q + 3] = w
}

// ---------------------------------------------------------------------------------------------
// Public API

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

/** Changes a cloth's guard settings (over its current ones); `false` turns its guard off. */
export function setClothGuard(world: object, cloth: number, options: boolean | ClothGuardOptions): void {
  const c = getCloth(getClothWorld(world), cloth)
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
