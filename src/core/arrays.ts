/**
 * Small helpers for snapshot sections: reuse an array when it has the right length, so saving every
 * frame into the same snapshot allocates nothing.
 */

/** `a` when it holds exactly `len` doubles, else a new array. */
export function fit64(a: Float64Array | undefined, len: number): Float64Array {
  return a && a.length === len ? a : new Float64Array(len)
}

/** `a` when it holds exactly `len` int32s, else a new array. */
export function fit32(a: Int32Array | undefined, len: number): Int32Array {
  return a && a.length === len ? a : new Int32Array(len)
}

/** `a` when it holds exactly `len` bytes, else a new array. */
export function fit8(a: Uint8Array | undefined, len: number): Uint8Array {
  return a && a.length === len ? a : new Uint8Array(len)
}

/** The first `len` values of `src` in `dst` (reused when it fits). */
export function copyInto(dst: Float64Array | undefined, src: Float64Array, len: number): Float64Array {
  const out = fit64(dst, len)
  if (src.length === len) out.set(src) // a block copy (the usual case: the arrays hold no spare room)
  else for (let i = 0; i < len; i++) out[i] = src[i]
  return out
}

/** Whether every value is finite. */
export function allFinite(a: ArrayLike<number>): boolean {
  for (let i = 0; i < a.length; i++) if (!Number.isFinite(a[i])) return false
  return true
}
