import type { ClothState } from '../../world/state'

/** The collision section of a cloth's per-step handoff (see `src/threads/handoff.ts`): settings, collider list length, self-collision counts. */
export const COLLISION_HANDOFF = 16

export function writeCollisionHandoff(c: ClothState, io: Float64Array, o: number): void {
  const cc = c.collision
  io[o] = cc.layer
  io[o + 1] = cc.mask
  io[o + 2] = cc.thickness
  io[o + 3] = cc.friction
  io[o + 4] = cc.staticFriction
  io[o + 5] = cc.activeCount
  const st = cc.self
  if (st === null) return
  io[o + 6] = st.thickness
  io[o + 7] = st.friction
  io[o + 8] = st.staticFriction
  io[o + 9] = st.mask
  io[o + 10] = st.capacity
  io[o + 11] = st.pairCount
  io[o + 12] = st.crossCapacity
  io[o + 13] = st.crossCount
  io[o + 14] = st.blockCount
  io[o + 15] = st.hashed
}

export function readCollisionHandoff(io: Float64Array, o: number, c: ClothState): void {
  const cc = c.collision
  cc.layer = io[o]
  cc.mask = io[o + 1]
  cc.thickness = io[o + 2]
  cc.friction = io[o + 3]
  cc.staticFriction = io[o + 4]
  cc.activeCount = io[o + 5]
  const st = cc.self
  if (st === null) return
  st.thickness = io[o + 6]
  st.friction = io[o + 7]
  st.staticFriction = io[o + 8]
  st.mask = io[o + 9]
  st.capacity = io[o + 10]
  st.pairCount = io[o + 11]
  st.crossCapacity = io[o + 12]
  st.crossCount = io[o + 13]
  st.blockCount = io[o + 14]
  st.hashed = io[o + 15]
}
