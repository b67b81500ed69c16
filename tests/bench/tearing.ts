import { createWorld } from 'bitecs'
import {
  createCloth,
  getClothStats,
  installClothPlugin,
  makeTearable,
  pinParticle,
  resetClothStats,
  setTransform,
  stepCloth,
} from '../../src/index'
import { cpuMs, fmt, saveJson, table, timeIt } from './harness'
import { pinSidesToBars } from '../fixtures/bars'

function sheet(n: number, mode: 'plain' | 'tearable' | 'tearable elsewhere') {
  const world = installClothPlugin(createWorld(), { sleep: false })
  const cloth = createCloth(world, { width: 1, height: 1, resolution: n, position: [0, 2, 0], substeps: 4 })
  pinParticle(world, cloth, 0)
  pinParticle(world, cloth, n - 1)
  if (mode === 'tearable') makeTearable(world, cloth)
  if (mode === 'tearable elsewhere') {
    const other = createCloth(world, { width: 1, height: 1, resolution: 4, position: [5, 2, 0], substeps: 1 })
    makeTearable(world, other)
  }
  return { world, cloth }
}

/**
 * Tear-detection cost per edge (a hanging sheet that never tears: the per-step strain check is all
 * it pays), a plain sheet in a world with a tearable cloth elsewhere (must cost nothing), and the
 * cost of a step in which a sheet tears (split, constraint repair, tether rebuild next step).
 */
export function tearCost(): void {
  const rows: Record<string, string | number>[] = []
  for (const n of [32, 64]) {
    const scenes = (['plain', 'tearable elsewhere', 'tearable'] as const).map((m) => ({ m, ...sheet(n, m) }))
    for (const s of scenes) for (let f = 0; f < 60; f++) stepCloth(s.world, 1 / 60)
    const ms = new Map<string, number>()
    for (let round = 0; round < 3; round++) {
      for (const s of scenes) {
        const t = timeIt(() => stepCloth(s.world, 1 / 60), 60, 5)
        ms.set(s.m, Math.min(ms.get(s.m) ?? Infinity, t))
      }
    }
    const base = ms.get('plain')!
    for (const s of scenes) {
      resetClothStats(s.world)
      stepCloth(s.world, 1 / 60)
      const checks = getClothStats(s.world).strainChecks
      const t = ms.get(s.m)!
      rows.push({
        sheet: `${n}×${n}`,
        cloth: s.m,
        'ms per step': fmt(t, 3),
        'ratio to plain': fmt(t / base, 3),
        'strain checks per step': checks,
        'ns per edge': s.m === 'tearable' ? fmt(((t - base) * 1e6) / checks, 2) : '-',
      })
    }
  }
  table('Tearing: detection cost on a hanging sheet that does not tear (4 substeps, min of 3 rounds)', rows)

  // steps with tears: a 32×32 sheet pulled apart by its side pins
  const world = installClothPlugin(createWorld(), { sleep: false })
  const n = 32
  const cloth = createCloth(world, { width: 1, height: 1, resolution: n, position: [0, 2, 0], substeps: 4 })
  const [left, right] = pinSidesToBars(world, cloth, n)
  makeTearable(world, cloth, { maxTearsPerStep: 4 })
  let worst = 0, tearSteps = 0, quiet = 0, quietSteps = 0
  for (let f = 0; f < 120; f++) {
    const d = f * 0.004
    setTransform(world, left, [-d, 0, 0])
    setTransform(world, right, [d, 0, 0])
    const before = getClothStats(world).tears
    const t0 = cpuMs()
    stepCloth(world, 1 / 60)
    const t = cpuMs() - t0
    if (getClothStats(world).tears > before) {
      worst = Math.max(worst, t)
      tearSteps++
    } else if (f > 10) {
      quiet += t
      quietSteps++
    }
  }
  const rows2 = [{
    sheet: '32×32 pulled apart',
    tears: getClothStats(world).tears,
    'steps with tears': tearSteps,
    'slowest tearing step, ms': fmt(worst, 3),
    'mean step without tears, ms': fmt(quiet / Math.max(1, quietSteps), 3),
  }]
  table('Tearing: steps in which the sheet tears (the tether rebuild runs at the next step)', rows2)
  saveJson('tearing', { detection: rows, tearing: rows2 })
}
