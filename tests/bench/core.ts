import { addEntity, createWorld } from 'bitecs'
import { PerformanceObserver } from 'node:perf_hooks'
import { createCloth, getClothComponents, getClothState, getClothStats, getClothStretch, installClothPlugin, pinParticle, pinRow, resetClothStats, setTransform, stepCloth } from '../../src/index'
import { solveDistancesXpbd } from '../../src/kernels/distance'
import { fmt, saveJson, table, timeIt } from './harness'

/** A 1 m sheet of n×n particles hanging from its two top corners (or its top row). */
function sheet(n: number, substeps: number, iterations: number, pins: 'corners' | 'row' = 'corners', tethers = true, bending: 'line' | 'distance' = 'line') {
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
        substeps,
        iterations,
        'ms/step': fmt(ms, 3),
        'M proj/s': fmt(projections / ms / 1e3, 1),
        'mean stretch %': fmt(stretch.mean * 100, 3),
        'max stretch %': fmt(stretch.max * 100, 2),
      })
    }
  }
  table('Sheets hanging from two corners (cotton, line bending, tethers on), 300 steps of 1/60 s', rows)
  saveJson('core-sheets', rows)
}

/**
 * The solve phase's distance loop alone, 8 XPBD iterations on a cloth's own arrays (multipliers
 * zeroed first, as at a substep start): the rate the issue compares with a plain typed-array loop
 * (~85 M/s here) and optimized C (~120 M/s). Two closures exist so V8 cannot fold one sheet's
 * arrays into the loop as constants, which the plugin cannot have either.
 */
function solveLoop(c: ReturnType<typeof getClothState>): () => void {
  const t = c.topology
  return () => {
    c.distLambda.fill(0)
    for (let it = 0; it < 8; it++) solveDistancesXpbd(c.pos, c.invMass3, t.distOffsets, t.distRest, t.distCompliance, c.distLambda, c.params, 0, t.distCount)
  }
}

/**
 * The throughput target: 64×64, structural + shear + skip-one bending, 8 iterations. The runs are
 * timed interleaved (15 rounds of 30 steps each, the median round per run), so a slow spell of
 * the machine or a collection lands in one round, not in one run.
 */
export function throughput(): void {
  const solo = sheet(64, 1, 8, 'row', false, 'distance')
  const configs = [[1, 8, false], [1, 8, true], [8, 1, false]] as const
  const worlds = configs.map(([substeps, iterations, tethers]) => sheet(64, substeps, iterations, 'row', tethers, 'distance').world)
  for (const w of [solo.world, ...worlds]) for (let f = 0; f < 100; f++) stepCloth(w, 1 / 60)
  const c = getClothState(solo.world, solo.cloth)
  solveLoop(c)
  const runs = [solveLoop(c), ...worlds.map((w) => () => stepCloth(w, 1 / 60))]
  const samples: number[][] = runs.map(() => [])
  for (const f of runs) for (let i = 0; i < 30; i++) f()
  for (let r = 0; r < 15; r++) {
    runs.forEach((f, k) => {
      const t0 = performance.now()
      for (let i = 0; i < 30; i++) f()
      samples[k].push((performance.now() - t0) / 30)
    })
  }
  const ms = samples.map((x) => x.sort((a, b) => a - b)[x.length >> 1])
  const dist = 8 * c.topology.distCount
  const rows: Record<string, string | number>[] = [{
    config: 'solve loop alone, 8 it',
    'ms/step': fmt(ms[0], 3),
    'distance proj/step': dist,
    'M distance proj/s': fmt(dist / ms[0] / 1e3, 1),
    'M all proj/s': fmt(dist / ms[0] / 1e3, 1),
  }]
  configs.forEach(([substeps, iterations, tethers], k) => {
    const w = worlds[k]
    resetClothStats(w)
    stepCloth(w, 1 / 60)
    const s = getClothStats(w)
    const all = s.distanceProjections + s.tetherProjections
    rows.push({
      config: `${substeps} substep × ${iterations} it${tethers ? ', tethers' : ''}`,
      'ms/step': fmt(ms[k + 1], 3),
      'distance proj/step': s.distanceProjections,
      'M distance proj/s': fmt(s.distanceProjections / ms[k + 1] / 1e3, 1),
      'M all proj/s': fmt(all / ms[k + 1] / 1e3, 1),
    })
  })
  table('Throughput, 64×64 sheet with structural, shear and skip-one bending (23,938 distance constraints): the solve loop alone, then whole steps including predict, pins, writeback, stretch damping and the guard (median of 15 interleaved rounds of 30 steps)', rows)
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
