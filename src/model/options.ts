import { ClothError, MAX_COORDINATE, checkBoundedArray, checkIndex, checkObject, checkOneOf, isArrayLike } from '../core/errors'
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
  const bending = o.bending === undefined ? 'line' : checkOneOf(`${arg}.bending`, o.bending, ['line', 'distance', 'dihedral', 'both', 'none'] as const)
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
    if (a === b || b === c || a === c) throw new ClothError(`${prefix}indices[${t}..${t + 2}]`, [a, b, c], 'must name three different vertices')
  }
  return n
}
