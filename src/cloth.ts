import { addComponent, addEntity, entityExists, hasComponent, removeEntity } from 'bitecs'
import type { quat, vec3 } from 'gl-matrix'
import {
  ClothError,
  checkBoolean,
  checkFiniteArray,
  checkOutObject,
  checkInteger,
  checkObject,
  checkPoint,
  checkNonNegative,
  checkOneOf,
  checkPositive,
  checkQuat,
  checkKeys,
  keysOf,
} from './core/errors'
import { normalizedQuat, rotateVec3 } from './core/math'
import { measureStretch } from './kernels/mesh'
import { createKernelParams } from './kernels/params'
import { resolveMaterial, type ClothMaterialSpec } from './model/materials'
import { checkGridOptions, checkMeshInput, checkTopologyOptions, type CheckedTopologyOptions } from './model/options'
import { buildLines } from './model/lines'
import { EMPTY_TETHERS, buildTethers, loosenTethers, type TetherMode } from './model/tethers'
import { buildGridTopology, buildMeshTopology } from './model/builders'
import { checkUvs, gridUvs, planarUvs } from './model/uvs'
import type { BendSide, BendingModel, ClothTopology, ShearModel } from './model/topology'
import { getCloth, getClothWorld, getClothWorldForChange, getClothWorldForRead } from './world/access'
import type { ClothState, ClothWorldState } from './world/state'
import { wakeClothState } from './world/wake'
import { createClothBudget, setWantedQuality } from './features/budget/api'
import type { ClothGuardOptions, GuardSettings } from './features/guard/types'
import { createClothGuard, resolveGuardOptions } from './features/guard/api'
import { createClothCollision } from './features/collision/api'
import { createClothSleep } from './features/sleep/api'
import { createClothGrabs } from './features/grab/api'
import { HAND } from './features/pins/types'
import { rebuildTearTethers } from './features/tearing/tethers'
import { arrayOf, newArray, touchLayout } from './core/shared'
import { liveColliders } from './features/collision/list'

/**
 * Long-range attachment settings (Kim, Chentanez and Müller-Fischer 2012). Each free particle is
 * tied to its `perParticle` nearest pinned particles by a one-sided constraint that acts only when
 * the particle is farther than its rest distance × (1 + `slack`), so tension reaches the hem within
 * one projection however few iterations run. Tethers never cross between separate pieces of a
 * mesh; they are rebuilt when pins change (and, on a tearable cloth, after tears, along the mesh).
 */
export interface TetherOptions {
  /** Tie free particles to their nearest pinned particles. Default true. */
  enabled?: boolean
  /** Rest distance measured straight ('euclidean', default) or along the mesh ('geodesic'). */
  mode?: TetherMode
  /**
   * Allowed extra length before a tether pulls, as a fraction (0.01 = 1 %). Default 0: the cloth
   * cannot stretch away from its pins at all. Slack lets a cloth hung taut between pins sag, but
   * also lets its taut edges buzz at high substep counts; keep it small.
   */
  slack?: number
  /** Anchors per particle (the nearest ones). Default 2: a sheet between two pins needs both. */
  perParticle?: number
}

/** Options shared by `createCloth` and `createClothFromMesh`. */
export interface ClothOptions {
  /** A preset name ('cotton', 'silk', ...), a preset (`ClothMaterial.SILK`) or a custom material. Default cotton. */
  material?: ClothMaterialSpec | string
  /** Solver iterations per substep. Default 1 (substeps buy more accuracy per ms than iterations). */
  iterations?: number
  /** Substeps per fixed step. Default 8. */
  substeps?: number
  /**
   * 'xpbd' (default): compliance, so the converged stiffness is independent of the iteration count
   * and time step (one spring: within 0.5 % at 1 to 16 iterations); a whole cloth reaches it only
   * with enough substeps × iterations (see README, Materials and accuracy). 'pbd': classic, stiffness per
   * iteration.
   */
  solver?: 'xpbd' | 'pbd'
  /**
   * Solve the structural edges that form lines (a grid's rows and columns, chains of nearly
   * straight edges on a mesh) a line at a time, each iteration in place of their projections in
   * the sweep and once more at the substep's end, after the tethers (a tridiagonal solve per line;
   * a segment held at both ends is projected). A sweep carries a correction one edge per pass, a
   * line solve the whole length: a swinging 64×64 sheet meets 1 % mean / 5 % max stretch at 3
   * substeps instead of 24. Default false. Costs about 1.4–1.8× per substep; give it 2 substeps
   * or more (README, Materials and accuracy). Not used while a cloth is tearable.
   */
  lineSolve?: boolean
  /**
   * Bending model. Default 'line': three-particle constraints along rows and columns (along nearly
   * straight edge pairs on meshes). 'distance': skip-one (grids) or cross-edge (meshes) springs.
   * 'dihedral': hinge angles. 'both': distance + dihedral. See `BendingModel`.
   */
  bending?: BendingModel
  /** Dihedral hinges resist folds both ways ('both', default) or one way only. */
  bendSide?: BendSide
  /** Shear diagonals: two-sided ('distance', default), compression-only or none. */
  shear?: ShearModel
  /** Long-range attachments (on by default once the cloth is pinned); false turns them off. */
  tethers?: boolean | TetherOptions
  /** Velocity damping, 1/s. Default: the material's. */
  damping?: number
  /** Internal stretch damping, 1/s. Default: the material's (60/s for the presets). */
  stretchDamping?: number
  /** Total mass, kg. Default: material density × area. */
  mass?: number
  /** Particles to sweep constraints outward from (where it will be pinned). Default: from the top. */
  orderFrom?: ArrayLike<number>
  /** Explosion guard for this cloth, over the world's defaults; false turns it off. */
  guard?: boolean | ClothGuardOptions
}

/** Options of `createCloth` (a rectangular sheet). */
export interface CreateClothOptions extends ClothOptions {
  /** Width along local +x, m. */
  width: number
  /** Height along local −y, m. */
  height: number
  /** Particles per row, or [columns, rows]. With one number, rows = columns. */
  resolution: number | readonly [number, number]
  /** 'quad' (default): rows, columns, both diagonals as shear. 'triangle': derived like any mesh. */
  topology?: 'quad' | 'triangle'
  /** World position of the middle of the top edge. Default origin. */
  position?: Readonly<vec3> | ArrayLike<number>
  /** World rotation of the sheet (it hangs in its local x-y plane, front facing +z). */
  rotation?: Readonly<quat> | ArrayLike<number>
}

/** Options of `createClothFromMesh`. */
export interface CreateClothFromMeshOptions extends ClothOptions {
  /** World positions, xyz per vertex. */
  positions: ArrayLike<number>
  /**
   * Triangle indices, 3 per triangle (counter-clockwise from the front). Windings that disagree with
   * their neighbours are made to agree with most of their patch (`getClothMesh` gives them so).
   */
  indices: ArrayLike<number>
  /** Per-vertex masses, kg (overrides density and `mass`). */
  masses?: ArrayLike<number>
  /**
   * Texture coordinates, u v per vertex (finite, within ±1e6). Default: a planar projection of the
   * mesh seen from its front (u right, v up, each spanning 0..1; see `getClothMesh`).
   */
  uvs?: ArrayLike<number>
}

/** The keys each options object may have (`checkKeys`). */
const COMMON_KEYS: { [K in keyof Required<ClothOptions>]: true } = {
  material: true,
  iterations: true,
  substeps: true,
  solver: true,
  lineSolve: true,
  bending: true,
  bendSide: true,
  shear: true,
  tethers: true,
  damping: true,
  stretchDamping: true,
  mass: true,
  orderFrom: true,
  guard: true,
}
const GRID_CLOTH_KEYS = keysOf<CreateClothOptions>({
  ...COMMON_KEYS,
  width: true,
  height: true,
  resolution: true,
  topology: true,
  position: true,
  rotation: true,
})
const MESH_CLOTH_KEYS = keysOf<CreateClothFromMeshOptions>({
  ...COMMON_KEYS,
  positions: true,
  indices: true,
  masses: true,
  uvs: true,
})
const QUALITY_KEYS = keysOf<ClothQuality>({ substeps: true, iterations: true, lineSolve: true })
const TETHER_KEYS = keysOf<TetherOptions>({ enabled: true, mode: true, slack: true, perParticle: true })

/**
 * Creates a rectangular cloth. Particles are row-major from the top-left corner (index = row ·
 * columns + column, row 0 at the top); the sheet hangs in its local x-y plane with the middle of the
 * top edge at `position`. Returns the cloth entity.
 */
export function createCloth(world: object, options: CreateClothOptions): number {
  const state = getClothWorldForChange(world)
  const { width, height, columns, rows } = checkGridOptions(options)
  checkKeys('options', options, GRID_CLOTH_KEYS)
  const topo = options.topology === undefined ? 'quad' : checkOneOf('options.topology', options.topology, ['quad', 'triangle'] as const)
  const position = options.position === undefined ? ORIGIN : checkPoint('options.position', options.position)
  const rotation = options.rotation === undefined ? IDENTITY : normalizedQuat(checkQuat('options.rotation', options.rotation))
  const common = checkCommon(options, columns * rows, state)
  const topology = buildGridTopology(width, height, columns, rows, common.material, topo, common.topologyOptions)

  const pos = newArray(Float64Array, 3 * topology.particleCount)
  const p = new Float64Array(3)
  for (let i = 0; i < topology.particleCount; i++) {
    const r = topology.restPositions
    rotateVec3(rotation[0], rotation[1], rotation[2], rotation[3], r[3 * i], r[3 * i + 1], r[3 * i + 2], p, 0)
    pos[3 * i] = position[0] + p[0]
    pos[3 * i + 1] = position[1] + p[1]
    pos[3 * i + 2] = position[2] + p[2]
  }
  return spawnCloth(world, state, topology, pos, common, undefined, gridUvs(columns, rows))
}

/**
 * Creates a cloth from any indexed triangle mesh. Edges become stretch constraints; where two
 * triangles form a quad, its diagonals become shear pairs; bending comes from nearly opposite edge
 * pairs at each vertex ('line'), from the vertices opposite each interior edge ('distance') or from
 * hinges on interior edges ('dihedral'). Vertices no triangle uses are no part of the cloth: they
 * keep their place (inverse mass 0) and are left out of every bounds. Returns the cloth entity.
 */
export function createClothFromMesh(world: object, options: CreateClothFromMeshOptions): number {
  const state = getClothWorldForChange(world)
  checkObject('options', options)
  checkKeys('options', options, MESH_CLOTH_KEYS)
  const n = checkMeshInput(options.positions, options.indices, 'options.')
  const positions = options.positions
  const indices = options.indices
  let masses: ArrayLike<number> | undefined
  if (options.masses !== undefined) {
    masses = checkFiniteArray('options.masses', options.masses)
    if (masses.length !== n) throw new ClothError('options.masses', masses, `must have one entry per vertex (${n})`)
  }
  const uvs = options.uvs === undefined ? undefined : checkUvs('options.uvs', options.uvs, n)
  const common = checkCommon(options, n, state)
  const topology = buildMeshTopology(positions, indices, common.material, common.topologyOptions)
  // (a vertex no triangle uses is no part of the cloth: its mass is not read, and may be 0)
  const unused = topology.unused
  if (masses) {
    for (let i = 0; i < n; i++)
      if (!(masses[i] > 0) && (unused === null || unused[i] === 0 || masses[i] < 0))
        throw new ClothError(`options.masses[${i}]`, masses[i], 'must be > 0')
  }
  const uv = uvs === undefined ? planarUvs(topology.restPositions, n, topology.triangles, topology.triangleCount) : Float32Array.from(uvs)
  return spawnCloth(world, state, topology, arrayOf(Float64Array, positions), common, masses, uv)
}

interface CommonOptions {
  material: ClothMaterialSpec
  iterations: number
  substeps: number
  solver: 'xpbd' | 'pbd'
  lineSolve: boolean
  damping: number
  stretchDamping: number
  mass: number | undefined
  tethers: Required<TetherOptions>
  topologyOptions: CheckedTopologyOptions
  guard: GuardSettings
}

function checkCommon(o: ClothOptions, n: number, state: ClothWorldState): CommonOptions {
  const material = resolveMaterial(o.material)
  const iterations = o.iterations === undefined ? 1 : checkInteger('options.iterations', o.iterations, 1, 256)
  const substeps = o.substeps === undefined ? 8 : checkInteger('options.substeps', o.substeps, 1, 256)
  const solver = o.solver === undefined ? 'xpbd' : checkOneOf('options.solver', o.solver, ['xpbd', 'pbd'] as const)
  const lineSolve = o.lineSolve === undefined ? false : checkBoolean('options.lineSolve', o.lineSolve)
  const damping = o.damping === undefined ? material.damping : checkNonNegative('options.damping', o.damping)
  const stretchDamping = o.stretchDamping === undefined ? material.stretchDamping
    : checkNonNegative('options.stretchDamping', o.stretchDamping)
  const mass = o.mass === undefined ? undefined : checkPositive('options.mass', o.mass)
  const guard = resolveGuardOptions(o.guard, state.guard.defaults, 'options.guard')
  return {
    material,
    iterations,
    substeps,
    solver,
    lineSolve,
    damping,
    stretchDamping,
    mass,
    tethers: checkTetherOptions(o.tethers, 'options.tethers'),
    topologyOptions: checkTopologyOptions(o, n),
    guard,
  }
}

function checkTetherOptions(t: boolean | TetherOptions | undefined, arg: string): Required<TetherOptions> {
  const out: Required<TetherOptions> = { enabled: true, mode: 'euclidean', slack: 0, perParticle: 2 }
  if (t === undefined || t === true) return out
  if (t === false) return { ...out, enabled: false }
  if (typeof t !== 'object' || t === null) throw new ClothError(arg, t, 'must be a boolean or tether options')
  checkKeys(arg, t, TETHER_KEYS)
  if (t.enabled !== undefined) out.enabled = checkBoolean(`${arg}.enabled`, t.enabled)
  if (t.mode !== undefined) out.mode = checkOneOf(`${arg}.mode`, t.mode, ['euclidean', 'geodesic'] as const)
  if (t.slack !== undefined) out.slack = checkNonNegative(`${arg}.slack`, t.slack)
  if (t.perParticle !== undefined) out.perParticle = checkInteger(`${arg}.perParticle`, t.perParticle, 1, 16)
  return out
}

/**
 * Inverse masses of a new cloth: from `masses`, or the topology's scaled to `o.mass`; 0 for vertices
 * no triangle uses. Throws ClothError for a particle too light for the solver.
 */
function inverseMasses(topology: ClothTopology, o: CommonOptions, masses: ArrayLike<number> | undefined): Float64Array {
  const n = topology.particleCount
  const invMass = newArray(Float64Array, n)
  let scale = 1
  if (o.mass !== undefined) {
    let total = 0
    for (let i = 0; i < n; i++) total += topology.masses[i]
    scale = o.mass / total
  }
  const unused = topology.unused
  for (let i = 0; i < n; i++) invMass[i] = 1 / (masses ? masses[i] : topology.masses[i] * scale)
  for (let i = 0; i < n; i++) {
    // a vertex no triangle uses is no part of the cloth: it stays where it is (see ClothTopology.unused)
    if (unused !== null && unused[i] === 1) {
      invMass[i] = 0
      continue
    }
    // a particle lighter than a nanogram (or a density or mass so small that 1/m overflows) is
    // rejected: its inverse mass would turn the constraint sums into Infinity and NaN; one heavier
    // than 1e12 kg too (no cloth's, and past 1e300 kg its own snapshot could not be restored)
    if (!(invMass[i] <= MAX_INV_MASS && invMass[i] >= 1 / MAX_INV_MASS)) {
      const m = masses ? masses[i] : topology.masses[i] * scale
      const arg = masses ? `options.masses[${i}]` : o.mass !== undefined ? 'options.mass' : 'options.material.density'
      throw new ClothError(
        arg,
        masses ? m : o.mass ?? o.material.density,
        `gives particle ${i} a mass of ${m} kg; particles need ${1 / MAX_INV_MASS} to ${MAX_INV_MASS} kg`,
      )
    }
  }
  return invMass
}

function spawnCloth(
  world: object,
  state: ClothWorldState,
  topology: ClothTopology,
  pos: Float64Array,
  o: CommonOptions,
  masses: ArrayLike<number> | undefined,
  uvs: Float32Array,
): number {
  const n = topology.particleCount
  const invMass = inverseMasses(topology, o, masses)

  const eid = addEntity(world as never)
  const c: ClothState = {
    eid,
    seq: state.nextSeq++,
    topology,
    material: o.material,
    count: n,
    pos,
    prev: arrayOf(Float64Array, pos),
    vel: newArray(Float64Array, 3 * n),
    invMass,
    baseInvMass: arrayOf(Float64Array, invMass),
    invMass3: newArray(Float64Array, 3 * n),
    pinCount: newArray(Uint16Array, n),
    accel: null,
    piece: topology.pieces, // (a tearable cloth gets its own labels, relabelled as it tears)
    pieceCount: topology.pieceCount,
    detached: newArray(Int32Array, topology.pieces === null ? 1 : n + 1),
    substeps: o.substeps,
    iterations: o.iterations,
    solver: o.solver,
    damping: o.damping,
    stretchDamping: o.stretchDamping,
    h: state.fixedTimeStep / o.substeps,
    subIndex: -1,
    idle: false,
    params: createKernelParams(),
    distLambda: newArray(Float64Array, topology.distCount),
    compLambda: newArray(Float64Array, topology.compCount),
    lineLambda: newArray(Float64Array, 3 * topology.lineCount),
    hingeLambda: newArray(Float64Array, topology.hingeCount),
    lines: o.lineSolve ? buildLines(topology) : null,
    version: 0,
    tethers: {
      set: EMPTY_TETHERS,
      enabled: o.tethers.enabled,
      mode: o.tethers.mode,
      slack: o.tethers.slack,
      perParticle: o.tethers.perParticle,
      dirty: false,
      loosen: false,
    },
    render: {
      positions: new Float32Array(3 * n),
      normals: new Float32Array(3 * n),
      indices: Uint32Array.from(topology.triangles),
      uvs,
      version: -1,
      mesh: null,
    },
    sleep: createClothSleep(state.sleep.defaults),
    pins: { list: [], skipTeleport: false, hand: new Float64Array(HAND), fresh: true, backdate: new Float64Array(12) },
    grab: createClothGrabs(),
    wind: null,
    collision: createClothCollision(Math.max(4, liveColliders(state.collision).length)),
    budget: createClothBudget(o.substeps, o.iterations),
    guard: createClothGuard(topology, pos, o.guard),
    character: null,
    tear: null,
  }
  state.components.Cloth.state[eid] = c
  state.cloths.push(c)
  addComponent(world as never, eid, state.components.Cloth)
  return eid
}

/** Rebuilds a cloth's tethers from its current pins (called by the sync phase when pins changed). */
export function rebuildTethers(state: ClothWorldState, c: ClothState): void {
  const ct = c.tethers
  ct.dirty = false
  touchLayout() // the cloth holds another tether set
  if (!ct.enabled) {
    ct.loosen = false
    ct.set = EMPTY_TETHERS
    return
  }
  if (c.tear !== null) {
    rebuildTearTethers(state, c) // into reserved arrays: a tear step allocates nothing
    return
  }
  const anchors: number[] = []
  for (let i = 0; i < c.count; i++) if (c.pinCount[i] > 0) anchors.push(i)
  const t = c.topology
  ct.set = buildTethers(t.restPositions, c.count, t.edges, t.edgeCount, anchors, ct.mode, ct.perParticle, ct.slack)
  if (ct.loosen) loosenTethers(ct.set, c.pos)
  ct.loosen = false
  state.stats.tetherRebuilds++
}

/**
 * The cloth's internal state: `pos`, `prev`, `vel` and `invMass` (Float64Array, xyz interleaved for
 * the vectors), `count` live particles, `topology` (rest data, shared and read-only unless the
 * cloth is tearable), pins and settings, and one sub-object per feature. Read freely; write with
 * care, and call `wakeCloth` after writing a sleeping cloth's arrays.
 */
export function getClothState(world: object, cloth: number): ClothState {
  return getCloth(getClothWorld(world), cloth)
}

/** All cloth entities of a world, in creation order. */
export function getCloths(world: object): number[] {
  return getClothWorld(world).cloths.map((c) => c.eid)
}

/**
 * Changes a cloth's substeps and/or iterations per substep. With a world budget (`setClothBudget`)
 * these are the most it runs; a quality target (`setClothQualityTarget`) moves them from here.
 */
export function setClothQuality(world: object, cloth: number, quality: ClothQuality): void {
  const state = getClothWorldForChange(world)
  const c = getCloth(state, cloth)
  checkObject('quality', quality)
  checkKeys('quality', quality, QUALITY_KEYS)
  const substeps = quality.substeps === undefined ? c.budget.wantSubsteps : checkInteger('quality.substeps', quality.substeps, 1, 256)
  const iterations = quality.iterations === undefined ? c.budget.wantIterations
    : checkInteger('quality.iterations', quality.iterations, 1, 256)
  const lineSolve = quality.lineSolve === undefined ? c.lines !== null : checkBoolean('quality.lineSolve', quality.lineSolve)
  setWantedQuality(state, c, substeps, iterations)
  if (lineSolve !== (c.lines !== null)) {
    c.lines = lineSolve ? buildLines(c.topology) : null
    touchLayout() // the cloth holds other arrays
  }
  wakeClothState(state, c)
}

/** What `setClothQuality` sets (each optional: what is not given stays). */
export interface ClothQuality {
  substeps?: number
  iterations?: number
  /** Solve lines of edges directly (see `ClothOptions.lineSolve`). */
  lineSolve?: boolean
}

/** Changes a cloth's tether settings (`false` turns tethers off); they are rebuilt at the next step. */
export function setClothTethers(world: object, cloth: number, tethers: boolean | TetherOptions): void {
  const state = getClothWorldForChange(world)
  const c = getCloth(state, cloth)
  if (typeof tethers !== 'boolean') checkObject('tethers', tethers)
  const ct = c.tethers
  const current: TetherOptions = { enabled: ct.enabled, mode: ct.mode, slack: ct.slack, perParticle: ct.perParticle }
  const t = checkTetherOptions(typeof tethers === 'boolean' ? { ...current, enabled: tethers } : { ...current, ...tethers }, 'tethers')
  ct.enabled = t.enabled
  ct.mode = t.mode
  ct.slack = t.slack
  ct.perParticle = t.perParticle
  ct.dirty = true
  ct.loosen = true
  wakeClothState(state, c)
}

/**
 * Edge stretch of a cloth now: mean and max over its structural edges of max(0, length/rest − 1)
 * (0.01 = 1 % longer than rest).
 */
export function getClothStretch(world: object, cloth: number, out = { mean: 0, max: 0 }): { mean: number; max: number } {
  const c = getCloth(getClothWorldForRead(world, 'getClothStretch'), cloth)
  checkOutObject('out', out)
  const t = c.topology
  return measureStretch(c.pos, t.stretchIds, t.stretchRest, t.stretchCount, out)
}

/** Removes a cloth with its pins, and ends its grabs (as does `removeEntity` on the cloth). */
export function removeCloth(world: object, cloth: number): void {
  const state = getClothWorldForChange(world)
  getCloth(state, cloth)
  if (entityExists(world as never, cloth) && hasComponent(world as never, cloth, state.components.Cloth))
    removeEntity(world as never, cloth)
}

const ORIGIN = [0, 0, 0]
/** Largest inverse mass, 1/kg (particles of at least 1e-12 kg). */
const MAX_INV_MASS = 1e12

const IDENTITY = [0, 0, 0, 1]
