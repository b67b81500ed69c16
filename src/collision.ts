import { hasComponent, observe, onAdd, onRemove, removeComponent, entityExists } from 'bitecs'
import { SHAPE_BOX, SHAPE_CAPSULE, SHAPE_HULL, SHAPE_PLANE, SHAPE_SPHERE, createColliderStore, type ColliderStore } from '../components/Collider'
import { createSelfCollisionStore, type SelfCollisionStore } from '../components/SelfCollision'
import { checkAtMost, checkInteger, checkNonNegative, ClothError, MAX_COORDINATE } from './errors'
import {
  COLLIDE_SCRATCH,
  FRAME_SIZE,
  F_MU_K,
  F_MU_S,
  F_RADIUS,
  collideBox,
  collideCapsule,
  collideHull,
  collidePlane,
  collideSphere,
  measureCloth,
} from './kernels/collide'
import { fillColliderFrame, releaseCollider, sweepColliderBounds } from './colliders'
import { allocateSelfCollision, buildSelfCollisionPairs, releaseSelfCollision, solveSelfCollision, type SelfCollisionState } from './selfCollision'
import { SELF_PARAM_COUNT } from './kernels/selfCollide'
import { getCloth } from './pins'
import { ensureStoreCapacity } from './store'
import { getClothWorld, type ClothState, type ClothWorldState } from './state'
import { wakeClothState } from './sleep'

/**
 * Per-world collision state: the Collider and SelfCollision stores, colliders and self-colliding
 * cloths in creation order (the solver never iterates in query order), and scratch blocks for
 * the kernels. Lives on `ClothWorldState.collision`.
 */
export interface CollisionWorld {
  Collider: ColliderStore
  SelfCollision: SelfCollisionStore
  /** Entity capacity of the two stores. */
  capacity: number
  /** Collider entities in creation order. */
  colliders: number[]
  /** Cloths with self-collision, in creation order. */
  selfCloths: ClothState[]
  /** Kernel frame block (see `kernels/collide.ts`). */
  frame: Float64Array
  /** Kernel scratch block. */
  scratch: Float64Array
  /** Pose scratch (4 poses of 7) and substep fractions. */
  poses: Float64Array
  fractions: Float64Array
  /** Per-cloth measurement scratch (see `measureCloth`). */
  measure: Float64Array
  /** Parameter block of the particle–particle kernels (see `kernels/selfCollide.ts`). */
  selfParams: Float64Array
}

/** Collision settings and per-step state of one cloth (`ClothState.collision`). */
export interface ClothCollision {
  /** Layer bits of the cloth. */
  layer: number
  /** Collider layers (and other cloths' layers) the cloth collides with. */
  mask: number
  /** Thickness override, m; 0 means the material's. */
  thickness: number
  /** Kinetic friction override; < 0 means the material's. */
  friction: number
  /** Static friction override; < 0 means the same as the kinetic one. */
  staticFriction: number
  /**
   * This step's bounds of the particles (min xyz, max xyz), grown by how far they can travel in
   * the step; then mean velocity xyz and largest deviation from it, m/s (for self-collision).
   */
  bounds: Float64Array
  /** Colliders in range this step (entity ids, creation order). */
  active: Int32Array
  activeCount: number
  /** Self-collision state while enabled. */
  self: SelfCollisionState | null
}

/** Slots of `ClothCollision.bounds` after the bounds (0-5). */
export const B_MEAN_V = 6
export const B_MAX_DEV = 9

export function createCollisionWorld(capacity: number): CollisionWorld {
  return {
    Collider: createColliderStore(capacity),
    SelfCollision: createSelfCollisionStore(capacity),
    capacity,
    colliders: [],
    selfCloths: [],
    frame: new Float64Array(FRAME_SIZE),
    scratch: new Float64Array(COLLIDE_SCRATCH),
    poses: new Float64Array(28),
    fractions: new Float64Array(2),
    measure: new Float64Array(12),
    selfParams: new Float64Array(SELF_PARAM_COUNT),
  }
}

/** Makes the collision stores large enough for entity `eid`. */
export function growCollisionStores(cw: CollisionWorld, eid: number): void {
  if (eid < cw.capacity) return
  const c = cw.capacity
  ensureStoreCapacity(cw.Collider, c, eid)
  cw.capacity = ensureStoreCapacity(cw.SelfCollision, c, eid)
}

/**
 * Registers the collision observers (called by `installClothPlugin`): every cloth gets its
 * collision state when created; removing a Collider or SelfCollision component (or its entity)
 * releases what it held; removing a body's Transform removes the colliders following it.
 */
export function installCollision(world: object, state: ClothWorldState): void {
  const cw = state.collision
  const w = world as never
  observe(w, onAdd(state.components.Cloth), (eid: number) => {
    const c = state.components.Cloth.state[eid]
    if (c) c.collision = createClothCollision(Math.max(4, cw.colliders.length))
  })
  observe(w, onRemove(state.components.Cloth), (eid: number) => {
    for (let k = 0; k < cw.selfCloths.length; k++) {
      if (cw.selfCloths[k].eid === eid) releaseSelfCollision(state, cw.selfCloths[k])
    }
  })
  observe(w, onAdd(cw.SelfCollision), (eid: number) => {
    const c = state.components.Cloth.state[eid]
    if (c) allocateSelfCollision(state, c)
  })
  observe(w, onRemove(cw.SelfCollision), (eid: number) => {
    const c = state.components.Cloth.state[eid]
    if (c) releaseSelfCollision(state, c)
  })
  observe(w, onRemove(cw.Collider), (eid: number) => releaseCollider(state, eid))
  observe(w, onRemove(state.transforms.component), (eid: number) => {
    const C = cw.Collider
    for (let k = cw.colliders.length - 1; k >= 0; k--) {
      const e = cw.colliders[k]
      if (e !== eid && C.body[e] === eid && entityExists(w, e) && hasComponent(w, e, C)) removeComponent(w, e, C)
    }
  })
}

function createClothCollision(capacity: number): ClothCollision {
  return {
    layer: 1,
    mask: 0xffffffff,
    thickness: 0,
    friction: -1,
    staticFriction: -1,
    bounds: new Float64Array(12),
    active: new Int32Array(capacity),
    activeCount: 0,
    self: null,
  }
}

/** Options of `setClothCollision`. */
export interface ClothCollisionOptions {
  /** Layer bits of the cloth (default 1): colliders whose mask has one of them collide with it. */
  layer?: number
  /** Layers the cloth collides with (default all, 0xffffffff); 0 turns collisions off. */
  mask?: number
  /** Collision thickness (particle radius), m; default the material's `thickness`. */
  thickness?: number
  /** Kinetic friction against colliders; default the material's `friction`. */
  friction?: number
  /** Static friction against colliders; default equal to the kinetic one. */
  staticFriction?: number
}

/**
 * Sets how a cloth collides: its layer and mask (a cloth and a collider touch only when each one's
 * layer is in the other's mask), its thickness and its friction against colliders. Options left
 * out keep their current values.
 *
 * @example setClothCollision(world, cape, { layer: 2, mask: HERO_BODY, thickness: 0.01 })
 */
export function setClothCollision(world: object, cloth: number, options: ClothCollisionOptions): void {
  const state = getClothWorld(world)
  const c = getCloth(state, cloth)
  if (typeof options !== 'object' || options === null) throw new ClothError('options', options, 'must be an object')
  const cc = c.collision!
  const layer = options.layer === undefined ? cc.layer : checkInteger('options.layer', options.layer, 0, 0xffffffff)
  const mask = options.mask === undefined ? cc.mask : checkInteger('options.mask', options.mask, 0, 0xffffffff)
  const thickness = options.thickness === undefined ? cc.thickness : checkAtMost('options.thickness', checkNonNegative('options.thickness', options.thickness), MAX_COORDINATE, ' m')
  const friction = options.friction === undefined ? cc.friction : checkNonNegative('options.friction', options.friction)
  const staticFriction = options.staticFriction === undefined ? cc.staticFriction : checkNonNegative('options.staticFriction', options.staticFriction)
  cc.layer = layer
  cc.mask = mask
  cc.thickness = thickness
  cc.friction = friction
  cc.staticFriction = staticFriction
  wakeClothState(state, c)
}

/**
 * Once per fixed step (the sync phase): each collider's bounds swept over the step, from its
 * body's pose at the step's start and end (read by the broadphase and by the sleep test).
 */
export function sweepColliders(state: ClothWorldState): void {
  const colliders = state.collision.colliders
  for (let k = 0; k < colliders.length; k++) sweepColliderBounds(state, colliders[k])
}

/**
 * Whether collider `e`'s swept bounds come within the cloth's thickness of the box `b` (min xyz,
 * max xyz); a plane, whether the box's lowest point along the normal, at the step's start or end
 * pose, is nearer than the thickness.
 */
export function colliderReaches(C: ColliderStore, e: number, b: Float64Array, c: ClothState): boolean {
  const cc = c.collision!
  const r = cc.thickness > 0 ? cc.thickness : c.material.thickness
  const o = 8 * e
  const sw = C.swept
  if (C.shape[e] === SHAPE_PLANE) {
    const cx = 0.5 * (b[0] + b[3]), cy = 0.5 * (b[1] + b[4]), cz = 0.5 * (b[2] + b[5])
    const ex = 0.5 * (b[3] - b[0]), ey = 0.5 * (b[4] - b[1]), ez = 0.5 * (b[5] - b[2])
    const d0 = sw[o] * cx + sw[o + 1] * cy + sw[o + 2] * cz - Math.abs(sw[o]) * ex - Math.abs(sw[o + 1]) * ey - Math.abs(sw[o + 2]) * ez - sw[o + 3]
    const d1 = sw[o + 4] * cx + sw[o + 5] * cy + sw[o + 6] * cz - Math.abs(sw[o + 4]) * ex - Math.abs(sw[o + 5]) * ey - Math.abs(sw[o + 6]) * ez - sw[o + 7]
    return d0 < r || d1 < r
  }
  return !(
    sw[o] > b[3] + r || sw[o + 3] < b[0] - r ||
    sw[o + 1] > b[4] + r || sw[o + 4] < b[1] - r ||
    sw[o + 2] > b[5] + r || sw[o + 5] < b[2] - r
  )
}

/** Whether cloth `cc` and collider `eid` may touch (each one's layer is in the other's mask). */
export function colliderLayersMatch(C: ColliderStore, eid: number, cc: ClothCollision): boolean {
  return (C.layer[eid] & cc.mask) !== 0 && (C.mask[eid] & cc.layer) !== 0
}

/** Whether two cloths' layers and masks let them collide with each other (both ways). */
export function clothLayersMatch(a: ClothCollision, b: ClothCollision): boolean {
  return (a.layer & b.mask) !== 0 && (b.layer & a.mask) !== 0
}

/**
 * Once per fixed step (the collide phase's first substep): for each running cloth that could
 * touch a collider (layers) or collides with itself, its particle bounds grown by how far
 * particles can travel in the step, and the list of colliders whose swept bounds (see
 * `sweepColliders`) reach them; then the self-collision hashes and pair lists. A cloth far from
 * every collider gets an empty list and costs nothing per particle in the substeps; an idle
 * cloth (asleep, frozen) keeps its last bounds.
 */
export function beginCollisionStep(state: ClothWorldState): void {
  const cw = state.collision
  const C = cw.Collider
  const colliders = cw.colliders
  const g = state.gravity
  const gravity = Math.sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2])
  const m = cw.measure
  const cloths = state.cloths
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    const cc = c.collision!
    cc.activeCount = 0
    if (c.idle) continue
    let candidates = false
    for (let k = 0; k < colliders.length; k++) {
      if (colliderLayersMatch(C, colliders[k], cc)) {
        candidates = true
        break
      }
    }
    if (!candidates && cc.self === null) continue
    measureCloth(c.pos, c.vel, c.invMass, c.count, cc.self !== null ? 1 : 0, m)
    // how far a particle can get this step: its speed now, gravity, and room for acceleration
    const dt = c.h * c.substeps // the cloth's step (longer when it steps every n-th)
    const travel = 1.5 * (Math.sqrt(m[6]) * dt + gravity * dt * dt) + 0.01
    const b = cc.bounds
    for (let a = 0; a < 3; a++) {
      b[a] = m[a] - travel
      b[3 + a] = m[3 + a] + travel
      b[B_MEAN_V + a] = m[7 + a]
    }
    b[B_MAX_DEV] = m[10]
    if (!candidates) continue
    for (let k = 0; k < colliders.length; k++) {
      const e = colliders[k]
      if (colliderLayersMatch(C, e, cc) && colliderReaches(C, e, b, c)) cc.active[cc.activeCount++] = e
    }
  }
  if (cw.selfCloths.length > 0) buildSelfCollisionPairs(state)
}

/**
 * Every substep: particle–particle collisions first (self and cloth–cloth), then each running
 * cloth against the colliders in range, in creation order, so colliders have the last word.
 */
export function collideSubstep(state: ClothWorldState): void {
  const cw = state.collision
  if (cw.selfCloths.length > 0) solveSelfCollision(state)
  collideColliders(state)
}

function collideColliders(state: ClothWorldState): void {
  const cw = state.collision
  // with no collider a self-colliding cloth still forgets its collider contacts below
  if (cw.colliders.length === 0 && cw.selfCloths.length === 0) return
  const C = cw.Collider
  const f = cw.frame, s = cw.scratch
  const stats = state.stats
  const cloths = state.cloths
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    if (c.subIndex < 0) continue
    const cc = c.collision!
    // self-colliding cloths remember which particles rest on a collider (heavier in particle pairs);
    // forgotten every substep, also with no collider in range (a cloth lifted off the ground)
    const touched = cc.self !== null ? cc.self.touched : null
    if (touched !== null) touched.fill(0)
    if (cc.activeCount === 0) continue
    const muK = cc.friction >= 0 ? cc.friction : c.material.friction
    const muS = cc.staticFriction >= 0 ? cc.staticFriction : muK
    const r = cc.thickness > 0 ? cc.thickness : c.material.thickness
    for (let a = 0; a < cc.activeCount; a++) {
      const e = cc.active[a]
      f[F_RADIUS] = r
      fillColliderFrame(state, e, c.subIndex, c.substeps, f)
      // friction: the cloth's, or the geometric mean with the collider's when it sets one
      const ck = C.friction[e], cs = C.staticFriction[e]
      f[F_MU_K] = ck >= 0 ? Math.sqrt(muK * ck) : muK
      f[F_MU_S] = cs >= 0 ? Math.sqrt(muS * cs) : ck >= 0 ? Math.sqrt(muS * ck) : muS
      const shape = C.shape[e]
      if (shape === SHAPE_SPHERE) collideSphere(c.pos, c.prev, c.invMass, c.count, f, s, touched)
      else if (shape === SHAPE_CAPSULE) collideCapsule(c.pos, c.prev, c.invMass, c.count, f, s, touched)
      else if (shape === SHAPE_BOX) collideBox(c.pos, c.prev, c.invMass, c.count, f, s, touched)
      else if (shape === SHAPE_HULL) {
        const hull = C.hulls[e]!
        collideHull(c.pos, c.prev, c.invMass, c.count, f, hull.planes, hull.planeCount, s, touched)
      } else collidePlane(c.pos, c.prev, c.invMass, c.count, f, s, touched)
      stats.colliderTests += c.count
    }
  }
}

/** Resets every cloth's collider list (a collider went away mid-step; the next step rebuilds them). */
export function clearActiveColliders(state: ClothWorldState): void {
  for (let ci = 0; ci < state.cloths.length; ci++) state.cloths[ci].collision!.activeCount = 0
}

/** Grows every cloth's collider list to hold all colliders (at collider creation, never in a step). */
export function reserveActiveColliders(state: ClothWorldState): void {
  const n = state.collision.colliders.length
  for (let ci = 0; ci < state.cloths.length; ci++) {
    const cc = state.cloths[ci].collision!
    if (cc.active.length < n) {
      const grown = new Int32Array(Math.max(n, 2 * cc.active.length))
      grown.set(cc.active)
      cc.active = grown
    }
  }
}

/** The Collider and SelfCollision stores of a world (for queries and direct reads). */
export function getCollisionComponents(world: object): { Collider: ColliderStore; SelfCollision: SelfCollisionStore } {
  const cw = getClothWorld(world).collision
  return { Collider: cw.Collider, SelfCollision: cw.SelfCollision }
}
