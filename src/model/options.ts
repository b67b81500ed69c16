import {
  ClothError,
  MAX_COORDINATE,
  checkAtMost,
  checkBoundedArray,
  checkIndex,
  checkInteger,
  checkObject,
  checkOneOf,
  checkPositive,
  isArrayLike,
} from '../core/errors'
import type { BendSide, BendingModel, ShearModel, TopologyOptions } from './topology'

/** Topology options as the builders take them, with every default filled in. */
export interface CheckedTopologyOptions {
  bending: BendingModel
  shear: ShearModel
  bendSide: BendSide
  orderFrom?: ArrayLike<number>
}

/**
 * Checks the topology options of a builder or `createCloth` (`bending`, `shear`, `bendSide`,
 * `orderFrom` over `n` particles) on `o`; undefined fields take the builders' defaults. The one
 * check both entry points use, so the lists of allowed values cannot drift apart.
 */
export function checkTopologyOptions(o: TopologyOptions | undefined, n: number, arg = 'options'): CheckedTopologyOptions {
  if (o === undefined) return { bending: 'line', shear: 'distance', bendSide: 'both' }
  checkObject(arg, o)
  const bending = o.bending === undefined ? 'line'
    : checkOneOf(`${arg}.bending`, o.bending, ['line', 'distance', 'dihedral', 'both', 'none'] as const)
  const shear = o.shear === undefined ? 'distance' : checkOneOf(`${arg}.shear`, o.shear, ['distance', 'compression', 'none'] as const)
  const bendSide = o.bendSide === undefined ? 'both' : checkOneOf(`${arg}.bendSide`, o.bendSide, ['both', 'front', 'back'] as const)
  let orderFrom: ArrayLike<number> | undefined
  if (o.orderFrom !== undefined) {
    if (!isArrayLike(o.orderFrom)) throw new ClothError(`${arg}.orderFrom`, o.orderFrom, 'must be an array of particle indices')
    for (let k = 0; k < o.orderFrom.length; k++) checkIndex(`${arg}.orderFrom[${k}]`, o.orderFrom[k], n)
    orderFrom = o.orderFrom
  }
  return { bending, shear, bendSide, orderFrom }
}

/**
 * Checks an indexed triangle mesh: xyz positions of at least 3 vertices within ±MAX_COORDINATE,
 * and a non-empty index list whose triangles each name three different vertices. `prefix` goes
 * before the argument names ('options.' for `createClothFromMesh`). Returns the vertex count.
 */
export function checkMeshInput(positions: unknown, indices: unknown, prefix = ''): number {
  checkBoundedArray(`${prefix}positions`, positions, 3, MAX_COORDINATE)
  const n = (positions as ArrayLike<number>).length / 3
  if (n < 3) throw new ClothError(`${prefix}positions`, positions, 'must hold at least 3 vertices')
  if (!isArrayLike(indices) || indices.length === 0 || indices.length % 3 !== 0) {
    throw new ClothError(`${prefix}indices`, indices, 'must be a non-empty array of triangle indices (length a multiple of 3)')
  }
  for (let k = 0; k < indices.length; k++) checkIndex(`${prefix}indices[${k}]`, indices[k], n)
  for (let t = 0; t < indices.length; t += 3) {
    const a = indices[t], b = indices[t + 1], c = indices[t + 2]
    if (a === b || b === c || a === c)
      throw new ClothError(`${prefix}indices[${t}..${t + 2}]`, [a, b, c], 'must name three different vertices')
  }
  return n
}

/** The size of a rectangular sheet: width and height, m, and particles per row, or [columns, rows]. */
export interface GridOptions {
  width: number
  height: number
  resolution: number | readonly [number, number]
}

/**
 * Checks a sheet's `width`, `height` (> 0, at most MAX_COORDINATE) and `resolution` (2..4096 per
 * side; one number for both) on `options`, for `createCloth` and `buildGridMesh`.
 */
export function checkGridOptions(options: GridOptions): { width: number; height: number; columns: number; rows: number } {
  checkObject('options', options)
  const width = checkAtMost('options.width', checkPositive('options.width', options.width), MAX_COORDINATE, ' m')
  const height = checkAtMost('options.height', checkPositive('options.height', options.height), MAX_COORDINATE, ' m')
  let columns: number, rows: number
  if (isArrayLike(options.resolution)) {
    const r = options.resolution as ArrayLike<number>
    if (r.length !== 2) throw new ClothError('options.resolution', r, 'must be a number or [columns, rows]')
    columns = checkInteger('options.resolution[0]', r[0], 2, 4096)
    rows = checkInteger('options.resolution[1]', r[1], 2, 4096)
  } else {
    columns = rows = checkInteger('options.resolution', options.resolution, 2, 4096)
  }
  return { width, height, columns, rows }
}
