/**
 * Snapshots of a cloth's simulation state: everything the next step reads, so that restoring a
 * snapshot and stepping again reproduces the original run byte for byte (rollback netcode,
 * replays, "undo" in an editor, deterministic tests).
 *
 * A snapshot holds: particle positions, previous positions, velocities and inverse masses; the
 * pins (particle, target, offset, blend progress) in order; the motion history of the pins' target
 * entities (their frame samples and step poses, as interpolated between frames); the cloth's
 * quality and tether settings and its current tethers; its explosion-guard state (last good pose,
 * counters); whether it sleeps; and the world's step accumulator and frame timing. XPBD
 * multipliers are not saved: they start from zero every substep. With colliders and wind zones in
 * the world it also holds the motion history of the entities they follow, the wind clock and each
 * zone's gust and turbulence drift (world state, like the frame timing); for a tearable cloth its
 * tear counters and tethers; for a self-colliding one which particles rest on a collider.
 *
 * Not in a snapshot: the Transform of target entities (the host owns them: restore those too, or
 * the next frame sample sees where they are now), colliders and zones themselves and their settings
 * (added or removed since: not undone), and the rest data (the mesh), which must match. A torn
 * mesh is not restored either: a tearable cloth's snapshot restores only while the cloth still has
 * the mesh it was saved with (no tear since); otherwise restoring throws.
 */
import { entityExists, hasComponent, removeEntity } from 'bitecs'
import type { Kinematics } from './kinematics'
import { ClothError } from './errors'
import { applyGuardSettings, type GuardSettings } from './guard'
import { K_SINCE_SAMPLE, K_STEP_FRACTION } from './kinematics'
import { getCloth, pinParticle } from './pins'
import { getClothWorld, type ClothState, type ClothWorldState } from './state'
import type { TetherMode, TetherSet } from './tethers'
import { SL_STILL } from './sleep'

/** A saved cloth state (see `saveClothState`). Plain data: structured-clone it, keep it, reuse it. */
export interface ClothSnapshot {
  readonly format: 'bitecs-cloth-state/1'
  /** Shape of the cloth it came from: particles, distance constraints, hinges, triangles. */
  readonly shape: Int32Array
  pos: Float64Array
  prev: Float64Array
  vel: Float64Array
  invMass: Float64Array
  pinCount: Uint16Array
  /** Per pin, in order: entity, particle, target (0 = world point). */
  pins: Int32Array
  /** Per pin: ox, oy, oz, blendFrom xyz, blendLeft, blendTime. */
  pinData: Float64Array
  /** Distinct target entities of the pins. */
  targets: Int32Array
  /** Per target: sampleFrom, sampleTo, stepFrom, stepTo (7 each), jump (10), jumped, forceJump. */
  targetData: Float64Array
  /** substeps, iterations, h, damping, stretchDamping, useTethers, tetherSlack, tethersPerParticle, tethersDirty, skipTeleport. */
  settings: Float64Array
  tetherMode: TetherMode
  /** The cloth's tethers (immutable arrays, shared rather than copied). */
  tethers: TetherSet
  /** World: accumulator, time since the last frame sample, step fraction, newFrame, framed. */
  world: Float64Array
  /** Guard: last good pose, and safeCount, sinceSafe, failStreak. */
  guardSafe: Float64Array
  guardCounters: Float64Array
  guardSettings: GuardSettings
  /** Sleep: asleep (1/0), stillness timer, bounds it sleeps in (6). Absent: awake. */
  sleep?: Float64Array
  /** Entities the world's colliders and wind zones follow (distinct, creation order), and their motion history as in `targetData`. */
  bodies: Int32Array
  bodyData: Float64Array
  /** Wind zones, and the wind: clock, then per zone gustFrom, gustPeak, gustTime, gustDuration, gust, drift xyz. */
  windZones: Int32Array
  wind: Float64Array
  /** Tearable cloths: tears so far, mesh fingerprint, particle count (empty for other cloths). */
  tear: Float64Array
  /** Tearable cloths: the mesh edges' over-threshold step counters. */
  tearOver: Uint8Array
  /** Tearable cloths: their tethers (particle, anchor per tether; rest lengths), rebuilt in place as they tear. */
  tearTethers: Int32Array
  tearTetherRest: Float64Array
  /** Self-colliding cloths: particles that touched a collider in the last substep (empty otherwise). */
  touched: Uint8Array
}

const PIN_DATA = 8
const TARGET_DATA = 7 * 4 + 10 + 2

/**
 * Saves everything the next steps of `cloth` depend on. With `into` (an earlier snapshot of the
 * same cloth), its arrays are reused when the sizes still fit, so saving every frame allocates
 * nothing.
 *
 * @example
 * const saved = saveClothState(world, cape)
 * // ... step, the player rolls back ...
 * restoreClothState(world, cape, saved)
 */
export function saveClothState(world: object, cloth: number, into?: ClothSnapshot): ClothSnapshot {
  const state = getClothWorld(world)
  const c = getCloth(state, cloth)
  if (into !== undefined && (typeof into !== 'object' || into === null || into.format !== 'bitecs-cloth-state/1')) {
    throw new ClothError('into', into, 'must be a snapshot returned by saveClothState')
  }
  const n = c.count
  const P = state.components.Pin
  const k = state.kinematics
  const np = c.pins.length
  // distinct targets, in pin order
  let nt = 0
  for (let q = 0; q < np; q++) {
    const t = P.target[c.pins[q]]
    if (t !== 0 && firstTargetIndex(P, c.pins, q, t)) nt++
  }
  const s: ClothSnapshot = into ?? ({ format: 'bitecs-cloth-state/1' } as ClothSnapshot)
  const w = s as { -readonly [K in keyof ClothSnapshot]: ClothSnapshot[K] }
  w.shape = fit32(s.shape, 4)
  s.shape[0] = n
  s.shape[1] = c.topology.distCount
  s.shape[2] = c.topology.hingeCount
  s.shape[3] = c.topology.triangleCount
  w.pos = copyInto(s.pos, c.pos, 3 * n)
  w.prev = copyInto(s.prev, c.prev, 3 * n)
  w.vel = copyInto(s.vel, c.vel, 3 * n)
  w.invMass = copyInto(s.invMass, c.invMass, n)
  w.pinCount = s.pinCount && s.pinCount.length === n ? s.pinCount : new Uint16Array(n)
  for (let i = 0; i < n; i++) s.pinCount[i] = c.pinCount[i]
  w.pins = fit32(s.pins, 3 * np)
  w.pinData = fit64(s.pinData, PIN_DATA * np)
  w.targets = fit32(s.targets, nt)
  w.targetData = fit64(s.targetData, TARGET_DATA * nt)
  let t = 0
  for (let q = 0; q < np; q++) {
    const pin = c.pins[q]
    const target = P.target[pin]
    s.pins[3 * q] = pin
    s.pins[3 * q + 1] = P.particle[pin]
    s.pins[3 * q + 2] = target
    const d = PIN_DATA * q
    s.pinData[d] = P.ox[pin]
    s.pinData[d + 1] = P.oy[pin]
    s.pinData[d + 2] = P.oz[pin]
    s.pinData[d + 3] = P.blendFrom[3 * pin]
    s.pinData[d + 4] = P.blendFrom[3 * pin + 1]
    s.pinData[d + 5] = P.blendFrom[3 * pin + 2]
    s.pinData[d + 6] = P.blendLeft[pin]
    s.pinData[d + 7] = P.blendTime[pin]
    if (target === 0 || !firstTargetIndex(P, c.pins, q, target)) continue
    s.targets[t] = target
    saveSlot(k, k.slotOf[target], s.targetData, TARGET_DATA * t)
    t++
  }
  w.settings = fit64(s.settings, 10)
  s.settings[0] = c.substeps
  s.settings[1] = c.iterations
  s.settings[2] = c.h
  s.settings[3] = c.damping
  s.settings[4] = c.stretchDamping
  s.settings[5] = c.useTethers ? 1 : 0
  s.settings[6] = c.tetherSlack
  s.settings[7] = c.tethersPerParticle
  s.settings[8] = c.tethersDirty ? 1 : 0
  s.settings[9] = c.skipTeleport ? 1 : 0
  w.tetherMode = c.tetherMode
  w.tethers = c.tethers
  w.world = fit64(s.world, 5)
  s.world[0] = state.accumulator
  s.world[1] = k.time[K_SINCE_SAMPLE]
  s.world[2] = k.time[K_STEP_FRACTION]
  s.world[3] = k.newFrame ? 1 : 0
  s.world[4] = k.framed ? 1 : 0
  const g = c.guard
  w.guardSafe = copyInto(s.guardSafe, g.safe, 3 * g.safeCount)
  w.guardCounters = fit64(s.guardCounters, 3)
  s.guardCounters[0] = g.safeCount
  s.guardCounters[1] = g.sinceSafe
  s.guardCounters[2] = g.failStreak
  w.guardSettings = s.guardSettings ?? { ...g.settings }
  copySettings(g.settings, s.guardSettings)
  const sl = (w.sleep = fit64(s.sleep, 8))
  sl[0] = c.sleeping ? 1 : 0
  sl[1] = c.sleep[SL_STILL]
  for (let j = 0; j < 6; j++) sl[2 + j] = c.sleepBounds[j]

  // what the world's colliders and wind zones follow, and the wind's own state
  const cw = state.collision
  const zones = state.wind.zones
  let nb = 0
  for (let q = 0; q < cw.colliders.length + zones.length; q++) if (bodyAt(state, q) >= 0 && firstBody(state, q)) nb++
  w.bodies = fit32(s.bodies, nb)
  w.bodyData = fit64(s.bodyData, TARGET_DATA * nb)
  let b = 0
  for (let q = 0; q < cw.colliders.length + zones.length; q++) {
    const e = bodyAt(state, q)
    if (e < 0 || !firstBody(state, q)) continue
    s.bodies[b] = e
    saveSlot(k, k.slotOf[e], s.bodyData, TARGET_DATA * b)
    b++
  }
  const Z = state.components.WindZone
  w.windZones = fit32(s.windZones, zones.length)
  w.wind = fit64(s.wind, 1 + WIND_DATA * zones.length)
  s.wind[0] = state.wind.time[0]
  for (let q = 0; q < zones.length; q++) {
    const z = zones[q], o = 1 + WIND_DATA * q
    s.windZones[q] = z
    s.wind[o] = Z.gustFrom[z]
    s.wind[o + 1] = Z.gustPeak[z]
    s.wind[o + 2] = Z.gustTime[z]
    s.wind[o + 3] = Z.gustDuration[z]
    s.wind[o + 4] = Z.gust[z]
    s.wind[o + 5] = Z.drift[3 * z]
    s.wind[o + 6] = Z.drift[3 * z + 1]
    s.wind[o + 7] = Z.drift[3 * z + 2]
  }

  // tearing: counters and tethers (the mesh itself is not copied: see restoreClothState)
  const T = c.tear
  const edges = T === null ? 0 : T.edges.count
  const ntt = T === null ? 0 : T.tethers.count
  w.tear = fit64(s.tear, T === null ? 0 : 3)
  w.tearOver = s.tearOver && s.tearOver.length === edges ? s.tearOver : new Uint8Array(edges)
  w.tearTethers = fit32(s.tearTethers, 2 * ntt)
  w.tearTetherRest = fit64(s.tearTetherRest, ntt)
  if (T !== null) {
    s.tear[0] = state.components.Tearable.tears[cloth]
    s.tear[1] = meshFingerprint(c)
    s.tear[2] = n
    for (let e = 0; e < edges; e++) s.tearOver[e] = T.over[e]
    for (let q = 0; q < ntt; q++) {
      s.tearTethers[2 * q] = T.tethers.particle[q]
      s.tearTethers[2 * q + 1] = T.tethers.anchor[q]
      s.tearTetherRest[q] = T.tethers.rest[q]
    }
  }
  const self = c.collision?.self ?? null
  const nTouched = self === null ? 0 : n
  w.touched = s.touched && s.touched.length === nTouched ? s.touched : new Uint8Array(nTouched)
  for (let i = 0; i < nTouched; i++) s.touched[i] = self!.touched[i]
  return s
}

const WIND_DATA = 8

/** The entity followed by collider q (q < colliders) or wind zone q − colliders, or −1 when untracked. */
function bodyAt(state: ClothWorldState, q: number): number {
  const cw = state.collision
  const nc = cw.colliders.length
  const e = q < nc ? cw.Collider.body[cw.colliders[q]] : state.wind.zones[q - nc]
  return e < state.kinematics.slotOf.length && state.kinematics.slotOf[e] >= 0 ? e : -1
}

/** True when entry q's body has not appeared at an earlier entry. */
function firstBody(state: ClothWorldState, q: number): boolean {
  const e = bodyAt(state, q)
  for (let r = 0; r < q; r++) if (bodyAt(state, r) === e) return false
  return true
}

function saveSlot(k: Kinematics, slot: number, out: Float64Array, e: number): void {
  const o = 7 * slot
  for (let j = 0; j < 7; j++) {
    out[e + j] = k.sampleFrom[o + j]
    out[e + 7 + j] = k.sampleTo[o + j]
    out[e + 14 + j] = k.stepFrom[o + j]
    out[e + 21 + j] = k.stepTo[o + j]
  }
  for (let j = 0; j < 10; j++) out[e + 28 + j] = k.jump[10 * slot + j]
  out[e + 38] = k.jumped[slot]
  out[e + 39] = k.forceJump[slot]
}

function restoreSlot(k: Kinematics, slot: number, from: Float64Array, e: number): void {
  const o = 7 * slot
  for (let j = 0; j < 7; j++) {
    k.sampleFrom[o + j] = from[e + j]
    k.sampleTo[o + j] = from[e + 7 + j]
    k.stepFrom[o + j] = from[e + 14 + j]
    k.stepTo[o + j] = from[e + 21 + j]
  }
  for (let j = 0; j < 10; j++) k.jump[10 * slot + j] = from[e + 28 + j]
  k.jumped[slot] = from[e + 38]
  k.forceJump[slot] = from[e + 39]
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

/**
 * Puts `cloth` back into a saved state, so that stepping on reproduces the run that followed the
 * save, byte for byte (given the same inputs: the host must also restore its Transforms). The
 * snapshot may come from this cloth or from another cloth built the same way (same mesh and
 * options), also in another world whose pin target entities have the same ids.
 *
 * Pins are made to match the snapshot: pins added since are removed, pins removed since are
 * created again (as new entities; `getPins` lists them). The motion history of the pin targets and
 * the world's step accumulator and frame timing are part of the snapshot, so they are rewound for
 * the whole world: when rolling back, restore every cloth from snapshots taken at the same time.
 */
export function restoreClothState(world: object, cloth: number, snapshot: ClothSnapshot): void {
  const state = getClothWorld(world)
  const c = getCloth(state, cloth)
  checkSnapshot(snapshot, 'state')
  const s = snapshot
  const n = s.shape[0]
  const T = c.tear
  if ((s.tear.length > 0) !== (T !== null)) {
    throw new ClothError('state', snapshot, T !== null ? 'was saved from a cloth that was not tearable, and this one is' : 'was saved from a tearable cloth, and this one is not')
  }
  if (T !== null && (s.tear[2] !== c.count || s.tear[1] !== meshFingerprint(c))) {
    const since = state.components.Tearable.tears[cloth] - s.tear[0]
    throw new ClothError(
      'state', snapshot,
      since > 0 && s.tear[2] < c.count
        ? `was saved before this cloth tore (${since} tear${since === 1 ? '' : 's'} since): a snapshot does not restore a torn mesh, only a tearable cloth whose mesh is still the one it was saved with`
        : 'was saved from a tearable cloth whose mesh (torn differently) is not this one\'s: a snapshot does not restore a torn mesh',
    )
  }
  if (T !== null && s.tearTetherRest.length > T.tethers.rest.length) throw new ClothError('state', snapshot, 'holds more tethers than this cloth has room for')
  if (n !== c.count || s.shape[1] !== c.topology.distCount || s.shape[2] !== c.topology.hingeCount || s.shape[3] !== c.topology.triangleCount) {
    throw new ClothError('state', snapshot, `was saved from a cloth of a different mesh (${n} particles, this one has ${c.count})`)
  }
  const np = s.pins.length / 3
  for (let q = 0; q < np; q++) {
    const target = s.pins[3 * q + 2]
    if (target !== 0 && (!entityExists(world as never, target) || !hasComponent(world as never, target, state.transforms.component))) {
      throw new ClothError('state', snapshot, `pins entity ${target}, which no longer exists or has no Transform`)
    }
    if (!(s.pins[3 * q + 1] >= 0 && s.pins[3 * q + 1] < n)) throw new ClothError('state', snapshot, 'holds a pin on a particle out of range')
  }
  restorePins(world, state, c, s)

  c.pos.set(s.pos)
  c.prev.set(s.prev)
  c.vel.set(s.vel)
  c.invMass.set(s.invMass)
  c.pinCount.set(s.pinCount)
  // integers back as integers (| 0): a float64 read stored into a small-integer field would turn
  // the field into a boxed number for every cloth
  c.substeps = s.settings[0] | 0
  c.iterations = s.settings[1] | 0
  if (state.quality.budget === null) {
    c.lod.wantSubsteps = c.substeps
    c.lod.wantIterations = c.iterations
  }
  c.h = s.settings[2]
  c.damping = s.settings[3]
  c.stretchDamping = s.settings[4]
  c.useTethers = s.settings[5] === 1
  c.tetherSlack = s.settings[6]
  c.tethersPerParticle = s.settings[7] | 0
  c.tethersDirty = s.settings[8] === 1
  c.skipTeleport = s.settings[9] === 1
  c.tetherMode = s.tetherMode
  c.tethers = s.tethers

  const k = state.kinematics
  for (let t = 0; t < s.targets.length; t++) restoreSlot(k, k.slotOf[s.targets[t]], s.targetData, TARGET_DATA * t)
  // colliders' and zones' bodies still tracked (a collider or zone removed since has nothing to restore)
  for (let b = 0; b < s.bodies.length; b++) {
    const e = s.bodies[b]
    if (e < k.slotOf.length && k.slotOf[e] >= 0) restoreSlot(k, k.slotOf[e], s.bodyData, TARGET_DATA * b)
  }
  const wind = state.wind
  const Z = state.components.WindZone
  wind.time[0] = s.wind[0]
  for (let q = 0; q < s.windZones.length; q++) {
    const z = s.windZones[q], o = 1 + WIND_DATA * q
    if (wind.zones.indexOf(z) < 0) continue
    Z.gustFrom[z] = s.wind[o]
    Z.gustPeak[z] = s.wind[o + 1]
    Z.gustTime[z] = s.wind[o + 2]
    Z.gustDuration[z] = s.wind[o + 3]
    Z.gust[z] = s.wind[o + 4]
    Z.drift[3 * z] = s.wind[o + 5]
    Z.drift[3 * z + 1] = s.wind[o + 6]
    Z.drift[3 * z + 2] = s.wind[o + 7]
  }
  wind.compiled = false
  if (T !== null) {
    state.components.Tearable.tears[cloth] = s.tear[0]
    for (let e = 0; e < s.tearOver.length; e++) T.over[e] = s.tearOver[e]
    const tt = T.tethers
    tt.count = s.tearTetherRest.length
    for (let q = 0; q < tt.count; q++) {
      tt.particle[q] = s.tearTethers[2 * q]
      tt.anchor[q] = s.tearTethers[2 * q + 1]
      tt.rest[q] = s.tearTetherRest[q]
    }
    if (c.useTethers) c.tethers = tt
  }
  const self = c.collision?.self ?? null
  if (self !== null && s.touched.length === n) for (let i = 0; i < n; i++) self.touched[i] = s.touched[i]
  state.accumulator = s.world[0]
  k.time[K_SINCE_SAMPLE] = s.world[1]
  k.time[K_STEP_FRACTION] = s.world[2]
  k.newFrame = s.world[3] === 1
  k.framed = s.world[4] === 1

  const g = c.guard
  if (g.safe.length < s.guardSafe.length) g.safe = new Float64Array(c.pos.length)
  g.safe.set(s.guardSafe)
  g.safeCount = s.guardCounters[0] | 0
  g.sinceSafe = s.guardCounters[1] | 0
  g.failStreak = s.guardCounters[2] | 0
  copySettings(s.guardSettings, g.settings)
  applyGuardSettings(g)
  const sl = s.sleep
  const asleep = sl !== undefined && sl[0] === 1
  if (asleep !== c.sleeping) {
    c.sleeping = asleep
    state.sleep.count += asleep ? 1 : -1
  }
  c.sleep[SL_STILL] = sl !== undefined ? sl[1] : 0
  if (sl !== undefined) for (let j = 0; j < 6; j++) c.sleepBounds[j] = sl[2 + j]
  c.version++
}

/** Makes the cloth's pins those of the snapshot (same particles, targets, order) and restores their data. */
function restorePins(world: object, state: ClothWorldState, c: ClothState, s: ClothSnapshot): void {
  const P = state.components.Pin
  const np = s.pins.length / 3
  let same = c.pins.length === np
  for (let q = 0; same && q < np; q++) {
    const pin = c.pins[q]
    same = pin === s.pins[3 * q] && P.particle[pin] === s.pins[3 * q + 1] && P.target[pin] === s.pins[3 * q + 2]
  }
  if (!same) {
    for (let q = c.pins.length - 1; q >= 0; q--) {
      const pin = c.pins[q]
      if (entityExists(world as never, pin)) removeEntity(world as never, pin)
    }
    for (let q = 0; q < np; q++) {
      const target = s.pins[3 * q + 2]
      const d = PIN_DATA * q
      pinParticle(world, c.eid, s.pins[3 * q + 1], target === 0 ? null : target, [s.pinData[d], s.pinData[d + 1], s.pinData[d + 2]], { blendTime: 0 })
    }
  }
  for (let q = 0; q < np; q++) {
    const pin = c.pins[q]
    const d = PIN_DATA * q
    P.ox[pin] = s.pinData[d]
    P.oy[pin] = s.pinData[d + 1]
    P.oz[pin] = s.pinData[d + 2]
    P.blendFrom[3 * pin] = s.pinData[d + 3]
    P.blendFrom[3 * pin + 1] = s.pinData[d + 4]
    P.blendFrom[3 * pin + 2] = s.pinData[d + 5]
    P.blendLeft[pin] = s.pinData[d + 6]
    P.blendTime[pin] = s.pinData[d + 7]
  }
}

function copySettings(from: GuardSettings, to: GuardSettings): void {
  to.enabled = from.enabled
  to.finite = from.finite
  to.bounds = from.bounds
  to.speed = from.speed
  to.snapshotInterval = from.snapshotInterval
}

function checkSnapshot(s: unknown, arg: string): void {
  const x = s as ClothSnapshot
  if (typeof s !== 'object' || s === null || x.format !== 'bitecs-cloth-state/1' || !(x.shape instanceof Int32Array) || !(x.pos instanceof Float64Array)) {
    throw new ClothError(arg, s, 'must be a snapshot returned by saveClothState')
  }
  const n = x.shape[0]
  if (
    x.pos.length !== 3 * n || x.prev.length !== 3 * n || x.vel.length !== 3 * n || x.invMass.length !== n ||
    x.pinCount.length !== n || x.pins.length % 3 !== 0 || x.pinData.length !== (PIN_DATA * x.pins.length) / 3 ||
    x.targetData.length !== TARGET_DATA * x.targets.length || x.settings.length !== 10 || x.world.length !== 5
  ) {
    throw new ClothError(arg, s, 'is not a complete snapshot (array sizes do not match)')
  }
  if (
    !allFinite(x.pos) || !allFinite(x.prev) || !allFinite(x.vel) || !allFinite(x.invMass) || !allFinite(x.pinData) ||
    !allFinite(x.targetData) || !allFinite(x.settings) || !allFinite(x.world) || !(x.guardSafe instanceof Float64Array) || !allFinite(x.guardSafe) ||
    (x.sleep !== undefined && (!(x.sleep instanceof Float64Array) || x.sleep.length !== 8 || !allFinite(x.sleep)))
  ) {
    throw new ClothError(arg, s, 'holds a non-finite number')
  }
  if (
    !(x.bodies instanceof Int32Array) || !(x.bodyData instanceof Float64Array) || x.bodyData.length !== TARGET_DATA * x.bodies.length ||
    !(x.windZones instanceof Int32Array) || !(x.wind instanceof Float64Array) || x.wind.length !== 1 + WIND_DATA * x.windZones.length ||
    !(x.tear instanceof Float64Array) || (x.tear.length !== 0 && x.tear.length !== 3) || !(x.tearOver instanceof Uint8Array) ||
    !(x.tearTethers instanceof Int32Array) || !(x.tearTetherRest instanceof Float64Array) || x.tearTethers.length !== 2 * x.tearTetherRest.length ||
    !(x.touched instanceof Uint8Array)
  ) {
    throw new ClothError(arg, s, 'is not a complete snapshot (collider, wind or tearing state missing)')
  }
  if (!allFinite(x.bodyData) || !allFinite(x.wind) || !allFinite(x.tear) || !allFinite(x.tearTetherRest)) {
    throw new ClothError(arg, s, 'holds a non-finite number')
  }
  for (let q = 0; q < x.tearTethers.length; q++) {
    if (!(x.tearTethers[q] >= 0 && x.tearTethers[q] < n)) throw new ClothError(arg, s, 'holds a tether on a particle out of range')
  }
  for (let i = 0; i < n; i++) if (!(x.invMass[i] >= 0)) throw new ClothError(`${arg}.invMass[${i}]`, x.invMass[i], 'must be ≥ 0')
  const v = x.settings
  if (!(Number.isInteger(v[0]) && v[0] >= 1 && Number.isInteger(v[1]) && v[1] >= 1 && v[2] > 0 && v[3] >= 0 && v[4] >= 0 && v[6] >= 0 && Number.isInteger(v[7]) && v[7] >= 1)) {
    throw new ClothError(`${arg}.settings`, v, 'must be the settings saved by saveClothState (substeps, iterations ≥ 1, h > 0, ...)')
  }
  const t = x.tethers
  if (
    (x.tetherMode !== 'euclidean' && x.tetherMode !== 'geodesic') ||
    typeof t !== 'object' || t === null || !(t.particle instanceof Int32Array) || !(t.anchor instanceof Int32Array) || !(t.rest instanceof Float64Array) ||
    !Number.isInteger(t.count) || t.count < 0 || t.count > t.particle.length || t.count > t.anchor.length || t.count > t.rest.length
  ) {
    throw new ClothError(`${arg}.tethers`, t, 'must be the tethers saved by saveClothState')
  }
  // (a tearable cloth's tethers are live arrays rebuilt as it tears; it restores from tearTethers)
  if (x.tear.length === 0) for (let q = 0; q < t.count; q++) {
    if (!(t.particle[q] >= 0 && t.particle[q] < n && t.anchor[q] >= 0 && t.anchor[q] < n && t.rest[q] >= 0 && t.rest[q] < Infinity)) {
      throw new ClothError(`${arg}.tethers`, t, `holds a bad tether at ${q} (particles out of range or a bad rest length)`)
    }
  }
  const g = x.guardSettings
  if (
    typeof g !== 'object' || g === null || typeof g.enabled !== 'boolean' || typeof g.finite !== 'boolean' ||
    !(g.bounds === false || (g.bounds > 0 && g.bounds < Infinity)) || !(g.speed === false || (g.speed > 0 && g.speed < Infinity)) ||
    !Number.isInteger(g.snapshotInterval) || g.snapshotInterval < 1
  ) {
    throw new ClothError(`${arg}.guardSettings`, g, 'must be guard settings as saved by saveClothState')
  }
}

function allFinite(a: ArrayLike<number>): boolean {
  for (let i = 0; i < a.length; i++) if (!Number.isFinite(a[i])) return false
  return true
}

function firstTargetIndex(P: { target: Uint32Array }, pins: number[], q: number, t: number): boolean {
  for (let r = 0; r < q; r++) if (P.target[pins[r]] === t) return false
  return true
}

function copyInto(dst: Float64Array | undefined, src: Float64Array, len: number): Float64Array {
  const out = dst && dst.length === len ? dst : new Float64Array(len)
  if (src.length === len) out.set(src) // a block copy (the usual case: the arrays hold no spare room)
  else for (let i = 0; i < len; i++) out[i] = src[i]
  return out
}

function fit64(a: Float64Array | undefined, len: number): Float64Array {
  return a && a.length === len ? a : new Float64Array(len)
}

function fit32(a: Int32Array | undefined, len: number): Int32Array {
  return a && a.length === len ? a : new Int32Array(len)
}
