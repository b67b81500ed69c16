import { addEntity, createWorld } from 'bitecs'
import { PerformanceObserver } from 'node:perf_hooks'
import {
  createCloth,
  getClothComponents,
  getClothState,
  getClothStats,
  getClothStretch,
  installClothPlugin,
  pinParticle,
  pinRow,
  resetClothStats,
  setTransform,
  stepCloth,
} from '../../src/index'
import { solveDistancesXpbd } from '../../src/kernels/distance'
import { cpuMs, fmt, saveJson, table, timeIt } from './harness'
import { createTextbook } from './textbook'

/** A 1 m sheet of n×n particles hanging from its two top corners (or its top row). */
function sheet(
  n: number,
  substeps: number,
  iterations: number,
  pins: 'corners' | 'row' = 'corners',
  tethers = true,
  bending: 'line' | 'distance' = 'line',
) {
  const world = installClothPlugin(createWorld(), { sleep: false })
  const cloth = createCloth(world, { width: 1, height: 1, resolution: n, substeps, iterations, tethers, bending, material: 'cotton' })
  if (pins === 'row') pinRow(world, cloth, 0)
  else {
    pinParticle(world, cloth, 0)
    pinParticle(world, cloth, n - 1)
  }
  return { world, cloth }
}

/** ms per step, projections per second and stretch after 300 steps of 1/60 s. */
export function sheets(): void {
  const rows: Record<string, string | number>[] = []
  const settings: [number, number][] = [[1, 8], [2, 1], [4, 1], [8, 1], [4, 2]]
  for (const n of [32, 64, 128]) {
    for (const [substeps, iterations] of settings) {
      const { world, cloth } = sheet(n, substeps, iterations)
      for (let f = 0; f < 100; f++) stepCloth(world, 1 / 60)
      resetClothStats(world)
      const ms = timeIt(() => stepCloth(world, 1 / 60), 200, 0)
      const s = getClothStats(world)
      const projections = (s.distanceProjections + s.lineProjections + s.dihedralProjections + s.tetherProjections) / 200
      const stretch = getClothStretch(world, cloth)
      rows.push({
        sheet: `${n}×${n}`,
        'substeps × iterations': `${substeps} × ${iterations}`,
        'ms per step': fmt(ms, 3),
        'M projections/s': fmt(projections / ms / 1e3, 1),
        'mean stretch': `${fmt(stretch.mean * 100, 3)} %`,
        'max stretch': `${fmt(stretch.max * 100, 2)} %`,
      })
    }
  }
  table(
    'Sheets of 1 m hanging from their two top corners (cotton, line bending, tethers on), after 300 steps of 1/60 s (projections: distance, line-bending and tether constraints)',
    rows,
  )
  saveJson('core-sheets', rows)
}

/**
 * The solve phase's distance loop alone, 8 XPBD iterations on a cloth's own arrays (multipliers
 * zeroed first, as at a substep start). Two closures exist so V8 cannot fold one sheet's arrays
 * into the loop as constants, which the plugin cannot have either.
 */
function solveLoop(c: ReturnType<typeof getClothState>): () => void {
  const t = c.topology
  return () => {
    c.distLambda.fill(0)
    for (let it = 0; it < 8; it++)
      solveDistancesXpbd(c.pos, c.invMass3, t.distOffsets, t.distRest, t.distCompliance, c.distLambda, c.params, 0, t.distCount)
  }
}

/** Median CPU ms per call over interleaved rounds: each run times `steps` calls per round, rounds alternate runs. */
export function interleaved(runs: (() => void)[], rounds: number, steps: number): number[] {
  const samples: number[][] = runs.map(() => [])
  for (const f of runs) for (let i = 0; i < steps; i++) f() // warm up
  for (let r = 0; r < rounds; r++) {
    runs.forEach((f, k) => {
      const t0 = cpuMs()
      for (let i = 0; i < steps; i++) f()
      samples[k].push((cpuMs() - t0) / steps)
    })
  }
  return samples.map((x) => x.sort((a, b) => a - b)[x.length >> 1])
}

/**
 * Whole-step throughput on a 64×64 sheet hanging from its top row, 1 substep × 8 iterations:
 * projections per second of the default constraint set (structural, shear, line bending, tethers)
 * against the textbook PBD loop (tests/bench/textbook.ts: structural, shear and skip-one bending,
 * each projected with a square root) on the same sheet, in the same process, timed interleaved
 * (CPU time, 15 rounds of 30 steps, the median round). Goal: the default set at ≥ 0.8× the textbook loop's
 * projections per second. Also: the plugin on the textbook's own constraint set, and its distance
 * loop alone. Projections count every constraint solved: distance pairs and line triples per
 * iteration, tethers per pass.
 */
export function throughput(): void {
  const n = 64
  const book = createTextbook(n, 'row')
  const dflt = sheet(n, 1, 8, 'row', true, 'line')
  const same = sheet(n, 1, 8, 'row', false, 'distance')
  const loopSheet = sheet(n, 1, 8, 'row', false, 'distance')
  for (const w of [dflt.world, same.world, loopSheet.world]) for (let f = 0; f < 100; f++) stepCloth(w, 1 / 60)
  for (let f = 0; f < 100; f++) book.step(1, 8)
  const c = getClothState(loopSheet.world, loopSheet.cloth)
  solveLoop(c)
  const runs = [() => book.step(1, 8), () => stepCloth(dflt.world, 1 / 60), () => stepCloth(same.world, 1 / 60), solveLoop(c)]
  const ms = interleaved(runs, 15, 30)
  const perStep = (w: object) => {
    resetClothStats(w)
    stepCloth(w, 1 / 60)
    const s = getClothStats(w)
    return s.distanceProjections + s.lineProjections + s.dihedralProjections + s.tetherProjections
  }
  const projections = [8 * book.constraints, perStep(dflt.world), perStep(same.world), 8 * c.topology.distCount]
  const rate = projections.map((p, k) => p / ms[k] / 1e3)
  const ratio = rate.map((r) => r / rate[0])
  const names = [
    'textbook PBD loop: structural, shear, skip-one bending',
    'bitecs-cloth, default set: structural, shear, line bending, tethers',
    "bitecs-cloth, the textbook's set: structural, shear, skip-one bending",
    'bitecs-cloth, its distance loop alone (same set, 8 sweeps)',
  ]
  const rows: Record<string, string | number>[] = names.map((name, k) => ({
    run: name,
    'projections per step': projections[k],
    'ms per step': fmt(ms[k], 3),
    'M projections/s': fmt(rate[k], 1),
    'vs textbook': fmt(ratio[k], 2),
    'goal ≥ 0.8× textbook': k === 1 ? (ratio[k] >= 0.8 ? 'met' : 'missed') : '',
  }))
  table(
    `Whole-step throughput, ${n}×${n} sheet hanging from its top row, 1 substep × 8 iterations (CPU time, median of 15 interleaved rounds of 30 steps)`,
    rows,
  )
  saveJson('core-throughput', rows)
}

/**
 * Heap before and after 10,000 steps, and the garbage collections during them (a step that
 * allocates nothing triggers none). Two scenes: a sheet on world pins, and a cape on a character
 * whose Transform store is written every frame.
 */
export async function allocation(): Promise<void> {
  const rows: Record<string, string | number>[] = []
  for (const scene of ['sheet', 'cape'] as const) {
    const world = installClothPlugin(createWorld(), { sleep: false })
    const cloth = createCloth(world, { width: 1, height: 1, resolution: 32, substeps: 4 })
    const { Transform } = getClothComponents(world)
    const hero = addEntity(world)
    setTransform(world, hero, [0, 0, 0])
    if (scene === 'cape') pinRow(world, cloth, 0, hero)
    else {
      pinParticle(world, cloth, 0)
      pinParticle(world, cloth, 31)
    }
    let frame = 0
    const step = () => {
      frame++
      Transform.px[hero] = Math.sin(frame * 0.05)
      Transform.qy[hero] = Math.sin(frame * 0.01)
      Transform.qw[hero] = Math.cos(frame * 0.01)
      stepCloth(world, 1 / 60)
    }
    for (let f = 0; f < 3000; f++) step() // warm up: let the JIT finish compiling
    const gc = (globalThis as { gc?: () => void }).gc
    gc?.()
    let collections = 0
    const observer = new PerformanceObserver((list) => (collections += list.getEntries().length))
    observer.observe({ entryTypes: ['gc'] })
    const before = process.memoryUsage().heapUsed
    for (let f = 0; f < 10_000; f++) step()
    const after = process.memoryUsage().heapUsed
    await new Promise((resolve) => setTimeout(resolve, 50)) // GC entries are delivered asynchronously
    observer.disconnect()
    rows.push({
      scene: `${scene} (32×32, 4 substeps)`,
      'heap before (KB)': fmt(before / 1024, 0),
      'heap after (KB)': fmt(after / 1024, 0),
      'grew (KB)': fmt((after - before) / 1024, 1),
      'GCs during run': collections,
    })
  }
  table('Allocation over 10,000 steps (no GC in between)', rows)
  saveJson('core-allocation', rows)
}
