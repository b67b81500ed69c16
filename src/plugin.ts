import { observe, onAdd, onRemove, removeEntity, entityExists } from 'bitecs'
import { createClothStore } from '../components/Cloth'
import { createPinStore } from '../components/Pin'
import { createTransformStore, resetTransform } from '../components/Transform'
import { createWindZoneStore } from '../components/WindZone'
import { createTearableStore } from '../components/Tearable'
import {
  ClothError,
  MAX_COORDINATE,
  checkBoundedArray,
  checkInteger,
  checkObject,
  checkPositive,
  checkVec3,
  checkKeys,
  keysOf,
} from './core/errors'
import { findClothWorld, getClothWorld } from './world/access'
import { growStores, transformSourceOf } from './world/capacity'
import { createKinematics, transformLost } from './world/kinematics'
import { $cloth, type ClothPluginOptions, type ClothState, type ClothWorldState, type TransformSource } from './world/state'
import { createStats } from './world/stats'
import { releasePin } from './features/pins/api'
import { createGrabWorld } from './features/grab/api'
import { createWindWorld, installWind } from './features/wind/api'
import { createCollisionWorld, installCollision } from './features/collision/api'
import { createBudgetWorld, installBudget } from './features/budget/api'
import { DEFAULT_SLEEP, createSleepWorld, resolveSleepOptions } from './features/sleep/api'
import { createGuardWorld, defaultGuardSettings, forgetResetEvents, resolveGuardOptions } from './features/guard/api'
import { releaseCharacter } from './features/character/api'
import { installCharacter } from './features/character/lifetimes'
import { createTearWorld, installTearing } from './features/tearing/api'
import { forgetTearEvents } from './features/tearing/events'
import { arrayOf, releaseSharedMemory, retainSharedMemory, touchLayout } from './core/shared'
import { releaseWithWorld, resolveThreadOptions, startThreads } from './threads/bind'
import { createClothFrame, deferrable } from './world/flight'

/**
 * Installs the cloth plugin on a bitECS world: creates the component stores (Transform, Cloth,
 * Pin) and the per-world state, and registers the lifecycle observers. Everything lives on this
 * world, so two worlds never share a store. Installing twice is a no-op that returns the world;
 * options apply at the first install only, so a second install given any throws a `ClothError`
 * (it would silently keep the first's settings).
 *
 * @example
 * const world = installClothPlugin(createWorld(), { gravity: [0, -9.81, 0] })
 * const cape = createCloth(world, { width: 0.6, height: 0.9, resolution: 16, material: 'cotton' })
 * stepCloth(world, frameSeconds)
 */
export function installClothPlugin<W extends object>(world: W, options: ClothPluginOptions = {}): W {
  if (typeof world !== 'object' || world === null) throw new ClothError('world', world, 'must be a bitECS world')
  if (findClothWorld(world)) {
    if (typeof options !== 'object' || options === null || Object.keys(options).length > 0) {
      throw new ClothError(
        'options',
        options,
        'apply at the first install only: this world already has the plugin (make a new world for other settings)',
      )
    }
    return world
  }
  checkObject('options', options)
  checkKeys('options', options, PLUGIN_KEYS)
  const gravity = options.gravity === undefined ? [0, -9.81, 0] : checkVec3('options.gravity', options.gravity)
  checkBoundedArray('options.gravity', gravity, 3, MAX_COORDINATE)
  const fixedTimeStep = options.fixedTimeStep === undefined ? 1 / 60 : checkPositive('options.fixedTimeStep', options.fixedTimeStep)
  // 1/h² of a step shorter than a microsecond split into 256 substeps still fits a double; a step
  // longer than a second is not real time
  if (fixedTimeStep < 1e-6 || fixedTimeStep > 1)
    throw new ClothError('options.fixedTimeStep', fixedTimeStep, 'must be between 1e-6 and 1 s')
  // (by default the steps of a 1/15 s frame, from 4 to the option's own limit of 1000: counted in
  // steps alone, a 1/240 s step ran 30 Hz frames at half speed, a fall of 1.23 m in a second, not 4.9)
  const maxStepsPerFrame = options.maxStepsPerFrame === undefined ? Math.min(1000, Math.max(4, Math.ceil(1 / 15 / fixedTimeStep - 1e-9)))
    : checkInteger('options.maxStepsPerFrame', options.maxStepsPerFrame, 1, 1000)
  const teleportDistance = options.teleportDistance === undefined ? 2 : checkPositive('options.teleportDistance', options.teleportDistance)
  const maxSpeed = options.maxSpeed === undefined ? 250 : checkPositive('options.maxSpeed', options.maxSpeed)
  const capacity = options.capacity === undefined ? 1024 : checkInteger('options.capacity', options.capacity, 1, 1 << 26)
  if (options.transforms !== undefined) validateTransformSource(options.transforms)
  const guard = resolveGuardOptions(options.guard, defaultGuardSettings(maxSpeed), 'options.guard')
  const sleep = resolveSleepOptions(options.sleep, DEFAULT_SLEEP, 'options.sleep')
  // a threaded world's arrays live in shared memory from the start
  const threads = resolveThreadOptions(options)
  if (threads !== null) retainSharedMemory()

  const Transform = createTransformStore(capacity)
  const Cloth = createClothStore<ClothState>()
  const Pin = createPinStore(capacity)
  const WindZone = createWindZoneStore(capacity)
  const Tearable = createTearableStore(capacity)
  const wind = createWindWorld(options.airDensity)
  const state: ClothWorldState = {
    gravity: arrayOf(Float64Array, gravity),
    fixedTimeStep,
    maxStepsPerFrame,
    teleportDistance,
    maxSpeed,
    accumulator: 0,
    components: { Transform, Cloth, Pin, WindZone, Tearable },
    transforms: options.transforms ?? transformSourceOf(Transform),
    capacity,
    cloths: [],
    nextSeq: 0,
    kinematics: createKinematics(),
    substep: 0,
    substepCount: 0,
    scheduledWritebacks: -1,
    stats: createStats(),
    sleep: createSleepWorld(sleep),
    grab: createGrabWorld(),
    wind,
    collision: createCollisionWorld(capacity),
    budget: createBudgetWorld(),
    guard: createGuardWorld(guard),
    tearing: createTearWorld(),
    frame: createClothFrame(),
    threads: threads !== null ? startThreadsOrRelease(threads) : null,
  }
  if (state.threads !== null) releaseWithWorld(world, state.threads)
  Object.defineProperty(world, $cloth, { value: state, enumerable: false, configurable: true })

  observeLifecycle(world, state)
  installWind(world, state)
  installTearing(world, state)
  installCollision(world, state)
  installBudget(world, state)
  installCharacter(world, state)
  return world
}

/**
 * The plugin's own lifecycle observers: a new Transform gets room and identity values; a removed
 * pin target releases its pins; a removed pin frees its particle; a removed cloth takes its pins
 * and state with it.
 */
function observeLifecycle(world: object, state: ClothWorldState): void {
  const w = world as never
  const { Transform, Pin, Cloth } = state.components
  observe(w, onAdd(Transform), (eid: number) => {
    growStores(state, eid)
    resetTransform(state.components.Transform, eid)
  })
  observe(
    w,
    onRemove(state.transforms.component),
    deferrable(state, (eid: number) => {
      transformLost(state, eid)
      state.kinematics.losing = eid // (read by the pins' observers: their target is going)
      for (const cloth of state.cloths) {
        const pins = cloth.pins.list
        for (let k = pins.length - 1; k >= 0; k--) {
          const pin = pins[k]
          if (Pin.target[pin] === eid && entityExists(w, pin)) removeEntity(w, pin)
        }
      }
      state.kinematics.losing = -1
    }),
  )
  observe(w, onRemove(Pin), deferrable(state, (pin: number) => releasePin(state, pin)))
  observe(
    w,
    onRemove(Cloth),
    deferrable(state, (eid: number) => {
      const cloth = Cloth.state[eid]
      if (!cloth) return
      const pins = cloth.pins.list
      for (let k = pins.length - 1; k >= 0; k--) {
        const pin = pins[k]
        if (entityExists(w, pin)) removeEntity(w, pin)
      }
      Cloth.state[eid] = undefined
      // events not yet delivered would name an id another cloth may get next
      forgetTearEvents(state, eid)
      forgetResetEvents(state.guard, eid)
      releaseCharacter(state, cloth)
      if (cloth.sleep.asleep) {
        cloth.sleep.asleep = false
        state.sleep.count--
      }
      if (cloth.budget.hasTarget) {
        cloth.budget.hasTarget = false
        state.budget.targets--
      }
      const i = state.cloths.indexOf(cloth)
      if (i >= 0) state.cloths.splice(i, 1)
      touchLayout()
    }),
  )
}

/**
 * The stores this world's plugin uses (Transform, Cloth, Pin, WindZone, Tearable), for queries and
 * direct reads. Read fields through the store each time (`Transform.px[eid]`), not through a saved
 * array: the arrays are replaced when they grow.
 */
export function getClothComponents(world: object): ClothWorldState['components'] {
  return getClothWorld(world).components
}

/** Work counters since install or the last `resetClothStats`. */
export function getClothStats(world: object): Readonly<ClothWorldState['stats']> {
  return getClothWorld(world).stats
}

/** Zeroes the work counters. */
export function resetClothStats(world: object): void {
  const stats = getClothWorld(world).stats
  for (const key of Object.keys(stats) as (keyof typeof stats)[]) stats[key] = 0
}

const PLUGIN_KEYS = keysOf<ClothPluginOptions>({
  gravity: true,
  fixedTimeStep: true,
  maxStepsPerFrame: true,
  transforms: true,
  teleportDistance: true,
  maxSpeed: true,
  capacity: true,
  airDensity: true,
  guard: true,
  sleep: true,
  threads: true,
  workerUrl: true,
  requireThreads: true,
  threadMinStepMs: true,
})
const TRANSFORM_KEYS = keysOf<TransformSource>({
  component: true,
  px: true,
  py: true,
  pz: true,
  qx: true,
  qy: true,
  qz: true,
  qw: true,
  sx: true,
  sy: true,
  sz: true,
})

function validateTransformSource(t: TransformSource): void {
  if (typeof t !== 'object' || t === null) throw new ClothError('options.transforms', t, 'must be an object of transform arrays')
  checkKeys('options.transforms', t, TRANSFORM_KEYS)
  if (typeof t.component !== 'object' || t.component === null) {
    throw new ClothError('options.transforms.component', t.component, 'must be the component that marks entities with a transform')
  }
  // float arrays only: integer stores rounded a position of (0.5, 1.7, −0.25) to (0, 1, 0) and a
  // quarter turn to nothing, silently; strings and frozen arrays threw at the first setTransform
  const store = (key: keyof TransformSource) => {
    const arr = t[key]
    if (!(arr instanceof Float64Array || arr instanceof Float32Array || (Array.isArray(arr) && !Object.isFrozen(arr)))) {
      throw new ClothError(`options.transforms.${key}`, arr, 'must be an entity-indexed Float64Array, Float32Array or (writable) array')
    }
  }
  for (const key of ['px', 'py', 'pz', 'qx', 'qy', 'qz', 'qw'] as const) store(key)
  const scales = (['sx', 'sy', 'sz'] as const).filter((key) => t[key] !== undefined)
  if (scales.length > 0) {
    for (const key of ['sx', 'sy', 'sz'] as const) {
      if (t[key] === undefined)
        throw new ClothError(`options.transforms.${key}`, t[key], 'is missing: give sx, sy and sz together, or none')
      store(key)
    }
  }
}

/**
 * Starts a threaded world's workers; when that fails (a missing worker script), gives back the
 * shared memory the world had retained: every later plain world had allocated its arrays in shared
 * memory.
 */
function startThreadsOrRelease(t: { count: number; url: URL | string; inlineNs: number }): ReturnType<typeof startThreads> {
  try {
    return startThreads(t.count, t.url, t.inlineNs)
  } catch (e) {
    releaseSharedMemory()
    throw e
  }
}
