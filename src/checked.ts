/**
 * The kernels and builders as the package exports them: each call first checks its arguments
 * (array types and lengths, index ranges, finite values, the parameter block) and throws
 * ClothError naming the bad one, then runs the kernel. The checks cost a pass over the inputs,
 * which is why the plugin's own systems call the unchecked kernels in `src/kernels/` directly:
 * their data was validated once, when it entered through the API.
 */
import {
  ClothError,
  checkIndex,
  checkInteger,
  checkOneOf,
  checkPositive,
  isArrayLike,
  MAX_COORDINATE,
  MAX_SNAPSHOT_COORDINATE,
  checkKeys,
  keysOf,
} from './core/errors'
import { solveLineBending as solveLineBendingKernel } from './kernels/bending'
import { dampPairs as dampPairsKernel } from './kernels/damping'
import { solveDihedrals as solveDihedralsKernel } from './kernels/dihedral'
import {
  solveCompression as solveCompressionKernel,
  solveDistances as solveDistancesKernel,
  solveDistancesXpbd as solveDistancesXpbdKernel,
  spreadInverseMasses as spreadInverseMassesKernel,
} from './kernels/distance'
import {
  G_ANCHOR,
  G_OUT_EXCESS,
  G_OUT_SPEED2,
  GUARD_PARAM_COUNT,
  checkClothHealth as checkClothHealthKernel,
  clearGuardAnchor,
} from './kernels/guard'
import { predictPositions as predictKernel, updateVelocities as updateKernel } from './kernels/integrate'
import { measureStretch as measureStretchKernel, writeRenderMesh as writeRenderMeshKernel } from './kernels/mesh'
import { PARAM_COUNT } from './kernels/params'
import { solveTethers as solveTethersKernel } from './kernels/tether'
import { resolveMaterial, type ClothMaterialSpec } from './model/materials'
import { buildTethers as buildTethersKernel, type TetherMode, type TetherSet } from './model/tethers'
import { buildGridTopology as buildGridKernel, buildMeshTopology as buildMeshKernel, gridMesh } from './model/builders'
import { dihedralAngle as dihedralAngleKernel, type ClothTopology, type TopologyOptions } from './model/topology'
import { checkGridOptions, checkMeshInput, checkTopologyOptions, type GridOptions } from './model/options'
import { gridUvs } from './model/uvs'

// ---------------------------------------------------------------------------------------------
// Argument checks

function f64(arg: string, v: unknown, len: number, finite = true): Float64Array {
  if (!(v instanceof Float64Array)) throw new ClothError(arg, v, 'must be a Float64Array')
  if (v.length < len) throw new ClothError(arg, v, `must hold at least ${len} numbers`)
  if (finite) {
    for (let i = 0; i < len; i++) if (!Number.isFinite(v[i])) throw new ClothError(`${arg}[${i}]`, v[i], 'must be a finite number')
  }
  return v
}

function nonNegative(arg: string, v: Float64Array, len: number): void {
  for (let i = 0; i < len; i++) if (!(v[i] >= 0)) throw new ClothError(`${arg}[${i}]`, v[i], 'must be ≥ 0')
}

function ids(arg: string, v: unknown, len: number, n: number, Type: typeof Int32Array | typeof Uint32Array = Int32Array): void {
  if (!(v instanceof Type)) throw new ClothError(arg, v, `must be an ${Type.name}`)
  if (v.length < len) throw new ClothError(arg, v, `must hold at least ${len} indices`)
  for (let i = 0; i < len; i++)
    if (!(v[i] >= 0 && v[i] < n)) throw new ClothError(`${arg}[${i}]`, v[i], `must be a particle index in [0, ${n - 1}]`)
}

function params(arg: string, p: unknown): Float64Array {
  return f64(arg, p, PARAM_COUNT)
}

function count(arg: string, v: unknown): number {
  return checkInteger(arg, v, 0)
}

function range(start: unknown, end: unknown, total: number): void {
  checkInteger('start', start, 0)
  checkInteger('end', end, start as number)
  if ((end as number) > total) throw new ClothError('end', end, `must be at most ${total}`)
}

/** Particle count implied by an inverse-mass array (checked: finite, ≥ 0). */
function masses(arg: string, invMass: unknown, n?: number): number {
  if (!(invMass instanceof Float64Array)) throw new ClothError(arg, invMass, 'must be a Float64Array')
  const m = n ?? invMass.length
  f64(arg, invMass, m)
  nonNegative(arg, invMass, m)
  return m
}

/**
 * Positions (velocities, accelerations) of n particles: finite and within ±MAX_SNAPSHOT_COORDINATE
 * (farther, squared lengths overflow: a position of 1e300 made NaN of a distance constraint).
 */
function positionsFor(arg: string, pos: unknown, n: number): Float64Array {
  const v = f64(arg, pos, 3 * n)
  bounded(arg, v, 3 * n)
  return v
}

function bounded(arg: string, v: ArrayLike<number>, len: number): void {
  for (let i = 0; i < len; i++) {
    if (!(Math.abs(v[i]) <= MAX_SNAPSHOT_COORDINATE))
      throw new ClothError(`${arg}[${i}]`, v[i], `must lie within ±${MAX_SNAPSHOT_COORDINATE}`)
  }
}

// ---------------------------------------------------------------------------------------------
// Kernels

/** Checked `predictPositions` (see `src/kernels/integrate.ts`). */
export function predictPositions(
  pos: Float64Array,
  prev: Float64Array,
  vel: Float64Array,
  invMass: Float64Array,
  accel: Float64Array | null,
  p: Float64Array,
  n: number,
): void {
  count('count', n)
  masses('invMass', invMass, n)
  positionsFor('pos', pos, n)
  f64('prev', prev, 3 * n, false)
  positionsFor('vel', vel, n)
  if (accel !== null) positionsFor('accel', accel, n)
  params('params', p)
  predictKernel(pos, prev, vel, invMass, accel, p, n)
}

/** Checked `updateVelocities`. */
export function updateVelocities(pos: Float64Array, prev: Float64Array, vel: Float64Array, p: Float64Array, n: number): void {
  count('count', n)
  positionsFor('pos', pos, n)
  positionsFor('prev', prev, n)
  f64('vel', vel, 3 * n, false)
  params('params', p)
  updateKernel(pos, prev, vel, p, n)
}

/** A constraint list's rest values and compliances over [start, end), both ≥ 0; returns end. */
function pairData(rest: unknown, compliance: unknown, start: unknown, end: unknown): number {
  if (!(rest instanceof Float64Array)) throw new ClothError('rest', rest, 'must be a Float64Array')
  range(start, end, rest.length)
  const e = end as number
  f64('rest', rest, e)
  nonNegative('rest', rest, e)
  f64('compliance', compliance, e)
  nonNegative('compliance', compliance as Float64Array, e)
  return e
}

function pairs(pos: unknown, invMass: unknown, idArr: unknown, rest: unknown, compliance: unknown, start: unknown, end: unknown): void {
  const n = masses('invMass', invMass)
  positionsFor('pos', pos, n)
  ids('ids', idArr, 2 * pairData(rest, compliance, start, end), n)
}

/** The distance loops' arguments: positions, inverse masses at position offsets, offset pairs. */
function offsetPairs(
  pos: unknown,
  invMass3: unknown,
  offsets: unknown,
  rest: unknown,
  compliance: unknown,
  start: unknown,
  end: unknown,
): void {
  if (!(invMass3 instanceof Float64Array)) throw new ClothError('invMass3', invMass3, 'must be a Float64Array')
  const n = Math.floor(invMass3.length / 3)
  for (let i = 0; i < n; i++) {
    const w = invMass3[3 * i]
    if (!(Number.isFinite(w) && w >= 0)) throw new ClothError(`invMass3[${3 * i}]`, w, 'must be a finite number ≥ 0')
  }
  positionsFor('pos', pos, n)
  const e = pairData(rest, compliance, start, end)
  if (!(offsets instanceof Int32Array)) throw new ClothError('offsets', offsets, 'must be an Int32Array')
  if (offsets.length < 2 * e) throw new ClothError('offsets', offsets, `must hold at least ${2 * e} offsets`)
  for (let i = 0; i < 2 * e; i++) {
    const o = offsets[i]
    if (!(o >= 0 && o <= 3 * (n - 1) && o % 3 === 0))
      throw new ClothError(`offsets[${i}]`, o, `must be a position offset (particle index × 3) in [0, ${3 * (n - 1)}]`)
  }
}

/**
 * Checked `solveDistances`. Pairs are position offsets (particle index × 3, as in a topology's
 * `distOffsets`) and `invMass3[3i]` holds particle i's inverse mass (`spreadInverseMasses`).
 */
export function solveDistances(
  pos: Float64Array,
  invMass3: Float64Array,
  offsets: Int32Array,
  rest: Float64Array,
  compliance: Float64Array,
  p: Float64Array,
  start: number,
  end: number,
): void {
  offsetPairs(pos, invMass3, offsets, rest, compliance, start, end)
  params('params', p)
  solveDistancesKernel(pos, invMass3, offsets, rest, compliance, p, start, end)
}

/** Checked `solveDistancesXpbd` (arguments as `solveDistances`, plus the multipliers). */
export function solveDistancesXpbd(
  pos: Float64Array,
  invMass3: Float64Array,
  offsets: Int32Array,
  rest: Float64Array,
  compliance: Float64Array,
  lambda: Float64Array,
  p: Float64Array,
  start: number,
  end: number,
): void {
  offsetPairs(pos, invMass3, offsets, rest, compliance, start, end)
  f64('lambda', lambda, end)
  params('params', p)
  solveDistancesXpbdKernel(pos, invMass3, offsets, rest, compliance, lambda, p, start, end)
}

/** Checked `spreadInverseMasses`: `invMass3` must hold 3 × count numbers. */
export function spreadInverseMasses(invMass: Float64Array, invMass3: Float64Array, n: number): void {
  count('n', n)
  masses('invMass', invMass, n)
  f64('invMass3', invMass3, 3 * n, false)
  spreadInverseMassesKernel(invMass, invMass3, n)
}

/** Checked `solveCompression`. */
export function solveCompression(
  pos: Float64Array,
  invMass: Float64Array,
  idArr: Int32Array,
  rest: Float64Array,
  compliance: Float64Array,
  lambda: Float64Array | null,
  p: Float64Array,
  start: number,
  end: number,
): void {
  pairs(pos, invMass, idArr, rest, compliance, start, end)
  if (lambda !== null) f64('lambda', lambda, end)
  params('params', p)
  solveCompressionKernel(pos, invMass, idArr, rest, compliance, lambda, p, start, end)
}

/** Checked `dampPairs`. */
export function dampPairs(
  pos: Float64Array,
  vel: Float64Array,
  invMass: Float64Array,
  idArr: Int32Array,
  m: number,
  p: Float64Array,
): void {
  const n = masses('invMass', invMass)
  positionsFor('pos', pos, n)
  positionsFor('vel', vel, n)
  count('count', m)
  ids('ids', idArr, 2 * m, n)
  params('params', p)
  dampPairsKernel(pos, vel, invMass, idArr, m, p)
}

/** Checked `solveLineBending`. */
export function solveLineBending(
  pos: Float64Array,
  invMass: Float64Array,
  idArr: Int32Array,
  rest: Float64Array,
  compliance: Float64Array,
  lambda: Float64Array | null,
  p: Float64Array,
  start: number,
  end: number,
): void {
  const n = masses('invMass', invMass)
  positionsFor('pos', pos, n)
  ids('ids', idArr, 3 * pairData(rest, compliance, start, end), n)
  if (lambda !== null) f64('lambda', lambda, 3 * end)
  params('params', p)
  solveLineBendingKernel(pos, invMass, idArr, rest, compliance, lambda, p, start, end)
}

/** Checked `solveDihedrals`. */
export function solveDihedrals(
  pos: Float64Array,
  invMass: Float64Array,
  idArr: Int32Array,
  restAngle: Float64Array,
  compliance: Float64Array,
  lambda: Float64Array | null,
  side: number,
  p: Float64Array,
  start: number,
  end: number,
): void {
  const n = masses('invMass', invMass)
  positionsFor('pos', pos, n)
  if (!(restAngle instanceof Float64Array)) throw new ClothError('restAngle', restAngle, 'must be a Float64Array')
  range(start, end, restAngle.length)
  ids('ids', idArr, 4 * end, n)
  f64('restAngle', restAngle, end)
  f64('compliance', compliance, end)
  nonNegative('compliance', compliance, end)
  if (lambda !== null) f64('lambda', lambda, end)
  if (side !== -1 && side !== 0 && side !== 1) throw new ClothError('side', side, 'must be −1, 0 or 1')
  params('params', p)
  solveDihedralsKernel(pos, invMass, idArr, restAngle, compliance, lambda, side, p, start, end)
}

/** Checked `solveTethers` (`restPos`, the rest positions, when the anchors may move apart; see the kernel). */
export function solveTethers(
  pos: Float64Array,
  invMass: Float64Array,
  particle: Int32Array,
  anchor: Int32Array,
  rest: Float64Array,
  m: number,
  restPos: Float64Array | null = null,
): void {
  const n = masses('invMass', invMass)
  positionsFor('pos', pos, n)
  count('m', m)
  ids('particle', particle, m, n)
  ids('anchor', anchor, m, n)
  f64('rest', rest, m)
  nonNegative('rest', rest, m)
  if (restPos !== null) f64('restPos', restPos, 3 * n)
  solveTethersKernel(pos, invMass, particle, anchor, rest, restPos, m)
}

/** Checked `writeRenderMesh`. */
export function writeRenderMesh(
  pos: Float64Array,
  n: number,
  tris: Uint32Array,
  triCount: number,
  outPos: Float32Array,
  outNormal: Float32Array,
): void {
  count('count', n)
  positionsFor('pos', pos, n)
  count('triCount', triCount)
  ids('tris', tris, 3 * triCount, n, Uint32Array)
  if (!(outPos instanceof Float32Array) || outPos.length < 3 * n)
    throw new ClothError('outPos', outPos, `must be a Float32Array of at least ${3 * n} numbers`)
  if (!(outNormal instanceof Float32Array) || outNormal.length < 3 * n)
    throw new ClothError('outNormal', outNormal, `must be a Float32Array of at least ${3 * n} numbers`)
  writeRenderMeshKernel(pos, n, tris, triCount, outPos, outNormal)
}

/** Checked `measureStretch`. */
export function measureStretch(
  pos: ArrayLike<number>,
  edges: Int32Array,
  edgeRest: Float64Array,
  edgeCount: number,
  out: { mean: number; max: number } = { mean: 0, max: 0 },
): { mean: number; max: number } {
  if (!isArrayLike(pos) || pos.length % 3 !== 0) throw new ClothError('pos', pos, 'must be an array of xyz positions')
  for (let i = 0; i < pos.length; i++) if (!Number.isFinite(pos[i])) throw new ClothError(`pos[${i}]`, pos[i], 'must be a finite number')
  bounded('pos', pos, pos.length)
  count('edgeCount', edgeCount)
  ids('edges', edges, 2 * edgeCount, pos.length / 3)
  f64('edgeRest', edgeRest, edgeCount)
  if (typeof out !== 'object' || out === null) throw new ClothError('out', out, 'must be an object')
  return measureStretchKernel(pos, edges, edgeRest, edgeCount, out)
}

/** A full threshold block for a caller's block without the anchor box (its first G_ANCHOR slots). */
const shortGuard = new Float64Array(GUARD_PARAM_COUNT)

/**
 * Checked `checkClothHealth` (see `src/kernels/guard.ts`); non-finite positions are its subject, so
 * they pass. `skip` (optional, one byte per particle): particles marked 1 are left out. A block of
 * only the first 5 slots (without the anchor box) is read with the box empty.
 */
export function checkClothHealth(
  pos: Float64Array,
  vel: Float64Array,
  invMass: Float64Array,
  n: number,
  g: Float64Array,
  skip: Uint8Array | null = null,
): number {
  count('count', n)
  masses('invMass', invMass, n)
  f64('pos', pos, 3 * n, false)
  f64('vel', vel, 3 * n, false)
  f64('guard', g, G_ANCHOR)
  if (skip !== null && (!(skip instanceof Uint8Array) || skip.length < n))
    throw new ClothError('skip', skip, `must be null or a Uint8Array of at least ${n} entries`)
  if (g.length >= GUARD_PARAM_COUNT) return checkClothHealthKernel(pos, vel, invMass, n, g, skip)
  for (let k = 0; k < G_ANCHOR; k++) shortGuard[k] = g[k]
  clearGuardAnchor(shortGuard)
  const health = checkClothHealthKernel(pos, vel, invMass, n, shortGuard, skip)
  g[G_OUT_SPEED2] = shortGuard[G_OUT_SPEED2]
  g[G_OUT_EXCESS] = shortGuard[G_OUT_EXCESS]
  return health
}

// ---------------------------------------------------------------------------------------------
// Builders

/** Checked `buildGridTopology` (rest data of a rectangular sheet, no world needed). */
export function buildGridTopology(
  width: number,
  height: number,
  columns: number,
  rows: number,
  material: ClothMaterialSpec | string,
  topology: 'quad' | 'triangle' = 'quad',
  options?: TopologyOptions,
): ClothTopology {
  checkPositive('width', width)
  checkPositive('height', height)
  if (width > MAX_COORDINATE || height > MAX_COORDINATE)
    throw new ClothError(width > MAX_COORDINATE ? 'width' : 'height', Math.max(width, height), `must be at most ${MAX_COORDINATE} m`)
  checkInteger('columns', columns, 2, 4096)
  checkInteger('rows', rows, 2, 4096)
  checkOneOf('topology', topology, ['quad', 'triangle'] as const)
  return buildGridKernel(
    width,
    height,
    columns,
    rows,
    resolveMaterial(material, 'material'),
    topology,
    checkTopologyOptions(options, columns * rows),
  )
}

const GRID_KEYS = keysOf<GridOptions>({ width: true, height: true, resolution: true })

/**
 * The mesh of a rectangular sheet, as `createCloth` lays it out: vertices row-major from the top
 * left in the sheet's local frame (x right, y up, front facing +z, the middle of the top edge at the
 * origin), triangles counter-clockwise from the front, uvs as on the cloth. With a cloth's width
 * and height and a higher resolution it is that cloth's usual render proxy mesh.
 */
export function buildGridMesh(options: GridOptions): { positions: Float64Array; indices: Uint32Array; uvs: Float32Array } {
  const { width, height, columns, rows } = checkGridOptions(options)
  checkKeys('options', options, GRID_KEYS)
  return { ...gridMesh(width, height, columns, rows), uvs: gridUvs(columns, rows) }
}

/** Checked `buildMeshTopology` (rest data of an indexed triangle mesh). */
export function buildMeshTopology(
  positions: ArrayLike<number>,
  indices: ArrayLike<number>,
  material: ClothMaterialSpec | string,
  options?: TopologyOptions,
): ClothTopology {
  const n = checkMeshInput(positions, indices)
  return buildMeshKernel(positions, indices, resolveMaterial(material, 'material'), checkTopologyOptions(options, n))
}

/** Checked `dihedralAngle`: the signed angle of hinge (e0, e1, w0, w1) in positions `p`. */
export function dihedralAngle(p: ArrayLike<number>, e0: number, e1: number, w0: number, w1: number): number {
  if (!isArrayLike(p) || p.length % 3 !== 0) throw new ClothError('p', p, 'must be an array of xyz positions')
  const n = p.length / 3
  checkIndex('e0', e0, n)
  checkIndex('e1', e1, n)
  checkIndex('w0', w0, n)
  checkIndex('w1', w1, n)
  for (const i of [e0, e1, w0, w1]) {
    for (let k = 0; k < 3; k++)
      if (!Number.isFinite(p[3 * i + k])) throw new ClothError(`p[${3 * i + k}]`, p[3 * i + k], 'must be a finite number')
  }
  return dihedralAngleKernel(p, e0, e1, w0, w1)
}

/** Checked `buildTethers` (long-range attachments from rest positions, edges and anchors). */
export function buildTethers(
  rest: ArrayLike<number>,
  n: number,
  edges: ArrayLike<number>,
  edgeCount: number,
  anchors: ArrayLike<number>,
  mode: TetherMode,
  perParticle: number,
  slack: number,
): TetherSet {
  count('count', n)
  if (!isArrayLike(rest) || rest.length < 3 * n) throw new ClothError('rest', rest, `must hold xyz positions of ${n} particles`)
  for (let i = 0; i < 3 * n; i++) if (!Number.isFinite(rest[i])) throw new ClothError(`rest[${i}]`, rest[i], 'must be a finite number')
  count('edgeCount', edgeCount)
  if (!isArrayLike(edges) || edges.length < 2 * edgeCount) throw new ClothError('edges', edges, `must hold ${2 * edgeCount} indices`)
  for (let k = 0; k < 2 * edgeCount; k++) checkIndex(`edges[${k}]`, edges[k], n)
  if (!isArrayLike(anchors)) throw new ClothError('anchors', anchors, 'must be an array of particle indices')
  for (let k = 0; k < anchors.length; k++) checkIndex(`anchors[${k}]`, anchors[k], n)
  checkOneOf('mode', mode, ['euclidean', 'geodesic'] as const)
  checkInteger('perParticle', perParticle, 1, 16)
  if (!(slack >= 0) || !Number.isFinite(slack)) throw new ClothError('slack', slack, 'must be a finite number ≥ 0')
  return buildTethersKernel(rest, n, edges, edgeCount, anchors, mode, perParticle, slack)
}
