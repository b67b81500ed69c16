import { newArrayLike, type TypedArray } from './shared'

/** Typed arrays a component store may hold. */
export type StoreArray = TypedArray

/**
 * Grows every typed-array field of an entity-indexed store so that index `eid` fits (capacity
 * doubles). Fields are replaced, not resized in place: read them through the store object
 * (`Transform.px[eid]`) rather than caching the arrays across frames. `stride` fields hold several
 * values per entity (their length is a multiple of the capacity).
 */
export function ensureStoreCapacity(store: object, capacity: number, eid: number): number {
  if (eid < capacity) return capacity
  let next = Math.max(capacity, 16)
  while (next <= eid) next *= 2
  const fields = store as Record<string, unknown>
  for (const key of Object.keys(fields)) {
    const old = fields[key]
    if (!ArrayBuffer.isView(old) || old instanceof DataView) continue
    const arr = old as StoreArray
    const stride = Math.max(1, Math.round(arr.length / capacity))
    const grown = newArrayLike(arr, next * stride) // shared memory stays shared
    grown.set(arr)
    fields[key] = grown
  }
  return next
}

/**
 * A copy of `a` with room for at least `n` elements (the new tail zeroed), in shared memory when `a`
 * is; creation time only.
 */
export function grownArray<T extends StoreArray>(a: T, n: number): T {
  const out = newArrayLike(a, Math.max(n, a.length))
  out.set(a)
  return out
}
