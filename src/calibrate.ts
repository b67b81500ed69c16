import { addEntity, createWorld } from 'bitecs'
import { createCloth, getClothState } from './cloth'
import { addSphereCollider } from './features/collision/colliders'
import {
  configureBudget,
  configureQualityTarget,
  type ClothBudgetOptions,
  type ClothCostCalibration,
  type ClothQualityTarget,
} from './features/budget/api'
import { pinRow } from './features/pins/api'
import { createWindZone } from './features/wind/api'
import { installClothPlugin } from './plugin'
import { setTransform } from './world/transform'
import { stepCloth } from '../systems/step'

/**
 * The cost model's calibration: a few small scenes built and stepped through the public API (so it
 * lives above the library, not inside the budget), and the two budget calls that may need it.
 */

let processCalibration: Float64Array | null = null

/**
 * Measures the cost model's per-unit costs on this machine (a few small scenes: 0.2 s here, 0.4 s
 * the first time in a process, which compiles the kernels; the result is kept for the process).
 * The first time budget or quality target in ms calls it: call it while loading to keep that out
 * of a frame. Pass `force` to measure again.
 */
export function calibrateClothCost(force = false): ClothCostCalibration {
  const c = measured(force)
  return { nsPerParticle: c[0], nsPerProjection: c[1], nsPerColliderTest: c[2], nsPerClothSubstep: c[3], nsPerWindTriangle: c[4] }
}

function measured(force = false): Float64Array {
  if (processCalibration === null || force) processCalibration = measureCalibration()
  return processCalibration
}

/**
 * Lets a cloth pick its own substeps: keep its largest edge stretch under `maxStretch` (checked
 * every 15 steps; substeps rise while it is exceeded and fall while it stays under 40 % of it),
 * and/or spend at most `msPerStep` per fixed step (by the cost model). `null` removes the target;
 * the cloth keeps the substeps it had.
 *
 * @example setClothQualityTarget(world, heroCape, { maxStretch: 0.02, msPerStep: 0.5 })
 */
export function setClothQualityTarget(world: object, cloth: number, target: ClothQualityTarget | null): void {
  configureQualityTarget(world, cloth, target, measured)
}

/**
 * Sets (or with `null` removes) the world's cloth budget: level of detail by distance from a
 * viewer, freezing of invisible or culled cloths, and optionally a time per fixed step shared by
 * all cloths. Levels are re-allocated every `interval` fixed steps. Removing the budget gives every
 * cloth its own quality back.
 *
 * @example setClothBudget(world, { msPerFrame: 4, viewer: camera, near: 8, far: 30, cull: 80 })
 */
export function setClothBudget(world: object, options: ClothBudgetOptions | null): void {
  configureBudget(world, options, measured)
}

function measureCalibration(): Float64Array {
  const api = {
    installClothPlugin,
    createWorld,
    createCloth,
    pinRow,
    addEntity,
    setTransform,
    addSphereCollider,
    createWindZone,
    stepCloth,
  }
  const time = (
    res: number,
    iterations: number,
    colliders: boolean,
    wind = false,
  ): { ms: number; particles: number; projections: number; tethers: number; triangles: number } => {
    const world = api.installClothPlugin(api.createWorld(), { sleep: false, guard: false })
    const cloth = api.createCloth(world, { width: 1, height: 1, resolution: res, position: [0, 2, 0], substeps: 4, iterations })
    api.pinRow(world, cloth, 0)
    if (colliders) {
      // two balls the sheet drapes over (contacts, as on a character), not ones it never nears
      for (let k = 0; k < 2; k++) {
        const e = api.addEntity(world)
        api.setTransform(world, e, [0.25 - 0.5 * k, 1.6 - 0.3 * k, 0.12])
        api.addSphereCollider(world, e, { radius: 0.2 })
      }
    }
    // a gusty breeze across the sheet (its aerodynamics every substep, the air sampled every step)
    if (wind) api.createWindZone(world, { direction: [0, 0, 1], strength: 6, turbulence: 0.3 })
    const c = getClothState(world, cloth)
    const t = c.topology
    for (let f = 0; f < 20; f++) api.stepCloth(world, 1 / 60)
    let best = Infinity
    for (let r = 0; r < 3; r++) {
      const t0 = performance.now()
      for (let f = 0; f < 15; f++) api.stepCloth(world, 1 / 60)
      best = Math.min(best, (performance.now() - t0) / 15)
    }
    // (tethers: once per substep, 0.6 of a projection, as in the model)
    const projections = iterations * (t.distCount + t.compCount + 0.8 * t.lineCount + 3 * t.hingeCount) + 0.6 * c.tethers.set.count
    return {
      ms: best,
      particles: c.count,
      projections: projections / iterations,
      tethers: 0.6 * c.tethers.set.count,
      triangles: t.triangleCount,
    }
  }
  const a = time(20, 1, false)
  const b = time(20, 5, false)
  const withColliders = time(20, 1, true)
  const tiny = time(3, 1, false)
  const windy = time(20, 1, false, true)
  const sub = 4
  // a and b differ by 4 iterations of the constraints (not the tethers, which run once)
  const nsProj = Math.max(0.5, ((b.ms - a.ms) * 1e6) / (sub * 4 * (a.projections - a.tethers)))
  const nsCol = Math.max(0.5, ((withColliders.ms - a.ms) * 1e6) / (sub * 2 * a.particles))
  // the small and the tiny sheet give the per-particle cost and the per-cloth overhead
  const perA = (a.ms * 1e6) / sub - nsProj * a.projections
  const perTiny = (tiny.ms * 1e6) / sub - nsProj * tiny.projections
  const nsPart = Math.max(0.5, (perA - perTiny) / (a.particles - tiny.particles))
  const nsCloth = Math.max(0, perTiny - nsPart * tiny.particles)
  const nsWind = Math.max(0.5, ((windy.ms - a.ms) * 1e6) / (sub * a.triangles))
  return Float64Array.from([nsPart, nsProj, nsCol, nsCloth, nsWind])
}
