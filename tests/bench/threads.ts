import { addEntity, createWorld } from 'bitecs'
import {
  addCapsuleCollider,
  beginClothStep,
  createCloth,
  disposeClothWorld,
  endClothStep,
  installClothPlugin,
  pinRow,
  setClothInertia,
  setClothMotionConstraints,
  setClothSkinning,
  setTransform,
  stepCloth,
} from '../../src/index'
import { getClothWorld } from '../../src/world/access'
import { waitForWorkers } from '../../src/threads/pool'
import { cpuMs, fmt, saveJson, table } from './harness'
import { Worker } from 'node:worker_threads'

const DT = 1 / 60
/** The cloth worker, bundled next to the benchmark bundle by run.mjs. */
const WORKER = new URL('./worker.mjs', import.meta.url)

/**
 * `n` capes of `res`×`res` on characters running in circles, each with a torso and two leg
 * capsules, tethers on, 8 substeps (the budget suite's crowd, without a budget), stepped on
 * `threads` workers. `animate` writes the frame's Transforms (the game's work, not timed).
 * `configure` may give each cape character-cloth settings, and return what it animates per frame.
 */
function crowd(threads: number, n: number, res: number, minStepMs?: number, configure?: Configure, first = 0) {
  const world = installClothPlugin(createWorld(), { sleep: false, threads, workerUrl: WORKER, threadMinStepMs: minStepMs })
  const heroes: { eid: number; x: number; z: number; phase: number }[] = []
  const moves: ((frame: number) => void)[] = []
  for (let i = first; i < first + n; i++) {
    const x = (i % 8) * 3, z = Math.floor(i / 8) * 3
    const phase = i * 0.7
    const turn: [number, number, number, number] = [0, Math.sin(-phase / 2), 0, Math.cos(-phase / 2)]
    const hx = x + Math.cos(phase), hz = z + Math.sin(phase)
    const hero = addEntity(world)
    setTransform(world, hero, [hx, 1.6, hz], turn)
    addCapsuleCollider(world, addEntity(world), { body: hero, offset: [0, -0.25, 0], radius: 0.17, halfHeight: 0.25 })
    addCapsuleCollider(world, addEntity(world), { body: hero, offset: [-0.1, -0.95, 0], radius: 0.08, halfHeight: 0.35 })
    addCapsuleCollider(world, addEntity(world), { body: hero, offset: [0.1, -0.95, 0], radius: 0.08, halfHeight: 0.35 })
    const back = [0.2 * Math.sin(phase), 1.62, -0.2 * Math.cos(phase)]
    const cape = createCloth(world, {
      width: 0.6,
      height: 1,
      resolution: res,
      position: [hx + back[0], back[1], hz + back[2]],
      rotation: turn,
      material: 'cotton',
    })
    pinRow(world, cape, 0, hero)
    const move = configure?.(world, hero, cape, res)
    if (move) moves.push(move)
    heroes.push({ eid: hero, x, z, phase })
  }
  let frame = 0
  const animate = () => {
    frame++
    for (const h of heroes) {
      const a = frame * DT * 3 + h.phase
      setTransform(world, h.eid, [h.x + Math.cos(a), 1.6, h.z + Math.sin(a)], [0, Math.sin(-a / 2), 0, Math.cos(-a / 2)])
    }
    for (const m of moves) m(frame)
  }
  return { world, animate }
}

type Crowd = ReturnType<typeof crowd>
type Configure = (world: object, hero: number, cape: number, res: number) => ((frame: number) => void) | void

/**
 * One frame, timed: main-thread ms (beginClothStep, then endClothStep once the workers are done:
 * what the calling thread spends) and wall ms (begin to end, waiting included). Without workers
 * both are stepCloth's time.
 */
function frame(c: Crowd, out: { main: number; wall: number; cpu: number }): void {
  c.animate()
  const th = getClothWorld(c.world).threads
  if (th === null) {
    const c0 = cpuMs()
    const t0 = performance.now()
    stepCloth(c.world, DT)
    out.main = out.wall = performance.now() - t0
    out.cpu = cpuMs() - c0
    return
  }
  const c0 = cpuMs()
  const t0 = performance.now()
  beginClothStep(c.world, DT)
  const t1 = performance.now()
  if (th.phase === 1) waitForWorkers(th.pool, th.step) // (blocking, not spinning: the workers need the cores)
  const t2 = performance.now()
  endClothStep(c.world)
  const t3 = performance.now()
  out.main = t1 - t0 + (t3 - t2)
  out.wall = t3 - t0
  out.cpu = cpuMs() - c0
}

const median = (a: number[]): number => [...a].sort((x, y) => x - y)[a.length >> 1]

/** Times one frame into `out` (main-thread, wall and CPU ms). */
type Runner = (out: { main: number; wall: number; cpu: number }) => void

const runner = (c: Crowd): Runner => (out) => frame(c, out)

/** Interleaved rounds of `frames` frames per runner; per runner the median per round of main, wall and CPU ms. */
function measure(runners: Runner[], rounds: number, frames: number): { main: number[]; wall: number[]; cpu: number[] }[] {
  const out = runners.map(() => ({ main: [] as number[], wall: [] as number[], cpu: [] as number[] }))
  const t = { main: 0, wall: 0, cpu: 0 }
  for (let r = 0; r < rounds; r++) {
    for (let w = 0; w < runners.length; w++) {
      const main: number[] = [], wall: number[] = [], cpu: number[] = []
      for (let f = 0; f < frames; f++) {
        runners[w](t)
        main.push(t.main)
        wall.push(t.wall)
        cpu.push(t.cpu)
      }
      out[w].main.push(median(main))
      out[w].wall.push(median(wall))
      out[w].cpu.push(median(cpu))
    }
  }
  return out
}

/** The median over rounds of one runner's round median over another's (both measured in the same round). */
const roundRatio = (a: number[], b: number[]): number => median(a.map((x, r) => x / b[r]))

/**
 * The machine's own best split of the crowd, beside the threaded mode: the 64 capes as two
 * independent single-threaded worlds of 32, each on a plain worker thread, stepped in lockstep (a
 * frame signals both and waits for both). No handoff, no partition, no shared world: what two
 * threads of this machine can do with this work in the same round, whatever the VM gives the
 * second core at that moment.
 */
interface Split {
  workers: Worker[]
  control: Int32Array
  frame: number
}

/** What a split worker is told (the benchmark bundle runs as the worker: see main.ts). */
interface SplitData {
  kind: 'split'
  control: SharedArrayBuffer
  index: number
  first: number
  count: number
  res: number
}

async function startSplit(n: number, res: number): Promise<Split> {
  const control = new Int32Array(new SharedArrayBuffer(16))
  const half = n >> 1
  const workers = [0, 1].map((index) => {
    const workerData: SplitData = {
      kind: 'split',
      control: control.buffer as SharedArrayBuffer,
      index,
      first: index * half,
      count: half,
      res,
    }
    return new Worker(new URL(import.meta.url), { workerData })
  })
  await Promise.all(workers.map((w) => new Promise<void>((resolve) => w.once('message', () => resolve()))))
  return { workers, control, frame: 0 }
}

function splitFrame(s: Split, out: { main: number; wall: number; cpu: number }): void {
  const c = s.control
  const c0 = cpuMs()
  const t0 = performance.now()
  const f = ++s.frame
  Atomics.store(c, 0, f)
  Atomics.notify(c, 0)
  for (let w = 0; w < 2; w++) {
    for (let v = Atomics.load(c, 1 + w); v !== f; v = Atomics.load(c, 1 + w)) Atomics.wait(c, 1 + w, v)
  }
  out.wall = performance.now() - t0
  out.main = 0
  out.cpu = cpuMs() - c0
}

async function stopSplit(s: Split): Promise<void> {
  Atomics.store(s.control, 0, -1)
  Atomics.notify(s.control, 0)
  await Promise.all(s.workers.map((w) => w.terminate()))
}

/** The split worker's side: builds its half of the crowd, says so, then steps a frame per signal until told -1. */
export function runSplitWorker(d: SplitData, ready: () => void): void {
  const c = crowd(0, d.count, d.res, undefined, undefined, d.first)
  for (let f = 0; f < 60; f++) frame(c, { main: 0, wall: 0, cpu: 0 })
  const control = new Int32Array(d.control)
  ready()
  let seen = 0
  for (;;) {
    Atomics.wait(control, 0, seen)
    const f = Atomics.load(control, 0)
    if (f < 0) return
    if (f === seen) continue
    c.animate()
    stepCloth(c.world, DT)
    seen = f
    Atomics.store(control, 1 + d.index, f)
    Atomics.notify(control, 1 + d.index)
  }
}

const spread = (a: number[]): string => `${fmt(Math.min(...a), 2)}–${fmt(Math.max(...a), 2)}`

/**
 * The crowd of 64 capes (24×24, three capsules each, tethers, 8 substeps) with 0, 1 and 2 workers:
 * main-thread and wall ms per 60 Hz frame (the wall clock: what a frame waits), and the CPU time
 * of all the process's threads per frame (the work done, which waiting for a busy machine's cores
 * does not inflate: with the work shared evenly, two free cores would take about half of it as wall
 * time), one run, interleaved rounds, beside the same crowd split by hand over two plain threads
 * (`Split`: what this machine's two cores give at that moment, so the threaded mode's own cost shows
 * apart from the VM's); then one small cape, to show what the handoff costs.
 */
export async function threadsCost(): Promise<void> {
  const free = await parallelism()
  const counts = [0, 1, 2]
  const worlds = counts.map((n) => crowd(n, 64, 24))
  for (const w of worlds) for (let f = 0; f < 60; f++) frame(w, { main: 0, wall: 0, cpu: 0 })
  const split = await startSplit(64, 24)
  const rounds = 11
  const m = measure([...worlds.map(runner), (t) => splitFrame(split, t)], rounds, 20)
  await stopSplit(split)
  const rows = [...counts.map((n) => `${n} workers`), '2 threads, split by hand']
  table(
    `64 capes of 24×24, 3 capsules each, tethers, 8 substeps: ms per 60 Hz frame (median of ${rounds} interleaved rounds of 20 frames; range of the round medians; wall / none: median of the rounds' ratios). Split by hand: two independent single-threaded worlds of 32 capes on two plain worker threads, in lockstep (the machine's own best split of this work, no handoff)`,
    rows.map((label, i) => ({
      mode: label,
      'main thread ms': fmt(median(m[i].main), 3),
      'main range': spread(m[i].main),
      'wall ms': fmt(median(m[i].wall), 2),
      'wall range': spread(m[i].wall),
      'wall / none': fmt(roundRatio(m[i].wall, m[0].wall), 2),
      'CPU ms, all threads': fmt(median(m[i].cpu), 2),
    })),
  )
  const fullCores = m[3].wall.map((x, r) => (x / m[0].wall[r] <= 0.55 ? r : -1)).filter((r) => r >= 0)
  const freeRounds = fullCores.length
  const inFree = fullCores.map((r) => m[2].wall[r] / m[0].wall[r])
  console.log(
    `\n2 workers against the split by hand, same round: ${
      fmt(roundRatio(m[2].wall, m[3].wall), 2)
    } (median of the rounds' ratios; 1.00: as fast as two independent half-crowds). ` +
      `Rounds where the split by hand ran at ≤ 0.55× none (two full cores): ${freeRounds} of ${rounds}` +
      (freeRounds > 0 ? `; in those, 2 workers / none: median ${fmt(median(inFree), 2)} (${spread(inFree)})` : ''),
  )
  for (const w of worlds) disposeClothWorld(w.world)

  // one small cape: the handoff (pack, wake a worker, wait, unpack) against the step itself
  const smalls = [crowd(0, 1, 12), crowd(1, 1, 12, 0), crowd(1, 1, 12)]
  for (const w of smalls) for (let f = 0; f < 200; f++) frame(w, { main: 0, wall: 0, cpu: 0 })
  const blocking = (c: Crowd) => () => {
    c.animate()
    stepCloth(c.world, DT)
  }
  const s = measureBlocking(smalls.map(blocking), 9, 200)
  table('One cape of 12×12 with 3 capsules, 8 substeps: stepCloth ms per frame (median of 9 interleaved rounds of 200 frames)', [
    { mode: 'no workers', 'ms/frame': fmt(median(s[0]), 4), range: spread(s[0]), 'vs none': '1.00' },
    {
      mode: '1 worker, every step handed over (threadMinStepMs 0)',
      'ms/frame': fmt(median(s[1]), 4),
      range: spread(s[1]),
      'vs none': fmt(median(s[1]) / median(s[0]), 2),
    },
    {
      mode: '1 worker, default (small steps stay on the calling thread)',
      'ms/frame': fmt(median(s[2]), 4),
      range: spread(s[2]),
      'vs none': fmt(median(s[2]) / median(s[0]), 2),
    },
  ])
  for (const w of smalls) disposeClothWorld(w.world)
  console.log(
    `\n(The machine during this run: the same arithmetic split over 2 workers ran ${
      fmt(free, 2)
    }× as fast as on 1; 2.00 means two free cores.)`,
  )
  saveJson('threads', { crowd: rows.map((mode, i) => ({ mode, ...m[i] })), small: s, parallelism: free })
}

/**
 * How many cores the run really had: a fixed amount of arithmetic on 1 worker, then split over 2
 * (median of 3 rounds): the ratio is the most any split of work could gain on this machine now.
 */
async function parallelism(): Promise<number> {
  const wt = (globalThis as { process?: { getBuiltinModule?: (id: string) => unknown } }).process?.getBuiltinModule?.(
    'node:worker_threads',
  ) as
    | {
      Worker: new(
        code: string,
        o: { eval: true },
      ) => { postMessage(m: unknown): void; once(e: 'message', f: () => void): void; terminate(): Promise<number> }
    }
    | undefined
  if (!wt) return NaN
  const code = `const { parentPort } = require('node:worker_threads')
parentPort.on('message', (n) => { let x = 0; for (let i = 0; i < n; i++) x += Math.sqrt(i); parentPort.postMessage(x) })`
  const run = async (k: number, n: number): Promise<number> => {
    const ws = Array.from({ length: k }, () => new wt.Worker(code, { eval: true }))
    const go = (m: number) =>
      Promise.all(ws.map((w) =>
        new Promise<void>((r) => {
          w.once('message', r)
          w.postMessage(m)
        })
      ))
    await go(1e6)
    const t0 = performance.now()
    await go(n / k)
    const t = performance.now() - t0
    await Promise.all(ws.map((w) => w.terminate()))
    return t
  }
  const ratios: number[] = []
  for (let r = 0; r < 3; r++) ratios.push((await run(1, 2e8)) / (await run(2, 2e8)))
  return median(ratios)
}

function measureBlocking(fns: (() => void)[], rounds: number, frames: number): number[][] {
  const out = fns.map(() => [] as number[])
  for (let r = 0; r < rounds; r++) {
    for (let k = 0; k < fns.length; k++) {
      const t0 = performance.now()
      for (let f = 0; f < frames; f++) fns[k]()
      out[k].push((performance.now() - t0) / frames)
    }
  }
  return out
}

/** Max distance 0 at the collar, 0.9·u² m below, free at the hem (u: the row, 0..1), with a backstop: the demo cape's painting. */
function painted(res: number) {
  const maxDistance = Array.from({ length: res * res }, (_, i) => {
    const u = Math.floor(i / res) / (res - 1)
    return u >= 1 ? Infinity : 0.9 * u * u
  })
  return { maxDistance, backstop: { distance: 0.02, radius: 0.5 } }
}

/** Each cape in its character's frame (inertia shares 0.5, a teleport angle), held by painted max distance and a backstop. */
const framed: Configure = (world, hero, cape, res) => {
  setClothInertia(world, cape, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5, teleport: { angle: Math.PI / 2 } })
  setClothMotionConstraints(world, cape, painted(res))
}

/** As `framed`, with the reference skinned by the character and a hip bone that sways (blended by row). */
const skinned: Configure = (world, hero, cape, res) => {
  const hip = addEntity(world)
  const place = (frame: number) => {
    const p = getClothWorld(world).transforms
    const a = 0.4 * Math.sin(frame * 0.1)
    setTransform(world, hip, [p.px[hero], 1.0, p.pz[hero]], [Math.sin(a / 2), 0, 0, Math.cos(a / 2)])
  }
  place(0)
  const joints: number[] = [], weights: number[] = []
  for (let i = 0; i < res * res; i++) {
    const u = Math.floor(i / res) / (res - 1)
    joints.push(0, 1, 0, 0)
    weights.push(1 - u, u, 0, 0)
  }
  setClothInertia(world, cape, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5, teleport: { angle: Math.PI / 2 } })
  setClothSkinning(world, cape, { bones: [hero, hip], joints, weights })
  setClothMotionConstraints(world, cape, painted(res))
  return place
}

/**
 * Character cloth in the threaded mode: the crowd of 64 capes (24×24) plain, in their characters'
 * frames with painted motion constraints, and with skinned references, on 2 workers and on none.
 * The sync phase (the frame's motion; a skinned reference's blend, per particle) runs on the main
 * thread; the predict in the frame and the constraints run on the workers.
 */
export async function threadsCharacterCost(): Promise<void> {
  const free = await parallelism()
  const kinds: [string, Configure | undefined][] = [['plain capes', undefined], ['inertia + motion constraints', framed], [
    'skinned (2 bones) + constraints',
    skinned,
  ]]
  const worlds = kinds.flatMap(([, configure]) => [crowd(0, 64, 24, undefined, configure), crowd(2, 64, 24, undefined, configure)])
  for (const w of worlds) for (let f = 0; f < 60; f++) frame(w, { main: 0, wall: 0, cpu: 0 })
  const m = measure(worlds.map(runner), 7, 20)
  table(
    '64 capes of 24×24 on 0 and 2 workers, plain and character cloth: ms per 60 Hz frame (median of 7 interleaved rounds of 20 frames)',
    worlds.map((_, i) => ({
      capes: kinds[i >> 1][0],
      workers: i % 2 === 0 ? 0 : 2,
      'main thread ms': fmt(median(m[i].main), 3),
      'main range': spread(m[i].main),
      'wall ms': fmt(median(m[i].wall), 2),
      'wall / none': fmt(median(m[i].wall) / median(m[i & ~1].wall), 2),
      'CPU ms, all threads': fmt(median(m[i].cpu), 2),
    })),
  )
  for (const w of worlds) disposeClothWorld(w.world)
  console.log(`\n(The machine during this run: the same arithmetic split over 2 workers ran ${fmt(free, 2)}× as fast as on 1.)`)
  saveJson('threads-character', { kinds: kinds.map((k) => k[0]), runs: m, parallelism: free })
}
