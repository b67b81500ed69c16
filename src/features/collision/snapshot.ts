import { fit8 } from '../../core/arrays'
import { ClothError } from '../../core/errors'
import type { ClothState } from '../../world/state'

/** The collision section of a snapshot. */
export interface CollisionSnapshot {
  /** Self-colliding cloths: particles that touched a collider in the last substep (empty otherwise). */
  touched: Uint8Array
}

/** Saves which particles of a self-colliding cloth rest on a collider. */
export function saveCollision(c: ClothState, s: CollisionSnapshot): void {
  const self = c.collision.self
  const n = self === null ? 0 : c.count
  s.touched = fit8(s.touched, n)
  for (let i = 0; i < n; i++) s.touched[i] = self!.touched[i]
}

export function checkCollision(s: CollisionSnapshot, arg: string): void {
  if (!(s.touched instanceof Uint8Array))
    throw new ClothError(arg, s, 'is not a complete snapshot (collider, wind or tearing state missing)')
}

export function restoreCollision(c: ClothState, s: CollisionSnapshot): void {
  const self = c.collision.self
  const n = c.count
  if (self !== null && s.touched.length === n) { for (let i = 0; i < n; i++) self.touched[i] = s.touched[i] }
}
