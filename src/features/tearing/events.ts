import { ClothError } from '../../core/errors'
import { nextListener } from '../../core/listeners'
import { getClothWorld } from '../../world/access'
import type { ClothWorldState } from '../../world/state'
import { EV, type ClothTearEvent, type ClothTearListener } from './types'

/**
 * Calls `listener` for every tear, right after the fixed step it happened in (inside `stepCloth` or
 * `clothFixedStep`, with the step complete). The event object is reused: copy what you keep.
 * Returns a function that unsubscribes.
 */
export function onClothTear(world: object, listener: ClothTearListener): () => void {
  const state = getClothWorld(world)
  if (typeof listener !== 'function') throw new ClothError('listener', listener, 'must be a function')
  const list = state.tearing.listeners
  list.push(listener)
  return () => {
    const i = list.indexOf(listener)
    if (i >= 0) list.splice(i, 1)
  }
}

/**
 * Hands the queued tear events (every tear since the last drain, oldest first) to `fn` and empties
 * the queue; for engines that poll in their own systems. The event object is reused. Returns the
 * number of events. The queue keeps 256 events; older undrained ones are kept and newer dropped.
 */
export function drainClothTears(world: object, fn: ClothTearListener): number {
  const tw = getClothWorld(world).tearing
  if (typeof fn !== 'function') throw new ClothError('fn', fn, 'must be a function')
  const n = tw.queueCount
  tw.queueCount = 0
  let delivered = 0
  // while `fn` runs, a cloth it removes has its remaining events dropped (forgetTearEvents)
  tw.draining = n
  try {
    for (let i = 0; i < n; i++) {
      if (tw.queue[i * EV] < 0) continue
      fn(readEvent(tw.queue, i, tw.event))
      delivered++
    }
  } finally {
    tw.draining = 0
  }
  return delivered
}

/**
 * Called when a cloth is removed: its tear events not yet delivered (to the listeners of the
 * current step, or by `drainClothTears`, queued or in a drain in progress) are dropped, since its id may soon name another cloth.
 */
export function forgetTearEvents(state: ClothWorldState, cloth: number): void {
  const tw = state.tearing
  const pending = tw.pendingCount > tw.delivering ? tw.pendingCount : tw.delivering
  for (let i = 0; i < pending; i++) if (tw.pending[i * EV] === cloth) tw.pending[i * EV] = -1
  // in a drain in progress (emptied first), its events not yet handed over are marked dead
  for (let i = 0; i < tw.draining; i++) if (tw.queue[i * EV] === cloth) tw.queue[i * EV] = -1
  // the drain queue is compacted (its dead events would keep the room live cloths' need)
  let kept = 0
  for (let i = 0; i < tw.queueCount; i++) {
    if (tw.queue[i * EV] === cloth) continue
    if (kept !== i) tw.queue.copyWithin(kept * EV, i * EV, (i + 1) * EV)
    kept++
  }
  tw.queueCount = kept
}

function readEvent(buf: Float64Array, i: number, e: ClothTearEvent): ClothTearEvent {
  const o = i * EV
  e.cloth = buf[o] | 0
  e.x = buf[o + 1]
  e.y = buf[o + 2]
  e.z = buf[o + 3]
  e.particle = buf[o + 4] | 0
  e.newParticle = buf[o + 5] | 0
  e.strain = buf[o + 6]
  return e
}

/**
 * After a fixed step: moves the step's tears to the drain queue and calls the listeners. Called by
 * the `clothEvents` system at the end of `clothFixedStep`.
 */
export function dispatchTearEvents(state: ClothWorldState): void {
  const tw = state.tearing
  const n = tw.pendingCount
  if (n === 0) return
  tw.pendingCount = 0
  const room = (tw.queue.length / EV) | 0
  for (let i = 0; i < n; i++) {
    if (tw.pending[i * EV] < 0) continue // its cloth was removed
    if (tw.queueCount >= room) {
      tw.dropped++
      continue
    }
    const from = i * EV, to = tw.queueCount * EV
    for (let j = 0; j < EV; j++) tw.queue[to + j] = tw.pending[from + j]
    tw.queueCount++
  }
  const listeners = tw.listeners
  if (listeners.length === 0) return
  // while the listeners run, a cloth one of them removes has its remaining events dropped
  tw.delivering = n
  for (let i = 0; i < n; i++) {
    for (let l = 0; l < listeners.length;) {
      if (tw.pending[i * EV] < 0) break
      const listener = listeners[l]
      listener(readEvent(tw.pending, i, tw.event))
      l = nextListener(listeners, l, listener)
    }
  }
  tw.delivering = 0
}

/** One event, while `orderTearEvents` moves it. */
const moving = new Float64Array(EV)
/** Each pending event's cloth's place in the world's cloth list (grown on the rare step with more events). */
let places = new Int32Array(64)

/**
 * Puts the step's tear events (`pending` from `from` on) in the order of their cloths' creation, each cloth's in
 * the order they happened (a stable insertion sort, allocation-free but for a rare growth): the
 * pipeline steps the self-colliding cloths after the others, and listeners see events cloth by
 * cloth in creation order in every mode (the workers' are merged so). The order is the world's
 * cloth list, in creation order on the main thread and on a worker alike (a worker has no
 * `Cloth` store to read each cloth's `seq` from: with one worker, the events went unsorted).
 */
export function orderTearEvents(state: ClothWorldState, from: number): void {
  const tw = state.tearing, p = tw.pending, n = tw.pendingCount - from
  const cloths = state.cloths
  if (places.length < n) places = new Int32Array(2 * n)
  for (let i = 0; i < n; i++) {
    const eid = p[(from + i) * EV]
    let at = -1
    for (let k = 0; k < cloths.length; k++) {
      if (cloths[k].eid === eid) {
        at = k
        break
      }
    }
    places[i] = at
  }
  for (let i = 1; i < n; i++) {
    const key = places[i]
    let j = i
    while (j > 0 && places[j - 1] > key) j--
    if (j === i) continue
    const o = from * EV
    for (let k = 0; k < EV; k++) moving[k] = p[o + i * EV + k]
    p.copyWithin(o + (j + 1) * EV, o + j * EV, o + i * EV)
    places.copyWithin(j + 1, j, i)
    for (let k = 0; k < EV; k++) p[o + j * EV + k] = moving[k]
    places[j] = key
  }
}
