import { ClothError, checkInteger, checkNonNegative } from '../core/errors'
import { layoutEpoch, releaseSharedMemory, sharedMemoryAvailable } from '../core/shared'
import type { ClothBinding, ClothPluginOptions, ClothState, ClothThreads, ClothWorldState } from '../world/state'
import { IO_SIZE, OUT_EVENTS, WORLD_IO_SIZE } from './handoff'
import { clothDescriptor, clothLayout, sameLayout, worldDescriptor, worldLayout, type AdoptCache } from './layout'
import { MAX_THREADS, createWorkerPool, disposeWorkerPool, type WorkerPool } from './pool'

/**
 * The main thread's side of the workers: starting them, and keeping what they know of the world and
 * its cloths current (see layout.ts). Runs between steps only.
 */

/** Doubles of fingerprint text per worker in verify mode. */
const VERIFY_WORDS = 1 << 21

/** Predicted step cost (the cost model's ns) below which `stepCloth` steps on its own thread by default. */
const DEFAULT_MIN_STEP_NS = 200_000

let warned = false

/**
 * The plugin's thread options, checked: null for a world that steps on the calling thread (also when
 * shared memory is missing and `requireThreads` is off, with a warning once per thread).
 */
export function resolveThreadOptions(o: ClothPluginOptions): { count: number; url: URL | string; inlineNs: number } | null {
  const count = o.threads === undefined ? 0 : checkInteger('options.threads', o.threads, 0, MAX_THREADS)
  // (typed as anything with an href, so that the declarations need no DOM or Node types for URL)
  const given: unknown = o.workerUrl
  const href = typeof given === 'object' && given !== null ? (given as { href?: unknown }).href : given
  if (given !== undefined && typeof href !== 'string') {
    throw new ClothError('options.workerUrl', given, 'must be a URL or a string (the cloth worker script)')
  }
  if (o.requireThreads !== undefined && typeof o.requireThreads !== 'boolean') {
    throw new ClothError('options.requireThreads', o.requireThreads, 'must be true or false')
  }
  const min = o.threadMinStepMs === undefined ? DEFAULT_MIN_STEP_NS * 1e-6 : checkNonNegative('options.threadMinStepMs', o.threadMinStepMs)
  if (count === 0) return null
  if (!sharedMemoryAvailable()) {
    const why =
      'needs SharedArrayBuffer, which this page does not have: serve it cross-origin isolated (headers Cross-Origin-Opener-Policy: same-origin and Cross-Origin-Embedder-Policy: require-corp)'
    if (o.requireThreads === true) throw new ClothError('options.threads', count, why)
    if (!warned) console.warn(`bitecs-cloth: options.threads ${why}; stepping cloths on the calling thread instead`)
    warned = true
    return null
  }
  const url = given === undefined ? defaultWorkerUrl() : given instanceof URL ? given : (href as string)
  return { count, url, inlineNs: min * 1e6 }
}

/**
 * The package's worker script, dist/worker.js: beside the library's entry files, one folder up from
 * the shared code (dist/chunks/) this module is bundled into. A bundler that moves the library
 * elsewhere needs `workerUrl`.
 */
function defaultWorkerUrl(): URL {
  const here = import.meta.url
  return new URL(here.includes('/chunks/') ? '../worker.js' : './worker.js', here)
}

/** Terminates a world's workers if the world is garbage-collected without `disposeClothWorld` (a safety net). */
const registry = typeof FinalizationRegistry === 'function'
  ? /* @__PURE__ */ new FinalizationRegistry<WorkerPool>((pool) => {
    disposeWorkerPool(pool)
    releaseSharedMemory()
  })
  : null

/** Ties the workers' lifetime to the world object (see `registry`). */
export function releaseWithWorld(world: object, th: ClothThreads): void {
  registry?.register(world, th.pool, th)
}

/** Starts `count` workers for a world (its arrays are already in shared memory). */
export function startThreads(count: number, url: URL | string, inlineNs: number): ClothThreads {
  const pool = createWorkerPool(count, url)
  return {
    pool,
    worldIO: sharedF64(WORLD_IO_SIZE),
    lists: [],
    outputs: [],
    slots: [],
    bindings: new Map(),
    epoch: -1,
    layoutSeq: 0,
    worldLayout: [],
    step: 0,
    phase: 0,
    inlineNs,
    cost: new Float64Array(0),
    group: new Int32Array(0),
    order: new Int32Array(0),
    sorted: new Int32Array(0),
    assign: new Int32Array(0),
    load: new Float64Array(count),
    verify: false,
    verifyText: [],
    verifyBefore: new Map(),
    adopt: new WeakMap(),
    finishedTears: new Uint32Array(0),
    finishedGrabs: new WeakMap(),
  }
}

/** Stops a world's workers (the world steps on the calling thread from now on). */
export function stopThreads(th: ClothThreads): void {
  registry?.unregister(th)
  disposeWorkerPool(th.pool)
  releaseSharedMemory()
  th.bindings.clear()
  th.slots.length = 0
}

function sharedF64(n: number): Float64Array {
  return new Float64Array(new SharedArrayBuffer(8 * n))
}

function sharedI32(n: number): Int32Array {
  return new Int32Array(new SharedArrayBuffer(4 * n))
}

/**
 * When the layout epoch moved since the last check (or every step in verify mode): sends the
 * workers every cloth whose layout changed, new cloths, dropped slots and the world's arrays if they
 * changed, in one message per worker, and sizes the per-worker lists and outputs. Returns whether a
 * message went out.
 */
export function refreshBindings(state: ClothWorldState, th: ClothThreads): boolean {
  const epoch = layoutEpoch()
  if (!th.verify && th.epoch === epoch) return false
  const adopt = th.adopt as AdoptCache
  const sends: ClothBinding[] = []
  const live = new Set<ClothState>(state.cloths)
  const drops: number[] = []
  for (const [c, b] of th.bindings) {
    if (live.has(c)) continue
    th.bindings.delete(c)
    th.slots[b.slot] = null
    drops.push(b.slot)
  }
  for (const c of state.cloths) {
    const layout = clothLayout(c, adopt)
    let b = th.bindings.get(c)
    if (b === undefined) {
      let slot = th.slots.indexOf(null)
      if (slot < 0) slot = th.slots.push(null) - 1
      b = { cloth: c, slot, io: sharedF64(IO_SIZE), layout }
      if (slot < th.assign.length) th.assign[slot] = -1
      th.slots[slot] = b
      th.bindings.set(c, b)
      sends.push(b)
    } else if (!sameLayout(layout, b.layout)) {
      if (th.verify && th.epoch === epoch)
        throw new Error(
          `bitecs-cloth: cloth ${c.eid}'s layout changed without touchLayout at step ${th.step} (${describeChange(b.layout, layout)})`,
        )
      b.layout = layout
      sends.push(b)
    }
  }
  const wd = worldDescriptor(state)
  const wl = worldLayout(wd)
  const worldChanged = !sameLayout(wl, th.worldLayout)
  th.worldLayout = wl
  const resized = sizeWorkerBuffers(state, th)
  const anything = worldChanged || resized || sends.length > 0 || drops.length > 0
  if (anything && th.verify && th.epoch === epoch) {
    throw new Error(
      `bitecs-cloth: the layout changed without touchLayout (${worldChanged ? 'world' : ''} ${sends.map((b) => b.slot).join(',')} ${
        drops.join(',')
      })`,
    )
  }
  th.epoch = layoutEpoch() // (adopting arrays moved it)
  if (!anything && !th.verify) return false
  th.layoutSeq++
  const workers = th.pool.workers.length
  const cloths = sends.map((b) => ({ slot: b.slot, cloth: clothDescriptor(b.cloth), io: b.io }))
  if (th.verify && th.verifyText.length === 0) { for (let w = 0; w < workers; w++) th.verifyText[w] = sharedI32(VERIFY_WORDS) }
  for (let w = 0; w < workers; w++) {
    th.pool.workers[w].postMessage({
      kind: 'layout',
      seq: th.layoutSeq,
      world: worldChanged ? wd : null,
      worldIO: th.worldIO,
      list: th.lists[w],
      output: th.outputs[w],
      cloths,
      drops,
      verify: th.verify ? th.verifyText[w] : null,
    })
  }
  return true
}

/**
 * Sizes the per-worker slot lists, the partition's scratch and the workers' output blocks for the
 * bound cloths and the world's tear events; returns whether any was replaced (the workers need it).
 */
function sizeWorkerBuffers(state: ClothWorldState, th: ClothThreads): boolean {
  const workers = th.pool.workers.length
  const need = th.slots.length + 1
  const newLists = th.lists.length === 0 || th.lists[0].length < need
  if (newLists) {
    const size = Math.max(16, 2 * need)
    for (let w = 0; w < workers; w++) th.lists[w] = sharedI32(size)
    th.cost = new Float64Array(size)
    th.group = new Int32Array(size)
    th.order = new Int32Array(size)
    th.sorted = new Int32Array(size)
    const assign = new Int32Array(size).fill(-1)
    assign.set(th.assign.subarray(0, Math.min(th.assign.length, size)))
    th.assign = assign
  }
  const outSize = OUT_EVENTS + state.tearing.pending.length
  const newOutputs = th.outputs.length === 0 || th.outputs[0].length < outSize
  if (newOutputs) { for (let w = 0; w < workers; w++) th.outputs[w] = sharedF64(outSize) }
  return newLists || newOutputs
}

function describeChange(a: unknown[], b: unknown[]): string {
  let i = 0
  while (i < a.length && i < b.length && a[i] === b[i]) i++
  const show = (v: unknown): string => (ArrayBuffer.isView(v) ? `${v.constructor.name}(${(v as Float64Array).length})` : String(v))
  return `entry ${i} of ${a.length}/${b.length}: ${show(a[i])} -> ${show(b[i])}`
}
