import { allFinite, fit32, fit64 } from '../../core/arrays'
import { ClothError } from '../../core/errors'
import { generationChanged, transformGeneration } from '../../world/kinematics'
import type { ClothWorldState } from '../../world/state'

/** The wind's section of a snapshot: world state (the wind clock, each zone's gust and drift). */
export interface WindSnapshot {
  /** Wind zones in creation order. */
  windZones: Int32Array
  /** The wind clock, then per zone gustFrom, gustPeak, gustTime, gustDuration, gust, drift xyz. */
  wind: Float64Array
  /**
   * Per zone: how many times an entity with its id had lost its Transform when saved (see
   * `Kinematics.generation`); a restore leaves alone a zone that got a removed zone's id since.
   * Absent in older snapshots: not checked.
   */
  windGenerations?: Uint32Array
}

const WIND_DATA = 8

/** Saves the wind clock and each zone's gust and turbulence drift. */
export function saveWind(state: ClothWorldState, s: WindSnapshot): void {
  const zones = state.wind.zones
  const Z = state.components.WindZone
  s.windZones = fit32(s.windZones, zones.length)
  s.wind = fit64(s.wind, 1 + WIND_DATA * zones.length)
  s.windGenerations = s.windGenerations && s.windGenerations.length === zones.length ? s.windGenerations
    : new Uint32Array(zones.length)
  s.wind[0] = state.wind.time[0]
  for (let q = 0; q < zones.length; q++) {
    const z = zones[q], o = 1 + WIND_DATA * q
    s.windZones[q] = z
    s.windGenerations[q] = transformGeneration(state.kinematics, z)
    s.wind[o] = Z.gustFrom[z]
    s.wind[o + 1] = Z.gustPeak[z]
    s.wind[o + 2] = Z.gustTime[z]
    s.wind[o + 3] = Z.gustDuration[z]
    s.wind[o + 4] = Z.gust[z]
    s.wind[o + 5] = Z.drift[3 * z]
    s.wind[o + 6] = Z.drift[3 * z + 1]
    s.wind[o + 7] = Z.drift[3 * z + 2]
  }
}

/** Throws ClothError unless the wind section is complete and finite. */
export function checkWind(s: WindSnapshot, arg: string): void {
  if (!(s.windZones instanceof Int32Array) || !(s.wind instanceof Float64Array) || s.wind.length !== 1 + WIND_DATA * s.windZones.length) {
    throw new ClothError(arg, s, 'is not a complete snapshot (collider, wind or tearing state missing)')
  }
  const gens = s.windGenerations
  if (gens !== undefined && (!(gens instanceof Uint32Array) || gens.length !== s.windZones.length)) {
    throw new ClothError(arg, s, 'is not a complete snapshot (collider, wind or tearing state missing)')
  }
  if (!allFinite(s.wind)) throw new ClothError(arg, s, 'holds a non-finite number')
}

/**
 * Restores the wind clock and the state of the zones that still exist (a zone removed since has
 * nothing to restore, nor does a zone that got a removed zone's id since).
 */
export function restoreWind(state: ClothWorldState, s: WindSnapshot): void {
  const wind = state.wind
  const Z = state.components.WindZone
  const gens = s.windGenerations
  wind.time[0] = s.wind[0]
  for (let q = 0; q < s.windZones.length; q++) {
    const z = s.windZones[q], o = 1 + WIND_DATA * q
    if (wind.zones.indexOf(z) < 0) continue
    if (gens !== undefined && generationChanged(state.kinematics, gens[q], z)) continue
    Z.gustFrom[z] = s.wind[o]
    Z.gustPeak[z] = s.wind[o + 1]
    Z.gustTime[z] = s.wind[o + 2]
    Z.gustDuration[z] = s.wind[o + 3]
    Z.gust[z] = s.wind[o + 4]
    Z.drift[3 * z] = s.wind[o + 5]
    Z.drift[3 * z + 1] = s.wind[o + 6]
    Z.drift[3 * z + 2] = s.wind[o + 7]
  }
  wind.compiled = false
}
