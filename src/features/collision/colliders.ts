import { addComponent, hasComponent, removeComponent } from 'bitecs'
import type { quat, vec3 } from 'gl-matrix'
import { SHAPE_BOX, SHAPE_CAPSULE, SHAPE_HULL, SHAPE_PLANE, SHAPE_SPHERE, type ConvexHull } from '../../core/shapes'
import type { ColliderStore } from '../../../components/Collider'
import { dropActiveCollider, reserveActiveColliders, wakeAroundCollider } from './reach'
import { liveColliders, markReleased } from './list'
import {
  ClothError,
  MAX_COORDINATE,
  checkAtMost,
  checkKeys,
  keysOf,
  checkBoundedArray,
  checkFinite,
  checkInteger,
  checkNonNegative,
  checkOut,
  checkPoint,
  checkPositive,
  checkQuat,
  checkVec3,
} from '../../core/errors'
import { buildConvexHull } from '../../model/hull'
import { F_BC, F_LIM2, F_M, F_PC, F_PE, F_PN, F_PS, F_RADIUS, F_RE, F_RS, F_S0, F_SW, F_SWR } from '../../kernels/colliderFrame'
import { interpolatePose, interpolateScale, readPoseInto, readScaleInto, trackEntity, untrackEntity } from '../../world/kinematics'
import { getClothWorld, getClothWorldForChange } from '../../world/access'
import { growStores } from '../../world/capacity'
import type { ClothWorldState } from '../../world/state'
import { checkEntity } from '../../world/transform'
import { multiplyQuatAt, normalizedQuat, quatToMatrix, rotateVecAt } from '../../core/math'
import { touchLayout } from '../../core/shared'

/** Options every collider takes. */
export interface ColliderOptions {
  /**
   * The entity whose Transform the collider follows; default the collider's own entity. Give a
   * character (or a bone) here to hang several colliders on it, one small entity each.
   */
  body?: number
  /** Position in the body's local frame (scaled by the body's scale), m. Default [0, 0, 0]. */
  offset?: Readonly<vec3> | ArrayLike<number>
  /** Rotation relative to the body, quaternion [x, y, z, w]. Default identity. */
  rotation?: Readonly<quat> | ArrayLike<number>
  /**
   * Kinetic friction coefficient. A contact uses √(cloth's × collider's); without it, the cloth's
   * own (the material's `friction` or `setClothCollision`'s).
   */
  friction?: number
  /** Static friction coefficient, combined the same way; default equal to `friction`. */
  staticFriction?: number
  /** Layer bits of the collider (default 1). */
  layer?: number
  /** Cloth layers it collides with (default all, 0xffffffff). */
  mask?: number
}

export interface SphereColliderOptions extends ColliderOptions {
  /** Radius, m. */
  radius: number
}

export interface CapsuleColliderOptions extends ColliderOptions {
  /** Radius, m. */
  radius: number
  /** Half the length of the core segment (without the caps), m. */
  halfHeight: number
  /** Direction of the segment in the collider's local frame; default [0, 1, 0] (local y). */
  axis?: Readonly<vec3> | ArrayLike<number>
}

export interface BoxColliderOptions extends ColliderOptions {
  /** Half-extents along local x, y, z, m. */
  halfExtents: Readonly<vec3> | ArrayLike<number>
}

export interface ConvexHullColliderOptions extends ColliderOptions {
  /** Points in the collider's local frame, xyz interleaved; their convex hull is the shape. */
  points: ArrayLike<number>
}

export interface PlaneColliderOptions extends ColliderOptions {
  /** Normal in the collider's local frame, pointing to the free side; default [0, 1, 0]. */
  normal?: Readonly<vec3> | ArrayLike<number>
  /** Offset of the plane along its normal from the collider's position, m. Default 0. */
  distance?: number
}

interface Common {
  body: number
  offset: ArrayLike<number>
  rotation: number[]
  friction: number
  staticFriction: number
  layer: number
  mask: number
}

/** Every collider's option keys, and each shape's (`checkKeys`). */
const COMMON_KEYS: { [K in keyof Required<ColliderOptions>]: true } = {
  body: true,
  offset: true,
  rotation: true,
  friction: true,
  staticFriction: true,
  layer: true,
  mask: true,
}
const SPHERE_KEYS = keysOf<SphereColliderOptions>({ ...COMMON_KEYS, radius: true })
const CAPSULE_KEYS = keysOf<CapsuleColliderOptions>({ ...COMMON_KEYS, radius: true, halfHeight: true, axis: true })
const BOX_KEYS = keysOf<BoxColliderOptions>({ ...COMMON_KEYS, halfExtents: true })
const HULL_KEYS = keysOf<ConvexHullColliderOptions>({ ...COMMON_KEYS, points: true })
const PLANE_KEYS = keysOf<PlaneColliderOptions>({ ...COMMON_KEYS, normal: true, distance: true })

function checkCommon(world: object, state: ClothWorldState, eid: number, o: ColliderOptions, keys: readonly string[]): Common {
  checkEntity(world, 'eid', eid)
  if (typeof o !== 'object' || o === null) throw new ClothError('options', o, 'must be an object')
  checkKeys('options', o, keys)
  const C = state.collision.Collider
  if (hasComponent(world as never, eid, C)) {
    throw new ClothError(
      'eid',
      eid,
      'already has a collider (an entity carries one; give each extra collider its own entity and options.body)',
    )
  }
  const body = o.body === undefined ? eid : checkEntity(world, 'options.body', o.body)
  if (!hasComponent(world as never, body, state.transforms.component)) {
    throw new ClothError(
      o.body === undefined ? 'eid' : 'options.body',
      body,
      'must have a Transform (call setTransform), or give options.body an entity that has one',
    )
  }
  const offset = o.offset === undefined ? [0, 0, 0] : checkPoint('options.offset', o.offset)
  const rotation = o.rotation === undefined ? [0, 0, 0, 1] : normalizedQuat(checkQuat('options.rotation', o.rotation))
  const friction = o.friction === undefined ? -1 : checkNonNegative('options.friction', o.friction)
  const staticFriction = o.staticFriction === undefined ? -1 : checkNonNegative('options.staticFriction', o.staticFriction)
  const layer = o.layer === undefined ? 1 : checkInteger('options.layer', o.layer, 0, 0xffffffff)
  const mask = o.mask === undefined ? 0xffffffff : checkInteger('options.mask', o.mask, 0, 0xffffffff)
  return { body, offset, rotation, friction, staticFriction, layer, mask }
}

/** Writes the collider into the store, starts tracking its body and adds the component. */
function spawnCollider(
  world: object,
  state: ClothWorldState,
  eid: number,
  shape: number,
  o: Common,
  size: ArrayLike<number>,
  bound: ArrayLike<number>,
  depth: number,
  hull?: ConvexHull,
): number {
  const cw = state.collision
  const list = liveColliders(cw) // (released entries gone first: eid may be one of theirs)
  growStores(state, Math.max(eid, o.body)) // (a body's Transform may come from another store)
  const C = cw.Collider
  C.shape[eid] = shape
  C.body[eid] = o.body
  for (let k = 0; k < 3; k++) C.offset[3 * eid + k] = o.offset[k]
  for (let k = 0; k < 4; k++) {
    C.rotation[4 * eid + k] = o.rotation[k]
    C.size[4 * eid + k] = k < size.length ? size[k] : 0
    C.bound[4 * eid + k] = bound[k]
  }
  C.depth[eid] = depth
  C.friction[eid] = o.friction
  C.staticFriction[eid] = o.staticFriction
  C.layer[eid] = o.layer
  C.mask[eid] = o.mask
  C.hulls[eid] = hull
  C.slot[eid] = trackEntity(state, o.body)
  C.serial[eid] = cw.serials++
  C.nextOnBody[eid] = C.firstOnBody[o.body]
  C.firstOnBody[o.body] = eid + 1
  list.push(eid)
  touchLayout()
  reserveActiveColliders(state)
  addComponent(world as never, eid, C)
  sweepColliderBounds(state, eid)
  wakeAroundCollider(state, eid) // a collider appearing on a sleeping cloth wakes it
  return eid
}

/**
 * Makes `eid` a sphere collider: cloths are kept `thickness` outside a sphere of `radius` around
 * the collider's position (the body's Transform, moved by `offset`). Returns `eid`.
 *
 * @example addSphereCollider(world, ball, { radius: 0.3 })
 */
export function addSphereCollider(world: object, eid: number, options: SphereColliderOptions): number {
  const state = getClothWorldForChange(world)
  const o = checkCommon(world, state, eid, options, SPHERE_KEYS)
  const r = checkLength('options.radius', options.radius, true)
  return spawnCollider(world, state, eid, SHAPE_SPHERE, o, [r], [0, 0, 0, r], r)
}

/**
 * Makes `eid` a capsule collider: all points within `radius` of a segment of length 2·`halfHeight`
 * along `axis` (local y by default) through the collider's position. Returns `eid`.
 *
 * @example
 * // a torso on a character: its own entity, following the character's Transform
 * addCapsuleCollider(world, addEntity(world), { body: hero, offset: [0, 1.15, 0], radius: 0.19, halfHeight: 0.22 })
 */
export function addCapsuleCollider(world: object, eid: number, options: CapsuleColliderOptions): number {
  const state = getClothWorldForChange(world)
  const o = checkCommon(world, state, eid, options, CAPSULE_KEYS)
  const r = checkLength('options.radius', options.radius, true)
  const hh = checkLength('options.halfHeight', options.halfHeight, false)
  if (options.axis !== undefined) {
    const a = checkVec3('options.axis', options.axis)
    const l = Math.hypot(a[0], a[1], a[2])
    if (!(l > 1e-9)) throw new ClothError('options.axis', options.axis, 'must have non-zero length')
    const r = Float64Array.from(o.rotation)
    multiplyQuatAt(r, 0, Float64Array.from(rotationFromY(a[0] / l, a[1] / l, a[2] / l)), 0, r, 0)
    o.rotation = Array.from(r)
  }
  return spawnCollider(world, state, eid, SHAPE_CAPSULE, o, [r, hh], [0, 0, 0, r + hh], r)
}

/** Makes `eid` a box collider with `halfExtents` along its local axes. Returns `eid`. */
export function addBoxCollider(world: object, eid: number, options: BoxColliderOptions): number {
  const state = getClothWorldForChange(world)
  const o = checkCommon(world, state, eid, options, BOX_KEYS)
  const h = checkPoint('options.halfExtents', options.halfExtents)
  for (let k = 0; k < 3; k++) if (!(h[k] > 0)) throw new ClothError('options.halfExtents', options.halfExtents, 'must be > 0 on every axis')
  return spawnCollider(
    world,
    state,
    eid,
    SHAPE_BOX,
    o,
    [h[0], h[1], h[2]],
    [0, 0, 0, Math.hypot(h[0], h[1], h[2])],
    Math.min(h[0], h[1], h[2]),
  )
}

/**
 * Makes `eid` a convex-hull collider: the convex hull of `points` (local frame, xyz interleaved),
 * stored as its face planes (up to 256). Returns `eid`.
 *
 * @example addConvexHullCollider(world, rock, { points: [0, 1, 0, 1, 0, 0, -1, 0, 0, 0, 0, 1, 0, 0, -1] })
 */
export function addConvexHullCollider(world: object, eid: number, options: ConvexHullColliderOptions): number {
  const state = getClothWorldForChange(world)
  const o = checkCommon(world, state, eid, options, HULL_KEYS)
  const hull = buildConvexHull(checkBoundedArray('options.points', options.points, 3, MAX_COORDINATE), 'options.points')
  const v = hull.vertices
  const nv = v.length / 3
  let cx = 0, cy = 0, cz = 0
  for (let i = 0; i < nv; i++) {
    cx += v[3 * i]
    cy += v[3 * i + 1]
    cz += v[3 * i + 2]
  }
  cx /= nv
  cy /= nv
  cz /= nv
  let radius = 0
  for (let i = 0; i < nv; i++) radius = Math.max(radius, Math.hypot(v[3 * i] - cx, v[3 * i + 1] - cy, v[3 * i + 2] - cz))
  let depth = Infinity
  const p = hull.planes
  for (let k = 0; k < hull.planeCount; k++) depth = Math.min(depth, p[4 * k + 3] - (p[4 * k] * cx + p[4 * k + 1] * cy + p[4 * k + 2] * cz))
  return spawnCollider(world, state, eid, SHAPE_HULL, o, [], [cx, cy, cz, radius], depth, hull)
}

/**
 * Makes `eid` a plane collider: cloths stay on the side `normal` points to, `thickness` above the
 * plane through the collider's position (moved `distance` along the normal). Returns `eid`.
 *
 * @example addPlaneCollider(world, ground)  // y = ground's y, normal +y
 */
export function addPlaneCollider(world: object, eid: number, options: PlaneColliderOptions = {}): number {
  const state = getClothWorldForChange(world)
  const o = checkCommon(world, state, eid, options, PLANE_KEYS)
  let n: ArrayLike<number> = [0, 1, 0]
  if (options.normal !== undefined) {
    const a = checkVec3('options.normal', options.normal)
    const l = Math.hypot(a[0], a[1], a[2])
    if (!(l > 1e-9)) throw new ClothError('options.normal', options.normal, 'must have non-zero length')
    n = [a[0] / l, a[1] / l, a[2] / l]
  }
  const distance = options.distance === undefined ? 0 : checkFinite('options.distance', options.distance)
  if (Math.abs(distance) > MAX_COORDINATE) throw new ClothError('options.distance', distance, `must lie within ±${MAX_COORDINATE} m`)
  return spawnCollider(world, state, eid, SHAPE_PLANE, o, [n[0], n[1], n[2], distance], [0, 0, 0, Infinity], Infinity)
}

/** Removes `eid`'s collider (the entity stays). Removing the entity does the same. */
export function removeCollider(world: object, eid: number): void {
  const state = getClothWorldForChange(world)
  const C = state.collision.Collider
  if (typeof eid !== 'number' || !hasComponent(world as never, eid, C))
    throw new ClothError('eid', eid, 'must be a collider entity of this world')
  removeComponent(world as never, eid, C)
}

/** Collider entities in creation order (a copy). */
export function getColliders(world: object): number[] {
  return liveColliders(getClothWorld(world).collision).slice()
}

/** Called when a Collider component goes away: stops tracking its body and forgets it. */
export function releaseCollider(state: ClothWorldState, eid: number): void {
  const cw = state.collision
  if (!markReleased(cw, eid)) return
  wakeAroundCollider(state, eid) // a cloth sleeping on it must fall
  touchLayout()
  const C = cw.Collider
  unlinkFromBody(C, eid)
  if (C.slot[eid] >= 0) untrackEntity(state, C.body[eid])
  C.slot[eid] = -1
  C.hulls[eid] = undefined
  dropActiveCollider(state, eid)
}

/** Takes collider `eid` out of its body's list. */
function unlinkFromBody(C: ColliderStore, eid: number): void {
  const body = C.body[eid], next = C.nextOnBody[eid]
  C.nextOnBody[eid] = 0
  if (C.firstOnBody[body] === eid + 1) {
    C.firstOnBody[body] = next
    return
  }
  for (let e = C.firstOnBody[body] - 1; e >= 0; e = C.nextOnBody[e] - 1) {
    if (C.nextOnBody[e] === eid + 1) {
      C.nextOnBody[e] = next
      return
    }
  }
}

/**
 * The collider's world pose now (its body's Transform composed with the collider's offset and
 * rotation), for drawing it. Returns false when `eid` is not a collider.
 */
export function getColliderPose(world: object, eid: number, outPosition?: vec3 | number[], outRotation?: quat | number[]): boolean {
  const state = getClothWorld(world)
  const C = state.collision.Collider
  if (outPosition !== undefined) checkOut('outPosition', outPosition, 3)
  if (outRotation !== undefined) checkOut('outRotation', outRotation, 4)
  if (typeof eid !== 'number' || !hasComponent(world as never, eid, C)) return false
  const t = state.collision.poses
  readPoseInto(state, C.body[eid], t)
  // a scale of 0 counts as the last one, as the step takes it (the tracked sample's; it was 1 here,
  // the drawn collider 0.5 m from where the cloth met it)
  const slot = C.slot[eid]
  for (let k = 0; k < 3; k++) scales[k] = slot >= 0 ? state.kinematics.scaleSampleTo[3 * slot + k] : 1
  readScaleInto(state, C.body[eid], scales, 0, true)
  composePose(state, eid, t, 0, scales, 0, t, 7)
  if (outPosition) { for (let k = 0; k < 3; k++) outPosition[k] = t[7 + k] }
  if (outRotation) { for (let k = 0; k < 4; k++) outRotation[k] = t[10 + k] }
  return true
}

/** The convex hull of a hull collider (local frame: planes, vertices, triangles), or undefined. */
export function getColliderHull(world: object, eid: number): Readonly<ConvexHull> | undefined {
  return getClothWorld(world).collision.Collider.hulls[eid]
}

// ---------------------------------------------------------------------------------------------
// Per-step and per-substep collider work (called by the collide phase). Scalars stay in typed
// arrays: the helpers take only arrays and integers, so nothing is boxed.

/** Scale scratch: the body's scale at two times of a step. */
const scales = new Float64Array(6)

/**
 * Collider pose from a body pose (src[so..so+6]) and scale (scale[sco..sco+2]) into
 * out[oo..oo+6]: p = pb + qb·(s ⊙ offset), q = qb·ql.
 */
function composePose(
  state: ClothWorldState,
  eid: number,
  src: Float64Array,
  so: number,
  scale: Float64Array,
  sco: number,
  out: Float64Array,
  oo: number,
): void {
  const C = state.collision.Collider
  const ox = C.offset[3 * eid] * scale[sco], oy = C.offset[3 * eid + 1] * scale[sco + 1], oz = C.offset[3 * eid + 2] * scale[sco + 2]
  const qx = src[so + 3], qy = src[so + 4], qz = src[so + 5], qw = src[so + 6]
  const tx = 2 * (qy * oz - qz * oy), ty = 2 * (qz * ox - qx * oz), tz = 2 * (qx * oy - qy * ox)
  const px = src[so] + ox + qw * tx + (qy * tz - qz * ty)
  const py = src[so + 1] + oy + qw * ty + (qz * tx - qx * tz)
  const pz = src[so + 2] + oz + qw * tz + (qx * ty - qy * tx)
  const r = 4 * eid
  out[oo] = px
  out[oo + 1] = py
  out[oo + 2] = pz
  multiplyQuatAt(src, so + 3, C.rotation, r, out, oo + 3)
}

/**
 * The collider's bounds swept over the current fixed step (`Collider.swept`): for solid shapes the
 * box around its bounding sphere at the step's start and end poses; for planes the world normal
 * and plane constant at both.
 */
export function sweepColliderBounds(state: ClothWorldState, eid: number): void {
  const C = state.collision.Collider
  const k = state.kinematics
  const t = state.collision.poses
  const so = 7 * C.slot[eid]
  composePose(state, eid, k.stepFrom, so, k.scaleStepFrom, 3 * C.slot[eid], t, 0)
  composePose(state, eid, k.stepTo, so, k.scaleStepTo, 3 * C.slot[eid], t, 7)
  // what it was computed from (see `sweptAtRest`)
  const at = C.sweptAt, a = 11 * eid, sc = 3 * C.slot[eid]
  let still = 1
  for (let j = 0; j < 7; j++) {
    at[a + j] = k.stepTo[so + j]
    if (k.stepFrom[so + j] !== k.stepTo[so + j]) still = 0
  }
  for (let j = 0; j < 3; j++) {
    at[a + 7 + j] = k.scaleStepTo[sc + j]
    if (k.scaleStepFrom[sc + j] !== k.scaleStepTo[sc + j]) still = 0
  }
  at[a + 10] = still
  const sw = C.swept
  const o = 8 * eid
  const b = 4 * eid
  if (C.shape[eid] === SHAPE_PLANE) {
    for (let e = 0; e < 2; e++) {
      const po = 7 * e
      rotateVecAt(t, po + 3, C.size, b, t, 14)
      sw[o + 4 * e] = t[14]
      sw[o + 4 * e + 1] = t[15]
      sw[o + 4 * e + 2] = t[16]
      sw[o + 4 * e + 3] = t[14] * t[po] + t[15] * t[po + 1] + t[16] * t[po + 2] + C.size[b + 3]
    }
    return
  }
  const rad = C.bound[b + 3]
  for (let e = 0; e < 2; e++) {
    const po = 7 * e
    rotateVecAt(t, po + 3, C.bound, b, t, 14)
    for (let a = 0; a < 3; a++) {
      const c = t[po + a] + t[14 + a]
      if (e === 0 || c - rad < sw[o + a]) sw[o + a] = c - rad
      if (e === 0 || c + rad > sw[o + 3 + a]) sw[o + 3 + a] = c + rad
    }
  }
}

/**
 * Whether collider `eid`'s swept bounds were computed from its body at rest at the pose and scale
 * it has now at the step's end (`Collider.sweptAt`): for a body at rest over this step too, they
 * are what `sweepColliderBounds` would compute. (The shape and offset change only when the
 * collider is made, which computes them.)
 */
export function sweptAtRest(state: ClothWorldState, eid: number): boolean {
  const C = state.collision.Collider
  const k = state.kinematics
  const at = C.sweptAt, a = 11 * eid, so = 7 * C.slot[eid], sc = 3 * C.slot[eid]
  if (at[a + 10] !== 1) return false
  for (let j = 0; j < 7; j++) if (at[a + j] !== k.stepTo[so + j]) return false
  for (let j = 0; j < 3; j++) if (at[a + 7 + j] !== k.scaleStepTo[sc + j]) return false
  return true
}

/**
 * Fills the kernel frame (see `kernels/collide.ts`) for collider `eid` during local substep k of
 * n: its world pose at k/n and (k + 1)/n of the fixed step (the body's pose interpolated like a
 * pin target's, then the collider's offset and rotation), the shape's dimensions, and how far a
 * particle may move this substep before it needs the swept test. f[F_RADIUS] must be set first.
 */
export function fillColliderFrame(state: ClothWorldState, eid: number, k: number, n: number, f: Float64Array): void {
  const cw = state.collision
  const C = cw.Collider
  const K = state.kinematics
  const t = cw.poses
  const T = cw.fractions
  T[0] = k / n
  T[1] = (k + 1) / n
  const so = 7 * C.slot[eid]
  interpolatePose(K.stepFrom, K.stepTo, so, T, 0, t, 0)
  interpolateScale(K, 3 * C.slot[eid], T, 0, scales, 0)
  composePose(state, eid, t, 0, scales, 0, t, 14)
  interpolatePose(K.stepFrom, K.stepTo, so, T, 1, t, 7)
  interpolateScale(K, 3 * C.slot[eid], T, 1, scales, 3)
  composePose(state, eid, t, 7, scales, 3, t, 21)
  f[F_PS] = t[14]
  f[F_PS + 1] = t[15]
  f[F_PS + 2] = t[16]
  f[F_PE] = t[21]
  f[F_PE + 1] = t[22]
  f[F_PE + 2] = t[23]
  quatToMatrix(t, 17, f, F_RS)
  quatToMatrix(t, 24, f, F_RE)
  // M = Rs·Reᵀ
  for (let r = 0; r < 3; r++) {
    for (let c = 0; c < 3; c++) {
      f[F_M + 3 * r + c] = f[F_RS + 3 * r] * f[F_RE + 3 * c] + f[F_RS + 3 * r + 1] * f[F_RE + 3 * c + 1] +
        f[F_RS + 3 * r + 2] * f[F_RE + 3 * c + 2]
    }
  }
  const b = 4 * eid
  f[F_S0] = C.size[b]
  f[F_S0 + 1] = C.size[b + 1]
  f[F_S0 + 2] = C.size[b + 2]
  f[F_S0 + 3] = C.size[b + 3]
  f[F_BC] = C.bound[b]
  f[F_BC + 1] = C.bound[b + 1]
  f[F_BC + 2] = C.bound[b + 2]
  f[F_BC + 3] = C.bound[b + 3]
  if (C.shape[eid] === SHAPE_PLANE) {
    const nx = f[F_S0], ny = f[F_S0 + 1], nz = f[F_S0 + 2]
    const wx = f[F_RE] * nx + f[F_RE + 1] * ny + f[F_RE + 2] * nz
    const wy = f[F_RE + 3] * nx + f[F_RE + 4] * ny + f[F_RE + 5] * nz
    const wz = f[F_RE + 6] * nx + f[F_RE + 7] * ny + f[F_RE + 8] * nz
    f[F_PN] = wx
    f[F_PN + 1] = wy
    f[F_PN + 2] = wz
    f[F_PC] = wx * f[F_PE] + wy * f[F_PE + 1] + wz * f[F_PE + 2] + f[F_S0 + 3]
    f[F_LIM2] = Infinity
    f[F_SWR] = Infinity
    return
  }
  // largest displacement of a point of the shape this substep: translation + angle × reach
  const dx = f[F_PE] - f[F_PS], dy = f[F_PE + 1] - f[F_PS + 1], dz = f[F_PE + 2] - f[F_PS + 2]
  let dot = Math.abs(t[17] * t[24] + t[18] * t[25] + t[19] * t[26] + t[20] * t[27])
  if (dot > 1) dot = 1
  // (not Math.hypot: with several arguments it allocates in optimised code)
  const bx = C.bound[b], by = C.bound[b + 1], bz = C.bound[b + 2]
  const reach = Math.sqrt(bx * bx + by * by + bz * bz) + C.bound[b + 3]
  const motion = Math.sqrt(dx * dx + dy * dy + dz * dz) + 2 * Math.acos(dot) * reach
  const lim = 0.5 * (C.depth[eid] + f[F_RADIUS]) - motion
  f[F_LIM2] = lim > 0 ? lim * lim : -1
  const lx = f[F_BC], ly = f[F_BC + 1], lz = f[F_BC + 2]
  f[F_SW] = f[F_PE] + f[F_RE] * lx + f[F_RE + 1] * ly + f[F_RE + 2] * lz
  f[F_SW + 1] = f[F_PE + 1] + f[F_RE + 3] * lx + f[F_RE + 4] * ly + f[F_RE + 5] * lz
  f[F_SW + 2] = f[F_PE + 2] + f[F_RE + 6] * lx + f[F_RE + 7] * ly + f[F_RE + 8] * lz
  f[F_SWR] = f[F_BC + 3] + f[F_RADIUS] + motion
}

/** A size in metres: > 0 (or ≥ 0 when `positive` is false) and at most MAX_COORDINATE (1e9 m). */
function checkLength(argument: string, value: unknown, positive: boolean): number {
  return checkAtMost(argument, positive ? checkPositive(argument, value) : checkNonNegative(argument, value), MAX_COORDINATE, ' m')
}

/** Rotation taking +y to the unit vector (x, y, z), as a quaternion. */
function rotationFromY(x: number, y: number, z: number): number[] {
  if (y > 1 - 1e-12) return [0, 0, 0, 1]
  if (y < -1 + 1e-12) return [1, 0, 0, 0]
  // axis = y × v = (z, 0, −x), w = 1 + y, normalised
  const q = [z, 0, -x, 1 + y]
  const l = Math.hypot(q[0], q[1], q[2], q[3])
  return [q[0] / l, q[1] / l, q[2] / l, q[3] / l]
}
