import type { ColliderStore } from '../../../components/Collider'
import type { CollisionWorld } from './types'

/**
 * The world's colliders in creation order. A removal only marks its entry (`releaseCollider`): the
 * list is compacted when next read, in one pass, so a level that unloads thousands of colliders
 * costs one pass, not one per collider (a splice per removal took 0.4 s for 20,000).
 */
export function liveColliders(cw: CollisionWorld): number[] {
  if (cw.released === 0) return cw.entries
  const list = cw.entries, slot = cw.Collider.slot
  let n = 0
  for (let q = 0; q < list.length; q++) if (slot[list[q]] >= 0) list[n++] = list[q]
  list.length = n
  cw.released = 0
  return list
}

/**
 * Marks collider `eid`'s entry as released, and returns false when it has none. Its entry is found
 * by binary search on the serial numbers, which increase along the list (released entries keep
 * theirs: a new collider, which could reuse the id, compacts the list first).
 */
export function markReleased(cw: CollisionWorld, eid: number): boolean {
  const C: ColliderStore = cw.Collider
  if (eid >= C.serial.length || C.slot[eid] < 0) return false
  const list = cw.entries, serial = C.serial[eid]
  let lo = 0, hi = list.length - 1
  while (lo <= hi) {
    const mid = (lo + hi) >> 1
    const s = C.serial[list[mid]]
    if (s < serial) lo = mid + 1
    else if (s > serial) hi = mid - 1
    else {
      if (list[mid] !== eid) return false
      cw.released++
      return true
    }
  }
  return false
}
