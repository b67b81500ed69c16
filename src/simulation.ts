import { createWorld, observe, onRemove } from 'bitecs'
import type { vec3 } from 'gl-matrix'
import { createCloth, getClothState, getClothStretch, type CreateClothOptions } from './cloth'
import { ClothError, checkKeys } from './core/errors'
import { getClothMesh } from './mesh'
import type { ClothMaterialSpec } from './model/materials'
import { installClothPlugin } from './plugin'
import type { ClothMesh, ClothPluginOptions } from './world/state'
import { pinParticle, pinRow, unpin } from './features/pins/api'
import { checkGlobalWindOptions, createWindZone, gustWind, removeWindZone, setWindZone } from './features/wind/api'
import { getClothWorld } from './world/access'
import { makeTearable, type TearableOptions } from './features/tearing/api'
import { onClothTear } from './features/tearing/events'
import type { ClothTearListener } from './features/tearing/types'
import { stepCloth } from '../systems/step'

/** Options of the `ClothSimulation` facade: a sheet plus optional world settings. */
export interface ClothSimulationOptions extends Omit<CreateClothOptions, 'material'> {
  material?: ClothMaterialSpec | string
  /** World settings (gravity, fixed time step, ...). */
  world?: ClothPluginOptions
}

/**
 * One cloth without an ECS: a thin wrapper that owns a private bitECS world with the plugin
 * installed and one sheet in it. Every method forwards to the ECS API (`world` and `cloth` are
 * exposed for anything the facade does not cover).
 *
 * @example
 * const sim = new ClothSimulation({ width: 1, height: 1, resolution: 32, material: 'silk' })
 * sim.pinRow(0)
 * sim.step(1 / 60)
 * const { positions, normals, indices } = sim.getMesh()
 */
export class ClothSimulation {
  /** The private world. */
  readonly world: object
  /** The cloth entity. */
  readonly cloth: number

  constructor(options: ClothSimulationOptions) {
    if (typeof options !== 'object' || options === null) throw new ClothError('options', options, 'must be an object')
    const { world, ...sheet } = options
    this.world = renamed('options', 'options.world', () => installClothPlugin(createWorld(), world))
    this.cloth = createCloth(this.world, sheet)
    // the zone `setWind` made, forgotten when it goes away (through `world`): its id may come back
    // as a zone of the game's, which `setWind` must not change or remove
    observe(this.world as never, onRemove(getClothWorld(this.world).components.WindZone), (eid: number) => {
      if (eid === this.windZone) this.windZone = 0
    })
  }

  /** Pins a grid row (0 = top) in place. Returns the pin entities. */
  pinRow(row: number): number[] {
    return pinRow(this.world, this.cloth, row)
  }

  /** Pins one particle where it is, or at a world position. Returns the pin entity. */
  pinParticle(index: number, position?: Readonly<vec3> | ArrayLike<number>): number {
    return renamed('offset', 'position', () => pinParticle(this.world, this.cloth, index, null, position))
  }

  /** Releases a pin returned by `pinRow` or `pinParticle`. */
  unpin(pin: number): void {
    unpin(this.world, pin)
  }

  /** Advances the simulation by `dt` seconds (fixed steps inside). Returns the steps run. */
  step(dt: number): number {
    return stepCloth(this.world, dt)
  }

  /** Particle positions, xyz per particle (float64, live view of the solver state). */
  get positions(): Float64Array {
    const c = getClothState(this.world, this.cloth)
    return c.pos.subarray(0, 3 * c.count)
  }

  /** Number of particles. */
  get particleCount(): number {
    return getClothState(this.world, this.cloth).count
  }

  /** GPU-ready positions, normals, texture coordinates and triangle indices (see `getClothMesh`). */
  getMesh(): ClothMesh {
    return getClothMesh(this.world, this.cloth)
  }

  /** Mean and max edge stretch now. */
  getStretch(): { mean: number; max: number } {
    return getClothStretch(this.world, this.cloth)
  }

  private windZone = 0

  /**
   * Sets a global wind (a global wind zone, created on first use): direction, speed in m/s and
   * turbulence (fraction of the speed). Strength 0 removes it, and the cloth is back in still air.
   */
  setWind(wind: { direction: ArrayLike<number>; strength: number; turbulence?: number }): void {
    if (typeof wind !== 'object' || wind === null) throw new ClothError('wind', wind, 'must be an object')
    checkKeys('wind', wind, ['direction', 'strength', 'turbulence'])
    const options = { direction: wind.direction, strength: wind.strength, turbulence: wind.turbulence ?? 0 }
    renamed('options', 'wind', () => checkGlobalWindOptions(options)) // (strength 0 too: nothing is left half done)
    if (wind.strength === 0 && this.windZone !== 0) {
      removeWindZone(this.world, this.windZone)
      this.windZone = 0
      return
    }
    if (this.windZone === 0) {
      if (wind.strength === 0) return
      this.windZone = createWindZone(this.world, options)
    } else {
      setWindZone(this.world, this.windZone, options)
    }
  }

  /** A gust on the wind set by `setWind`: extra m/s at its peak over `duration` seconds. */
  gust(strength: number, duration = 1): void {
    if (this.windZone === 0) throw new ClothError('wind', undefined, 'must be set with setWind before a gust')
    renamed('options.', '', () => gustWind(this.world, this.windZone, { strength, duration }))
  }

  /** Makes the cloth tearable (see `makeTearable`). */
  makeTearable(options?: TearableOptions): void {
    makeTearable(this.world, this.cloth, options)
  }

  /** Subscribes to tears (see `onClothTear`); returns the unsubscribe function. */
  onTear(listener: ClothTearListener): () => void {
    return onClothTear(this.world, listener)
  }
}

/**
 * Runs `call`, renaming the argument of a ClothError it throws from `from` (or a path under it) to
 * `to`: the facade's errors name the facade's parameters, not those of the call it forwards to.
 */
function renamed<T>(from: string, to: string, call: () => T): T {
  try {
    return call()
  } catch (e) {
    if (!(e instanceof ClothError)) throw e
    const a = e.argument
    const under = from.endsWith('.') ? a.startsWith(from) : a === from || a.startsWith(`${from}.`) || a.startsWith(`${from}[`)
    if (!under) throw e
    throw new ClothError(to + a.slice(from.length), e.value, e.expectation)
  }
}
