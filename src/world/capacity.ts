import type { TransformStore } from '../../components/Transform'
import { ensureStoreCapacity, grownArray } from '../core/store'
import type { ClothState, ClothWorldState, TransformSource } from './state'

/**
 * Makes every entity-indexed store of the world large enough for `eid`: Transform, Pin, WindZone,
 * Tearable, Collider and SelfCollision, all at one capacity. Called wherever an entity gets a
 * component of the plugin (never in a step).
 */
export function growStores(state: ClothWorldState, eid: number): void {
  if (eid < state.capacity) return
  const c = state.capacity
  const { Transform, Pin, WindZone, Tearable } = state.components
  // the workers stepping now write pin blends and tear counts into the arrays they were given
  const f = state.frame
  if (f.inFlight && f.stale === null) f.stale = { Pin: { ...Pin }, Tearable: { ...Tearable } }
  ensureStoreCapacity(Transform, c, eid)
  ensureStoreCapacity(WindZone, c, eid)
  ensureStoreCapacity(Tearable, c, eid)
  ensureStoreCapacity(state.collision.Collider, c, eid)
  ensureStoreCapacity(state.collision.SelfCollision, c, eid)
  state.capacity = ensureStoreCapacity(Pin, c, eid)
  // the default transform source aliases the Transform store's arrays: keep them in step
  if (state.transforms.component === Transform) Object.assign(state.transforms, transformSourceOf(Transform))
}

/** The plugin's own Transform store as a transform source. */
export function transformSourceOf(t: TransformStore): TransformSource {
  return { component: t, px: t.px, py: t.py, pz: t.pz, qx: t.qx, qy: t.qy, qz: t.qz, qw: t.qw, sx: t.sx, sy: t.sy, sz: t.sz }
}

/**
 * Grows a cloth's particle arrays and render buffers to a capacity of `P` particles (a tearable
 * cloth reserves room for the particles its tears add); live values are kept, the render mesh is
 * refreshed at the next read. Creation time only. Feature arrays are grown by their features.
 */
export function growClothParticles(c: ClothState, P: number): void {
  c.pos = grownArray(c.pos, 3 * P)
  c.prev = grownArray(c.prev, 3 * P)
  c.vel = grownArray(c.vel, 3 * P)
  c.invMass = grownArray(c.invMass, P)
  c.baseInvMass = grownArray(c.baseInvMass, P)
  c.invMass3 = grownArray(c.invMass3, 3 * P)
  c.pinCount = grownArray(c.pinCount, P)
  const r = c.render
  r.positions = new Float32Array(3 * P)
  r.normals = new Float32Array(3 * P)
  r.uvs = grownArray(r.uvs, 2 * P)
  r.mesh = null
  r.version = -1
}
