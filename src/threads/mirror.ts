import { createClothStore } from '../../components/Cloth'
import { createPinStore } from '../../components/Pin'
import { createTransformStore } from '../../components/Transform'
import { createWindZoneStore } from '../../components/WindZone'
import { createTearableStore } from '../../components/Tearable'
import type { ColliderStore } from '../../components/Collider'
import type { PinStore } from '../../components/Pin'
import type { TearableStore } from '../../components/Tearable'
import { transformSourceOf } from '../world/capacity'
import { createKinematics } from '../world/kinematics'
import { $cloth, type ClothState, type ClothWorldState } from '../world/state'
import { createStats } from '../world/stats'
import { createGrabWorld } from '../features/grab/api'
import { createWindWorld } from '../features/wind/api'
import { createCollisionWorld } from '../features/collision/api'
import { createBudgetWorld } from '../features/budget/api'
import { DEFAULT_SLEEP, createSleepWorld } from '../features/sleep/api'
import { createGuardWorld, defaultGuardSettings } from '../features/guard/api'
import { createTearWorld } from '../features/tearing/api'
import { readClothHandoff, readWorldHandoff } from './handoff'
import { createClothFrame } from '../world/flight'

/**
 * A worker's copy of a world: a `ClothWorldState` whose arrays are the main thread's shared ones and
 * whose cloths are the main thread's cloths as last sent (their arrays shared, their numbers read
 * from the handoff blocks each step). The phase systems run on it unchanged; `cloths` holds the
 * cloths the worker steps this step, in creation order, and `collision.selfCloths` those of them
 * that collide with themselves (the partition keeps cloths that may touch each other together).
 */
export interface WorkerWorld {
  /** The object the systems receive (`getClothWorld(world)` finds `state` on it). */
  world: object
  state: ClothWorldState
  /** Cloth and handoff block at each slot (null: none). */
  cloths: (ClothState | null)[]
  ios: (Float64Array | null)[]
  /** The slot list of the current step as last read (the cloth lists are rebuilt only when it changes). */
  list: Int32Array
}

export function createWorkerWorld(): WorkerWorld {
  const Transform = createTransformStore(1)
  const state: ClothWorldState = {
    gravity: new Float64Array(3),
    fixedTimeStep: 1 / 60,
    maxStepsPerFrame: 1,
    teleportDistance: 2,
    maxSpeed: 250,
    accumulator: 0,
    components: {
      Transform,
      Cloth: createClothStore<ClothState>(),
      Pin: createPinStore(1),
      WindZone: createWindZoneStore(1),
      Tearable: createTearableStore(1),
    },
    transforms: transformSourceOf(Transform),
    capacity: 1,
    cloths: [],
    nextSeq: 0,
    kinematics: createKinematics(),
    substep: 0,
    substepCount: 0,
    scheduledWritebacks: -1,
    stats: createStats(),
    sleep: createSleepWorld(DEFAULT_SLEEP),
    wind: createWindWorld(undefined),
    collision: createCollisionWorld(1),
    budget: createBudgetWorld(),
    grab: createGrabWorld(),
    guard: createGuardWorld(defaultGuardSettings(250)),
    tearing: createTearWorld(),
    frame: createClothFrame(),
    threads: null,
  }
  // the main thread compiles the zones every step before the workers read them
  state.wind.compiled = true
  const world = { [$cloth]: state }
  return { world, state, cloths: [], ios: [], list: new Int32Array(1) }
}

/** What the main thread sends about the world (see `worldDescriptor` in layout.ts). */
export interface WorldMessage {
  gravity: Float64Array
  Pin: PinStore
  Tearable: TearableStore
  Collider: ColliderStore
  colliders: number[]
  stepFrom: Float64Array
  stepTo: Float64Array
  scaleStepFrom: Float64Array
  scaleStepTo: Float64Array
  zones: number[]
  airDensity: Float64Array
  windParams: Float64Array
  pending: number
}

/** Takes the world's shared arrays and lists. */
export function bindWorld(ww: WorkerWorld, d: WorldMessage): void {
  const s = ww.state
  s.gravity = d.gravity
  s.components.Pin = d.Pin
  s.components.Tearable = d.Tearable
  s.collision.Collider = d.Collider
  s.collision.entries = d.colliders
  s.kinematics.stepFrom = d.stepFrom
  s.kinematics.stepTo = d.stepTo
  s.kinematics.scaleStepFrom = d.scaleStepFrom
  s.kinematics.scaleStepTo = d.scaleStepTo
  s.wind.zones = d.zones
  s.wind.airDensity = d.airDensity
  s.wind.params = d.windParams
  if (s.wind.active.length < d.zones.length) s.wind.active = new Int32Array(2 * d.zones.length)
  if (s.tearing.pending.length < d.pending) s.tearing.pending = new Float64Array(d.pending)
}

/** Takes a cloth (as sent) at `slot`, or drops the slot (`cloth` null). */
export function bindCloth(ww: WorkerWorld, slot: number, cloth: ClothState | null, io: Float64Array | null): void {
  while (ww.cloths.length <= slot) {
    ww.cloths.push(null)
    ww.ios.push(null)
  }
  ww.cloths[slot] = cloth
  ww.ios[slot] = io
  ww.list[0] = -1 // rebuild the cloth lists at the next step
}

/**
 * Reads the step's inputs: the world's numbers, then the handoff block of every cloth in `list`
 * ([0] = count, then slots in creation order), rebuilding the cloth lists when the list changed.
 */
export function readStepInputs(ww: WorkerWorld, list: Int32Array, worldIO: Float64Array): void {
  const s = ww.state
  readWorldHandoff(worldIO, s)
  const n = list[0]
  if (!sameList(ww.list, list)) {
    if (ww.list.length < list.length) ww.list = new Int32Array(list.length)
    ww.list.set(list.subarray(0, n + 1))
    s.cloths.length = 0
    s.collision.selfCloths.length = 0
    for (let i = 1; i <= n; i++) {
      const c = ww.cloths[list[i]]!
      s.cloths.push(c)
      if (c.collision.self !== null) s.collision.selfCloths.push(c)
    }
  }
  for (let i = 1; i <= n; i++) readClothHandoff(ww.ios[list[i]]!, ww.cloths[list[i]]!)
}

function sameList(a: Int32Array, b: Int32Array): boolean {
  const n = b[0]
  if (a[0] !== n) return false
  for (let i = 1; i <= n; i++) if (a[i] !== b[i]) return false
  return true
}
