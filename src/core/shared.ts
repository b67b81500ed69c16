/**
 * Memory the cloth step can share with worker threads.
 *
 * A world that steps its cloths on workers (`installClothPlugin(world, { threads })`) keeps every
 * array the step touches in SharedArrayBuffers, which the workers read and write in place. While
 * such a world exists in this thread, `newArray` allocates in shared memory (for every world of the
 * thread: a shared array behaves like any other), and growing an array keeps its kind.
 *
 * The layout epoch counts changes to which arrays the cloths hold: every `newArray` counts, and code
 * that points a cloth at an array it already had (an empty tether set, a released self-collision)
 * calls `touchLayout`. The threaded step re-reads the cloths' layout only when the epoch moved, so
 * a steady step costs one comparison.
 */

/** The typed arrays the plugin allocates. */
export type TypedArray = Float64Array | Float32Array | Int32Array | Uint32Array | Uint16Array | Uint8Array | Int8Array

/** A typed-array constructor (`Float64Array`, `Int32Array`, ...). */
export interface TypedArrayConstructor<T extends TypedArray> {
  new(length: number): T
  new(buffer: SharedArrayBuffer, byteOffset?: number, length?: number): T
  readonly BYTES_PER_ELEMENT: number
}

/** Threaded worlds alive in this thread (while > 0, new arrays go to shared memory). */
let sharers = 0
/** Layout changes so far (see the module comment). */
let epoch = 0

/**
 * Whether this thread can share memory with workers: SharedArrayBuffer exists (in a browser only on
 * a cross-origin isolated page: COOP same-origin, COEP require-corp) and Atomics with it.
 */
export function sharedMemoryAvailable(): boolean {
  if (typeof SharedArrayBuffer !== 'function' || typeof Atomics !== 'object') return false
  const isolated = (globalThis as { crossOriginIsolated?: boolean }).crossOriginIsolated
  return isolated !== false
}

/** A threaded world starts: new arrays go to shared memory until it ends. */
export function retainSharedMemory(): void {
  sharers++
}

/** A threaded world ended. */
export function releaseSharedMemory(): void {
  if (sharers > 0) sharers--
}

/** Whether new arrays go to shared memory now. */
export function allocatingShared(): boolean {
  return sharers > 0
}

/** A zeroed array of `length` elements, in shared memory while a threaded world exists. */
export function newArray<T extends TypedArray>(Ctor: TypedArrayConstructor<T>, length: number): T {
  epoch++
  if (sharers === 0) return new Ctor(length)
  return new Ctor(new SharedArrayBuffer(Ctor.BYTES_PER_ELEMENT * length))
}

/** A zeroed array of the same type as `like` and `length` elements, shared when `like` is (or when `newArray` would be). */
export function newArrayLike<T extends TypedArray>(like: T, length: number): T {
  const Ctor = like.constructor as TypedArrayConstructor<T>
  if (sharers === 0 && isShared(like)) {
    epoch++
    return new Ctor(new SharedArrayBuffer(Ctor.BYTES_PER_ELEMENT * length))
  }
  return newArray(Ctor, length)
}

/** A copy of `values` as a new array of type `Ctor` (see `newArray`). */
export function arrayOf<T extends TypedArray>(Ctor: TypedArrayConstructor<T>, values: ArrayLike<number>): T {
  const out = newArray(Ctor, values.length)
  out.set(values)
  return out
}

/** A copy of `a` in shared memory (same type and length). */
export function sharedCopy<T extends TypedArray>(a: T): T {
  const Ctor = a.constructor as TypedArrayConstructor<T>
  const out = new Ctor(new SharedArrayBuffer(Ctor.BYTES_PER_ELEMENT * a.length))
  out.set(a)
  epoch++
  return out
}

/** Whether `a` lives in a SharedArrayBuffer. */
export function isShared(a: ArrayBufferView): boolean {
  return typeof SharedArrayBuffer === 'function' && a.buffer instanceof SharedArrayBuffer
}

/** Records a change of which arrays a cloth or the world holds, made without `newArray`. */
export function touchLayout(): void {
  epoch++
}

/** The layout epoch (see the module comment). */
export function layoutEpoch(): number {
  return epoch
}
