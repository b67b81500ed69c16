/**
 * The one error the plugin throws for bad input. Every check runs at the API edge, before
 * anything reaches the solver, and the message names the argument and the value it got.
 *
 * Common limits: positions and offsets within ±1e9 m; rotations non-zero quaternions; scales
 * finite, above 0 and at most 1e6; `iterations` and `substeps` 1…256; grid `resolution` 2…4096;
 * a material's thickness at most 1e9 m, its drag and lift at most 1000; out arrays long enough; a
 * world must carry the plugin (`argument: 'world'`) and a cloth must be a cloth entity of it. A
 * Transform written straight into the stores with NaN, ±∞, a position beyond ±1e9 m or a scale above
 * 1e6 makes `stepCloth` throw with `argument: 'transform of entity N'` before it takes any of that
 * frame's transforms.
 */
export class ClothError extends Error {
  /** The argument (or option path) that was rejected, e.g. `options.resolution`. */
  readonly argument: string
  /** The rejected value, as given. */
  readonly value: unknown
  /** What the argument must be, e.g. `must be a positive integer`. */
  readonly expectation: string

  constructor(argument: string, value: unknown, expectation: string) {
    super(`bitecs-cloth: ${argument} ${expectation} (got ${describe(value)})`)
    this.name = 'ClothError'
    this.argument = argument
    this.value = value
    this.expectation = expectation
  }
}

function describe(value: unknown): string {
  if (typeof value === 'number') return Number.isNaN(value) ? 'NaN' : String(value)
  if (typeof value === 'string') return JSON.stringify(value)
  if (value === null || value === undefined) return String(value)
  if (Array.isArray(value) || ArrayBuffer.isView(value)) {
    const arr = value as ArrayLike<unknown>
    const head = Array.from({ length: Math.min(arr.length, 4) }, (_, i) => describe(arr[i]))
    return `[${head.join(', ')}${arr.length > 4 ? ', …' : ''}] (length ${arr.length})`
  }
  if (typeof value === 'object') return Object.prototype.toString.call(value)
  return String(value)
}

/** A finite number (not NaN, not ±Infinity). */
export function checkFinite(argument: string, value: unknown): number {
  if (typeof value !== 'number' || !Number.isFinite(value)) {
    throw new ClothError(argument, value, 'must be a finite number')
  }
  return value
}

/** A finite number ≥ 0. */
export function checkNonNegative(argument: string, value: unknown): number {
  if (typeof value !== 'number' || !Number.isFinite(value) || value < 0) {
    throw new ClothError(argument, value, 'must be a finite number ≥ 0')
  }
  return value
}

/** A finite number > 0. */
export function checkPositive(argument: string, value: unknown): number {
  if (typeof value !== 'number' || !Number.isFinite(value) || value <= 0) {
    throw new ClothError(argument, value, 'must be a finite number > 0')
  }
  return value
}

/** An integer in [min, max]. */
export function checkInteger(argument: string, value: unknown, min: number, max = Number.MAX_SAFE_INTEGER): number {
  if (typeof value !== 'number' || !Number.isInteger(value) || value < min || value > max) {
    const range = max === Number.MAX_SAFE_INTEGER ? `≥ ${min}` : `in [${min}, ${max}]`
    throw new ClothError(argument, value, `must be an integer ${range}`)
  }
  return value
}

/** An index into a collection of `count` items. */
export function checkIndex(argument: string, value: unknown, count: number): number {
  if (typeof value !== 'number' || !Number.isInteger(value) || value < 0 || value >= count) {
    throw new ClothError(argument, value, `must be an integer index in [0, ${count - 1}]`)
  }
  return value
}

/** A 3-vector of finite numbers (array, typed array or gl-matrix vec3). */
export function checkVec3(argument: string, value: unknown): ArrayLike<number> {
  if (!isArrayLike(value) || value.length !== 3) {
    throw new ClothError(argument, value, 'must be a 3-vector [x, y, z]')
  }
  for (let i = 0; i < 3; i++) {
    if (typeof value[i] !== 'number' || !Number.isFinite(value[i] as number)) {
      throw new ClothError(argument, value, 'must contain finite numbers')
    }
  }
  return value as ArrayLike<number>
}

/** A unit-length-able quaternion [x, y, z, w] of finite numbers, not all zero. */
export function checkQuat(argument: string, value: unknown): ArrayLike<number> {
  if (!isArrayLike(value) || value.length !== 4) {
    throw new ClothError(argument, value, 'must be a quaternion [x, y, z, w]')
  }
  let len2 = 0
  for (let i = 0; i < 4; i++) {
    const v = value[i]
    if (typeof v !== 'number' || !Number.isFinite(v)) {
      throw new ClothError(argument, value, 'must contain finite numbers')
    }
    len2 += v * v
  }
  if (len2 < 1e-12) throw new ClothError(argument, value, 'must have non-zero length')
  return value as ArrayLike<number>
}

/** A flat array of finite numbers whose length is a multiple of `stride`. */
export function checkFiniteArray(argument: string, value: unknown, stride = 1): ArrayLike<number> {
  if (!isArrayLike(value)) throw new ClothError(argument, value, 'must be an array of numbers')
  if (value.length % stride !== 0) {
    throw new ClothError(argument, value, `must have a length that is a multiple of ${stride}`)
  }
  for (let i = 0; i < value.length; i++) {
    const v = value[i]
    if (typeof v !== 'number' || !Number.isFinite(v)) {
      throw new ClothError(`${argument}[${i}]`, v, 'must be a finite number')
    }
  }
  return value as ArrayLike<number>
}

/** One of a fixed set of strings. */
export function checkOneOf<T extends string>(argument: string, value: unknown, allowed: readonly T[]): T {
  if (typeof value !== 'string' || !(allowed as readonly string[]).includes(value)) {
    throw new ClothError(argument, value, `must be one of ${allowed.map((a) => `'${a}'`).join(', ')}`)
  }
  return value as T
}

/** An array the caller gives to be written into: writable and at least `length` long (typed, plain or gl-matrix). */
export function checkOut(argument: string, value: unknown, length: number): void {
  if (!isArrayLike(value) || typeof value === 'string' || value.length < length || Object.isFrozen(value)) {
    throw new ClothError(argument, value, `must be a writable array of at least ${length} numbers to write into`)
  }
}

/** An object the caller gives to be written into: not frozen (a shared constant threw a TypeError). */
export function checkOutObject(argument: string, value: unknown): object {
  checkObject(argument, value)
  if (Object.isFrozen(value)) throw new ClothError(argument, value, 'must be writable (it is frozen)')
  return value as object
}

/**
 * Every key of an options type, listed once for `checkKeys`: the mapped type makes a listing that
 * misses a key of T, or names one T lacks, a compile error.
 */
export function keysOf<T>(keys: { [K in keyof Required<T>]: true }): readonly string[] {
  return Object.freeze(Object.keys(keys))
}

/**
 * Throws a ClothError naming the first own key of `value` that is not one of `known`: a misspelt
 * option (`{ offest }`, `{ enable: false }`) was silently ignored, leaving the default.
 */
export function checkKeys(argument: string, value: object, known: readonly string[]): void {
  for (const key in value) {
    if (!Object.hasOwn(value, key) || known.includes(key)) continue
    throw new ClothError(
      `${argument}.${key}`,
      (value as Record<string, unknown>)[key],
      `is not an option here (known: ${known.join(', ')})`,
    )
  }
}

/** true or false (not a truthy string: 'false' turned tethers on). */
export function checkBoolean(argument: string, value: unknown): boolean {
  if (typeof value !== 'boolean') throw new ClothError(argument, value, 'must be true or false')
  return value
}

export function isArrayLike(value: unknown): value is ArrayLike<unknown> {
  return (
    Array.isArray(value) ||
    (ArrayBuffer.isView(value) && !(value instanceof DataView)) ||
    (typeof value === 'object' && value !== null && typeof (value as { length?: unknown }).length === 'number')
  )
}

/**
 * Largest accepted world coordinate, size or offset, m. Beyond ~1e150 squared lengths overflow to
 * Infinity (and Infinity − Infinity is NaN); 1e9 m keeps sub-micrometre precision in float64.
 */
export const MAX_COORDINATE = 1e9

/**
 * How far from the origin a snapshot's points may lie, m. The API takes points within
 * ±MAX_COORDINATE, but a cloth's own extent, its pins' targets, teleports and falls carry its
 * particles (and grab targets carried along) past that: a sheet made at x = 1e9, a cape hanging
 * below a hero at y = −1e9 + 0.5. A cloth's snapshot must restore wherever it got; a double still
 * resolves 0.1 mm at 1e12 m.
 */
export const MAX_SNAPSHOT_COORDINATE = 1e12

/**
 * Largest accepted transform scale (per axis). A scale multiplies offsets of up to MAX_COORDINATE;
 * beyond 1e6 the products leave the range where squared lengths stay finite.
 */
export const MAX_SCALE = 1e6

/** A 3-vector of finite numbers, each within ±MAX_COORDINATE (a world position or offset). */
export function checkPoint(argument: string, value: unknown): ArrayLike<number> {
  const v = checkVec3(argument, value)
  for (let i = 0; i < 3; i++) {
    if (Math.abs(v[i]) > MAX_COORDINATE) throw new ClothError(argument, value, `must lie within ±${MAX_COORDINATE} m`)
  }
  return v
}

/** `value` (already checked to be a number) if it is at most `max`, else a ClothError naming `unit`. */
export function checkAtMost(argument: string, value: number, max: number, unit: string): number {
  if (value > max) throw new ClothError(argument, value, `must be at most ${max}${unit}`)
  return value
}

/** A flat array of finite numbers within ±max, length a multiple of `stride`. */
export function checkBoundedArray(argument: string, value: unknown, stride: number, max: number): ArrayLike<number> {
  const arr = checkFiniteArray(argument, value, stride)
  for (let i = 0; i < arr.length; i++) {
    if (Math.abs(arr[i]) > max) throw new ClothError(`${argument}[${i}]`, arr[i], `must lie within ±${max}`)
  }
  return arr
}

/** A non-null object (an options bag). */
export function checkObject(argument: string, value: unknown): object {
  if (typeof value !== 'object' || value === null) throw new ClothError(argument, value, 'must be an object')
  return value
}
