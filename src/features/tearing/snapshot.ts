import { allFinite, fit32, fit64, fit8 } from '../../core/arrays'
import { ClothError } from '../../core/errors'
import type { ClothState, ClothWorldState } from '../../world/state'

/**
 * The tearing section of a snapshot: counters and tethers. The torn mesh itself is not copied: a
 * tearable cloth restores only while it still has the mesh it was saved with.
 */
export interface TearSnapshot {
  /** Tearable cloths: tears so far, mesh fingerprint, particle count (empty for other cloths). */
  tear: Float64Array
  /** Tearable cloths: the mesh edges' over-threshold step counters. */
  tearOver: Uint8Array
  /** Tearable cloths: their tethers (particle, anchor per tether; rest lengths), rebuilt in place as they tear. */
  tearTethers: Int32Array
  tearTetherRest: Float64Array
  /**
   * Tearable cloths: the tear clock, [steps run, the step a crack last grew] (empty for other
   * cloths), which decides whether a new crack may start. Absent in older snapshots (the three
   * fields come together): the cloth's own clock is kept.
   */
  tearClock?: Float64Array
  /** Tearable cloths, per particle: 1 at a crack's tip. */
  tearTip?: Uint8Array
  /** Tearable cloths, per particle: the tear step it last split in (on the clock of `tearClock`). */
  tearSplitAt?: Int32Array
}

/** Latest tear step a clock may hold (`splitAt` stamps are int32). */
const MAX_TEAR_STEP = 0x7fffffff

export function saveTearing(state: ClothWorldState, c: ClothState, s: TearSnapshot): void {
  const T = c.tear
  const edges = T === null ? 0 : T.edges.count
  const ntt = T === null ? 0 : T.tethers.count
  s.tear = fit64(s.tear, T === null ? 0 : 3)
  s.tearOver = fit8(s.tearOver, edges)
  s.tearTethers = fit32(s.tearTethers, 2 * ntt)
  s.tearTetherRest = fit64(s.tearTetherRest, ntt)
  const n = T === null ? 0 : c.count
  s.tearClock = fit64(s.tearClock, T === null ? 0 : 2)
  s.tearTip = fit8(s.tearTip, n)
  s.tearSplitAt = fit32(s.tearSplitAt, n)
  if (T === null) return
  s.tear[0] = state.components.Tearable.tears[c.eid]
  s.tear[1] = meshFingerprint(c)
  s.tear[2] = c.count
  s.tearClock[0] = T.stepCount
  s.tearClock[1] = T.grewAt
  for (let i = 0; i < n; i++) {
    s.tearTip[i] = T.tip[i]
    s.tearSplitAt[i] = T.splitAt[i]
  }
  for (let e = 0; e < edges; e++) s.tearOver[e] = T.over[e]
  for (let q = 0; q < ntt; q++) {
    s.tearTethers[2 * q] = T.tethers.particle[q]
    s.tearTethers[2 * q + 1] = T.tethers.anchor[q]
    s.tearTetherRest[q] = T.tethers.rest[q]
  }
}

/** Throws ClothError unless the tearing section is complete, finite and within `n` particles. */
export function checkTearing(s: TearSnapshot, arg: string, n: number): void {
  if (
    !(s.tear instanceof Float64Array) || (s.tear.length !== 0 && s.tear.length !== 3) || !(s.tearOver instanceof Uint8Array) ||
    !(s.tearTethers instanceof Int32Array) || !(s.tearTetherRest instanceof Float64Array) ||
    s.tearTethers.length !== 2 * s.tearTetherRest.length
  ) {
    throw new ClothError(arg, s, 'is not a complete snapshot (collider, wind or tearing state missing)')
  }
  if (!allFinite(s.tear) || !allFinite(s.tearTetherRest)) throw new ClothError(arg, s, 'holds a non-finite number')
  for (let q = 0; q < s.tearTethers.length; q++) {
    if (!(s.tearTethers[q] >= 0 && s.tearTethers[q] < n)) throw new ClothError(arg, s, 'holds a tether on a particle out of range')
  }
  checkTearClock(s, arg, n)
}

/** Throws ClothError unless the tear clock is absent (an older snapshot) or complete and consistent. */
function checkTearClock(s: TearSnapshot, arg: string, n: number): void {
  const clock = s.tearClock, tip = s.tearTip, splitAt = s.tearSplitAt
  if (clock === undefined && tip === undefined && splitAt === undefined) return
  const tearable = s.tear.length > 0
  if (
    !(clock instanceof Float64Array) || !(tip instanceof Uint8Array) || !(splitAt instanceof Int32Array) ||
    clock.length !== (tearable ? 2 : 0) || tip.length !== (tearable ? n : 0) || splitAt.length !== tip.length
  ) {
    throw new ClothError(arg, s, 'is not a complete snapshot (collider, wind or tearing state missing)')
  }
  if (!tearable) return
  const steps = clock[0], grewAt = clock[1]
  if (
    !(Number.isInteger(steps) && steps >= 0 && steps <= MAX_TEAR_STEP && Number.isInteger(grewAt) && grewAt >= -2 && grewAt <= steps)
  ) {
    throw new ClothError(
      `${arg}.tearClock`,
      clock,
      'must be the tear clock saved by saveClothState (steps ≥ 0, a crack grown at −2..steps)',
    )
  }
  for (let i = 0; i < n; i++) {
    if (tip[i] > 1) throw new ClothError(`${arg}.tearTip[${i}]`, tip[i], 'must be 0 or 1')
    if (!(splitAt[i] >= 0 && splitAt[i] <= steps)) {
      throw new ClothError(`${arg}.tearSplitAt[${i}]`, splitAt[i], `must be a tear step within 0..${steps} (the saved clock)`)
    }
  }
}

/** Throws ClothError unless the snapshot's tearing state fits this cloth (tearable both, same mesh). */
export function checkTearingFits(state: ClothWorldState, c: ClothState, s: TearSnapshot, arg: string): void {
  const T = c.tear
  if ((s.tear.length > 0) !== (T !== null)) {
    throw new ClothError(
      arg,
      s,
      T !== null ? 'was saved from a cloth that was not tearable, and this one is' : 'was saved from a tearable cloth, and this one is not',
    )
  }
  if (T === null) return
  if (s.tear[2] !== c.count || s.tear[1] !== meshFingerprint(c)) {
    const since = state.components.Tearable.tears[c.eid] - s.tear[0]
    throw new ClothError(
      arg,
      s,
      since > 0 && s.tear[2] < c.count
        ? `was saved before this cloth tore (${since} tear${
          since === 1 ? '' : 's'
        } since): a snapshot does not restore a torn mesh, only a tearable cloth whose mesh is still the one it was saved with`
        : "was saved from a tearable cloth whose mesh (torn differently) is not this one's: a snapshot does not restore a torn mesh",
    )
  }
  if (s.tearTetherRest.length > T.tethers.rest.length) throw new ClothError(arg, s, 'holds more tethers than this cloth has room for')
}

export function restoreTearing(state: ClothWorldState, c: ClothState, s: TearSnapshot): void {
  const T = c.tear
  if (T === null) return
  state.components.Tearable.tears[c.eid] = s.tear[0]
  for (let e = 0; e < s.tearOver.length; e++) T.over[e] = s.tearOver[e]
  const tt = T.tethers
  tt.count = s.tearTetherRest.length
  for (let q = 0; q < tt.count; q++) {
    tt.particle[q] = s.tearTethers[2 * q]
    tt.anchor[q] = s.tearTethers[2 * q + 1]
    tt.rest[q] = s.tearTetherRest[q]
  }
  if (c.tethers.enabled) c.tethers.set = tt
  // the clock decides whether a crack may start and which particles split this step already
  if (s.tearClock === undefined || s.tearTip === undefined || s.tearSplitAt === undefined) return
  T.stepCount = s.tearClock[0] | 0 // integers back as integers (see restoreCore)
  T.grewAt = s.tearClock[1] | 0
  for (let i = 0; i < s.tearTip.length; i++) {
    T.tip[i] = s.tearTip[i]
    T.splitAt[i] = s.tearSplitAt[i]
  }
}

/**
 * A 32-bit FNV-1a hash of a tearable cloth's current mesh: triangles and every constraint list (the
 * order included), which tearing rewrites. Equal fingerprints: the same torn mesh.
 */
function meshFingerprint(c: ClothState): number {
  const t = c.topology
  let h = 0x811c9dc5
  h = mix(h, c.count)
  h = mixAll(h, t.triangles, 3 * t.triangleCount)
  h = mixAll(h, t.edges, 2 * t.edgeCount)
  h = mixAll(h, t.stretchIds, 2 * t.stretchCount)
  h = mixAll(h, t.distOffsets, 2 * t.distCount)
  h = mixAll(h, t.compIds, 2 * t.compCount)
  h = mixAll(h, t.lineIds, 3 * t.lineCount)
  h = mixAll(h, t.hingeIds, 4 * t.hingeCount)
  return h
}

function mixAll(h: number, a: ArrayLike<number>, n: number): number {
  h = mix(h, n)
  for (let i = 0; i < n; i++) h = mix(h, a[i])
  return h
}

function mix(h: number, v: number): number {
  for (let b = 0; b < 4; b++) {
    h ^= (v >>> (8 * b)) & 0xff
    h = Math.imul(h, 0x01000193) >>> 0
  }
  return h
}
