import { addComponent, hasComponent, removeComponent } from 'bitecs'
import { clothLayersMatch, selfReaches } from './reach'
import { B_MAX_DEV, B_MEAN_V, B_REFRESH, type CollisionWorld, type SelfCollisionState, type SelfSweep } from './types'
import { ClothError, MAX_COORDINATE, checkAtMost, checkKeys, checkNonNegative, checkPositive, keysOf } from '../../core/errors'
import {
  S_DIST,
  S_INV_CELL,
  S_LIMIT,
  S_MU_K,
  S_CONTACT_SCALE,
  S_MU_S,
  S_RADIUS,
  S_REST_FILTER,
  S_SLOP,
  S_W_A,
  S_W_B,
  buildHash,
  clampRelativeMotion,
  gatherPairs,
  solvePairs,
} from '../../kernels/selfCollide'
import { pairsByFirst, sweepPairs } from '../../kernels/sweep'
import { getCloth, getClothWorld, getClothWorldForChange } from '../../world/access'
import { growStores } from '../../world/capacity'
import type { ClothState, ClothWorldState } from '../../world/state'
import { wakeClothState } from '../../world/wake'
import { newArray, touchLayout } from '../../core/shared'

/**
 * How far particles may travel relative to their cloth's mean motion within one fixed step, in
 * collision distances D: the step's measured spread of velocities × TRAVEL_GAIN plus TRAVEL_FLOOR.
 * Pairs are gathered within D + 2·travel. When that travel exceeds TRAVEL_CAP, the step is split
 * into up to MAX_REBUILDS intervals, each with its own hash and pair list (fast motion costs more
 * gathers, slow motion one). Predicted relative motion beyond the allowance is clamped (see
 * `clampSelfCollidingMotion`), so at most 4·D per step: 4 × 1.6 cm × 60 Hz ≈ 3.8 m/s for a 64×64
 * metre sheet.
 */
const TRAVEL_GAIN = 1.5
const TRAVEL_FLOOR = 0.25
const TRAVEL_CAP = 1
const MAX_REBUILDS = 4
/** Inverse-mass scale in particle pairs of a particle resting on a collider (see S_CONTACT_SCALE). */
const CONTACT_MASS_SCALE = 0.2
/** Speed, m/s, up to which a pair's push-out becomes velocity (see S_SLOP). */
const DEPENETRATION_SPEED = 0.5
/**
 * Self pairs closer than this × the thickness in the rest shape are never pushed apart: at the
 * default thickness (the particle spacing) these are the direct and diagonal mesh neighbours,
 * which the distance constraints already keep apart. Skipping them keeps collisions from fighting
 * the constraints, and a flat or gently curved cloth from paying for pairs that never touch.
 */
export const REST_FILTER = 1.5
/** Pair list capacity per particle (self pairs; cross-cloth pairs get the same again). */
const PAIRS_PER_PARTICLE = 48

/** Options of `enableSelfCollision`. */
export interface SelfCollisionOptions {
  /**
   * Smallest distance kept between two particles, m. Default: the cloth's mean edge length (its
   * particle spacing), the least that keeps layers from slipping between particles.
   */
  thickness?: number
  /** Kinetic friction between touching particles; default the material's `friction`. */
  friction?: number
  /** Static friction; default equal to the kinetic one. */
  staticFriction?: number
}

const SELF_KEYS = keysOf<SelfCollisionOptions>({ thickness: true, friction: true, staticFriction: true })

/**
 * Turns on self-collision for a cloth (adds its SelfCollision component): particles are kept
 * `thickness` apart from each other, and from the particles of every other cloth that has it on
 * (where layers and masks allow). Calling it again updates the settings.
 *
 * @example enableSelfCollision(world, curtain, { thickness: 0.02 })
 */
export function enableSelfCollision(world: object, cloth: number, options: SelfCollisionOptions = {}): void {
  const state = getClothWorldForChange(world)
  const c = getCloth(state, cloth)
  if (typeof options !== 'object' || options === null) throw new ClothError('options', options, 'must be an object')
  checkKeys('options', options, SELF_KEYS)
  const thickness = options.thickness === undefined ? 0
    : checkAtMost('options.thickness', checkPositive('options.thickness', options.thickness), MAX_COORDINATE, ' m')
  const friction = options.friction === undefined ? -1 : checkNonNegative('options.friction', options.friction)
  const staticFriction = options.staticFriction === undefined ? -1 : checkNonNegative('options.staticFriction', options.staticFriction)
  const cw = state.collision
  growStores(state, cloth)
  const S = cw.SelfCollision
  S.thickness[cloth] = thickness
  S.friction[cloth] = friction
  S.staticFriction[cloth] = staticFriction
  if (hasComponent(world as never, cloth, S)) allocateSelfCollision(state, c)
  else addComponent(world as never, cloth, S)
}

/** Turns self-collision off for a cloth (removes its SelfCollision component). */
export function disableSelfCollision(world: object, cloth: number): void {
  const state = getClothWorldForChange(world)
  getCloth(state, cloth)
  const S = state.collision.SelfCollision
  if (hasComponent(world as never, cloth, S)) removeComponent(world as never, cloth, S)
}

/** Whether a cloth has self-collision on. */
export function hasSelfCollision(world: object, cloth: number): boolean {
  return getCloth(getClothWorld(world), cloth).collision.self !== null
}

/** Called when a SelfCollision component is added (or its settings change): sizes the hash and pair lists. */
export function allocateSelfCollision(state: ClothWorldState, c: ClothState): void {
  wakeClothState(state, c)
  const cw = state.collision
  const S = cw.SelfCollision
  const eid = c.eid
  const n = c.pos.length / 3
  const t = c.topology
  let spacing = 0
  for (let k = 0; k < t.stretchCount; k++) spacing += t.stretchRest[k]
  spacing = t.stretchCount > 0 ? spacing / t.stretchCount : 2 * c.material.thickness
  const friction = S.friction[eid] >= 0 ? S.friction[eid] : c.material.friction
  let table = 16
  while (table < 8 * n) table *= 2 // sparse: fewer particles of other cells in a scanned bucket
  const capacity = PAIRS_PER_PARTICLE * n
  const old = c.collision.self
  const st: SelfCollisionState = {
    thickness: S.thickness[eid] > 0 ? S.thickness[eid] : spacing,
    friction,
    staticFriction: S.staticFriction[eid] >= 0 ? S.staticFriction[eid] : friction,
    mask: table - 1,
    start: old && old.start.length === table + 1 ? old.start : newArray(Int32Array, table + 1),
    visited: old && old.visited.length === table + 1 ? old.visited : newArray(Int32Array, table + 1),
    entries: old && old.entries.length === n ? old.entries : newArray(Int32Array, n),
    hashed: 0,
    bucket: old && old.bucket.length === n ? old.bucket : newArray(Int32Array, n),
    sorted: old && old.sorted.length === 3 * n ? old.sorted : newArray(Float64Array, 3 * n),
    pairs: old && old.capacity === capacity ? old.pairs : newArray(Int32Array, 2 * capacity),
    capacity,
    pairCount: 0,
    cross: old ? old.cross : newArray(Int32Array, 0),
    crossCapacity: old ? old.crossCapacity : 0,
    crossCount: 0,
    blocks: old ? old.blocks : newArray(Int32Array, 0),
    blockCount: 0,
    values: newArray(Float64Array, 4),
    touched: old && old.touched.length === n ? old.touched : newArray(Uint8Array, n),
  }
  c.collision.self = st
  if (cw.selfCloths.indexOf(c) < 0) {
    let k = cw.selfCloths.length
    while (k > 0 && cw.selfCloths[k - 1].seq > c.seq) k--
    cw.selfCloths.splice(k, 0, c)
  }
  // cloth–cloth pairs need room once two cloths collide with each other
  const m = cw.selfCloths.length
  for (let k = 0; k < m; k++) {
    const other = cw.selfCloths[k].collision.self!
    if (other.blocks.length < 3 * m) other.blocks = newArray(Int32Array, 3 * m)
    // (again when a cloth grew: tearing reserves more particles, whatever came first)
    if (m >= 2 && other.crossCapacity < PAIRS_PER_PARTICLE * other.bucket.length) {
      other.crossCapacity = PAIRS_PER_PARTICLE * other.bucket.length
      other.cross = newArray(Int32Array, 2 * other.crossCapacity)
    }
  }
}

/** Called when a SelfCollision component (or its cloth) goes away. */
export function releaseSelfCollision(state: ClothWorldState, c: ClothState): void {
  const cw = state.collision
  wakeSelfNeighbours(state, c)
  const k = cw.selfCloths.indexOf(c)
  if (k >= 0) cw.selfCloths.splice(k, 1)
  touchLayout()
  wakeClothState(state, c)
  if (c.collision) c.collision.self = null
  for (let q = 0; q < cw.selfCloths.length; q++) cw.selfCloths[q].collision.self!.blockCount = 0
}

/**
 * Wakes the sleeping self-colliding cloths within reach of the self-colliding cloth `c`, which is
 * about to go, to stop colliding or to be moved away: one asleep on it would stay asleep where it
 * lay (a napkin on a hammock removed, teleported or made not to collide hung in the air).
 */
export function wakeSelfNeighbours(state: ClothWorldState, c: ClothState): void {
  if (c.collision.self === null) return
  const group = state.collision.selfCloths
  for (let q = 0; q < group.length; q++) {
    const o = group[q]
    if (o !== c && o.sleep.asleep && selfReaches(c, o)) wakeClothState(state, o)
  }
}

/**
 * Once per fixed step (after the cloth bounds are measured): picks each self-colliding cloth's
 * travel allowance from the spread of its velocities (and how many times to rebuild its pairs this
 * step), builds its spatial hash (pair radius = collision distance + 2 × travel, cells twice that)
 * and gathers its pairs, then the pairs between overlapping cloths. An idle cloth (asleep,
 * frozen) keeps its hash; next to a running one it is an immovable obstacle (a sleeper until the
 * sync phase wakes it).
 */
export function buildSelfCollisionPairs(state: ClothWorldState): void {
  const cw = state.collision
  const sp = cw.selfParams
  const group = cw.selfCloths
  for (let a = 0; a < group.length; a++) {
    const c = group[a]
    const refresh = c.collision.bounds
    if (c.idle && refresh[B_REFRESH] === 0) continue // keeps its last hash (it has not moved since)
    refresh[B_REFRESH] = 0
    const st = c.collision.self!
    const D = st.thickness
    const dt = c.h * c.substeps // the cloth's step (longer when it steps every n-th)
    let travel = TRAVEL_GAIN * c.collision.bounds[B_MAX_DEV] * dt + TRAVEL_FLOOR * D
    let intervals = Math.ceil(travel / (TRAVEL_CAP * D))
    const most = c.substeps < MAX_REBUILDS ? c.substeps : MAX_REBUILDS
    if (intervals > most) intervals = most
    if (travel > intervals * TRAVEL_CAP * D) travel = intervals * TRAVEL_CAP * D
    const v = st.values
    v[1] = travel / intervals
    v[0] = 2 * (D + 2 * v[1]) // cells twice the pair radius: a query spans 1–2 cells per axis
    v[2] = intervals
    v[3] = travel
    rebuildSelfPairs(c, st, sp)
  }
  const sw = overlapsAlongX(cw)
  for (let a = 0; a < group.length; a++) {
    const A = group[a]
    const ca = A.collision!
    const st = ca.self!
    st.crossCount = 0
    st.blockCount = 0
    // (the partners whose extents along x overlap, ascending: the pairs and their order of a loop over all b > a)
    for (let p = sw.head[a]; p < sw.head[a + 1]; p++) {
      const b = sw.list[p]
      const B = group[b]
      if (A.idle && B.idle) continue
      const cb = B.collision!
      if (!clothLayersMatch(ca, cb)) continue
      const sb = cb.self!
      const ba = ca.bounds, bb = cb.bounds
      const D = 0.5 * (st.thickness + sb.thickness)
      if (ba[0] > bb[3] + D || bb[0] > ba[3] + D || ba[1] > bb[4] + D || bb[1] > ba[4] + D || ba[2] > bb[5] + D || bb[2] > ba[5] + D)
        continue
      // both cloths' travel over the whole step plus their mean motion toward each other
      const vx = ba[B_MEAN_V] - bb[B_MEAN_V], vy = ba[B_MEAN_V + 1] - bb[B_MEAN_V + 1], vz = ba[B_MEAN_V + 2] - bb[B_MEAN_V + 2]
      const dtA = A.h * A.substeps, dtB = B.h * B.substeps
      let R = D + st.values[3] + sb.values[3] + 1.25 * Math.sqrt(vx * vx + vy * vy + vz * vz) * (dtA > dtB ? dtA : dtB)
      if (R > D + 2 * sb.values[0]) R = D + 2 * sb.values[0]
      sp[S_RADIUS] = R
      sp[S_INV_CELL] = 1 / sb.values[0]
      const first = st.crossCount
      st.crossCount = gatherPairs(
        st.sorted,
        st.entries,
        A.invMass,
        st.hashed,
        null,
        sb.sorted,
        sb.entries,
        B.invMass,
        sb.start,
        sb.mask,
        sb.visited,
        st.cross,
        first,
        st.crossCapacity,
        sp,
      )
      if (st.crossCount === first) continue
      const o = 3 * st.blockCount++
      st.blocks[o] = b
      st.blocks[o + 1] = first
      st.blocks[o + 2] = st.crossCount - first
    }
  }
}

/**
 * The pairs of self-colliding cloths whose boxes overlap along x within the largest collision
 * distance, by first cloth (`SelfSweep.head`, `list`). With a loop over all pairs, 800 small
 * cloths hanging apart cost 2.31× the step without self-collision (320,000 box tests a step);
 * 2.02× so. Allocates only when the group or its pairs outgrow the scratch.
 */
function overlapsAlongX(cw: CollisionWorld<ClothState>): SelfSweep {
  const group = cw.selfCloths, sw = cw.sweep
  const n = group.length
  if (sw.count !== n) {
    // the group changed: its order starts afresh (the sort's result does not depend on it)
    if (sw.order.length < n) {
      sw.lo = new Float64Array(2 * n)
      sw.hi = new Float64Array(2 * n)
      sw.order = new Int32Array(2 * n)
      sw.head = new Int32Array(2 * n + 1)
    }
    for (let a = 0; a < n; a++) sw.order[a] = a
    sw.count = n
  }
  let margin = 0
  for (let a = 0; a < n; a++) {
    const c = group[a], b = c.collision.bounds
    const t = c.collision.self!.thickness
    if (t > margin) margin = t
    // (a cloth whose box is not a number overlaps every other, as the box test lets it)
    const broken = !(b[0] <= b[3])
    sw.lo[a] = broken ? -Infinity : b[0]
    sw.hi[a] = broken ? Infinity : b[3]
  }
  let m = sweepPairs(sw.lo, sw.hi, sw.order, n, margin, sw.pairs, sw.pairs.length >> 1)
  if (2 * m > sw.pairs.length) {
    sw.pairs = new Int32Array(4 * m)
    sw.list = new Int32Array(2 * m)
    m = sweepPairs(sw.lo, sw.hi, sw.order, n, margin, sw.pairs, sw.pairs.length >> 1)
  }
  pairsByFirst(sw.pairs, m, n, sw.head, sw.list)
  return sw
}

/** Builds a cloth's hash from its current positions and gathers its self pairs. */
function rebuildSelfPairs(c: ClothState, st: SelfCollisionState, sp: Float64Array): void {
  sp[S_INV_CELL] = 1 / st.values[0]
  st.hashed = buildHash(c.pos, c.count, st.start, st.entries, st.bucket, st.sorted, st.mask, sp, c.topology.unused)
  sp[S_RADIUS] = st.thickness + 2 * st.values[1]
  sp[S_REST_FILTER] = REST_FILTER * st.thickness
  st.pairCount = gatherPairs(
    st.sorted,
    st.entries,
    c.invMass,
    st.hashed,
    c.topology.restPositions,
    st.sorted,
    st.entries,
    c.invMass,
    st.start,
    st.mask,
    st.visited,
    st.pairs,
    0,
    st.capacity,
    sp,
  )
}

/**
 * Predict phase, for a self-colliding cloth: clamps its predicted motion relative to its mean motion
 * to its travel allowance (see `clampRelativeMotion`), before the solve. Not at the step's first
 * substep: the step's pairs are gathered after it, from where it left the particles (and the
 * allowance is measured then).
 */
export function clampSelfCollidingMotion(state: ClothWorldState, c: ClothState): void {
  if (c.subIndex === 0) return
  const st = c.collision.self!
  const sp = state.collision.selfParams
  sp[S_LIMIT] = st.values[3] / c.substeps
  clampRelativeMotion(c.pos, c.prev, c.invMass, c.count, sp, c.pins.list.length === 0)
}

/**
 * Every substep: rebuilds a fast cloth's pairs at its intervals, then pushes apart the cloth–cloth
 * pairs (a cloth sitting this substep out counts as immovable) and each running cloth's self pairs.
 */
export function solveSelfCollision(state: ClothWorldState): void {
  const cw = state.collision
  const sp = cw.selfParams
  const group = cw.selfCloths
  const stats = state.stats
  sp[S_CONTACT_SCALE] = CONTACT_MASS_SCALE
  for (let a = 0; a < group.length; a++) {
    const c = group[a]
    const k = c.subIndex
    if (k < 0) continue
    const st = c.collision.self!
    const v = st.values
    // fast motion: a fresh hash and pair list at each interval of the step
    const n = c.substeps, intervals = v[2]
    if (k > 0 && Math.floor((k * intervals) / n) !== Math.floor(((k - 1) * intervals) / n)) rebuildSelfPairs(c, st, sp)
  }
  for (let a = 0; a < group.length; a++) {
    const A = group[a]
    const st = A.collision.self!
    for (let q = 0; q < st.blockCount; q++) {
      const B = group[st.blocks[3 * q]]
      if (A.subIndex < 0 && B.subIndex < 0) continue
      const sb = B.collision.self!
      sp[S_DIST] = 0.5 * (st.thickness + sb.thickness)
      sp[S_MU_K] = Math.sqrt(st.friction * sb.friction)
      sp[S_MU_S] = Math.sqrt(st.staticFriction * sb.staticFriction)
      sp[S_SLOP] = DEPENETRATION_SPEED * Math.min(A.h, B.h)
      sp[S_W_A] = A.subIndex >= 0 ? 1 : 0
      sp[S_W_B] = B.subIndex >= 0 ? 1 : 0
      const count = st.blocks[3 * q + 2]
      solvePairs(A.pos, A.prev, A.invMass, st.touched, B.pos, B.prev, B.invMass, sb.touched, st.cross, st.blocks[3 * q + 1], count, sp)
      stats.selfCollisionTests += count
    }
  }
  for (let a = 0; a < group.length; a++) {
    const c = group[a]
    if (c.subIndex < 0) continue
    const st = c.collision.self!
    sp[S_DIST] = st.thickness
    sp[S_MU_K] = st.friction
    sp[S_MU_S] = st.staticFriction
    sp[S_SLOP] = DEPENETRATION_SPEED * c.h
    sp[S_W_A] = 1
    sp[S_W_B] = 1
    solvePairs(c.pos, c.prev, c.invMass, st.touched, c.pos, c.prev, c.invMass, st.touched, st.pairs, 0, st.pairCount, sp)
    stats.selfCollisionTests += st.pairCount
  }
}
