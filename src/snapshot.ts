/**
 * Snapshots of a cloth's simulation state: everything the next step reads, so that restoring a
 * snapshot and stepping again reproduces the original run byte for byte (rollback netcode,
 * replays, "undo" in an editor, deterministic tests).
 *
 * A snapshot holds: particle positions, previous positions, velocities and inverse masses; the
 * pins (particle, target, offset, blend progress) in order; the motion history of the pins' target
 * entities (their frame samples and step poses, as interpolated between frames); the grabs holding
 * the cloth (handles, particles, targets, grip settings); the cloth's quality and tether settings
 * and its current tethers; its explosion-guard state (last good pose, counters); whether it
 * sleeps; and the world's step accumulator and frame timing. XPBD multipliers are not saved: they
 * start from zero every substep. With colliders and wind zones in
 * the world it also holds the motion history of the entities they follow, the wind clock and each
 * zone's gust and turbulence drift (world state, like the frame timing); for a tearable cloth its
 * tear counters, tear clock (crack tips, last splits) and tethers; for a self-colliding one which particles rest on a collider; for a
 * character cloth its settings, its frame's motion history, its reference pose, motion
 * constraints, held particles and skin (and the tracked history of its frame and bones).
 *
 * Not in a snapshot: the Transform of target entities (the host owns them: restore those too, or
 * the next frame sample sees where they are now), colliders and zones themselves and their settings
 * (added or removed since: not undone), and the rest data (the mesh), which must match. A torn
 * mesh is not restored either: a tearable cloth's snapshot restores only while the cloth still has
 * the mesh it was saved with (no tear since); otherwise restoring throws.
 */
import { allFinite, copyInto, fit32, fit64 } from './core/arrays'
import { ClothError, MAX_COORDINATE, MAX_SCALE, MAX_SNAPSHOT_COORDINATE } from './core/errors'
import { HAND } from './features/pins/types'
import type { TetherMode, TetherSet } from './model/tethers'
import { getCloth, getClothWorldForChange } from './world/access'
import {
  K_DROPPED,
  K_LAST_SPAN,
  K_SINCE_SAMPLE,
  K_STEP_FRACTION,
  SLOT_DATA,
  SLOT_SCALE_DATA,
  restoreSlot,
  restoreSlotScale,
  saveSlot,
  saveSlotScale,
  scalesInRange,
  generationChanged,
  transformGeneration,
} from './world/kinematics'
import type { ClothState, ClothWorldState } from './world/state'
import { checkPins, restorePinEntities, restorePins, savePins, type PinsSnapshot } from './features/pins/snapshot'
import { checkGrabs, restoreGrabs, saveGrabs, type GrabSnapshot } from './features/grab/snapshot'
import { checkWind, restoreWind, saveWind, type WindSnapshot } from './features/wind/snapshot'
import { checkCollision, restoreCollision, saveCollision, type CollisionSnapshot } from './features/collision/snapshot'
import { B_REFRESH } from './features/collision/types'
import { buildLines } from './model/lines'
import { checkBudget, restoreBudget, saveBudget, type BudgetSnapshot } from './features/budget/snapshot'
import { checkSleep, restoreSleep, saveSleep, type SleepSnapshot } from './features/sleep/snapshot'
import { checkGuard, restoreGuard, saveGuard, type GuardSnapshot } from './features/guard/snapshot'
import { checkCharacter, restoreCharacter, saveCharacter, type CharacterSnapshot } from './features/character/snapshot'
import { checkTearing, checkTearingFits, restoreTearing, saveTearing, type TearSnapshot } from './features/tearing/snapshot'
import { touchLayout } from './core/shared'
import { wakeClothState } from './world/wake'
import { liveColliders } from './features/collision/list'

/**
 * A saved cloth state (see `saveClothState`). Plain data: structured-clone it, keep it, reuse it.
 * Each feature writes its own section (`src/features/<feature>/snapshot.ts`); this file keeps the
 * header, the particles and settings, the world's step timing, the order and the checks.
 */
export interface ClothSnapshot
  extends
    PinsSnapshot,
    GrabSnapshot,
    WindSnapshot,
    CollisionSnapshot,
    BudgetSnapshot,
    SleepSnapshot,
    GuardSnapshot,
    CharacterSnapshot,
    TearSnapshot
{
  readonly format: 'bitecs-cloth-state/1'
  /** Shape of the cloth it came from: particles, distance constraints, hinges, triangles. */
  readonly shape: Int32Array
  pos: Float64Array
  prev: Float64Array
  vel: Float64Array
  invMass: Float64Array
  /**
   * substeps, iterations, h, damping, stretchDamping, useTethers, tetherSlack, tethersPerParticle,
   * tethersDirty (0; 1; 2: after a change of pins or settings), skipTeleport, then the pending hand
   * move of `teleportCloth` (`ClothPins.hand`, 11 values; absent in older snapshots), then
   * `lineSolve` (1/0; absent in older snapshots).
   */
  settings: Float64Array
  tetherMode: TetherMode
  /** The cloth's tethers (immutable arrays, shared rather than copied). */
  tethers: TetherSet
  /** World: accumulator, time since the last frame sample, step fraction, newFrame, framed, dropped time not yet sampled, the last sample's span (the last two absent in older snapshots). */
  world: Float64Array
  /** Entities the world's colliders and wind zones follow (distinct, creation order), and their motion history. */
  bodies: Int32Array
  bodyData: Float64Array
  /** Their scale history (see `PinsSnapshot.targetScales`); absent in older snapshots. */
  bodyScales?: Float64Array
  /** Their generations (see `PinsSnapshot.targetGenerations`): a body that lost its transform since is not rewound. */
  bodyGenerations?: Uint32Array
}

/**
 * The world each snapshot object was last saved in: the generations a snapshot holds are compared
 * only when it is restored there (a copy, or one loaded from storage, is restored as into a twin
 * world). Kept outside the snapshot so that twin worlds save the same bytes.
 */
const savedIn = new WeakMap<object, object>()

type Writable = { -readonly [K in keyof ClothSnapshot]: ClothSnapshot[K] }

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
  const state = getClothWorldForChange(world)
  const c = getCloth(state, cloth)
  const f = state.frame
  if (f.open && f.next <= f.steps) {
    throw new ClothError(
      'world',
      world,
      "is between two fixed steps of one frame (a listener of a step before the frame's last): save in a listener of the frame's last step or after the frame",
    )
  }
  if (into !== undefined && (typeof into !== 'object' || into === null || into.format !== 'bitecs-cloth-state/1')) {
    throw new ClothError('into', into, 'must be a snapshot returned by saveClothState')
  }
  if (into !== undefined && Object.isFrozen(into)) throw new ClothError('into', into, 'must be writable (it is frozen)')
  const s = (into ?? { format: 'bitecs-cloth-state/1' }) as Writable
  saveCore(state, c, s)
  savedIn.set(s, state.kinematics)
  savePins(state, c, s)
  saveGrabs(c, s)
  saveBodies(state, s)
  saveWind(state, s)
  saveCollision(c, s)
  saveBudget(state, c, s)
  saveSleep(state, c, s)
  saveGuard(c, s)
  saveCharacter(state, c, s)
  saveTearing(state, c, s)
  return s
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
  const state = getClothWorldForChange(world)
  const c = getCloth(state, cloth)
  const s = snapshot
  const arg = 'snapshot'
  const k = state.kinematics
  k.foreign = s === null || typeof s !== 'object' || savedIn.get(s) !== k
  try {
    restoreChecked(world, state, c, s, arg)
  } finally {
    k.foreign = false
  }
}

function restoreChecked(world: object, state: ClothWorldState, c: ClothState, s: ClothSnapshot, arg: string): void {
  checkCore(s, arg)
  const n = s.shape[0]
  checkPins(world, state, s, arg, n)
  checkGrabs(state, c, s, arg, n)
  checkBodies(s, arg)
  checkWind(s, arg)
  checkCollision(s, arg)
  checkBudget(s, arg, s.pins.length / 3)
  checkSleep(s, arg)
  checkGuard(s, arg)
  checkCharacter(world, state, s, arg, n)
  checkTearing(s, arg, n)
  checkTearingFits(state, c, s, arg)
  if (
    n !== c.count || s.shape[1] !== c.topology.distCount || s.shape[2] !== c.topology.hingeCount || s.shape[3] !== c.topology.triangleCount
  ) {
    throw new ClothError(arg, s, `was saved from a cloth of a different mesh (${n} particles, this one has ${c.count})`)
  }
  restorePinEntities(world, state, c, s)
  restoreCore(state, c, s)
  restorePins(state, c, s)
  restoreGrabs(state, c, s)
  const bodyGone = restoreBodies(state, s)
  restoreWind(state, s)
  restoreCollision(c, s)
  restoreCharacter(state, c, s) // (before the budget: a frozen cloth may be carried by its frame or bone)
  restoreBudget(state, c, s)
  c.budget.shownCarried = false // (a teleportCloth since the save moved the mesh this restore replaced)
  restoreSleep(state, c, s)
  // a collider or zone body gone since the save may have been what it lay on: restored asleep, a
  // sheet whose box was removed hung in the air for good (its wake test sees moved colliders only)
  if (bodyGone && c.sleep.asleep) wakeClothState(state, c)
  c.collision.bounds[B_REFRESH] = 1 // (an idle cloth's collision bounds and hash are made again from the restored positions)
  restoreGuard(c, s)
  restoreTearing(state, c, s)
  c.version++
}

// ---------------------------------------------------------------------------------------------
// The core section: particles, settings, tethers, the world's step timing

function saveCore(state: ClothWorldState, c: ClothState, s: Writable): void {
  const n = c.count
  const k = state.kinematics
  s.shape = fit32(s.shape, 4)
  s.shape[0] = n
  s.shape[1] = c.topology.distCount
  s.shape[2] = c.topology.hingeCount
  s.shape[3] = c.topology.triangleCount
  s.pos = copyInto(s.pos, c.pos, 3 * n)
  s.prev = copyInto(s.prev, c.prev, 3 * n)
  s.vel = copyInto(s.vel, c.vel, 3 * n)
  s.invMass = copyInto(s.invMass, c.invMass, n)
  const ct = c.tethers
  s.settings = fit64(s.settings, 11 + HAND)
  s.settings[0] = c.substeps
  s.settings[1] = c.iterations
  s.settings[2] = c.h
  s.settings[3] = c.damping
  s.settings[4] = c.stretchDamping
  s.settings[5] = ct.enabled ? 1 : 0
  s.settings[6] = ct.slack
  s.settings[7] = ct.perParticle
  // 1: rebuild; 2: rebuild after a change of pins or settings (loosened, see loosenTethers)
  s.settings[8] = ct.dirty ? (ct.loosen ? 2 : 1) : 0
  s.settings[9] = c.pins.skipTeleport ? 1 : 0
  s.settings.set(c.pins.hand, 10)
  s.settings[10 + HAND] = c.lines !== null ? 1 : 0
  s.tetherMode = ct.mode
  s.tethers = ct.set
  s.world = fit64(s.world, 7)
  s.world[0] = state.accumulator
  s.world[1] = k.time[K_SINCE_SAMPLE]
  s.world[2] = k.time[K_STEP_FRACTION]
  s.world[3] = k.newFrame ? 1 : 0
  s.world[4] = k.framed ? 1 : 0
  s.world[5] = k.time[K_DROPPED] // (pending after a frame refused at its sample)
  s.world[6] = k.time[K_LAST_SPAN]
  if (state.frame.open) {
    // a listener after the frame's last step: the timing the frame leaves when it closes (saved as
    // it stood, a restore outside a frame never sampled the next frame's transforms: 3.5 cm off)
    s.world[0] = state.frame.overflow || state.accumulator < 0 ? 0 : state.accumulator
    s.world[1] = 0
    s.world[3] = 1
    s.world[4] = 0
  }
}

/** Throws unless every value of `a` lies within ±bound. */
function checkBounded(a: Float64Array, arg: string, name: string, bound = MAX_COORDINATE): void {
  for (let j = 0; j < a.length; j++) {
    if (!(Math.abs(a[j]) <= bound)) throw new ClothError(`${arg}.${name}[${j}]`, a[j], `must lie within ±${bound}`)
  }
}

function checkCore(s: unknown, arg: string): asserts s is ClothSnapshot {
  const x = s as ClothSnapshot
  if (
    typeof s !== 'object' || s === null || x.format !== 'bitecs-cloth-state/1' || !(x.shape instanceof Int32Array) ||
    !(x.pos instanceof Float64Array)
  ) {
    throw new ClothError(arg, s, 'must be a snapshot returned by saveClothState')
  }
  const n = x.shape[0]
  if (
    x.pos.length !== 3 * n || !(x.prev instanceof Float64Array) || x.prev.length !== 3 * n || !(x.vel instanceof Float64Array) ||
    x.vel.length !== 3 * n ||
    !(x.invMass instanceof Float64Array) || x.invMass.length !== n || !(x.settings instanceof Float64Array) ||
    (x.settings.length !== 10 && x.settings.length !== 10 + HAND && x.settings.length !== 11 + HAND) ||
    !(x.world instanceof Float64Array) || x.world.length < 5 || x.world.length > 7
  ) {
    throw new ClothError(arg, s, 'is not a complete snapshot (array sizes do not match)')
  }
  if (
    !allFinite(x.pos) || !allFinite(x.prev) || !allFinite(x.vel) || !allFinite(x.invMass) || !allFinite(x.settings) || !allFinite(x.world)
  ) {
    throw new ClothError(arg, s, 'holds a non-finite number')
  }
  if (x.world.length > 5 && !(x.world[5] >= 0 && x.world[5] <= 1e9)) {
    throw new ClothError(arg, s, 'holds a dropped frame time outside [0, 1e9] s')
  }
  // what the API gives: points within ±MAX_SNAPSHOT_COORDINATE, speeds within ±MAX_COORDINATE (a
  // step moves at most that), inverse masses 0 (pinned) or normal numbers whose inverse is finite
  checkBounded(x.pos, arg, 'pos', MAX_SNAPSHOT_COORDINATE)
  checkBounded(x.prev, arg, 'prev', MAX_SNAPSHOT_COORDINATE)
  checkBounded(x.vel, arg, 'vel')
  for (let i = 0; i < n; i++) {
    const w = x.invMass[i]
    if (!(w === 0 || (w >= 1e-300 && w <= 1e300))) throw new ClothError(`${arg}.invMass[${i}]`, w, 'must be 0 or within [1e-300, 1e300]')
  }
  const v = x.settings
  if (
    !(Number.isInteger(v[0]) && v[0] >= 1 && v[0] <= 256 && Number.isInteger(v[1]) && v[1] >= 1 && v[1] <= 256 && v[2] > 0 && v[2] <= 1e6 &&
      v[3] >= 0 && v[4] >= 0 && v[6] >= 0 && Number.isInteger(v[7]) && v[7] >= 1 && v[7] <= 16)
  ) {
    throw new ClothError(
      `${arg}.settings`,
      v,
      'must be the settings saved by saveClothState (substeps and iterations 1…256, h in (0, 1e6] s, 1…16 tethers per particle, ...)',
    )
  }
  if (v.length > 10 + HAND && v[10 + HAND] !== 0 && v[10 + HAND] !== 1) {
    throw new ClothError(`${arg}.settings`, v, 'holds a bad line solve switch (0 or 1)')
  }
  if (v.length > 10 && v[20] === 1) {
    const q = Math.hypot(v[13], v[14], v[15], v[16])
    let bounded = Math.abs(q - 1) < 1e-6
    for (const d of [10, 11, 12, 17, 18, 19]) bounded &&= Math.abs(v[d]) <= MAX_SNAPSHOT_COORDINATE
    if (!bounded) throw new ClothError(`${arg}.settings`, v, 'holds a bad teleport (a unit quaternion and points within ±1e12 m)')
  }
  const t = x.tethers
  if (
    (x.tetherMode !== 'euclidean' && x.tetherMode !== 'geodesic') ||
    typeof t !== 'object' || t === null || !(t.particle instanceof Int32Array) || !(t.anchor instanceof Int32Array) ||
    !(t.rest instanceof Float64Array) ||
    !Number.isInteger(t.count) || t.count < 0 || t.count > t.particle.length || t.count > t.anchor.length || t.count > t.rest.length
  ) {
    throw new ClothError(`${arg}.tethers`, t, 'must be the tethers saved by saveClothState')
  }
  // (a tearable cloth's tethers are live arrays rebuilt as it tears; it restores from tearTethers)
  if (!(x.tear instanceof Float64Array) || x.tear.length === 0) {
    for (let q = 0; q < t.count; q++) {
      if (!(t.particle[q] >= 0 && t.particle[q] < n && t.anchor[q] >= 0 && t.anchor[q] < n && t.rest[q] >= 0 && t.rest[q] < Infinity)) {
        throw new ClothError(`${arg}.tethers`, t, `holds a bad tether at ${q} (particles out of range or a bad rest length)`)
      }
    }
  }
}

function restoreCore(state: ClothWorldState, c: ClothState, s: ClothSnapshot): void {
  c.pos.set(s.pos)
  c.prev.set(s.prev)
  c.vel.set(s.vel)
  c.invMass.set(s.invMass)
  // integers back as integers (| 0): a float64 read stored into a small-integer field would turn
  // the field into a boxed number for every cloth
  c.substeps = s.settings[0] | 0
  c.iterations = s.settings[1] | 0
  c.h = s.settings[2]
  c.damping = s.settings[3]
  c.stretchDamping = s.settings[4]
  const ct = c.tethers
  ct.enabled = s.settings[5] === 1
  ct.slack = s.settings[6]
  ct.perParticle = s.settings[7] | 0
  ct.dirty = s.settings[8] === 1 || s.settings[8] === 2
  ct.loosen = s.settings[8] === 2
  c.pins.skipTeleport = s.settings[9] === 1
  if (s.settings.length > 10) c.pins.hand.set(s.settings.subarray(10, 10 + HAND))
  else c.pins.hand[10] = 0 // (an older snapshot: the hand move is not known, and stays)
  if (s.settings.length > 10 + HAND && (s.settings[10 + HAND] === 1) !== (c.lines !== null)) {
    // the line solve as saved (a setting like substeps; older snapshots: it stays as it is)
    c.lines = s.settings[10 + HAND] === 1 ? buildLines(c.topology) : null
    touchLayout()
  }
  ct.mode = s.tetherMode
  if (ct.set !== s.tethers) touchLayout() // the cloth holds another tether set
  ct.set = s.tethers
  const k = state.kinematics
  state.accumulator = s.world[0]
  k.time[K_SINCE_SAMPLE] = s.world[1]
  k.time[K_STEP_FRACTION] = s.world[2]
  k.time[K_DROPPED] = s.world.length > 5 ? s.world[5] : 0 // (older snapshots: none)
  k.time[K_LAST_SPAN] = s.world.length > 6 && s.world[6] > 0 ? s.world[6] : 1 // (older snapshots: one step)
  k.newFrame = s.world[3] === 1
  k.framed = s.world[4] === 1
}

// ---------------------------------------------------------------------------------------------
// Tracked bodies: the entities the world's colliders and wind zones follow (one list for both, as
// an entity may carry a collider and a zone), and their motion history

function saveBodies(state: ClothWorldState, s: Writable): void {
  const k = state.kinematics
  const total = liveColliders(state.collision).length + state.wind.zones.length
  // each body once, at its first entry (marked per slot: a scan of the entries before each made a
  // save quadratic in the colliders, 141 ms with 4,000)
  if (firstSeen.length < k.count) firstSeen = new Int32Array(Math.max(k.count, 2 * firstSeen.length))
  firstSeen.fill(-1, 0, k.count)
  let nb = 0
  for (let q = 0; q < total; q++) {
    const e = bodyAt(state, q)
    if (e < 0 || firstSeen[k.slotOf[e]] >= 0) continue
    firstSeen[k.slotOf[e]] = q
    nb++
  }
  s.bodies = fit32(s.bodies, nb)
  s.bodyData = fit64(s.bodyData, SLOT_DATA * nb)
  s.bodyScales = fit64(s.bodyScales, SLOT_SCALE_DATA * nb)
  s.bodyGenerations = s.bodyGenerations && s.bodyGenerations.length === nb ? s.bodyGenerations : new Uint32Array(nb)
  let b = 0
  for (let q = 0; q < total; q++) {
    const e = bodyAt(state, q)
    if (e < 0 || firstSeen[k.slotOf[e]] !== q) continue
    s.bodies[b] = e
    saveSlot(k, k.slotOf[e], s.bodyData, SLOT_DATA * b)
    saveSlotScale(k, k.slotOf[e], s.bodyScales, SLOT_SCALE_DATA * b)
    s.bodyGenerations[b] = transformGeneration(k, e)
    b++
  }
}

function checkBodies(s: ClothSnapshot, arg: string): void {
  if (!(s.bodies instanceof Int32Array) || !(s.bodyData instanceof Float64Array) || s.bodyData.length !== SLOT_DATA * s.bodies.length) {
    throw new ClothError(arg, s, 'is not a complete snapshot (collider, wind or tearing state missing)')
  }
  if (
    (s.bodyScales !== undefined &&
      (!(s.bodyScales instanceof Float64Array) || s.bodyScales.length !== SLOT_SCALE_DATA * s.bodies.length)) ||
    (s.bodyGenerations !== undefined && (!(s.bodyGenerations instanceof Uint32Array) || s.bodyGenerations.length !== s.bodies.length))
  ) {
    throw new ClothError(arg, s, 'is not a complete snapshot (collider, wind or tearing state missing)')
  }
  if (!allFinite(s.bodyData) || (s.bodyScales !== undefined && !allFinite(s.bodyScales)))
    throw new ClothError(arg, s, 'holds a non-finite number')
  if (s.bodyScales !== undefined && !scalesInRange(s.bodyScales))
    throw new ClothError(`${arg}.bodyScales`, s.bodyScales, `must hold scales in (0, ${MAX_SCALE}], as a Transform's`)
}

/**
 * Restores the bodies still tracked (a collider or zone removed since has nothing to restore, nor
 * does an entity that got a removed body's id since). Returns whether some saved body is gone.
 */
function restoreBodies(state: ClothWorldState, s: ClothSnapshot): boolean {
  const k = state.kinematics
  let gone = false
  for (let b = 0; b < s.bodies.length; b++) {
    const e = s.bodies[b]
    if (s.bodyGenerations !== undefined && generationChanged(k, s.bodyGenerations[b], e)) gone = true
    else if (e < k.slotOf.length && k.slotOf[e] >= 0) {
      restoreSlot(k, k.slotOf[e], s.bodyData, SLOT_DATA * b)
      restoreSlotScale(state, k.slotOf[e], s.bodyScales ?? null, SLOT_SCALE_DATA * b)
    } else gone = true
  }
  return gone
}

/** The entity followed by collider q (q < colliders) or wind zone q − colliders, or −1 when untracked. */
function bodyAt(state: ClothWorldState, q: number): number {
  const cw = state.collision
  const list = liveColliders(cw), nc = list.length
  const e = q < nc ? cw.Collider.body[list[q]] : state.wind.zones[q - nc]
  return e < state.kinematics.slotOf.length && state.kinematics.slotOf[e] >= 0 ? e : -1
}

/** Scratch of `saveBodies`: per kinematic slot, the first entry whose body it is (−1: none yet). */
let firstSeen = new Int32Array(0)
