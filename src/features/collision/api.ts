import { hasComponent, observe, onAdd, onRemove, removeComponent, entityExists } from 'bitecs'
import { createColliderStore, type ColliderStore } from '../../../components/Collider'
import { createSelfCollisionStore, type SelfCollisionStore } from '../../../components/SelfCollision'
import { checkAtMost, checkInteger, checkKeys, checkNonNegative, ClothError, keysOf, MAX_COORDINATE } from '../../core/errors'
import { COLLIDE_SCRATCH, FRAME_SIZE } from '../../kernels/colliderFrame'
import { SELF_PARAM_COUNT } from '../../kernels/selfCollide'
import { getCloth, getClothWorld, getClothWorldForChange } from '../../world/access'
import type { ClothState, ClothWorldState } from '../../world/state'
import { wakeClothState } from '../../world/wake'
import { releaseCollider } from './colliders'
import { allocateSelfCollision, releaseSelfCollision } from './selfCollision'
import type { ClothCollision, CollisionWorld } from './types'
import { newArray } from '../../core/shared'
import { deferrable } from '../../world/flight'

export function createCollisionWorld(capacity: number): CollisionWorld<ClothState> {
  return {
    Collider: createColliderStore(capacity),
    SelfCollision: createSelfCollisionStore(capacity),
    entries: [],
    released: 0,
    serials: 0,
    selfCloths: [],
    frame: new Float64Array(FRAME_SIZE),
    scratch: new Float64Array(COLLIDE_SCRATCH),
    poses: new Float64Array(28),
    fractions: new Float64Array(2),
    measure: new Float64Array(12),
    selfParams: new Float64Array(SELF_PARAM_COUNT),
    sweep: {
      count: 0,
      lo: new Float64Array(0),
      hi: new Float64Array(0),
      order: new Int32Array(0),
      head: new Int32Array(1),
      pairs: new Int32Array(0),
      list: new Int32Array(0),
    },
  }
}

/**
 * Registers the collision observers (called by `installClothPlugin`): removing a Collider or SelfCollision component (or its entity)
 * releases what it held; removing a body's Transform removes the colliders following it, its own
 * collider included (a collider on an entity without a Transform would follow a stale pose).
 */
export function installCollision(world: object, state: ClothWorldState): void {
  const cw = state.collision
  const w = world as never
  observe(
    w,
    onRemove(state.components.Cloth),
    deferrable(state, (eid: number) => {
      for (let k = 0; k < cw.selfCloths.length; k++) {
        if (cw.selfCloths[k].eid === eid) releaseSelfCollision(state, cw.selfCloths[k])
      }
    }),
  )
  observe(
    w,
    onAdd(cw.SelfCollision),
    deferrable(state, (eid: number) => {
      const c = state.components.Cloth.state[eid]
      if (c) allocateSelfCollision(state, c)
    }),
  )
  observe(
    w,
    onRemove(cw.SelfCollision),
    deferrable(state, (eid: number) => {
      const c = state.components.Cloth.state[eid]
      if (c) releaseSelfCollision(state, c)
    }),
  )
  observe(w, onRemove(cw.Collider), deferrable(state, (eid: number) => releaseCollider(state, eid)))
  // (the Transform's observers run before any Collider query's, as the Transform store is older:
  // when the whole entity is removed, removing its Collider here notifies each of those once)
  observe(
    w,
    onRemove(state.transforms.component),
    deferrable(state, (eid: number) => {
      // (the body's own list, not a pass over every collider: a level's unload was quadratic,
      // 1.3 s for 20,000 colliders, and each removed character cost a pass over them)
      const C = cw.Collider
      for (let e = eid < C.firstOnBody.length ? C.firstOnBody[eid] - 1 : -1; e >= 0;) {
        const next = C.nextOnBody[e] - 1 // (read first: the removal unlinks e)
        if (entityExists(w, e) && hasComponent(w, e, C)) removeComponent(w, e, C)
        e = next
      }
    }),
  )
}

/** A cloth's collision state: layer 1, every mask bit, the material's thickness and friction (−1: the material's). */
export function createClothCollision(capacity: number): ClothCollision {
  return {
    layer: 1,
    mask: 0xffffffff,
    thickness: -1,
    friction: -1,
    staticFriction: -1,
    bounds: newArray(Float64Array, 12),
    active: newArray(Int32Array, capacity),
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
  /** Collision thickness (particle radius), m, 0 allowed (particles touch surfaces); default the material's `thickness`. */
  thickness?: number
  /** Kinetic friction against colliders; default the material's `friction`. */
  friction?: number
  /** Static friction against colliders; default equal to the kinetic one. */
  staticFriction?: number
}

const COLLISION_KEYS = keysOf<ClothCollisionOptions>({ layer: true, mask: true, thickness: true, friction: true, staticFriction: true })

/**
 * Sets how a cloth collides: its layer and mask (a cloth and a collider touch only when each one's
 * layer is in the other's mask), its thickness and its friction against colliders. Options left
 * out keep their current values.
 *
 * @example setClothCollision(world, cape, { layer: 2, mask: HERO_BODY, thickness: 0.01 })
 */
export function setClothCollision(world: object, cloth: number, options: ClothCollisionOptions): void {
  const state = getClothWorldForChange(world)
  const c = getCloth(state, cloth)
  if (typeof options !== 'object' || options === null) throw new ClothError('options', options, 'must be an object')
  checkKeys(
    'options',
    options,
    COLLISION_KEYS,
  )
  const cc = c.collision
  const layer = options.layer === undefined ? cc.layer : checkInteger('options.layer', options.layer, 0, 0xffffffff)
  const mask = options.mask === undefined ? cc.mask : checkInteger('options.mask', options.mask, 0, 0xffffffff)
  const thickness = options.thickness === undefined ? cc.thickness
    : checkAtMost('options.thickness', checkNonNegative('options.thickness', options.thickness), MAX_COORDINATE, ' m')
  const friction = options.friction === undefined ? cc.friction : checkNonNegative('options.friction', options.friction)
  const staticFriction = options.staticFriction === undefined ? cc.staticFriction
    : checkNonNegative('options.staticFriction', options.staticFriction)
  cc.layer = layer
  cc.mask = mask
  cc.thickness = thickness
  cc.friction = friction
  cc.staticFriction = staticFriction
  wakeClothState(state, c)
}

/** The Collider and SelfCollision stores of a world (for queries and direct reads). */
export function getCollisionComponents(world: object): { Collider: ColliderStore; SelfCollision: SelfCollisionStore } {
  const cw = getClothWorld(world).collision
  return { Collider: cw.Collider, SelfCollision: cw.SelfCollision }
}
