/**
 * The cloth worker: the script a threaded world (`installClothPlugin(world, { threads })`) runs
 * in each of its workers. Build it as its own bundle (the package ships it as `dist/worker.js`;
 * `bitecs-cloth/worker` for your bundler) and pass its URL as `workerUrl` when it does not sit
 * next to the library file. It runs in a Web Worker (module type) or a Node `worker_threads`
 * worker, and needs nothing from the page.
 *
 * Its loop: block in Atomics.wait until the main thread asks for a step, run it, say so, wait
 * again. Messages (new cloths, new arrays) arrive through the event loop, so when a step needs a
 * layout the worker has not received yet, the loop returns and resumes once the message is in.
 */
import { runWorkerStep } from '../systems/pipeline'
import { clothFingerprint } from './threads/layout'
import { bindCloth, bindWorld, createWorkerWorld, readStepInputs, type WorldMessage } from './threads/mirror'
import { C_DONE, C_LAYOUT, C_QUIT, C_STATE, C_STEP, reportWorkerFailure } from './threads/pool'
import type { ClothState } from './world/state'

interface LayoutMessage {
  kind: 'layout'
  seq: number
  world: WorldMessage | null
  worldIO: Float64Array
  list: Int32Array
  output: Float64Array
  cloths: { slot: number; cloth: ClothState; io: Float64Array }[]
  drops: number[]
  verify: Int32Array | null
}

const ww = createWorkerWorld()
let index = -1
let control: Int32Array | null = null
let layout = 0
let done = 0
let worldIO: Float64Array | null = null
let list: Int32Array | null = null
let output: Float64Array | null = null
let verify: Int32Array | null = null

function receive(data: unknown): void {
  const m = data as { kind: string }
  try {
    if (m.kind === 'init') {
      const init = m as unknown as { index: number; control: Int32Array }
      index = init.index
      control = init.control
      done = 0 // the main thread's first step is 1, whenever this worker comes up
      Atomics.store(control, C_DONE + index, done)
      Atomics.store(control, C_STATE + index, 1)
    } else if (m.kind === 'layout') applyLayout(m as LayoutMessage)
    loop()
  } catch (e) {
    fail(e)
  }
}

function applyLayout(m: LayoutMessage): void {
  if (m.world !== null) bindWorld(ww, m.world)
  for (const slot of m.drops) bindCloth(ww, slot, null, null)
  for (const b of m.cloths) bindCloth(ww, b.slot, b.cloth, b.io)
  worldIO = m.worldIO
  list = m.list
  output = m.output
  verify = m.verify
  layout = m.seq
}

/** Runs steps until the main thread asks for one whose layout has not arrived (or to quit). */
function loop(): void {
  const c = control
  if (c === null) return
  for (;;) {
    if (Atomics.load(c, C_QUIT) === 1) {
      close()
      return
    }
    const step = Atomics.load(c, C_STEP)
    if (step === done) {
      Atomics.wait(c, C_STEP, done)
      continue
    }
    if (Atomics.load(c, C_LAYOUT) > layout) return // the message is on its way
    runStep()
    done = step
    Atomics.store(c, C_DONE + index, step)
    Atomics.notify(c, C_DONE + index)
  }
}

function runStep(): void {
  readStepInputs(ww, list!, worldIO!)
  const before = verify !== null ? fingerprints() : null
  runWorkerStep(ww, list!, output!)
  if (verify !== null) writeText(verify, JSON.stringify({ before, after: fingerprints() }))
}

/** The fingerprints of this step's cloths, by slot (verify mode). */
function fingerprints(): Record<number, string[]> {
  const out: Record<number, string[]> = {}
  for (let i = 1; i <= list![0]; i++) out[list![i]] = clothFingerprint(ww.cloths[list![i]]!)
  return out
}

function writeText(buf: Int32Array, text: string): void {
  const n = Math.min(text.length, buf.length - 1)
  buf[0] = n
  for (let i = 0; i < n; i++) buf[i + 1] = text.charCodeAt(i)
}

function fail(e: unknown): void {
  const text = e instanceof Error ? `${e.message}\n${e.stack ?? ''}` : String(e)
  if (control !== null && index >= 0) reportWorkerFailure(control, index, text)
  post({ kind: 'error', error: text })
}

// Node worker_threads or a Web Worker (no static import of Node modules: browser bundles stay clean)
type Port = { on(event: 'message', fn: (data: unknown) => void): void; postMessage(m: unknown): void; close(): void }
const proc = (globalThis as { process?: { getBuiltinModule?: (id: string) => unknown; versions?: { node?: string } } }).process
const nodePort = proc?.versions?.node && typeof proc.getBuiltinModule === 'function'
  ? ((proc.getBuiltinModule('node:worker_threads') as { parentPort: Port | null }).parentPort)
  : null
const scope = globalThis as unknown as {
  addEventListener(t: 'message', fn: (e: MessageEvent) => void): void
  postMessage(m: unknown): void
  close(): void
}

function post(m: unknown): void {
  if (nodePort !== null) nodePort.postMessage(m)
  else scope.postMessage(m)
}

function close(): void {
  if (nodePort !== null) nodePort.close()
  else scope.close()
}

if (nodePort !== null) nodePort.on('message', receive)
else scope.addEventListener('message', (e) => receive(e.data))
