/**
 * A wind zone is an entity with a Transform and this component: moving air that drives the
 * aerodynamics of every cloth triangle it reaches. Structure of arrays indexed by the zone's entity
 * id; create, change and remove zones with `createWindZone`, `setWindZone`, `gustWind` and
 * `removeWindZone` (they validate), and read fields through the store (arrays are replaced when
 * they grow).
 *
 * Shapes: 0 = global (everywhere), 1 = box (centred on the Transform, oriented by its rotation),
 * 2 = sphere (centred on the Transform). Outside a box or sphere the wind fades to nothing over
 * `falloff` metres (smoothstep).
 */
export interface WindZoneStore {
  /** 0 global, 1 box, 2 sphere. */
  shape: Uint8Array
  /** Unit wind direction, world space. */
  dirX: Float64Array
  dirY: Float64Array
  dirZ: Float64Array
  /** Mean wind speed, m/s. */
  strength: Float64Array
  /** Turbulence intensity: each turbulent velocity component stays within ±turbulence × speed. */
  turbulence: Float64Array
  /** Size of the turbulent eddies (noise lattice spacing), m. */
  turbulenceScale: Float64Array
  /** Time over which the turbulence pattern renews itself, s. */
  turbulencePeriod: Float64Array
  /** Box half extents, m (a sphere's radius is `halfX`). */
  halfX: Float64Array
  halfY: Float64Array
  halfZ: Float64Array
  /** Distance beyond the shape over which the wind fades out, m. */
  falloff: Float64Array
  /** Air density inside the zone, kg/m³; −1 uses the world's `airDensity`. */
  airDensity: Float64Array
  /** Noise seed. */
  seed: Uint32Array
  /** Gust state: value the current gust started from and its peak, m/s; time into it and length, s. */
  gustFrom: Float64Array
  gustPeak: Float64Array
  gustTime: Float64Array
  gustDuration: Float64Array
  /** Current gust speed added to `strength`, m/s (computed each step). */
  gust: Float64Array
  /** Turbulence advection: how far the mean wind has carried the noise pattern, xyz per zone (stride 3), m. */
  drift: Float64Array
  /** The zone's kinematic slot (its Transform, sampled like a pin target). */
  slot: Int32Array
}

/** Allocates a WindZone store for `capacity` entity ids. Called by `installClothPlugin`. */
export function createWindZoneStore(capacity: number): WindZoneStore {
  return {
    shape: new Uint8Array(capacity),
    dirX: new Float64Array(capacity),
    dirY: new Float64Array(capacity),
    dirZ: new Float64Array(capacity),
    strength: new Float64Array(capacity),
    turbulence: new Float64Array(capacity),
    turbulenceScale: new Float64Array(capacity),
    turbulencePeriod: new Float64Array(capacity),
    halfX: new Float64Array(capacity),
    halfY: new Float64Array(capacity),
    halfZ: new Float64Array(capacity),
    falloff: new Float64Array(capacity),
    airDensity: new Float64Array(capacity),
    seed: new Uint32Array(capacity),
    gustFrom: new Float64Array(capacity),
    gustPeak: new Float64Array(capacity),
    gustTime: new Float64Array(capacity),
    gustDuration: new Float64Array(capacity),
    gust: new Float64Array(capacity),
    drift: new Float64Array(3 * capacity),
    slot: new Int32Array(capacity),
  }
}
