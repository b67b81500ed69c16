import type { ClothFrame, ClothWorldState } from './state'

/**
 * What the game does while a fixed step is in flight: between `beginClothStep` and `endClothStep`,
 * while the step's substeps run on workers, or wait for `endClothStep` on this thread
 * (`ClothFrame.inFlight`, from the sync phase to the step's results).
 *
 * Removals. bitECS's `removeEntity` and `removeComponent` cannot be refused, and a game may call
 * them between `beginClothStep` and `endClothStep` (a character killed mid-frame). The plugin's
 * removal observers are wrapped by `deferrable`: in flight, their callbacks are queued, and
 * `landRemovals` runs them in arrival order when the step's results are in, before its listeners. The step in flight thus runs on the world
 * its sync phase saw, in every mode: workers never see a pin, collider or cloth go at a moment that
 * depends on timing.
 *
 * Growth. An entity spawned past the stores' capacity grows them at once (its Transform is written
 * there); the workers keep writing the stores they were given (pin blends, tear counts), so
 * `growStores` keeps those as they were (`ClothFrame.stale`) and `landStores` copies them over the
 * grown ones once workers ran the step.
 *
 * Additions. A SelfCollision component added with bitECS's `addComponent` waits the same way (its
 * buffers are allocated when the step has landed); other components come through the API, which
 * refuses changes in flight.
 */
export function deferrable(state: ClothWorldState, fn: (eid: number) => void): (eid: number) => void {
  return (eid: number) => {
    const f = state.frame
    if (!f.inFlight) {
      fn(eid)
      return
    }
    f.removals.push(fn)
    f.removed.push(eid)
  }
}

/**
 * Once the workers finished a step, before its results are read (a guard reset places pins from
 * the Pin store): the stores they wrote carried over into any grown ones (`threaded`); without
 * workers the step runs on the grown ones, and the copies are dropped.
 */
export function landStores(state: ClothWorldState, threaded: boolean): void {
  const stale = state.frame.stale
  if (stale === null) return
  state.frame.stale = null
  if (!threaded) return
  copyFields(stale.Pin, state.components.Pin)
  copyFields(stale.Tearable, state.components.Tearable)
}

/** Each typed array of `from` into the field of the same name of `to` (a grown copy: it fits). */
function copyFields(from: Record<string, unknown>, to: object): void {
  const fields = to as Record<string, unknown>
  for (const key of Object.keys(from)) {
    const a = from[key], b = fields[key]
    if (ArrayBuffer.isView(a) && ArrayBuffer.isView(b) && a !== b) (b as Float64Array).set(a as Float64Array)
  }
}

/**
 * Ends the step's flight once its results are in, before its listeners: the queued removal
 * callbacks, in arrival order (those they cause run at once).
 */
export function landRemovals(state: ClothWorldState): void {
  const f = state.frame
  f.inFlight = false
  const fns = f.removals, eids = f.removed
  try {
    for (let q = 0; q < fns.length; q++) fns[q](eids[q])
  } finally {
    fns.length = 0
    eids.length = 0
  }
}

/** A world's frame state between frames. */
export function createClothFrame(): ClothFrame {
  return {
    open: false,
    steps: 0,
    next: 0,
    overflow: false,
    deferred: false,
    ending: false,
    delivering: false,
    stepping: false,
    inFlight: false,
    removals: [],
    removed: [],
    stale: null,
  }
}
