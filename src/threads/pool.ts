import { ClothError } from '../core/errors'
import type { ClothWorker } from '../world/state'

/**
 * The workers of a threaded world and the control words they share with the main thread.
 *
 * Each step: the main thread writes the step's inputs into shared memory, stores a new step number
 * in `control[C_STEP]` and notifies; each worker runs its cloths, stores the number in its
 * `control[C_DONE + w]` and notifies. Nothing is posted per step. Messages carry only what shared
 * memory cannot: new arrays after the layout changed (a cloth created, pinned, torn open...), each
 * tagged with a layout number; a worker woken for a step whose `control[C_LAYOUT]` it has not
 * received yet returns to its event loop until the message arrives.
 *
 * Node: `worker_threads` (no import at module level, so browser bundles stay clean), workers
 * unref'd so a forgotten world never keeps the process alive. Browsers: module Web Workers.
 */

/** Step number the main thread asks for. */
export const C_STEP = 0
/** Layout number the step needs. */
export const C_LAYOUT = 1
/** 1: workers quit. */
export const C_QUIT = 2
/** Per worker: the last step number it finished (−1 before it started), then its state. */
export const C_DONE = 8
/** Per worker, at C_STATE + w: 0 starting, 1 ready, 2 failed (its message at C_ERROR). */
export const C_STATE = 40
/** Length of the first failure's message, then its UTF-16 code units (one per word). */
export const C_ERROR_LENGTH = 3
export const C_ERROR = 72
export const ERROR_CHARS = 2048
export const CONTROL_WORDS = C_ERROR + ERROR_CHARS
/** Most workers per world. */
export const MAX_THREADS = 32

interface NodeWorkerThreads {
  Worker: new(url: URL | string, options?: { workerData?: unknown }) => ClothWorker & {
    unref(): void
    on(event: string, fn: (value: unknown) => void): void
  }
}

/** Node's worker_threads module, or null outside Node. */
function nodeWorkerThreads(): NodeWorkerThreads | null {
  const p = (globalThis as { process?: { getBuiltinModule?: (id: string) => unknown; versions?: { node?: string } } }).process
  if (!p || !p.versions?.node || typeof p.getBuiltinModule !== 'function') return null
  return p.getBuiltinModule('node:worker_threads') as NodeWorkerThreads
}

/** Whether this thread may block in Atomics.wait (workers and Node may; a browser's main thread may not). */
export function canBlock(): boolean {
  if (nodeWorkerThreads() !== null) return true
  const g = globalThis as { document?: unknown; WorkerGlobalScope?: unknown }
  return g.document === undefined
}

export interface WorkerPool {
  workers: ClothWorker[]
  control: Int32Array
  /** This thread may block in Atomics.wait (see `canBlock`). */
  block: boolean
  /** Messages the workers posted (errors), newest last. */
  errors: string[]
  /** Workers that exited. */
  exited: number
}

/** Starts `count` workers running the script at `url`; they wait for their first message. */
export function createWorkerPool(count: number, url: URL | string): WorkerPool {
  const control = new Int32Array(new SharedArrayBuffer(4 * CONTROL_WORDS))
  for (let w = 0; w < count; w++) control[C_DONE + w] = -1
  const pool: WorkerPool = { workers: [], control, block: canBlock(), errors: [], exited: 0 }
  const node = nodeWorkerThreads()
  if (node !== null) checkScript(url)
  for (let w = 0; w < count; w++) {
    let worker: ClothWorker
    if (node !== null) {
      // (Node takes file URLs as URL objects, paths as strings)
      const nw = new node.Worker(typeof url === 'string' && url.startsWith('file:') ? new URL(url) : url)
      nw.on('error', (e) => pool.errors.push(String((e as Error)?.stack ?? e)))
      nw.on('message', (m) => receive(pool, m))
      nw.on('exit', () => pool.exited++)
      nw.unref() // after the listeners: a 'message' listener refs the worker again
      worker = nw
    } else {
      const Ctor = (globalThis as { Worker?: new(url: URL | string, o: { type: 'module' }) => ClothWorker & EventTarget }).Worker
      if (typeof Ctor !== 'function')
        throw new ClothError('options.threads', count, 'needs Web Workers, which this environment does not have')
      const bw = new Ctor(url, { type: 'module' })
      bw.addEventListener('error', (e) => pool.errors.push(String((e as ErrorEvent).message ?? e)))
      bw.addEventListener('message', (e) => receive(pool, (e as MessageEvent).data))
      worker = bw
    }
    worker.postMessage({ kind: 'init', index: w, control })
    pool.workers.push(worker)
  }
  return pool
}

/** Node: a worker script that is not there would only fail inside the worker; say so here. */
function checkScript(url: URL | string): void {
  const fs = (globalThis as { process?: { getBuiltinModule?: (id: string) => unknown } }).process?.getBuiltinModule?.('node:fs') as {
    existsSync(p: URL | string): boolean
  } | undefined
  const file = typeof url === 'string' && url.startsWith('file:') ? new URL(url) : url
  // (Node runs a worker from a file only: an https: URL threw a TypeError from new Worker)
  if (typeof file !== 'string' && file.protocol !== 'file:') {
    throw new ClothError('options.workerUrl', String(url), 'must be a file path or file: URL in Node (the cloth worker script)')
  }
  if (fs && !fs.existsSync(file)) {
    throw new ClothError(
      'options.workerUrl',
      String(url),
      'must name the cloth worker script (the package ships dist/worker.js; bundle bitecs-cloth/worker yourself when you bundle the library)',
    )
  }
}

function receive(pool: WorkerPool, m: unknown): void {
  const msg = m as { kind?: string; error?: string }
  if (msg && msg.kind === 'error') pool.errors.push(String(msg.error))
}

/** Asks every worker to run step `step` (needing layout `layout`). */
export function startWorkers(pool: WorkerPool, step: number, layout: number): void {
  const c = pool.control
  Atomics.store(c, C_LAYOUT, layout)
  Atomics.store(c, C_STEP, step)
  Atomics.notify(c, C_STEP)
}

/** Whether every worker finished step `step`; throws when one failed. */
export function workersDone(pool: WorkerPool, step: number): boolean {
  const c = pool.control
  for (let w = 0; w < pool.workers.length; w++) {
    if (Atomics.load(c, C_STATE + w) === 2) throw workerFailure(pool, w)
    if (Atomics.load(c, C_DONE + w) !== step) return false
  }
  return true
}

/** Whether every worker has started (loaded its script and taken its control words). */
export function workersReady(pool: WorkerPool): boolean {
  for (let w = 0; w < pool.workers.length; w++) if (Atomics.load(pool.control, C_STATE + w) !== 1) return false
  return true
}

/** How long a wait gives the workers before it reports them stuck: this many 50 ms waits. */
const STUCK_WAITS = 1200

/**
 * Waits until every worker finished step `step`: Atomics.wait where the thread may block, else a
 * spin on the control words (a browser's main thread; prefer `endClothStepAsync` there). (No
 * clock reads: performance.now allocates.)
 */
export function waitForWorkers(pool: WorkerPool, step: number): void {
  const c = pool.control
  let waits = 0
  let spins = 0
  for (let w = 0; w < pool.workers.length; w++) {
    for (;;) {
      const done = Atomics.load(c, C_DONE + w)
      if (done === step) break
      if (Atomics.load(c, C_STATE + w) === 2) throw workerFailure(pool, w)
      if (pool.block) {
        if (Atomics.wait(c, C_DONE + w, done, 50) === 'timed-out') waits++
      } else if (++spins === 1 << 22) {
        spins = 0
        waits++ // (a rough clock: some milliseconds per 4 M spins)
      }
      if (waits > STUCK_WAITS) throw stuck(pool)
    }
  }
}

function stuck(pool: WorkerPool): ClothError {
  return new ClothError(
    'world',
    undefined,
    `has a cloth worker that did not finish a step in a minute (did the worker script load? ${
      pool.errors.join('; ') || 'no error reported'
    })`,
  )
}

/**
 * Resolves when every worker finished step `step` (Atomics.waitAsync where there is one). While it
 * waits, a timer keeps the event loop alive: in Node neither a pending Atomics.waitAsync nor the
 * (unref'd) workers do, so an awaited step would otherwise let the process end mid-frame. The timer
 * goes when the wait settles, so an idle world still never holds a process open.
 */
export async function waitForWorkersAsync(pool: WorkerPool, step: number): Promise<void> {
  const c = pool.control
  const waitAsync =
    (Atomics as { waitAsync?: (a: Int32Array, i: number, v: number, t?: number) => { async: boolean; value: Promise<string> | string } })
      .waitAsync
  const t0 = performance.now()
  let alive: ReturnType<typeof setInterval> | null = null
  try {
    for (let w = 0; w < pool.workers.length; w++) {
      for (;;) {
        const done = Atomics.load(c, C_DONE + w)
        if (done === step) break
        if (Atomics.load(c, C_STATE + w) === 2) throw workerFailure(pool, w)
        if (performance.now() - t0 > 50 * STUCK_WAITS) throw stuck(pool)
        if (alive === null) alive = setInterval(keepAlive, 1 << 30)
        if (typeof waitAsync === 'function') {
          const r = waitAsync(c, C_DONE + w, done, 50)
          if (r.async) await r.value
        } else {
          await new Promise((resolve) => setTimeout(resolve, 0))
        }
      }
    }
  } finally {
    if (alive !== null) clearInterval(alive)
  }
}

/** The callback of the timer that keeps the event loop alive while a wait is pending (it never fires in practice). */
function keepAlive(): void {}

function workerFailure(pool: WorkerPool, w: number): Error {
  const c = pool.control
  const n = Math.min(Atomics.load(c, C_ERROR_LENGTH), ERROR_CHARS)
  let text = ''
  for (let i = 0; i < n; i++) text += String.fromCharCode(c[C_ERROR + i])
  return new Error(`bitecs-cloth: cloth worker ${w} failed: ${text || pool.errors.join('; ') || 'no message'}`)
}

/** Records a worker's failure in the control words (the first one wins), for the main thread to throw. */
export function reportWorkerFailure(control: Int32Array, w: number, text: string): void {
  if (Atomics.compareExchange(control, C_ERROR_LENGTH, 0, -1) === 0) {
    const n = Math.min(text.length, ERROR_CHARS)
    for (let i = 0; i < n; i++) control[C_ERROR + i] = text.charCodeAt(i)
    Atomics.store(control, C_ERROR_LENGTH, n)
  }
  Atomics.store(control, C_STATE + w, 2)
  Atomics.notify(control, C_DONE + w)
}

/** Tells the workers to quit and terminates them. */
export function disposeWorkerPool(pool: WorkerPool): void {
  const c = pool.control
  Atomics.store(c, C_QUIT, 1)
  Atomics.notify(c, C_STEP)
  for (const w of pool.workers) w.terminate()
  pool.workers.length = 0
}
