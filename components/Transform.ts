/**
 * World transform of an entity: position (m), rotation quaternion [x, y, z, w] and scale.
 * Structure of arrays indexed by entity id; the plugin grows the arrays when an entity id does not
 * fit, so always read fields through the store (`Transform.px[eid]`).
 *
 * Pins read their target's Transform and colliders read their own; a host engine with its own
 * transform stores can pass them to `installClothPlugin` instead (see `TransformSource`).
 */
export interface TransformStore {
  /** Position x, m. */
  px: Float64Array
  /** Position y, m. */
  py: Float64Array
  /** Position z, m. */
  pz: Float64Array
  /** Rotation quaternion x. */
  qx: Float64Array
  /** Rotation quaternion y. */
  qy: Float64Array
  /** Rotation quaternion z. */
  qz: Float64Array
  /** Rotation quaternion w (1 for identity). */
  qw: Float64Array
  /** Scale x (1 by default). */
  sx: Float64Array
  /** Scale y. */
  sy: Float64Array
  /** Scale z. */
  sz: Float64Array
}

/** Allocates a Transform store for `capacity` entity ids. Called by `installClothPlugin`. */
export function createTransformStore(capacity: number): TransformStore {
  return {
    px: new Float64Array(capacity),
    py: new Float64Array(capacity),
    pz: new Float64Array(capacity),
    qx: new Float64Array(capacity),
    qy: new Float64Array(capacity),
    qz: new Float64Array(capacity),
    qw: new Float64Array(capacity),
    sx: new Float64Array(capacity),
    sy: new Float64Array(capacity),
    sz: new Float64Array(capacity),
  }
}

/** Resets one entity's transform to the identity (bitECS never clears recycled data). */
export function resetTransform(t: TransformStore, eid: number): void {
  t.px[eid] = 0
  t.py[eid] = 0
  t.pz[eid] = 0
  t.qx[eid] = 0
  t.qy[eid] = 0
  t.qz[eid] = 0
  t.qw[eid] = 1
  t.sx[eid] = 1
  t.sy[eid] = 1
  t.sz[eid] = 1
}
