import { addComponent, hasComponent, observe, onRemove } from 'bitecs'
import { ClothError, checkInteger, checkPositive } from './errors'
import { findOverstrained } from './kernels/strain'
import { getCloth } from './pins'
import { growStores } from './plugin'
import { getClothWorld, type ClothState, type ClothWorldState } from './state'
import { createAnchorScratch, nearestAnchorsAlongMesh, type AnchorScratch, type TetherSet } from './tethers'
import type { ClothTopology } from './topology'
import { ensureClothWind, refreshClothWind } from './wind'
import { wakeClothState } from './sleep'

/**
 * Tearing by vertex splitting.
 *
 * After the solve on a cloth's last substep of a step, every mesh edge is measured (structural
 * edges and the triangles' diagonals, so a load that runs through a sheared diagonal breaks it
 * too); an edge
 * longer than (1 + strain)·rest for `hysteresis` consecutive steps breaks (the most strained first,
 * at most `maxTearsPerStep` per step, which keeps one overloaded step from unzipping the whole
 * cloth). Breaking edge (a, b) splits one of its ends, v: the plane through v perpendicular to the
 * edge sorts v's triangles by the side their centroid lies on (on the rest shape, where v's fan is
 * undistorted, so the cut is clean however far the edge has stretched); the triangles on the far side get a
 * new particle v′ (a copy of v: position, velocity, rest position; v's mass is shared between the
 * two by the rest area of their triangles) and are re-indexed to it. That is a crack across the
 * load, and the renderer shows a real hole because the triangles no longer share the vertex. The
 * unpinned end is split first; a split that would leave one side empty is not made.
 *
 * Every constraint keeps a "support": for each of its particles, a (triangle, corner) it is read
 * from, and the corners that must still coincide for it to make sense. After the splits of a step,
 * one pass over each constraint list re-reads the particles from the triangles and drops what is
 * no longer supported:
 * - an edge constraint (stretch, shear diagonal, stretch measurement, mesh edge) lives in a
 *   triangle; when its two triangles no longer share the edge, it is duplicated, one per side;
 * - a constraint across an edge (quad cross diagonal, bending pair, dihedral hinge) needs its two
 *   triangles to still share that edge, else it is removed;
 * - a skip-one bending pair needs the two edges it spans to still meet at the same middle particle.
 * Tethers are then rebuilt from the split mesh (without allocating): a tether only ties particles
 * to anchors in the same connected piece, so two torn pieces are never held together.
 *
 * A tearable cloth owns a copy of its rest data (the shared topology stays read-only) with room
 * for `capacity` more particles and the constraints their splits add, reserved by `makeTearable`:
 * nothing is allocated in a step, tear or not.
 */

/** Options of `makeTearable`. */
export interface TearableOptions {
  /** Strain at which an edge breaks (0.3 = 30 % longer than rest). Default: the material's `tearStrain`. */
  strain?: number
  /** Most tears per step for this cloth. Default 4. */
  maxTearsPerStep?: number
  /** Extra particles reserved for tears (each tear adds one; tearing stops when they run out). Default: the particle count. */
  capacity?: number
  /** Consecutive steps an edge must stay over the threshold before it breaks. Default 2. */
  hysteresis?: number
}

/** One tear: where and in which cloth a particle was split. */
export interface ClothTearEvent {
  /** The cloth entity. */
  cloth: number
  /** World position of the split, m. */
  x: number
  y: number
  z: number
  /** The particle that was split and the new particle made from it. */
  particle: number
  newParticle: number
  /** Strain of the edge that broke (0.35 = 35 % longer than rest). */
  strain: number
}

export type ClothTearListener = (event: Readonly<ClothTearEvent>) => void

/** Values per queued event: cloth, x, y, z, particle, newParticle, strain. */
const EV = 7

/** Per-world tearing state: event buffers and listeners. */
export interface TearWorld {
  /** Tears of the current step, EV doubles each (sized for every tearable cloth's cap). */
  pending: Float64Array
  pendingCount: number
  /** Events waiting for `drainClothTears`. */
  queue: Float64Array
  queueCount: number
  /** Events that found the drain queue full (nobody drained it). */
  dropped: number
  listeners: ClothTearListener[]
  /** The one event object handed to listeners (refilled for each event). */
  event: ClothTearEvent
}

type Mutable<T> = { -readonly [K in keyof T]: T[K] }
type TearTopology = Mutable<ClothTopology>

/**
 * A list of two-particle constraints with its support (see the module comment). `ids`, `f64` and
 * `u8` alias the topology's arrays; entries are re-read and compacted after splits.
 */
interface PairSet {
  /** Particles, each stored as index × `scale` (3 for the distance constraints' position offsets). */
  ids: Int32Array
  scale: number
  f64: Float64Array[]
  u8: Uint8Array[]
  /** The hysteresis counters (the mesh edges, which the tear phase measures): reset on duplicates. */
  over: Uint8Array | null
  count: number
  cap: number
  /** Triangle and corner each particle is read from (−1: fixed particles, no support). */
  endT: Int32Array
  endC: Uint8Array
  /** Up to two checks (t, t′) whose corners (c, c′) must hold the same particle; −1 = none. */
  chkT: Int32Array
  chkC: Uint8Array
  /** Edge constraints: the second triangle of the edge (−1 none) and its corners. */
  twinT: Int32Array
  twinC: Uint8Array
}

/** Dihedral hinges with support: e0, e1, w0 from triangle A, w1 from triangle B. */
interface HingeSet {
  ids: Int32Array
  f64: Float64Array[]
  count: number
  endT: Int32Array
  endC: Uint8Array
  chkT: Int32Array
  chkC: Uint8Array
}

/** Line-bending triples with support: a and v from triangle A (edge a–v), b from triangle B (edge v–b). */
interface LineSet {
  ids: Int32Array
  f64: Float64Array[]
  count: number
  endT: Int32Array
  endC: Uint8Array
  /** v as seen from A and from B: the triple breaks when they differ. */
  chkT: Int32Array
  chkC: Uint8Array
}

/** Tearing state of one cloth (`ClothState.tear`). */
export interface ClothTear {
  enabled: boolean
  /** The cloth's own rest data (also `ClothState.topology`). */
  topology: TearTopology
  particleCapacity: number
  stretch: PairSet
  edges: PairSet
  dist: PairSet
  comp: PairSet
  lines: LineSet
  hinges: HingeSet
  over: Uint8Array
  /** Split scratch: triangles around the split particle, their corner and side. */
  fan: Int32Array
  fanCorner: Uint8Array
  fanSide: Uint8Array
  /** Candidate edges of the step, most strained first. */
  cand: Int32Array
  candRatio: Float64Array
  /** Strain-check parameters: (1 + strain)², hysteresis, max candidates. */
  params: Float64Array
  tethers: TetherSet
  scratch: AnchorScratch
  /**
   * Connected piece of each particle (pieces numbered by their lowest particle), refreshed after
   * every step that tore; the explosion guard measures its bounds per piece once there are several.
   */
  piece: Int32Array
  pieceCount: number
  /** Union-find scratch for `piece`. */
  pieceRoot: Int32Array
  /** Per-piece boxes for the guard's check (7 per piece, see `kernels/guard.ts`). */
  pieceBox: Float64Array
}

/** Creates the per-world tearing state. Called by `installClothPlugin`. */
export function createTearWorld(): TearWorld {
  return {
    pending: new Float64Array(0),
    pendingCount: 0,
    queue: new Float64Array(256 * EV),
    queueCount: 0,
    dropped: 0,
    listeners: [],
    // doubles from the start, so refilling the fields never changes their representation
    event: { cloth: 0, x: 0.5, y: 0.5, z: 0.5, particle: 0, newParticle: 0, strain: 0.5 },
  }
}

/** Registers the tearing observers. Called by `installClothPlugin`. */
export function installTearing(world: object, state: ClothWorldState): void {
  // removing Tearable stops tearing; the split mesh stays as it is
  observe(world as never, onRemove(state.components.Tearable), (eid: number) => {
    const c = state.components.Cloth.state[eid]
    if (c && c.tear) c.tear.enabled = false
  })
}

/**
 * Makes a cloth tearable (adds the Tearable component). The cloth gets its own copy of its rest
 * data with room for `capacity` more particles, so tearing never allocates. Calling it again
 * changes strain, maxTearsPerStep and hysteresis (the capacity is fixed once reserved).
 *
 * @example
 * makeTearable(world, curtain, { strain: 0.25, maxTearsPerStep: 4 })
 * onClothTear(world, (e) => spawnDust(e.x, e.y, e.z))
 */
export function makeTearable(world: object, cloth: number, options: TearableOptions = {}): void {
  const state = getClothWorld(world)
  const c = getCloth(state, cloth)
  if (typeof options !== 'object' || options === null) throw new ClothError('options', options, 'must be an object')
  const strain = options.strain === undefined ? c.material.tearStrain : checkPositive('options.strain', options.strain)
  const maxTears = options.maxTearsPerStep === undefined ? 4 : checkInteger('options.maxTearsPerStep', options.maxTearsPerStep, 1, 4096)
  const hysteresis = options.hysteresis === undefined ? 2 : checkInteger('options.hysteresis', options.hysteresis, 1, 255)
  const extra = options.capacity === undefined ? Math.max(16, c.count) : checkInteger('options.capacity', options.capacity, 0, 1 << 22)
  if (c.tear !== null) {
    if (options.capacity !== undefined && c.count + extra > c.tear.particleCapacity) {
      throw new ClothError('options.capacity', options.capacity, 'cannot grow once the cloth is tearable')
    }
    if (2 * maxTears + 4 > c.tear.cand.length) {
      c.tear.cand = new Int32Array(2 * maxTears + 4)
      c.tear.candRatio = new Float64Array(2 * maxTears + 4)
    }
  } else {
    reserve(c, extra, maxTears)
  }
  c.tear!.enabled = true
  growStores(state, cloth)
  const T = state.components.Tearable
  T.strain[cloth] = strain
  T.maxTearsPerStep[cloth] = maxTears
  T.hysteresis[cloth] = hysteresis
  if (!hasComponent(world as never, cloth, T)) {
    T.tears[cloth] = 0
    addComponent(world as never, cloth, T)
  }
  // room for one step's tears of every tearable cloth
  let total = 0
  for (const other of state.cloths) if (other.tear) total += state.components.Tearable.maxTearsPerStep[other.eid]
  const tw = state.tearing
  if (tw.pending.length < total * EV) {
    const grown = new Float64Array(total * EV)
    grown.set(tw.pending)
    tw.pending = grown
  }
  if (c.wind !== null) ensureClothWind(c)
  wakeClothState(state, c)
}

/**
 * Calls `listener` for every tear, right after the fixed step it happened in (inside `stepCloth` or
 * `clothFixedStep`, with the step complete). The event object is reused: copy what you keep.
 * Returns a function that unsubscribes.
 */
export function onClothTear(world: object, listener: ClothTearListener): () => void {
  const state = getClothWorld(world)
  if (typeof listener !== 'function') throw new ClothError('listener', listener, 'must be a function')
  const list = state.tearing.listeners
  list.push(listener)
  return () => {
    const i = list.indexOf(listener)
    if (i >= 0) list.splice(i, 1)
  }
}

/**
 * Hands the queued tear events (every tear since the last drain, oldest first) to `fn` and empties
 * the queue; for engines that poll in their own systems. The event object is reused. Returns the
 * number of events. The queue keeps 256 events; older undrained ones are kept and newer dropped.
 */
export function drainClothTears(world: object, fn: ClothTearListener): number {
  const tw = getClothWorld(world).tearing
  if (typeof fn !== 'function') throw new ClothError('fn', fn, 'must be a function')
  const n = tw.queueCount
  tw.queueCount = 0
  for (let i = 0; i < n; i++) fn(readEvent(tw.queue, i, tw.event))
  return n
}

function readEvent(buf: Float64Array, i: number, e: ClothTearEvent): ClothTearEvent {
  const o = i * EV
  e.cloth = buf[o] | 0
  e.x = buf[o + 1]
  e.y = buf[o + 2]
  e.z = buf[o + 3]
  e.particle = buf[o + 4] | 0
  e.newParticle = buf[o + 5] | 0
  e.strain = buf[o + 6]
  return e
}

/**
 * After a fixed step: moves the step's tears to the drain queue and calls the listeners. Called by
 * the `clothEvents` system at the end of `clothFixedStep`.
 */
export function dispatchTearEvents(state: ClothWorldState): void {
  const tw = state.tearing
  const n = tw.pendingCount
  if (n === 0) return
  tw.pendingCount = 0
  const room = (tw.queue.length / EV) | 0
  for (let i = 0; i < n; i++) {
    if (tw.queueCount >= room) {
      tw.dropped++
      continue
    }
    const from = i * EV, to = tw.queueCount * EV
    for (let j = 0; j < EV; j++) tw.queue[to + j] = tw.pending[from + j]
    tw.queueCount++
  }
  const listeners = tw.listeners
  if (listeners.length === 0) return
  for (let i = 0; i < n; i++) {
    readEvent(tw.pending, i, tw.event)
    for (let l = 0; l < listeners.length; l++) listeners[l](tw.event)
  }
}

// ---------------------------------------------------------------------------------------------
// The tear phase

/** Tear phase for one cloth on its last substep of the step: measure, split, repair. */
export function tearCloth(state: ClothWorldState, c: ClothState): void {
  const T = c.tear!
  if (!T.enabled) return
  const store = state.components.Tearable
  const eid = c.eid
  const t = T.topology
  const S = T.edges
  const strain = store.strain[eid]
  const max = store.maxTearsPerStep[eid]
  const p = T.params
  p[0] = (1 + strain) * (1 + strain)
  p[1] = store.hysteresis[eid]
  // more candidates than tears allowed: an edge that cannot split yet must not block the others
  p[2] = Math.min(T.cand.length, 2 * max + 4)
  const n = findOverstrained(c.pos, t.edges, t.edgeRest, S.count, T.over, p, T.cand, T.candRatio)
  state.stats.strainChecks += S.count
  if (n === 0) return
  const tris = t.triangles
  const tw = state.tearing
  let tears = 0
  for (let q = 0; q < n; q++) {
    if (c.count >= T.particleCapacity || tears >= max) break
    const k = T.cand[q]
    // the edge's particles now (an earlier split this step may have re-indexed them)
    const tA = S.endT[2 * k]
    const a = tA >= 0 ? tris[3 * tA + S.endC[2 * k]] : t.edges[2 * k]
    const b = tA >= 0 ? tris[3 * S.endT[2 * k + 1] + S.endC[2 * k + 1]] : t.edges[2 * k + 1]
    let first = a, second = b
    if (c.pinCount[a] > 0 && c.pinCount[b] === 0) {
      first = b
      second = a
    }
    // a clean cut across the edge at either end; failing that (a fan already cut into a sliver),
    // cut the edge's own triangles away from the rest of an end's fan
    let split = first
    let nv = splitParticle(c, T, first, second, 0)
    if (nv < 0) nv = splitParticle(c, T, (split = second), first, 0)
    if (nv < 0) nv = splitParticle(c, T, (split = first), second, 1)
    if (nv < 0) nv = splitParticle(c, T, (split = second), first, 1)
    // both ends hold only the edge's own two triangles (a diamond left between two cracks): part them
    if (nv < 0) nv = splitParticle(c, T, (split = first), second, 2)
    if (nv < 0) continue
    T.over[k] = 0
    tears++
    if ((tw.pendingCount + 1) * EV <= tw.pending.length) {
      const o = tw.pendingCount++ * EV
      const pos = c.pos
      tw.pending[o] = eid
      tw.pending[o + 1] = pos[3 * split]
      tw.pending[o + 2] = pos[3 * split + 1]
      tw.pending[o + 3] = pos[3 * split + 2]
      tw.pending[o + 4] = split
      tw.pending[o + 5] = nv
      tw.pending[o + 6] = Math.sqrt(T.candRatio[q] * p[0]) - 1
    }
  }
  if (tears === 0) return
  repairConstraints(T)
  labelPieces(T, c.count)
  if (c.useTethers) c.tethersDirty = true
  refreshClothWind(c)
  store.tears[eid] += tears
  state.stats.tears += tears
}

/**
 * Splits particle v. Mode 0: across the plane through v perpendicular to v → o (rest shape), the
 * far side's triangles moving to the new particle. Mode 1: the triangles that hold o move. Mode 2:
 * all but the first triangle move. Returns
 * the new particle, or −1 when every triangle of v lies on one side (nothing to split) or the
 * capacity is used up.
 */
function splitParticle(c: ClothState, T: ClothTear, v: number, o: number, mode: number): number {
  const t = T.topology
  const tris = t.triangles
  const pos = c.pos
  // classified on the rest shape: a fan stretched to many times its size can have every centroid
  // on the far side in the current pose, while at rest it is a clean fan the plane cuts in two
  const rest = t.restPositions
  const px = rest[3 * v], py = rest[3 * v + 1], pz = rest[3 * v + 2]
  const dx = rest[3 * o] - px, dy = rest[3 * o + 1] - py, dz = rest[3 * o + 2] - pz
  const fan = T.fan, corner = T.fanCorner, side = T.fanSide
  let fc = 0, plus = 0
  for (let tt = 0; tt < t.triangleCount; tt++) {
    const base = 3 * tt
    const i0 = tris[base], i1 = tris[base + 1], i2 = tris[base + 2]
    const k = i0 === v ? 0 : i1 === v ? 1 : i2 === v ? 2 : -1
    if (k < 0) continue
    const sx = rest[3 * i0] + rest[3 * i1] + rest[3 * i2] - 3 * px
    const sy = rest[3 * i0 + 1] + rest[3 * i1 + 1] + rest[3 * i2 + 1] - 3 * py
    const sz = rest[3 * i0 + 2] + rest[3 * i1 + 2] + rest[3 * i2 + 2] - 3 * pz
    const s = mode === 0 ? (sx * dx + sy * dy + sz * dz > 0 ? 1 : 0) : mode === 1 ? (i0 === o || i1 === o || i2 === o ? 1 : 0) : fc > 0 ? 1 : 0
    fan[fc] = tt
    corner[fc] = k
    side[fc] = s
    plus += s
    fc++
  }
  if (plus === 0 || plus === fc) return -1
  const nv = c.count
  if (nv >= T.particleCapacity) return -1
  let areaPlus = 0, areaAll = 0
  for (let f = 0; f < fc; f++) {
    const base = 3 * fan[f]
    const ra = 3 * tris[base], rb = 3 * tris[base + 1], rc = 3 * tris[base + 2]
    const ux = rest[rb] - rest[ra], uy = rest[rb + 1] - rest[ra + 1], uz = rest[rb + 2] - rest[ra + 2]
    const vx = rest[rc] - rest[ra], vy = rest[rc + 1] - rest[ra + 1], vz = rest[rc + 2] - rest[ra + 2]
    const cx = uy * vz - uz * vy, cy = uz * vx - ux * vz, cz = ux * vy - uy * vx
    const A = Math.sqrt(cx * cx + cy * cy + cz * cz) // twice the area: only ratios matter
    areaAll += A
    if (side[f] === 1) {
      areaPlus += A
      tris[base + corner[f]] = nv
    }
  }
  const guardRest = c.guard.rest
  for (let j = 0; j < 3; j++) {
    pos[3 * nv + j] = pos[3 * v + j]
    c.prev[3 * nv + j] = c.prev[3 * v + j]
    c.vel[3 * nv + j] = c.vel[3 * v + j]
    rest[3 * nv + j] = rest[3 * v + j]
    // the guard's rest pose (its fallback after a failed reset) grows with the cloth: a torn cloth
    // goes back to its rest layout, every piece in place
    guardRest[3 * nv + j] = guardRest[3 * v + j]
  }
  // share the mass by rest area, neither part below 20 % (extreme mass ratios hurt Gauss-Seidel)
  let frac = areaAll > 0 ? areaPlus / areaAll : 0.5
  if (frac < 0.2) frac = 0.2
  else if (frac > 0.8) frac = 0.8
  const m = 1 / c.baseInvMass[v]
  const mPlus = m * frac, mMinus = m - mPlus
  t.masses[nv] = mPlus
  t.masses[v] = mMinus
  c.baseInvMass[nv] = 1 / mPlus
  c.baseInvMass[v] = 1 / mMinus
  c.invMass[nv] = 1 / mPlus
  if (c.pinCount[v] === 0) c.invMass[v] = 1 / mMinus
  c.pinCount[nv] = 0
  c.count = nv + 1
  t.particleCount = nv + 1
  return nv
}

/**
 * Labels the connected pieces of the split mesh (triangles joined through shared particles):
 * union-find with the smaller index as root, so labels follow the lowest particle of each piece.
 */
function labelPieces(T: ClothTear, count: number): void {
  const t = T.topology
  const tris = t.triangles
  const root = T.pieceRoot, label = T.piece
  for (let i = 0; i < count; i++) root[i] = i
  for (let k = 0; k < t.triangleCount; k++) {
    const a = findRoot(root, tris[3 * k])
    const b = findRoot(root, tris[3 * k + 1])
    const c = findRoot(root, tris[3 * k + 2])
    const m = a < b ? (a < c ? a : c) : b < c ? b : c
    root[a] = m
    root[b] = m
    root[c] = m
  }
  let n = 0
  for (let i = 0; i < count; i++) {
    const r = findRoot(root, i)
    label[i] = r === i ? n++ : label[r]
  }
  T.pieceCount = n
}

function findRoot(root: Int32Array, i: number): number {
  while (root[i] !== i) {
    root[i] = root[root[i]]
    i = root[i]
  }
  return i
}

/** Re-reads every constraint from the triangles, duplicates split edges, drops broken supports. */
function repairConstraints(T: ClothTear): void {
  const t = T.topology
  const tris = t.triangles
  t.stretchCount = repairPairs(T.stretch, tris)
  t.edgeCount = repairPairs(T.edges, tris)
  t.distCount = repairPairs(T.dist, tris)
  t.compCount = repairPairs(T.comp, tris)
  t.lineCount = repairLines(T.lines, tris)
  t.hingeCount = repairHinges(T.hinges, tris)
}

function repairPairs(s: PairSet, tris: Uint32Array): number {
  // 1. edges whose two triangles came apart get a second constraint, one per side
  const n = s.count
  for (let k = 0; k < n; k++) {
    const t2 = s.twinT[k]
    if (t2 < 0) continue
    const t1 = s.endT[2 * k]
    const a1 = tris[3 * t1 + s.endC[2 * k]], b1 = tris[3 * t1 + s.endC[2 * k + 1]]
    const a2 = tris[3 * t2 + s.twinC[2 * k]], b2 = tris[3 * t2 + s.twinC[2 * k + 1]]
    if (a1 === a2 && b1 === b2) continue
    s.twinT[k] = -1
    if (s.count >= s.cap) continue // out of room: this side keeps no constraint on the edge
    const m = s.count++
    copyPair(s, k, m)
    s.endT[2 * m] = t2
    s.endT[2 * m + 1] = t2
    s.endC[2 * m] = s.twinC[2 * k]
    s.endC[2 * m + 1] = s.twinC[2 * k + 1]
    s.twinT[m] = -1
    if (s.over !== null) s.over[m] = 0
  }
  // 2. re-read particles, drop the unsupported, compact in order
  let w = 0
  const chkT = s.chkT, chkC = s.chkC
  for (let k = 0; k < s.count; k++) {
    let ok = true
    for (let j = 0; j < 4; j += 2) {
      const ta = chkT[4 * k + j]
      if (ta < 0) continue
      const tb = chkT[4 * k + j + 1]
      if (tris[3 * ta + chkC[4 * k + j]] !== tris[3 * tb + chkC[4 * k + j + 1]]) ok = false
    }
    if (!ok) continue
    if (w !== k) copyPair(s, k, w)
    const tA = s.endT[2 * w]
    if (tA >= 0) {
      s.ids[2 * w] = s.scale * tris[3 * tA + s.endC[2 * w]]
      s.ids[2 * w + 1] = s.scale * tris[3 * s.endT[2 * w + 1] + s.endC[2 * w + 1]]
    }
    w++
  }
  s.count = w
  return w
}

function copyPair(s: PairSet, from: number, to: number): void {
  s.ids[2 * to] = s.ids[2 * from]
  s.ids[2 * to + 1] = s.ids[2 * from + 1]
  for (let i = 0; i < s.f64.length; i++) s.f64[i][to] = s.f64[i][from]
  for (let i = 0; i < s.u8.length; i++) s.u8[i][to] = s.u8[i][from]
  s.endT[2 * to] = s.endT[2 * from]
  s.endT[2 * to + 1] = s.endT[2 * from + 1]
  s.endC[2 * to] = s.endC[2 * from]
  s.endC[2 * to + 1] = s.endC[2 * from + 1]
  for (let j = 0; j < 4; j++) {
    s.chkT[4 * to + j] = s.chkT[4 * from + j]
    s.chkC[4 * to + j] = s.chkC[4 * from + j]
  }
  s.twinT[to] = s.twinT[from]
  s.twinC[2 * to] = s.twinC[2 * from]
  s.twinC[2 * to + 1] = s.twinC[2 * from + 1]
}

/** Drops triples whose middle particle was split between their two supports, re-reads the rest. */
function repairLines(l: LineSet, tris: Uint32Array): number {
  let w = 0
  for (let k = 0; k < l.count; k++) {
    if (tris[3 * l.chkT[2 * k] + l.chkC[2 * k]] !== tris[3 * l.chkT[2 * k + 1] + l.chkC[2 * k + 1]]) continue
    if (w !== k) {
      for (let j = 0; j < 3; j++) l.endC[3 * w + j] = l.endC[3 * k + j]
      for (let j = 0; j < 2; j++) {
        l.endT[2 * w + j] = l.endT[2 * k + j]
        l.chkT[2 * w + j] = l.chkT[2 * k + j]
        l.chkC[2 * w + j] = l.chkC[2 * k + j]
      }
      for (let i = 0; i < l.f64.length; i++) l.f64[i][w] = l.f64[i][k]
    }
    const A = 3 * l.endT[2 * w], B = 3 * l.endT[2 * w + 1]
    l.ids[3 * w] = tris[A + l.endC[3 * w]]
    l.ids[3 * w + 1] = tris[A + l.endC[3 * w + 1]]
    l.ids[3 * w + 2] = tris[B + l.endC[3 * w + 2]]
    w++
  }
  l.count = w
  return w
}

function repairHinges(h: HingeSet, tris: Uint32Array): number {
  let w = 0
  for (let k = 0; k < h.count; k++) {
    const ta = h.chkT[4 * k], tb = h.chkT[4 * k + 1]
    if (tris[3 * ta + h.chkC[4 * k]] !== tris[3 * tb + h.chkC[4 * k + 1]]) continue
    if (tris[3 * h.chkT[4 * k + 2] + h.chkC[4 * k + 2]] !== tris[3 * h.chkT[4 * k + 3] + h.chkC[4 * k + 3]]) continue
    if (w !== k) {
      for (let j = 0; j < 4; j++) {
        h.endC[4 * w + j] = h.endC[4 * k + j]
        h.chkT[4 * w + j] = h.chkT[4 * k + j]
        h.chkC[4 * w + j] = h.chkC[4 * k + j]
      }
      h.endT[2 * w] = h.endT[2 * k]
      h.endT[2 * w + 1] = h.endT[2 * k + 1]
      for (let i = 0; i < h.f64.length; i++) h.f64[i][w] = h.f64[i][k]
    }
    const A = 3 * h.endT[2 * w], B = 3 * h.endT[2 * w + 1]
    h.ids[4 * w] = tris[A + h.endC[4 * w]]
    h.ids[4 * w + 1] = tris[A + h.endC[4 * w + 1]]
    h.ids[4 * w + 2] = tris[A + h.endC[4 * w + 2]]
    h.ids[4 * w + 3] = tris[B + h.endC[4 * w + 3]]
    w++
  }
  h.count = w
  return w
}

// ---------------------------------------------------------------------------------------------
// Reservation and supports (creation time: allocation allowed)

function grow<T extends Float64Array | Int32Array | Uint32Array | Uint8Array | Uint16Array>(a: T, n: number): T {
  const out = new (a.constructor as new (n: number) => T)(Math.max(n, a.length))
  out.set(a)
  return out
}

function reserve(c: ClothState, extra: number, maxTears: number): void {
  const src = c.topology
  const P = c.count + extra
  const room = 4 * extra
  const E = src.edgeCount + room, S = src.stretchCount + room, D = src.distCount + room, C = src.compCount + room
  const t: TearTopology = {
    ...src,
    particleCount: c.count,
    restPositions: grow(src.restPositions, 3 * P),
    masses: grow(src.masses, P),
    triangles: Uint32Array.from(src.triangles),
    edges: grow(src.edges.subarray(0, 2 * src.edgeCount), 2 * E),
    edgeRest: grow(src.edgeRest.subarray(0, src.edgeCount), E),
    stretchIds: grow(src.stretchIds.subarray(0, 2 * src.stretchCount), 2 * S),
    stretchRest: grow(src.stretchRest.subarray(0, src.stretchCount), S),
    distOffsets: grow(src.distOffsets.subarray(0, 2 * src.distCount), 2 * D),
    distRest: grow(src.distRest.subarray(0, src.distCount), D),
    distCompliance: grow(src.distCompliance.subarray(0, src.distCount), D),
    distKind: grow(src.distKind.subarray(0, src.distCount), D),
    compIds: grow(src.compIds.subarray(0, 2 * src.compCount), 2 * C),
    compRest: grow(src.compRest.subarray(0, src.compCount), C),
    compCompliance: grow(src.compCompliance.subarray(0, src.compCount), C),
    lineIds: Int32Array.from(src.lineIds.subarray(0, 3 * src.lineCount)),
    lineRest: Float64Array.from(src.lineRest.subarray(0, src.lineCount)),
    lineCompliance: Float64Array.from(src.lineCompliance.subarray(0, src.lineCount)),
    hingeIds: Int32Array.from(src.hingeIds.subarray(0, 4 * src.hingeCount)),
    hingeRest: Float64Array.from(src.hingeRest.subarray(0, src.hingeCount)),
    hingeCompliance: Float64Array.from(src.hingeCompliance.subarray(0, src.hingeCount)),
  }
  const mesh = new MeshIndex(t.triangles, t.triangleCount)
  const over = new Uint8Array(E)
  const stretch = pairSet(t.stretchIds, 1, t.stretchCount, S, [t.stretchRest], [], null, mesh, t.restPositions)
  const edges = pairSet(t.edges, 1, t.edgeCount, E, [t.edgeRest], [over], over, mesh, t.restPositions)
  const dist = pairSet(t.distOffsets, 3, t.distCount, D, [t.distRest, t.distCompliance], [t.distKind], null, mesh, t.restPositions)
  const comp = pairSet(t.compIds, 1, t.compCount, C, [t.compRest, t.compCompliance], [], null, mesh, t.restPositions)
  const lines = lineSet(t, mesh)
  t.lineCount = lines.count
  const hinges = hingeSet(t, mesh)
  t.hingeCount = hinges.count

  // the cloth's particle arrays, at capacity
  c.pos = grow(c.pos, 3 * P)
  c.prev = grow(c.prev, 3 * P)
  c.vel = grow(c.vel, 3 * P)
  c.invMass = grow(c.invMass, P)
  c.baseInvMass = grow(c.baseInvMass, P)
  c.invMass3 = grow(c.invMass3, 3 * P)
  c.pinCount = grow(c.pinCount, P)
  c.distLambda = new Float64Array(D)
  c.compLambda = new Float64Array(C)
  c.lineLambda = new Float64Array(Math.max(1, t.lineCount))
  c.hingeLambda = new Float64Array(Math.max(1, t.hingeCount))
  c.renderPos = new Float32Array(3 * P)
  c.renderNormal = new Float32Array(3 * P)
  c.renderIndex = t.triangles
  c.mesh = null
  c.renderedVersion = -1
  c.topology = t

  c.tear = {
    enabled: true,
    topology: t,
    particleCapacity: P,
    stretch,
    edges,
    dist,
    comp,
    lines,
    hinges,
    over,
    fan: new Int32Array(t.triangleCount),
    fanCorner: new Uint8Array(t.triangleCount),
    fanSide: new Uint8Array(t.triangleCount),
    cand: new Int32Array(2 * maxTears + 4),
    candRatio: new Float64Array(2 * maxTears + 4),
    params: new Float64Array(3),
    ...tetherStore(P, E, c.tethersPerParticle),
    piece: new Int32Array(P),
    pieceCount: 1,
    pieceRoot: new Int32Array(P),
    pieceBox: new Float64Array(7 * P),
  }
  // the guard's copies at capacity too (no allocation when the torn cloth's pose is kept)
  const g = c.guard
  g.rest = grow(g.rest, 3 * P)
  g.safe = grow(g.safe, 3 * P)
  labelPieces(c.tear, c.count)
  c.tethersDirty = true
}

/** Triangles around each edge and vertex of a mesh (creation time). */
class MeshIndex {
  /** Triangles holding edge (min, max): key min·2²⁶… as a string-free number key. */
  readonly edgeTris = new Map<number, number[]>()
  readonly neighbours = new Map<number, Set<number>>()
  /** Across-edge pairs: key of (w0, w1) → [e0, e1, tA (holds w0), tB (holds w1)]. */
  readonly wings = new Map<number, [number, number, number, number]>()
  constructor(readonly tris: Uint32Array, triCount: number) {
    for (let t = 0; t < triCount; t++) {
      for (let k = 0; k < 3; k++) {
        const a = tris[3 * t + k], b = tris[3 * t + ((k + 1) % 3)]
        const key = pairKey(a, b)
        let list = this.edgeTris.get(key)
        if (!list) this.edgeTris.set(key, (list = []))
        list.push(t)
        this.link(a, b)
      }
    }
    for (const [key, list] of this.edgeTris) {
      if (list.length !== 2) continue
      const e0 = Math.floor(key / KEY), e1 = key % KEY
      const w0 = this.third(list[0], e0, e1), w1 = this.third(list[1], e0, e1)
      const wk = pairKey(w0, w1)
      if (!this.wings.has(wk)) this.wings.set(wk, w0 < w1 ? [e0, e1, list[0], list[1]] : [e0, e1, list[1], list[0]])
    }
  }
  private link(a: number, b: number): void {
    let s = this.neighbours.get(a)
    if (!s) this.neighbours.set(a, (s = new Set()))
    s.add(b)
    let r = this.neighbours.get(b)
    if (!r) this.neighbours.set(b, (r = new Set()))
    r.add(a)
  }
  corner(t: number, v: number): number {
    const tr = this.tris
    return tr[3 * t] === v ? 0 : tr[3 * t + 1] === v ? 1 : tr[3 * t + 2] === v ? 2 : -1
  }
  third(t: number, a: number, b: number): number {
    for (let k = 0; k < 3; k++) {
      const v = this.tris[3 * t + k]
      if (v !== a && v !== b) return v
    }
    return -1
  }
  /** True when triangle t runs a → b in its winding. */
  runs(t: number, a: number, b: number): boolean {
    const ca = this.corner(t, a)
    return ca >= 0 && this.tris[3 * t + ((ca + 1) % 3)] === b
  }
}

const KEY = 1 << 26
function pairKey(a: number, b: number): number {
  return a < b ? a * KEY + b : b * KEY + a
}

function pairSet(
  ids: Int32Array, scale: number, count: number, cap: number, f64: Float64Array[], u8: Uint8Array[], over: Uint8Array | null,
  mesh: MeshIndex, rest: Float64Array,
): PairSet {
  const s: PairSet = {
    ids, scale, f64, u8, over, count, cap,
    endT: new Int32Array(2 * cap).fill(-1),
    endC: new Uint8Array(2 * cap),
    chkT: new Int32Array(4 * cap).fill(-1),
    chkC: new Uint8Array(4 * cap),
    twinT: new Int32Array(cap).fill(-1),
    twinC: new Uint8Array(2 * cap),
  }
  for (let k = 0; k < count; k++) {
    const a = ids[2 * k] / scale, b = ids[2 * k + 1] / scale
    const tris = mesh.edgeTris.get(pairKey(a, b))
    if (tris) {
      // an edge: read from its first triangle; the second one is its twin
      const t1 = tris[0]
      s.endT[2 * k] = s.endT[2 * k + 1] = t1
      s.endC[2 * k] = mesh.corner(t1, a)
      s.endC[2 * k + 1] = mesh.corner(t1, b)
      if (tris.length === 2) {
        s.twinT[k] = tris[1]
        s.twinC[2 * k] = mesh.corner(tris[1], a)
        s.twinC[2 * k + 1] = mesh.corner(tris[1], b)
      }
      continue
    }
    const wing = mesh.wings.get(pairKey(a, b))
    if (wing) {
      // across an edge: a in one triangle, b in the other, and they must still share the edge
      const [e0, e1, t0, t1] = wing
      const tA = mesh.corner(t0, a) >= 0 ? t0 : t1, tB = tA === t0 ? t1 : t0
      s.endT[2 * k] = tA
      s.endT[2 * k + 1] = tB
      s.endC[2 * k] = mesh.corner(tA, a)
      s.endC[2 * k + 1] = mesh.corner(tB, b)
      setCheck(s.chkT, s.chkC, 4 * k, tA, mesh.corner(tA, e0), tB, mesh.corner(tB, e0))
      setCheck(s.chkT, s.chkC, 4 * k + 2, tA, mesh.corner(tA, e1), tB, mesh.corner(tB, e1))
      continue
    }
    // skip-one: a – m – b along two edges that must keep meeting at the same m
    const na = mesh.neighbours.get(a), nb = mesh.neighbours.get(b)
    if (!na || !nb) continue
    let m = -1, best = Infinity
    for (const x of na) {
      if (!nb.has(x)) continue
      let d = 0
      for (let j = 0; j < 3; j++) {
        const mid = 0.5 * (rest[3 * a + j] + rest[3 * b + j]) - rest[3 * x + j]
        d += mid * mid
      }
      if (d < best) {
        best = d
        m = x
      }
    }
    if (m < 0) continue
    const ta = mesh.edgeTris.get(pairKey(a, m))!, tb = mesh.edgeTris.get(pairKey(m, b))!
    // take both triangles from the same side of the line a – m – b (same winding direction)
    let tA = ta[0], tB = -1
    const forward = mesh.runs(tA, a, m)
    for (const x of tb) if (mesh.runs(x, m, b) === forward) tB = x
    if (tB < 0) tB = tb[0]
    s.endT[2 * k] = tA
    s.endT[2 * k + 1] = tB
    s.endC[2 * k] = mesh.corner(tA, a)
    s.endC[2 * k + 1] = mesh.corner(tB, b)
    setCheck(s.chkT, s.chkC, 4 * k, tA, mesh.corner(tA, m), tB, mesh.corner(tB, m))
  }
  return s
}

function setCheck(chkT: Int32Array, chkC: Uint8Array, o: number, ta: number, ca: number, tb: number, cb: number): void {
  chkT[o] = ta
  chkT[o + 1] = tb
  chkC[o] = ca
  chkC[o + 1] = cb
}

function lineSet(t: TearTopology, mesh: MeshIndex): LineSet {
  const n = t.lineCount
  const l: LineSet = {
    ids: t.lineIds,
    f64: [t.lineRest, t.lineCompliance],
    count: n,
    endT: new Int32Array(2 * n),
    endC: new Uint8Array(3 * n),
    chkT: new Int32Array(2 * n),
    chkC: new Uint8Array(2 * n),
  }
  let w = 0
  for (let k = 0; k < n; k++) {
    const a = t.lineIds[3 * k], v = t.lineIds[3 * k + 1], b = t.lineIds[3 * k + 2]
    const ta = mesh.edgeTris.get(pairKey(a, v)), tb = mesh.edgeTris.get(pairKey(v, b))
    if (!ta || !tb) continue // not along mesh edges (quad grids' rows are): keep no support, drop
    // both triangles from the same side of the line a – v – b (same winding direction)
    const tA = ta[0]
    const forward = mesh.runs(tA, a, v)
    let tB = -1
    for (const x of tb) if (mesh.runs(x, v, b) === forward) tB = x
    if (tB < 0) tB = tb[0]
    for (let j = 0; j < 3; j++) t.lineIds[3 * w + j] = t.lineIds[3 * k + j]
    t.lineRest[w] = t.lineRest[k]
    t.lineCompliance[w] = t.lineCompliance[k]
    l.endT[2 * w] = tA
    l.endT[2 * w + 1] = tB
    l.endC[3 * w] = mesh.corner(tA, a)
    l.endC[3 * w + 1] = mesh.corner(tA, v)
    l.endC[3 * w + 2] = mesh.corner(tB, b)
    l.chkT[2 * w] = tA
    l.chkT[2 * w + 1] = tB
    l.chkC[2 * w] = mesh.corner(tA, v)
    l.chkC[2 * w + 1] = mesh.corner(tB, v)
    w++
  }
  l.count = w
  return l
}

function hingeSet(t: TearTopology, mesh: MeshIndex): HingeSet {
  const n = t.hingeCount
  const h: HingeSet = {
    ids: t.hingeIds,
    f64: [t.hingeRest, t.hingeCompliance],
    count: n,
    endT: new Int32Array(2 * n),
    endC: new Uint8Array(4 * n),
    chkT: new Int32Array(4 * n),
    chkC: new Uint8Array(4 * n),
  }
  let w = 0
  for (let k = 0; k < n; k++) {
    const e0 = t.hingeIds[4 * k], e1 = t.hingeIds[4 * k + 1], w0 = t.hingeIds[4 * k + 2], w1 = t.hingeIds[4 * k + 3]
    const list = mesh.edgeTris.get(pairKey(e0, e1))
    if (!list) continue
    let tA = -1, tB = -1
    for (const x of list) {
      if (mesh.corner(x, w0) >= 0) tA = x
      if (mesh.corner(x, w1) >= 0) tB = x
    }
    if (tA < 0 || tB < 0) continue
    for (let j = 0; j < 4; j++) t.hingeIds[4 * w + j] = t.hingeIds[4 * k + j]
    t.hingeRest[w] = t.hingeRest[k]
    t.hingeCompliance[w] = t.hingeCompliance[k]
    h.endT[2 * w] = tA
    h.endT[2 * w + 1] = tB
    h.endC[4 * w] = mesh.corner(tA, e0)
    h.endC[4 * w + 1] = mesh.corner(tA, e1)
    h.endC[4 * w + 2] = mesh.corner(tA, w0)
    h.endC[4 * w + 3] = mesh.corner(tB, w1)
    setCheck(h.chkT, h.chkC, 4 * w, tA, mesh.corner(tA, e0), tB, mesh.corner(tB, e0))
    setCheck(h.chkT, h.chkC, 4 * w + 2, tA, mesh.corner(tA, e1), tB, mesh.corner(tB, e1))
    w++
  }
  h.count = w
  return h
}

// ---------------------------------------------------------------------------------------------
// Tethers of a tearable cloth, rebuilt into reserved arrays

/**
 * Rebuilds a tearable cloth's tethers without allocating: each free particle is tied to the
 * `perParticle` pinned particles nearest to it along the split mesh (multi-source Dijkstra on a
 * typed-array heap), with the straight rest distance ('euclidean') or the path length
 * ('geodesic'). Measured along the mesh, the nearest anchors are never across a tear and never in
 * another piece, so torn pieces hang free and a crack is not held shut by the pins on its far
 * side. Runs in the sync phase after pins changed or the cloth tore.
 */
export function rebuildTearTethers(state: ClothWorldState, c: ClothState): void {
  const T = c.tear!
  // more tethers per particle than reserved (setClothTethers, a restored snapshot): reserve again
  if (c.tethersPerParticle > T.scratch.kCap) reserveTearTethers(T, c.tethersPerParticle)
  const t = T.topology
  const s = T.scratch
  const out = T.tethers
  const n = c.count
  const K = c.tethersPerParticle
  let A = 0
  for (let i = 0; i < n; i++) if (c.pinCount[i] > 0) s.anchors[A++] = i
  out.count = 0
  c.tethers = out
  state.stats.tetherRebuilds++
  if (A === 0) return
  // anchors chosen along the split mesh (so a tether never reaches across a tear, and never into
  // another piece); the rest length is the straight distance ('euclidean') or the path ('geodesic')
  const rest = t.restPositions
  nearestAnchorsAlongMesh(rest, n, t.edges, t.edgeCount, s, A, K)
  const best = s.bestAnchor, dist = s.bestDist
  const straight = c.tetherMode !== 'geodesic'
  const slack = 1 + c.tetherSlack
  let m = 0
  for (let i = 0; i < n; i++) {
    if (c.pinCount[i] > 0) continue
    for (let k = 0; k < K; k++) {
      const a = best[i * K + k]
      if (a < 0) continue
      out.particle[m] = i
      out.anchor[m] = a
      let d = dist[i * K + k]
      if (straight) {
        const dx = rest[3 * a] - rest[3 * i], dy = rest[3 * a + 1] - rest[3 * i + 1], dz = rest[3 * a + 2] - rest[3 * i + 2]
        d = Math.sqrt(dx * dx + dy * dy + dz * dz)
      }
      out.rest[m] = d * slack
      m++
    }
  }
  out.count = m
}

/** Reserves a tearable cloth's tether arrays again for `perParticle` tethers per particle at its particle capacity. */
function reserveTearTethers(T: ClothTear, perParticle: number): void {
  Object.assign(T, tetherStore(T.particleCapacity, T.topology.edges.length / 2, perParticle))
}

/** Tether arrays and their scratch for P particles, E mesh edges and K tethers per particle. */
function tetherStore(P: number, E: number, K: number): { tethers: TetherSet; scratch: AnchorScratch } {
  return {
    tethers: { particle: new Int32Array(P * K), anchor: new Int32Array(P * K), rest: new Float64Array(P * K), count: 0 },
    scratch: createAnchorScratch(P, E, K),
  }
}

/** Tears so far of a tearable cloth (0 for any other cloth). */
export function getClothTearCount(world: object, cloth: number): number {
  const state = getClothWorld(world)
  const c = getCloth(state, cloth)
  return c.tear ? state.components.Tearable.tears[cloth] : 0
}
