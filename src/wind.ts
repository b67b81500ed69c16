import { addComponent, addEntity, entityExists, hasComponent, observe, onAdd, onRemove, removeEntity } from 'bitecs'
import type { quat, vec3 } from 'gl-matrix'
import { ClothError, MAX_COORDINATE, checkAtMost, checkInteger, checkNonNegative, checkOneOf, checkPositive, checkQuat, checkVec3, isArrayLike } from './errors'
import { A_DRAG, A_H, A_LIFT, A_MAX_SPEED, A_STRIDE, AERO_PARAM_COUNT, accumulateAerodynamics, aeroNormals, limitAerodynamics, triangleInverseMasses } from './kernels/aero'
import { particleBounds } from './kernels/mesh'
import { quatToMatrix } from './math'
import {
  NOISE_SCRATCH, ZONE_STRIDE, Z_CX, Z_CY, Z_CZ, Z_DENSITY, Z_DRIFT_X, Z_DRIFT_Y, Z_DRIFT_Z, Z_FALLOFF, Z_HX, Z_HY, Z_HZ,
  Z_INV_SCALE, Z_MAX, Z_MIN, Z_R, Z_SEED, Z_SHAPE, Z_TIME, Z_TURB, Z_VX, Z_VY, Z_VZ, addZoneAir,
} from './kernels/wind'
import { trackEntity, untrackEntity } from './kinematics'
import { getClothWorld, type ClothState, type ClothWorldState } from './state'
import { setTransform } from './transform'
import { growStores } from './plugin'

export type WindShape = 'global' | 'box' | 'sphere'

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
  /** Air density in the zone, kg/m³. Default: the world's `airDensity` (1.2). */
  airDensity?: number
}

/** Options of `gustWind`. */
export interface GustOptions {
  /** Extra wind speed at the gust's peak, m/s (negative for a lull; the speed never drops below 0). */
  strength: number
  /** Length of the gust, s: it ramps up over the first 30 %, holds, and ramps down over the last 30 %. Default 1. */
  duration?: number
}

/** Per-world wind state. */
export interface WindWorld {
  /** Zone entities in creation order (the order zones are summed in, never query order). */
  zones: number[]
  /** World air density, kg/m³, in a one-slot array (read by the kernels). */
  airDensity: Float64Array
  /** [0] wind time, s (advances one fixed step per step). */
  time: Float64Array
  /** Compiled zone blocks for the current step, ZONE_STRIDE doubles per zone (see `kernels/wind.ts`). */
  params: Float64Array
  /** Zone blocks active for the cloth being prepared (offsets into `params`). */
  active: Int32Array
  /** Cloth bounds scratch (min xyz, max xyz). */
  bounds: Float64Array
  /** Noise scratch. */
  scratch: Float64Array
  /** True once `params` holds this step's zones. */
  compiled: boolean
  /**
   * The aerodynamics' stability clamp (`limitAerodynamics`), always on in use. Only tests turn it
   * off, to show what it prevents (and that the explosion guard catches it).
   */
  clamp: boolean
}

/** Per-cloth aerodynamics buffers (allocated when a wind zone exists). */
export interface ClothWind {
  /** ux uy uz ρ per particle (stride 4), or once in [0..3] when the air is uniform. */
  air: Float64Array
  /** Aerodynamic acceleration per particle, m/s²; `ClothState.accel` points here while wind acts. */
  accel: Float64Array
  /** Smoothed normals for the aerodynamics and their scratch, xyz per particle. */
  normals: Float64Array
  scratch: Float64Array
  /** 1/(m_a + m_b + m_c) per triangle. */
  triInvMass: Float64Array
  /** Kernel parameters (see `kernels/aero.ts`). */
  params: Float64Array
  /** 1 while some zone reaches the cloth this step. */
  active: number
}

const ZERO_ROTATION = [0, 0, 0, 1]

/** Creates the per-world wind state (validates `airDensity`). Called by `installClothPlugin`. */
export function createWindWorld(airDensity: number | undefined): WindWorld {
  const rho = airDensity === undefined ? 1.2 : checkAtMost('options.airDensity', checkNonNegative('options.airDensity', airDensity), MAX_AIR_DENSITY, ' kg/m³')
  return {
    zones: [],
    airDensity: Float64Array.of(rho),
    time: new Float64Array(1),
    params: new Float64Array(4 * ZONE_STRIDE),
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
  observe(w, onRemove(state.components.WindZone), (eid: number) => {
    const zones = state.wind.zones
    const i = zones.indexOf(eid)
    if (i < 0) return
    zones.splice(i, 1)
    untrackEntity(state, eid)
    state.wind.compiled = false
    if (zones.length === 0) for (const c of state.cloths) c.accel = null
  })
}

/**
 * Creates a wind zone: an entity with a Transform (at `position`) and the WindZone component.
 * Global zones blow everywhere; box and sphere zones blow inside their volume and fade out over
 * `falloff` beyond it, following their Transform when it moves. Zones add up where they overlap.
 * Returns the zone entity (remove it with `removeWindZone` or `removeEntity`).
 *
 * @example
 * const breeze = createWindZone(world, { direction: [1, 0, 0.3], strength: 6, turbulence: 0.3 })
 * gustWind(world, breeze, { strength: 8, duration: 1.5 })
 */
export function createWindZone(world: object, options: WindZoneOptions): number {
  const state = getClothWorld(world)
  if (typeof options !== 'object' || options === null) throw new ClothError('options', options, 'must be an object')
  const shape = options.shape === undefined ? 'global' : checkOneOf('options.shape', options.shape, ['global', 'box', 'sphere'] as const)
  const position = options.position === undefined ? [0, 0, 0] : checkVec3('options.position', options.position)
  const rotation = options.rotation === undefined ? ZERO_ROTATION : checkQuat('options.rotation', options.rotation)
  if (options.direction === undefined) throw new ClothError('options.direction', undefined, 'is required (a 3-vector)')
  if (options.strength === undefined) throw new ClothError('options.strength', undefined, 'is required (m/s)')
  const checked = checkZoneOptions(options, shape)

  const eid = addEntity(world as never)
  growStores(state, eid)
  setTransform(world, eid, position, rotation)
  const Z = state.components.WindZone
  Z.shape[eid] = shape === 'global' ? 0 : shape === 'box' ? 1 : 2
  Z.turbulence[eid] = 0
  Z.turbulenceScale[eid] = 2
  Z.turbulencePeriod[eid] = 0.8
  Z.halfX[eid] = Z.halfY[eid] = Z.halfZ[eid] = 1
  Z.falloff[eid] = 0.5
  Z.airDensity[eid] = -1
  Z.seed[eid] = 1
  Z.gustFrom[eid] = Z.gustPeak[eid] = Z.gustTime[eid] = Z.gustDuration[eid] = Z.gust[eid] = 0
  Z.drift[3 * eid] = Z.drift[3 * eid + 1] = Z.drift[3 * eid + 2] = 0
  applyZoneOptions(Z, eid, checked)
  Z.slot[eid] = trackEntity(state, eid)
  addComponent(world as never, eid, Z)

  const wind = state.wind
  wind.zones.push(eid)
  if (wind.params.length < wind.zones.length * ZONE_STRIDE) {
    wind.params = new Float64Array(2 * wind.zones.length * ZONE_STRIDE)
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
  const state = getClothWorld(world)
  checkZone(world, state, zone)
  if (typeof options !== 'object' || options === null) throw new ClothError('options', options, 'must be an object')
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
  const state = getClothWorld(world)
  checkZone(world, state, zone)
  if (typeof options !== 'object' || options === null) throw new ClothError('options', options, 'must be an object')
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
  const state = getClothWorld(world)
  checkZone(world, state, zone)
  removeEntity(world as never, zone)
}

/** The wind zone entities of a world, in creation order (a copy). */
export function getWindZones(world: object): number[] {
  return getClothWorld(world).wind.zones.slice()
}

/**
 * The air velocity at a world point now (all zones summed, turbulence and gusts included), into
 * `out` (m/s). For gameplay: smoke, leaves, sails. Returns `out`.
 */
export function sampleWind(world: object, position: Readonly<vec3> | ArrayLike<number>, out: vec3 | number[] = [0, 0, 0]): vec3 | number[] {
  const state = getClothWorld(world)
  checkVec3('position', position)
  const wind = state.wind
  if (!wind.compiled) compileZones(state)
  samplePos[0] = position[0]
  samplePos[1] = position[1]
  samplePos[2] = position[2]
  sampleAir[0] = sampleAir[1] = sampleAir[2] = 0
  sampleAir[3] = wind.airDensity[0]
  for (let z = 0; z < wind.zones.length; z++) addZoneAir(samplePos, 1, sampleAir, wind.params, z * ZONE_STRIDE, wind.airDensity, wind.scratch)
  out[0] = sampleAir[0]
  out[1] = sampleAir[1]
  out[2] = sampleAir[2]
  return out
}

const samplePos = new Float64Array(3)
const sampleAir = new Float64Array(4)

// ---------------------------------------------------------------------------------------------
// Per-step and per-substep work (called by the sync and forces systems)

/**
 * Once per fixed step (sync phase): advances the wind time, the gusts and the drift of each zone's
 * turbulence, then compiles the zones (pose from their Transform, sampled like pin targets) into
 * the parameter blocks the kernels read. Nothing to do without zones.
 */
export function advanceWind(state: ClothWorldState): void {
  const wind = state.wind
  const zones = wind.zones
  if (zones.length === 0) return
  const dt = state.fixedTimeStep
  wind.time[0] += dt
  const Z = state.components.WindZone
  for (let k = 0; k < zones.length; k++) {
    const z = zones[k]
    const dur = Z.gustDuration[z]
    if (dur > 0) {
      const t = Z.gustTime[z] + dt
      Z.gustTime[z] = t
      const u = t / dur
      let g = 0
      if (u >= 1) Z.gustDuration[z] = 0
      else if (u < 0.3) {
        const s = u / 0.3
        g = Z.gustFrom[z] + (Z.gustPeak[z] - Z.gustFrom[z]) * s * s * (3 - 2 * s)
      } else if (u <= 0.7) g = Z.gustPeak[z]
      else {
        const s = (1 - u) / 0.3
        g = Z.gustPeak[z] * s * s * (3 - 2 * s)
      }
      Z.gust[z] = g
    }
    const speed = Math.max(0, Z.strength[z] + Z.gust[z])
    Z.drift[3 * z] += Z.dirX[z] * speed * dt
    Z.drift[3 * z + 1] += Z.dirY[z] * speed * dt
    Z.drift[3 * z + 2] += Z.dirZ[z] * speed * dt
  }
  compileZones(state)
}

/** Swaps a[i] and a[j]. */
function swap(a: Float64Array, i: number, j: number): void {
  const t = a[i]
  a[i] = a[j]
  a[j] = t
}

/** Writes each zone's parameter block for the current step. */
function compileZones(state: ClothWorldState): void {
  const wind = state.wind
  const zones = wind.zones
  const Z = state.components.WindZone
  const P = wind.params
  const poses = state.kinematics.stepTo
  for (let k = 0; k < zones.length; k++) {
    const z = zones[k]
    const o = k * ZONE_STRIDE
    const speed = Math.max(0, Z.strength[z] + Z.gust[z])
    const shape = Z.shape[z]
    P[o + Z_SHAPE] = shape
    P[o + Z_VX] = Z.dirX[z] * speed
    P[o + Z_VY] = Z.dirY[z] * speed
    P[o + Z_VZ] = Z.dirZ[z] * speed
    P[o + Z_TURB] = speed * Z.turbulence[z]
    P[o + Z_INV_SCALE] = 1 / Z.turbulenceScale[z]
    P[o + Z_DRIFT_X] = Z.drift[3 * z]
    P[o + Z_DRIFT_Y] = Z.drift[3 * z + 1]
    P[o + Z_DRIFT_Z] = Z.drift[3 * z + 2]
    P[o + Z_TIME] = wind.time[0] / Z.turbulencePeriod[z]
    P[o + Z_SEED] = Z.seed[z] | 0
    const s = 7 * Z.slot[z]
    const px = poses[s], py = poses[s + 1], pz = poses[s + 2]
    P[o + Z_CX] = px
    P[o + Z_CY] = py
    P[o + Z_CZ] = pz
    // the block stores Mᵀ (world → zone): M, then transposed in place
    const r = o + Z_R
    quatToMatrix(poses, s + 3, P, r)
    swap(P, r + 1, r + 3)
    swap(P, r + 2, r + 6)
    swap(P, r + 5, r + 7)
    const hx = Z.halfX[z], hy = Z.halfY[z], hz = Z.halfZ[z]
    P[o + Z_HX] = hx
    P[o + Z_HY] = hy
    P[o + Z_HZ] = hz
    const f = Z.falloff[z]
    P[o + Z_FALLOFF] = f
    P[o + Z_DENSITY] = Z.airDensity[z]
    // world bounds: a box's extent along each world axis is Σ|m_ij|·h_j
    let ex = hx, ey = hx, ez = hx
    if (shape === 1) {
      // Mᵀ: m_ij sits at r + 3j + i
      ex = Math.abs(P[r]) * hx + Math.abs(P[r + 3]) * hy + Math.abs(P[r + 6]) * hz
      ey = Math.abs(P[r + 1]) * hx + Math.abs(P[r + 4]) * hy + Math.abs(P[r + 7]) * hz
      ez = Math.abs(P[r + 2]) * hx + Math.abs(P[r + 5]) * hy + Math.abs(P[r + 8]) * hz
    }
    P[o + Z_MIN] = px - ex - f
    P[o + Z_MIN + 1] = py - ey - f
    P[o + Z_MIN + 2] = pz - ez - f
    P[o + Z_MAX] = px + ex + f
    P[o + Z_MAX + 1] = py + ey + f
    P[o + Z_MAX + 2] = pz + ez + f
  }
  wind.compiled = true
}

/**
 * Forces phase, per cloth and substep. On the cloth's first substep of the step it finds the zones
 * that reach the cloth (global zones always; box and sphere zones whose bounds overlap the cloth's)
 * and samples the air at its particles, once per step: the field is smooth on the scale of a step.
 * When the air is uniform (only steady global zones) nothing is sampled per particle. Then, every
 * substep, the triangle pass and the stability clamp fill `accel`; `ClothState.accel` is null when
 * no zone reaches the cloth, and the predict kernel skips it.
 */
export function applyWind(state: ClothWorldState, c: ClothState): void {
  const wind = state.wind
  const cw = c.wind
  if (cw === null || wind.zones.length === 0) {
    c.accel = null
    return
  }
  if (c.subIndex === 0) prepareClothWind(state, c, cw)
  if (cw.active === 0) {
    c.accel = null
    return
  }
  const t = c.topology
  const accel = cw.accel
  accel.fill(0, 0, 3 * c.count)
  const p = cw.params
  p[A_H] = c.h
  p[A_DRAG] = c.material.drag
  p[A_LIFT] = c.material.lift
  p[A_MAX_SPEED] = state.maxSpeed
  aeroNormals(c.pos, c.count, t.triangles, t.triangleCount, t.edges, t.edgeCount, cw.normals, cw.scratch)
  accumulateAerodynamics(c.pos, c.vel, t.triangles, t.triangleCount, cw.triInvMass, cw.air, cw.normals, accel, p)
  if (wind.clamp) limitAerodynamics(c.vel, c.invMass, cw.air, accel, p, c.count)
  c.accel = accel
  state.stats.windTriangles += t.triangleCount
}

/**
 * Whether some blowing wind zone reaches the box `b` (min xyz, max xyz): a global zone always; a
 * box or sphere zone when its bounds overlap the box (the forces phase's rule). A calm zone (no
 * speed, no turbulence, no gust this step) does not count: this is the sleep test.
 */
export function windReaches(state: ClothWorldState, b: Float64Array): boolean {
  const wind = state.wind
  const nz = wind.zones.length
  if (nz === 0) return false
  if (!wind.compiled) compileZones(state)
  const P = wind.params
  // every array slot is read on every call, before any test: a read first reached (through a
  // branch or a short-circuit) long after start-up would run unoptimized code, which boxes numbers
  const bx0 = b[0], by0 = b[1], bz0 = b[2], bx1 = b[3], by1 = b[4], bz1 = b[5]
  for (let k = 0; k < nz; k++) {
    const o = k * ZONE_STRIDE
    const shape = P[o + Z_SHAPE]
    const vx = P[o + Z_VX], vy = P[o + Z_VY], vz = P[o + Z_VZ], turb = P[o + Z_TURB]
    const x0 = P[o + Z_MIN], y0 = P[o + Z_MIN + 1], z0 = P[o + Z_MIN + 2]
    const x1 = P[o + Z_MAX], y1 = P[o + Z_MAX + 1], z1 = P[o + Z_MAX + 2]
    const cx = P[o + Z_CX], cy = P[o + Z_CY], cz = P[o + Z_CZ]
    const r = P[o + Z_HX] + P[o + Z_FALLOFF]
    const dx = Math.max(bx0 - cx, cx - bx1, 0)
    const dy = Math.max(by0 - cy, cy - by1, 0)
    const dz = Math.max(bz0 - cz, cz - bz1, 0)
    const blowing = vx * vx + vy * vy + vz * vz + turb * turb > 0
    const boxes = bx1 >= x0 && bx0 <= x1 && by1 >= y0 && by0 <= y1 && bz1 >= z0 && bz0 <= z1
    const inSphere = dx * dx + dy * dy + dz * dz <= r * r
    if (blowing && (shape === 0 || (boxes && (shape !== 2 || inSphere)))) return true
  }
  return false
}

function prepareClothWind(state: ClothWorldState, c: ClothState, cw: ClothWind): void {
  const wind = state.wind
  if (!wind.compiled) compileZones(state)
  const P = wind.params
  const nz = wind.zones.length
  let active = 0
  let uniform = true
  let haveBounds = false
  const b = wind.bounds
  for (let k = 0; k < nz; k++) {
    const o = k * ZONE_STRIDE
    if (P[o + Z_SHAPE] !== 0) {
      if (!haveBounds) {
        particleBounds(c.pos, c.count, b, 0)
        haveBounds = true
      }
      if (b[3] < P[o + Z_MIN] || b[0] > P[o + Z_MAX] || b[4] < P[o + Z_MIN + 1] || b[1] > P[o + Z_MAX + 1] ||
          b[5] < P[o + Z_MIN + 2] || b[2] > P[o + Z_MAX + 2]) continue
      if (P[o + Z_SHAPE] === 2) {
        // sphere: the exact distance from its centre to the cloth's box
        const cx = P[o + Z_CX], cy = P[o + Z_CY], cz = P[o + Z_CZ]
        const dx = cx < b[0] ? b[0] - cx : cx > b[3] ? cx - b[3] : 0
        const dy = cy < b[1] ? b[1] - cy : cy > b[4] ? cy - b[4] : 0
        const dz = cz < b[2] ? b[2] - cz : cz > b[5] ? cz - b[5] : 0
        const r = P[o + Z_HX] + P[o + Z_FALLOFF]
        if (dx * dx + dy * dy + dz * dz > r * r) continue
      }
      uniform = false
    }
    if (P[o + Z_TURB] > 0) uniform = false
    wind.active[active++] = o
  }
  cw.active = active > 0 ? 1 : 0
  if (active === 0) return
  const air = cw.air
  const rho = wind.airDensity[0]
  if (uniform) {
    let ux = 0, uy = 0, uz = 0, r = rho
    for (let k = 0; k < active; k++) {
      const o = wind.active[k]
      ux += P[o + Z_VX]
      uy += P[o + Z_VY]
      uz += P[o + Z_VZ]
      if (P[o + Z_DENSITY] >= 0) r += P[o + Z_DENSITY] - rho
    }
    air[0] = ux
    air[1] = uy
    air[2] = uz
    air[3] = r > 0 ? r : 0
    cw.params[A_STRIDE] = 0
    return
  }
  for (let i = 0; i < c.count; i++) {
    const k = 4 * i
    air[k] = 0
    air[k + 1] = 0
    air[k + 2] = 0
    air[k + 3] = rho
  }
  for (let k = 0; k < active; k++) addZoneAir(c.pos, c.count, air, P, wind.active[k], wind.airDensity, wind.scratch)
  cw.params[A_STRIDE] = 4
}

/**
 * Allocates (or regrows to the cloth's capacity) a cloth's aerodynamics buffers. Called when a zone
 * is created, when a cloth is created while zones exist, and when a cloth's capacity grows
 * (tearing): never in a step.
 */
export function ensureClothWind(c: ClothState): void {
  const particles = (c.pos.length / 3) | 0
  const t = c.topology
  const triangles = (t.triangles.length / 3) | 0
  let cw = c.wind
  if (cw === null || cw.accel.length < 3 * particles || cw.triInvMass.length < triangles) {
    cw = c.wind = {
      air: new Float64Array(4 * particles),
      accel: new Float64Array(3 * particles),
      normals: new Float64Array(3 * particles),
      scratch: new Float64Array(3 * particles),
      triInvMass: new Float64Array(triangles),
      params: new Float64Array(AERO_PARAM_COUNT),
      active: 0,
    }
    c.accel = null
  }
  triangleInverseMasses(t.triangles, t.triangleCount, c.baseInvMass, cw.triInvMass)
}

/** Recomputes the per-triangle masses after a cloth's masses changed (a tear). No allocation. */
export function refreshClothWind(c: ClothState): void {
  const cw = c.wind
  if (cw === null) return
  const t = c.topology
  triangleInverseMasses(t.triangles, t.triangleCount, c.baseInvMass, cw.triInvMass)
}

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

function checkZoneOptions(o: Partial<WindZoneOptions>, shape: WindShape): CheckedZone {
  const out: CheckedZone = {}
  if (o.direction !== undefined) {
    const d = checkVec3('options.direction', o.direction)
    const l = Math.hypot(d[0], d[1], d[2])
    if (!(l > 1e-9)) throw new ClothError('options.direction', o.direction, 'must have non-zero length')
    out.dir = [d[0] / l, d[1] / l, d[2] / l]
  }
  // bounded far beyond anything physical, so no product of them overflows to Infinity in a step
  if (o.strength !== undefined) out.strength = checkAtMost('options.strength', checkNonNegative('options.strength', o.strength), MAX_WIND, ' m/s')
  if (o.turbulence !== undefined) out.turbulence = checkAtMost('options.turbulence', checkNonNegative('options.turbulence', o.turbulence), 100, '')
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
      for (let i = 0; i < 3; i++) if (!(s[i] > 0 && s[i] <= MAX_COORDINATE)) throw new ClothError('options.size', o.size, `must have positive extents of at most ${MAX_COORDINATE} m`)
      out.half = [s[0] / 2, s[1] / 2, s[2] / 2]
    }
  }
  if (o.falloff !== undefined) out.falloff = checkAtMost('options.falloff', checkNonNegative('options.falloff', o.falloff), MAX_COORDINATE, ' m')
  if (o.seed !== undefined) out.seed = checkInteger('options.seed', o.seed, 0, 0xffffffff)
  if (o.airDensity !== undefined) out.airDensity = checkAtMost('options.airDensity', checkNonNegative('options.airDensity', o.airDensity), MAX_AIR_DENSITY, ' kg/m³')
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
