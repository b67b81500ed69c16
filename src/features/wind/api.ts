import { addComponent, addEntity, entityExists, hasComponent, observe, onAdd, onRemove, removeComponent, removeEntity } from 'bitecs'
import type { quat, vec3 } from 'gl-matrix'
import {
  ClothError,
  MAX_COORDINATE,
  checkAtMost,
  checkInteger,
  checkNonNegative,
  checkObject,
  checkOneOf,
  checkOut,
  checkPoint,
  checkPositive,
  checkQuat,
  checkVec3,
  isArrayLike,
  checkKeys,
  keysOf,
} from '../../core/errors'
import { NOISE_SCRATCH, ZONE_STRIDE, addZoneAir } from '../../kernels/wind'
import { getClothWorld, getClothWorldForChange } from '../../world/access'
import { growStores } from '../../world/capacity'
import { trackEntity, untrackEntity } from '../../world/kinematics'
import type { ClothWorldState } from '../../world/state'
import { setTransform } from '../../world/transform'
import { compileZones, ensureClothWind } from './step'
import type { WindShape, WindWorld } from './types'
import { arrayOf, newArray, touchLayout } from '../../core/shared'
import { deferrable } from '../../world/flight'

/** Options of `createWindZone` (and, all optional, of `setWindZone`). */
export interface WindZoneOptions {
  /** Direction the wind blows towards, world space (normalised for you). */
  direction: Readonly<vec3> | ArrayLike<number>
  /** Mean wind speed, m/s (≥ 0). */
  strength: number
  /**
   * Turbulence intensity as a fraction of the speed: each component of the turbulent velocity stays
   * within ±turbulence × speed. 0 (default) is a steady wind; 0.2–0.5 is gusty weather.
   */
  turbulence?: number
  /** Size of the turbulent eddies, m. Default 2. */
  turbulenceScale?: number
  /** Time over which the turbulence pattern renews itself, s. Default 0.8. */
  turbulencePeriod?: number
  /** 'global' (default): everywhere. 'box' or 'sphere': a volume around the zone's Transform. */
  shape?: WindShape
  /** Where the zone's Transform starts (its centre), m. Default origin. Move it with `setTransform`. */
  position?: Readonly<vec3> | ArrayLike<number>
  /** Rotation of a box zone (its Transform's rotation). Default identity. */
  rotation?: Readonly<quat> | ArrayLike<number>
  /** Box: full extents [x, y, z] (or one number for a cube), m. Sphere: the radius, m. Default: 2 m across (box extents 2, sphere radius 1). */
  size?: number | Readonly<vec3> | ArrayLike<number>
  /** Distance beyond the box or sphere over which the wind fades to nothing (smoothstep), m. Default 0.5. */
  falloff?: number
  /** Noise seed (integer). Default 1. */
  seed?: number
  /**
   * Air density in the zone, kg/m³. Default: the air's around it. A global zone's is the ambient
   * density (the last created global zone's that sets one); a box or sphere zone's replaces the
   * density inside it, blended over its falloff (densities of overlapping zones do not add).
   */
  airDensity?: number
}

/** Options of `gustWind`. */
export interface GustOptions {
  /** Extra wind speed at the gust's peak, m/s (negative for a lull; the speed never drops below 0). */
  strength: number
  /** Length of the gust, s: it ramps up over the first 30 %, holds, and ramps down over the last 30 %. Default 1. */
  duration?: number
}

const ZERO_ROTATION = [0, 0, 0, 1]

/** Creates the per-world wind state (validates `airDensity`). Called by `installClothPlugin`. */
const ZONE_KEYS = keysOf<WindZoneOptions>({
  direction: true,
  strength: true,
  turbulence: true,
  turbulenceScale: true,
  turbulencePeriod: true,
  shape: true,
  position: true,
  rotation: true,
  size: true,
  falloff: true,
  seed: true,
  airDensity: true,
})
const SETTABLE_ZONE_KEYS = ZONE_KEYS.filter((key) => key !== 'shape' && key !== 'position' && key !== 'rotation')
const GUST_KEYS = keysOf<GustOptions>({ strength: true, duration: true })

export function createWindWorld(airDensity: number | undefined): WindWorld {
  const rho = airDensity === undefined ? 1.2
    : checkAtMost('options.airDensity', checkNonNegative('options.airDensity', airDensity), MAX_AIR_DENSITY, ' kg/m³')
  return {
    zones: [],
    airDensity: arrayOf(Float64Array, [rho]),
    time: new Float64Array(1),
    params: newArray(Float64Array, 4 * ZONE_STRIDE),
    active: new Int32Array(4),
    bounds: new Float64Array(6),
    scratch: new Float64Array(NOISE_SCRATCH),
    compiled: false,
    clamp: true,
  }
}

/** Registers the wind observers on a world. Called by `installClothPlugin`. */
export function installWind(world: object, state: ClothWorldState): void {
  const w = world as never
  // a cloth created while zones exist gets its buffers now, never in a step
  observe(w, onAdd(state.components.Cloth), (eid: number) => {
    const c = state.components.Cloth.state[eid]
    if (c && state.wind.zones.length > 0) ensureClothWind(c)
  })
  observe(
    w,
    onRemove(state.components.WindZone),
    deferrable(state, (eid: number) => {
      const zones = state.wind.zones
      const i = zones.indexOf(eid)
      if (i < 0) return
      zones.splice(i, 1)
      touchLayout()
      untrackEntity(state, eid)
      state.wind.compiled = false
      if (zones.length === 0) { for (const c of state.cloths) c.accel = null }
    }),
  )
  // a zone whose entity loses its Transform is removed, as if its entity were (it would blow from
  // a stale pose); the Transform's observers run before the WindZone's, so removing the whole
  // entity still notifies each WindZone observer once
  observe(
    w,
    onRemove(state.transforms.component),
    deferrable(state, (eid: number) => {
      if (state.wind.zones.indexOf(eid) >= 0 && hasComponent(w, eid, state.components.WindZone)) {
        removeComponent(w, eid, state.components.WindZone)
      }
    }),
  )
}

/**
 * Creates a wind zone: an entity with a Transform (at `position`) and the WindZone component.
 * Global zones blow everywhere; box and sphere zones blow inside their volume and fade out over
 * `falloff` beyond it, following their Transform when it moves. Zones add up where they overlap.
 * Returns the zone entity (remove it with `removeWindZone` or `removeEntity`).
 *
 * Every cloth triangle a zone reaches (area A, normal n̂, air velocity relative to it w) feels drag
 * ½ρ·C_d·A·|w|(w·n̂)·n̂ along its normal, lift ½ρ·C_l·A·|w|(w·n̂)(1 − (n̂·ŵ)²)·n̂ (the extra normal
 * force at grazing incidence; pressure acts normal to a plate) and skin friction ρ·C_f·A·|w|·w_t along its surface (C_f = 0.01), two-sided, with the material's
 * `drag` (C_d) and `lift` (C_l) and the air density ρ (the plugin's `airDensity`, or the zone's);
 * each corner gets a third. The orientation is a smoothed normal, and a clamp limits a substep's
 * aerodynamic velocity change to the air's speed relative to the particle along the force.
 *
 * @example
 * const breeze = createWindZone(world, { direction: [1, 0, 0.3], strength: 6, turbulence: 0.3 })
 * gustWind(world, breeze, { strength: 8, duration: 1.5 })
 */
export function createWindZone(world: object, options: WindZoneOptions): number {
  const state = getClothWorldForChange(world)
  if (typeof options !== 'object' || options === null) throw new ClothError('options', options, 'must be an object')
  checkKeys('options', options, ZONE_KEYS)
  const shape = options.shape === undefined ? 'global' : checkOneOf('options.shape', options.shape, ['global', 'box', 'sphere'] as const)
  const position = options.position === undefined ? [0, 0, 0] : checkPoint('options.position', options.position)
  const rotation = options.rotation === undefined ? ZERO_ROTATION : checkQuat('options.rotation', options.rotation)
  if (options.direction === undefined) throw new ClothError('options.direction', undefined, 'is required (a 3-vector)')
  if (options.strength === undefined) throw new ClothError('options.strength', undefined, 'is required (m/s)')
  const checked = checkZoneOptions(options, shape)

  const eid = addEntity(world as never)
  growStores(state, eid)
  try {
    setTransform(world, eid, position, rotation)
  } catch (e) {
    // (host transform arrays too short for the new entity: it goes again, and the error names the world)
    removeEntity(world as never, eid)
    throw e instanceof ClothError && e.argument === 'eid' ? new ClothError('world', world, `has no room for a zone entity: ${e.message}`)
      : e
  }
  const Z = state.components.WindZone
  Z.shape[eid] = shape === 'global' ? 0 : shape === 'box' ? 1 : 2
  Z.turbulence[eid] = 0
  Z.turbulenceScale[eid] = 2
  Z.turbulencePeriod[eid] = 0.8
  Z.halfX[eid] = Z.halfY[eid] = Z.halfZ[eid] = 1
  Z.falloff[eid] = 0.5
  Z.airDensity[eid] = -1
  Z.seed[eid] = 1
  Z.gustFrom[eid] =
    Z.gustPeak[eid] =
    Z.gustTime[eid] =
    Z.gustDuration[eid] =
    Z.gust[eid] =
      0
  Z.drift[3 * eid] = Z.drift[3 * eid + 1] = Z.drift[3 * eid + 2] = 0
  applyZoneOptions(Z, eid, checked)
  Z.slot[eid] = trackEntity(state, eid)
  addComponent(world as never, eid, Z)

  const wind = state.wind
  wind.zones.push(eid)
  touchLayout()
  if (wind.params.length < wind.zones.length * ZONE_STRIDE) {
    wind.params = newArray(Float64Array, 2 * wind.zones.length * ZONE_STRIDE)
    wind.active = new Int32Array(2 * wind.zones.length)
  }
  wind.compiled = false
  for (const c of state.cloths) ensureClothWind(c)
  return eid
}

/**
 * Changes a zone at run time: any of direction, strength, turbulence, turbulenceScale,
 * turbulencePeriod, size, falloff, seed, airDensity (the shape is fixed; move the zone with
 * `setTransform`). Takes effect at the next step.
 */
export function setWindZone(world: object, zone: number, options: Partial<Omit<WindZoneOptions, 'shape' | 'position' | 'rotation'>>): void {
  const state = getClothWorldForChange(world)
  checkZone(world, state, zone)
  if (typeof options !== 'object' || options === null) throw new ClothError('options', options, 'must be an object')
  // (the shape, position and rotation are fixed: given here, they were silently ignored)
  checkKeys('options', options, SETTABLE_ZONE_KEYS)
  const Z = state.components.WindZone
  const shape = Z.shape[zone] === 0 ? 'global' : Z.shape[zone] === 1 ? 'box' : 'sphere'
  applyZoneOptions(Z, zone, checkZoneOptions(options, shape))
  state.wind.compiled = false
}

/**
 * Starts a gust on a zone: its speed rises by `strength` over the first 30 % of `duration`, holds,
 * and falls back over the last 30 % (smoothstep ramps, so the cloth gets no kick). A gust started
 * during another one ramps from the current gust speed, without a jump.
 */
export function gustWind(world: object, zone: number, options: GustOptions): void {
  const state = getClothWorldForChange(world)
  checkZone(world, state, zone)
  if (typeof options !== 'object' || options === null) throw new ClothError('options', options, 'must be an object')
  checkKeys('options', options, GUST_KEYS)
  if (typeof options.strength !== 'number' || !Number.isFinite(options.strength) || Math.abs(options.strength) > MAX_WIND) {
    throw new ClothError('options.strength', options.strength, `must be a finite number (m/s) within ±${MAX_WIND}`)
  }
  const duration = options.duration === undefined ? 1 : checkPositive('options.duration', options.duration)
  const Z = state.components.WindZone
  Z.gustFrom[zone] = Z.gust[zone]
  Z.gustPeak[zone] = options.strength
  Z.gustTime[zone] = 0
  Z.gustDuration[zone] = duration
  state.wind.compiled = false
}

/** Removes a wind zone (as `removeEntity` does). */
export function removeWindZone(world: object, zone: number): void {
  const state = getClothWorldForChange(world)
  checkZone(world, state, zone)
  removeEntity(world as never, zone)
}

/** The wind zone entities of a world, in creation order (a copy). */
export function getWindZones(world: object): number[] {
  return getClothWorld(world).wind.zones.slice()
}

/**
 * The air velocity at a world point now (all zones summed, turbulence and gusts included), into
 * `out` (m/s). For gameplay: smoke, leaves, sails. Returns `out`. Zones are where the last step
 * saw their Transforms: a zone moved since blows from its new place from the next step on.
 */
export function sampleWind(world: object, position: Readonly<vec3> | ArrayLike<number>, out: vec3 | number[] = [0, 0, 0]): vec3 | number[] {
  const state = getClothWorld(world)
  checkVec3('position', position)
  checkOut('out', out, 3)
  const wind = state.wind
  if (!wind.compiled) compileZones(state)
  samplePos[0] = position[0]
  samplePos[1] = position[1]
  samplePos[2] = position[2]
  sampleAir[0] = sampleAir[1] = sampleAir[2] = 0
  sampleAir[3] = wind.airDensity[0]
  for (let z = 0; z < wind.zones.length; z++)
    addZoneAir(samplePos, 1, sampleAir, wind.params, z * ZONE_STRIDE, wind.scratch)
  out[0] = sampleAir[0]
  out[1] = sampleAir[1]
  out[2] = sampleAir[2]
  return out
}

const samplePos = new Float64Array(3)
const sampleAir = new Float64Array(4)

// ---------------------------------------------------------------------------------------------
// Validation

interface CheckedZone {
  dir?: [number, number, number]
  strength?: number
  turbulence?: number
  turbulenceScale?: number
  turbulencePeriod?: number
  half?: [number, number, number]
  falloff?: number
  seed?: number
  airDensity?: number
}

/** Checks a global zone's options as `createWindZone` would (errors name `options.*`), creating nothing. */
export function checkGlobalWindOptions(o: Partial<WindZoneOptions>): void {
  checkObject('options', o)
  checkZoneOptions(o, 'global')
}

function checkZoneOptions(o: Partial<WindZoneOptions>, shape: WindShape): CheckedZone {
  const out: CheckedZone = {}
  if (o.direction !== undefined) {
    const d = checkVec3('options.direction', o.direction)
    const l = Math.hypot(d[0], d[1], d[2])
    if (!(l > 1e-9)) throw new ClothError('options.direction', o.direction, 'must have non-zero length')
    out.dir = [d[0] / l, d[1] / l, d[2] / l]
  }
  // bounded far beyond anything physical, so no product of them overflows to Infinity in a step
  if (o.strength !== undefined)
    out.strength = checkAtMost('options.strength', checkNonNegative('options.strength', o.strength), MAX_WIND, ' m/s')
  if (o.turbulence !== undefined)
    out.turbulence = checkAtMost('options.turbulence', checkNonNegative('options.turbulence', o.turbulence), 100, '')
  if (o.turbulenceScale !== undefined) out.turbulenceScale = checkScale('options.turbulenceScale', o.turbulenceScale, ' m')
  if (o.turbulencePeriod !== undefined) out.turbulencePeriod = checkScale('options.turbulencePeriod', o.turbulencePeriod, ' s')
  if (o.size !== undefined) {
    if (shape === 'sphere') {
      const r = checkAtMost('options.size', checkPositive('options.size', o.size), MAX_COORDINATE, ' m')
      out.half = [r, r, r]
    } else if (typeof o.size === 'number') {
      const s = checkAtMost('options.size', checkPositive('options.size', o.size), MAX_COORDINATE, ' m') / 2
      out.half = [s, s, s]
    } else {
      if (!isArrayLike(o.size)) throw new ClothError('options.size', o.size, 'must be a number or [x, y, z] extents')
      const s = checkVec3('options.size', o.size)
      for (let i = 0; i < 3; i++)
        if (!(s[i] > 0 && s[i] <= MAX_COORDINATE))
          throw new ClothError('options.size', o.size, `must have positive extents of at most ${MAX_COORDINATE} m`)
      out.half = [s[0] / 2, s[1] / 2, s[2] / 2]
    }
  }
  if (o.falloff !== undefined)
    out.falloff = checkAtMost('options.falloff', checkNonNegative('options.falloff', o.falloff), MAX_COORDINATE, ' m')
  if (o.seed !== undefined) out.seed = checkInteger('options.seed', o.seed, 0, 0xffffffff)
  if (o.airDensity !== undefined)
    out.airDensity = checkAtMost('options.airDensity', checkNonNegative('options.airDensity', o.airDensity), MAX_AIR_DENSITY, ' kg/m³')
  return out
}

/** Fastest wind a zone may blow (or a gust add), m/s. */
const MAX_WIND = 1e6
/** Densest air, kg/m³ (water is 1000). */
const MAX_AIR_DENSITY = 1e5

/** A length or time scale: within [1e-3, 1e9]. */
function checkScale(argument: string, value: unknown, unit: string): number {
  const v = checkAtMost(argument, checkPositive(argument, value), MAX_COORDINATE, unit)
  if (v < 1e-3) throw new ClothError(argument, value, `must be at least 0.001${unit}`)
  return v
}

function applyZoneOptions(Z: ClothWorldState['components']['WindZone'], eid: number, o: CheckedZone): void {
  if (o.dir) {
    Z.dirX[eid] = o.dir[0]
    Z.dirY[eid] = o.dir[1]
    Z.dirZ[eid] = o.dir[2]
  }
  if (o.strength !== undefined) Z.strength[eid] = o.strength
  if (o.turbulence !== undefined) Z.turbulence[eid] = o.turbulence
  if (o.turbulenceScale !== undefined) Z.turbulenceScale[eid] = o.turbulenceScale
  if (o.turbulencePeriod !== undefined) Z.turbulencePeriod[eid] = o.turbulencePeriod
  if (o.half) {
    Z.halfX[eid] = o.half[0]
    Z.halfY[eid] = o.half[1]
    Z.halfZ[eid] = o.half[2]
  }
  if (o.falloff !== undefined) Z.falloff[eid] = o.falloff
  if (o.seed !== undefined) Z.seed[eid] = o.seed
  if (o.airDensity !== undefined) Z.airDensity[eid] = o.airDensity
}

function checkZone(world: object, state: ClothWorldState, zone: unknown): void {
  if (typeof zone !== 'number' || !entityExists(world as never, zone) || !hasComponent(world as never, zone, state.components.WindZone)) {
    throw new ClothError('zone', zone, 'must be a wind zone entity of this world')
  }
}
