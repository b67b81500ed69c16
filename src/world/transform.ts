import { addComponent, entityExists, hasComponent } from 'bitecs'
import type { quat, vec3 } from 'gl-matrix'
import { ClothError, MAX_SCALE, checkOut, checkPoint, checkQuat, checkVec3 } from '../core/errors'
import { normalizeQuat } from '../core/math'
import { getClothWorld } from './access'
import { growStores } from './capacity'
import type { TransformSource } from './state'

type Writable = { [i: number]: number }

/**
 * Writes an entity's world transform (adding the transform component if it has none), for hosts
 * that do not write the stores themselves. The rotation is normalised; position and rotation must
 * be finite. With host transform stores (`installClothPlugin({ transforms })`), writes into those
 * (adding the host's component, with an identity transform, to an entity that lacks it).
 *
 * Hosts may write the stores directly instead. A negative scale there (a mirror scale) counts as
 * its size for pin and collider offsets and character frames, and a scale of 0 (a hidden object)
 * as the entity's last scale (1 when it has none); NaN, ±∞ or a scale above 1e6 is refused by the
 * next step. A change of scale is interpolated across the step like motion, and wakes what it moves.
 */
export function setTransform(
  world: object,
  eid: number,
  position: Readonly<vec3> | ArrayLike<number>,
  rotation?: Readonly<quat> | ArrayLike<number>,
  scale?: Readonly<vec3> | ArrayLike<number>,
): void {
  const state = getClothWorld(world)
  checkEntity(world, 'eid', eid)
  checkPoint('position', position)
  if (rotation !== undefined) checkQuat('rotation', rotation)
  if (scale !== undefined) {
    checkVec3('scale', scale)
    for (let i = 0; i < 3; i++)
      if (!(scale[i] > 0) || scale[i] > MAX_SCALE) throw new ClothError('scale', scale, `must be positive (at most ${MAX_SCALE})`)
  }
  const t = state.transforms
  const own = t.component === state.components.Transform
  if (!own) checkHostRoom(t, eid)
  if (!hasComponent(world as never, eid, t.component)) {
    if (own) {
      growStores(state, eid)
      addComponent(world as never, eid, state.components.Transform) // (its observer writes the identity)
    } else {
      addComponent(world as never, eid, t.component)
      // bitECS never clears data: an earlier entity with this id may have left its transform
      const w = t as unknown as Record<string, Writable | undefined>
      for (const key of ['px', 'py', 'pz', 'qx', 'qy', 'qz', 'sx', 'sy', 'sz']) {
        const arr = w[key]
        if (arr) arr[eid] = key[0] === 's' ? 1 : 0
      }
      ;(t.qw as Writable)[eid] = 1
    }
  }
  ;(t.px as Writable)[eid] = position[0]
  ;(t.py as Writable)[eid] = position[1]
  ;(t.pz as Writable)[eid] = position[2]
  if (rotation !== undefined) {
    const q = scratch
    normalizeQuat(rotation[0], rotation[1], rotation[2], rotation[3], q, 0)
    ;(t.qx as Writable)[eid] = q[0]
    ;(t.qy as Writable)[eid] = q[1]
    ;(t.qz as Writable)[eid] = q[2]
    ;(t.qw as Writable)[eid] = q[3]
  }
  if (scale !== undefined && t.sx && t.sy && t.sz) {
    ;(t.sx as Writable)[eid] = scale[0]
    ;(t.sy as Writable)[eid] = scale[1]
    ;(t.sz as Writable)[eid] = scale[2]
  }
}

/** Throws ClothError unless every typed array of host transform stores has an entry for `eid` (writes past the end would be dropped). */
function checkHostRoom(t: TransformSource, eid: number): void {
  for (const arr of [t.px, t.py, t.pz, t.qx, t.qy, t.qz, t.qw, t.sx, t.sy, t.sz]) {
    if (arr !== undefined && ArrayBuffer.isView(arr) && eid >= arr.length) {
      throw new ClothError('eid', eid, `does not fit the host's transform arrays (length ${arr.length}); grow them first`)
    }
  }
}

const scratch = new Float64Array(4)

/**
 * Reads an entity's world position into `outPosition` and rotation into `outRotation` (either may
 * be omitted). Returns false when the entity has no transform.
 */
export function getTransform(world: object, eid: number, outPosition?: vec3 | Writable, outRotation?: quat | Writable): boolean {
  const state = getClothWorld(world)
  if (outPosition !== undefined) checkOut('outPosition', outPosition, 3)
  if (outRotation !== undefined) checkOut('outRotation', outRotation, 4)
  if (!entityExists(world as never, eid) || !hasComponent(world as never, eid, state.transforms.component)) return false
  const t = state.transforms
  if (outPosition) {
    outPosition[0] = t.px[eid]
    outPosition[1] = t.py[eid]
    outPosition[2] = t.pz[eid]
  }
  if (outRotation) {
    outRotation[0] = t.qx[eid]
    outRotation[1] = t.qy[eid]
    outRotation[2] = t.qz[eid]
    outRotation[3] = t.qw[eid]
  }
  return true
}

/** Throws ClothError unless `eid` is a live entity of `world`. */
export function checkEntity(world: object, argument: string, eid: unknown): number {
  if (typeof eid !== 'number' || !Number.isInteger(eid) || eid < 0 || !entityExists(world as never, eid)) {
    throw new ClothError(argument, eid, 'must be an existing entity of this world')
  }
  return eid
}
