import { HEALTH_OK } from '../src/kernels/guard'
import type { ClothThreads, ClothWorldState } from '../src/world/state'
import { restoreSafePose } from '../src/features/guard/step'
import { placeHeldAfterReset } from '../src/features/character/step'
import { EV } from '../src/features/tearing/types'
import { Q_MEASURED } from '../src/features/budget/types'
import { refreshBindings } from '../src/threads/bind'
import {
  IO_HEALTH,
  OUT_EVENTS,
  OUT_MS,
  OUT_SLEPT,
  OUT_TEARS,
  readClothHandoff,
  writeClothHandoff,
  writeWorldHandoff,
} from '../src/threads/handoff'
import { addStats } from '../src/world/stats'
import { clothFingerprint } from '../src/threads/layout'
import { partitionCloths } from '../src/threads/partition'
import { startWorkers, workersReady } from '../src/threads/pool'
import { verifyWorker } from '../src/threads/verify'

/**
 * The fixed step of a threaded world, split between threads. The main thread runs the sync phase
 * (transforms, kinematics, wakes, budget, substep count), then `dispatchClothStep` shares the cloths
 * out and hands them to the workers; each worker runs the substeps of its cloths (forces, predict,
 * solve, collide, tear, writeback) and the guard's check (`runWorkerStep`); `collectClothStep` takes
 * the results back and, in creation order, puts failed cloths back into a safe pose (a character
 * cloth's held particles onto their reference) and queues the tear events, as the single-threaded guard and tear phases would.
 */

/**
 * Hands the step (after the sync phase) to the workers. Returns false when the step should run on
 * this thread instead: no cloth runs this step, or (`blocking`) its predicted cost is below the
 * handoff's (`ClothThreads.inlineNs`), or (`blocking`, on a thread that may not block: a page's
 * main thread) the workers have not started yet: a page's dedicated workers load their script
 * through the page's event loop, which a spinning wait would keep from running.
 */
export function dispatchClothStep(state: ClothWorldState, th: ClothThreads, blocking: boolean): boolean {
  if (state.substepCount === 0) return false
  refreshBindings(state, th)
  const total = partitionCloths(state, th)
  if (blocking && (total < th.inlineNs || (!th.pool.block && !workersReady(th.pool)))) return false
  writeWorldHandoff(state, th.worldIO)
  const lists = th.lists
  for (let w = 0; w < lists.length; w++) {
    const list = lists[w]
    for (let i = 1; i <= list[0]; i++) {
      const b = th.slots[list[i]]!
      writeClothHandoff(b.cloth, b.io)
      b.io[IO_HEALTH] = -1
      if (th.verify) th.verifyBefore.set(b.slot, clothFingerprint(b.cloth))
    }
  }
  keepFinishedReadings(state, th)
  th.step++
  startWorkers(th.pool, th.step, th.layoutSeq)
  th.phase = 1
  return true
}

/**
 * The tear counts and grab data the game reads while the workers step (`ClothThreads.finishedTears`,
 * `finishedGrabs`): the last finished step's, as without workers, where the step waits for its end.
 * Grown on demand (a new grabbing cloth, the stores' growth), reused every step.
 */
function keepFinishedReadings(state: ClothWorldState, th: ClothThreads): void {
  const tears = state.components.Tearable.tears
  if (th.finishedTears.length < tears.length) th.finishedTears = new Uint32Array(tears.length)
  th.finishedTears.set(tears)
  const cloths = state.cloths
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    const data = c.grab.data
    if (c.grab.count === 0) continue
    let kept = th.finishedGrabs.get(c)
    if (kept === undefined || kept.length < data.length) {
      kept = new Float64Array(data.length)
      th.finishedGrabs.set(c, kept)
    }
    kept.set(data)
  }
}

/**
 * After every worker finished: reads the cloths back, adds the workers' counters, then puts the
 * cloths the guard failed back into a safe pose and queues the tear events, in creation order
 * (workers step their cloths in creation order, so their events merge by cloth). The reset
 * listeners are called by `finishFixedStep`, as in every mode.
 */
export function collectClothStep(state: ClothWorldState, th: ClothThreads): void {
  th.phase = 0
  const lists = th.lists, outputs = th.outputs
  let slept = 0, ms = 0
  for (let w = 0; w < lists.length; w++) {
    const list = lists[w]
    for (let i = 1; i <= list[0]; i++) {
      const b = th.slots[list[i]]!
      readClothHandoff(b.io, b.cloth)
    }
    if (th.verify) verifyWorker(th, w)
    const out = outputs[w]
    addStats(state.stats, out, 0)
    slept += out[OUT_SLEPT]
    if (out[OUT_MS] > ms) ms = out[OUT_MS]
  }
  if (slept > 0) {
    state.sleep.count += slept
    state.sleep.gravity.set(state.gravity)
  }
  if (state.budget.timeNext) state.budget.timing[Q_MEASURED] = ms
  const cloths = state.cloths
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    const health = th.bindings.get(c)!.io[IO_HEALTH]
    if (health > HEALTH_OK) {
      restoreSafePose(state, c, health)
      if (c.character !== null) placeHeldAfterReset(c)
    }
  }
  mergeTearEvents(state, th)
}

/** Appends the workers' tear events to the world's, ordered by cloth (creation order). */
function mergeTearEvents(state: ClothWorldState, th: ClothThreads): void {
  const outputs = th.outputs
  const tw = state.tearing
  const at = th.load // read position per worker (reused scratch: the partition is done)
  let left = 0
  for (let w = 0; w < outputs.length; w++) {
    at[w] = 0
    left += outputs[w][OUT_TEARS]
  }
  const Cloth = state.components.Cloth.state
  while (left > 0) {
    let best = -1, bestSeq = Infinity
    for (let w = 0; w < outputs.length; w++) {
      const out = outputs[w]
      // events of cloths removed since the step began are dropped, as a removal drops its pending
      // ones (removed mid-frame while it tore, a cloth's events threw a TypeError here)
      while (at[w] < out[OUT_TEARS] && Cloth[out[OUT_EVENTS + at[w] * EV]] === undefined) {
        at[w]++
        left--
      }
      if (at[w] >= out[OUT_TEARS]) continue
      const seq = Cloth[out[OUT_EVENTS + at[w] * EV]]!.seq
      if (seq < bestSeq) {
        bestSeq = seq
        best = w
      }
    }
    if (best < 0) break
    const out = outputs[best]
    const from = OUT_EVENTS + at[best]++ * EV
    left--
    if ((tw.pendingCount + 1) * EV > tw.pending.length) continue
    const to = tw.pendingCount++ * EV
    for (let j = 0; j < EV; j++) tw.pending[to + j] = out[from + j]
  }
}
