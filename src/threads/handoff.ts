import { CORE_HANDOFF, readCoreHandoff, writeCoreHandoff } from '../world/handoff'
import type { ClothState, ClothWorldState } from '../world/state'
import { STAT_COUNT } from '../world/stats'
import { SLEEP_HANDOFF, readSleepHandoff, writeSleepHandoff } from '../features/sleep/handoff'
import { GRAB_HANDOFF, readGrabHandoff, writeGrabHandoff } from '../features/grab/handoff'
import { WIND_HANDOFF, readWindHandoff, writeWindHandoff } from '../features/wind/handoff'
import { COLLISION_HANDOFF, readCollisionHandoff, writeCollisionHandoff } from '../features/collision/handoff'
import { GUARD_HANDOFF, readGuardHandoff, writeGuardHandoff } from '../features/guard/handoff'
import { CHARACTER_HANDOFF, readCharacterHandoff, writeCharacterHandoff } from '../features/character/handoff'
import { TEAR_HANDOFF, readTearHandoff, writeTearHandoff } from '../features/tearing/handoff'

/**
 * The per-step handoff. A cloth's arrays live in shared memory, so only its plain numbers travel:
 * each cloth has a block of doubles in shared memory, one section per part of its state (core,
 * then the features in their order). Before a step the main thread writes every bound cloth's block
 * and the worker reads it into its copy of the cloth; after the step the worker writes the blocks of
 * the cloths it stepped and the main thread reads them back. Both directions use the same functions,
 * so a number the step uses cannot travel one way only.
 */

/** [0]: the guard's verdict on the step (a HEALTH_* code, written by the worker). */
export const IO_HEALTH = 0
const IO_CORE = 1
const IO_SLEEP = IO_CORE + CORE_HANDOFF
const IO_GRAB = IO_SLEEP + SLEEP_HANDOFF
const IO_WIND = IO_GRAB + GRAB_HANDOFF
const IO_COLLISION = IO_WIND + WIND_HANDOFF
const IO_GUARD = IO_COLLISION + COLLISION_HANDOFF
const IO_CHARACTER = IO_GUARD + GUARD_HANDOFF
const IO_TEAR = IO_CHARACTER + CHARACTER_HANDOFF
/** Doubles per cloth block. */
export const IO_SIZE = IO_TEAR + TEAR_HANDOFF

export function writeClothHandoff(c: ClothState, io: Float64Array): void {
  writeCoreHandoff(c, io, IO_CORE)
  writeSleepHandoff(c, io, IO_SLEEP)
  writeGrabHandoff(c, io, IO_GRAB)
  writeWindHandoff(c, io, IO_WIND)
  writeCollisionHandoff(c, io, IO_COLLISION)
  writeGuardHandoff(c, io, IO_GUARD)
  writeCharacterHandoff(c, io, IO_CHARACTER)
  writeTearHandoff(c, io, IO_TEAR)
}

export function readClothHandoff(io: Float64Array, c: ClothState): void {
  readCoreHandoff(io, IO_CORE, c)
  readSleepHandoff(io, IO_SLEEP, c)
  readGrabHandoff(io, IO_GRAB, c)
  readWindHandoff(io, IO_WIND, c)
  readCollisionHandoff(io, IO_COLLISION, c)
  readGuardHandoff(io, IO_GUARD, c)
  readCharacterHandoff(io, IO_CHARACTER, c)
  readTearHandoff(io, IO_TEAR, c)
}

/** World values per step (`ClothThreads.worldIO`): substep count, speed limit, fixed step, wind clamp, whether the budget times the step. */
const W_SUBSTEPS = 0
const W_MAX_SPEED = 1
const W_FIXED_STEP = 2
const W_WIND_CLAMP = 3
const W_TIMED = 4
export const WORLD_IO_SIZE = 5

export function writeWorldHandoff(state: ClothWorldState, io: Float64Array): void {
  io[W_SUBSTEPS] = state.substepCount
  io[W_MAX_SPEED] = state.maxSpeed
  io[W_FIXED_STEP] = state.fixedTimeStep
  io[W_WIND_CLAMP] = state.wind.clamp ? 1 : 0
  io[W_TIMED] = state.budget.timeNext ? 1 : 0
}

export function readWorldHandoff(io: Float64Array, state: ClothWorldState): void {
  state.substepCount = io[W_SUBSTEPS]
  state.maxSpeed = io[W_MAX_SPEED]
  state.fixedTimeStep = io[W_FIXED_STEP]
  state.wind.clamp = io[W_WIND_CLAMP] === 1
  state.budget.timeNext = io[W_TIMED] === 1
}

/**
 * A worker's output block (`ClothThreads.outputs[w]`): its work counters (see `takeStats`), how
 * many cloths fell asleep, its time for the step (ms, when the budget times it), then the tear
 * events it raised (count, then EV doubles each, in its cloths' order).
 */
export const OUT_SLEPT = STAT_COUNT
export const OUT_MS = OUT_SLEPT + 1
export const OUT_TEARS = OUT_MS + 1
export const OUT_EVENTS = OUT_TEARS + 1
