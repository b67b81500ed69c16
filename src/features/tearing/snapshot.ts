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
}

export function saveTearing(state: ClothWorldState, c: ClothState, s: TearSnapshot): void {
  const T = c.tear
  const edges = T === null ? 0 : T.edges.count
  const ntt = T === null ? 0 : T.tethers.count
  s.tear = fit64(s.tear, T === null ? 0 : 3)
  s.tearOver = fit8(s.tearOver, edges)
  s.tearTethers = fit32(s.tearTethers, 2 * ntt)
  s.tearTetherRest = fit64(s.tearTetherRest, ntt)
  if (T === null) return
  s.tear[0] = state.components.Tearable.tears[c.eid]
  s.tear[1] = meshFingerprint(c)
  s.tear[2] = c.count
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
