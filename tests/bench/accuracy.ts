import { addEntity, createWorld } from 'bitecs'
import { quat } from 'gl-matrix'
import { existsSync, mkdirSync, readFileSync, writeFileSync } from 'node:fs'
import { join } from 'node:path'
import {
  createCloth,
  getClothState,
  getClothStretch,
  installClothPlugin,
  pinParticle,
  pinRow,
  setTransform,
  stepCloth,
} from '../../src/index'
import { cpuMs, fmt, table } from './harness'
import { paretoFront, scatterPanels, type Series } from './svg'

/**
 * What accuracy costs in time: sweeps substeps × iterations (1-32 each, at most 64 sweeps per
 * step), tethers on/off and XPBD/PBD over three scenes, and records ms per step against error.
 * Writes tests/bench/results/accuracy.json and accuracy.svg and rewrites the quality-tier table in
 * README.md. Run with `npm run bench:accuracy`.
 */

const N = 24 // particles per side: a cape-sized cloth
const RESULTS = join('tests', 'bench', 'results')

type SceneId = 'corners' | 'row' | 'cape'
interface Config {
  substeps: number
  iterations: number
  tethers: boolean
  solver: 'xpbd' | 'pbd'
}
interface Row extends Config {
  scene: SceneId
  msPerStep: number
  meanStretch: number
  maxStretch: number
  /** Static scenes: |lowest point − reference|, m. Cape: RMS particle distance to the reference run over time, m. */
  shapeError: number
  /** Static scenes: (E_end − E_start)/(M·g·L) of an undamped sheet swinging for 10 s. */
  energyDrift: number | null
}

function build(scene: SceneId, c: Config, swing = false) {
  const world = installClothPlugin(createWorld(), { sleep: false })
  const hero = addEntity(world)
  setTransform(world, hero, [0, 1.6, 0])
  const lying = swing ? quat.setAxisAngle(quat.create(), [1, 0, 0], -Math.PI / 2) : quat.create()
  const cloth = createCloth(world, {
    width: scene === 'cape' ? 0.6 : 1,
    height: 1,
    resolution: N,
    position: scene === 'cape' ? [0, 1.5, -0.15] : [0, 2, 0],
    rotation: lying,
    material: 'cotton',
    substeps: c.substeps,
    iterations: c.iterations,
    tethers: c.tethers,
    solver: c.solver,
    ...(swing ? { damping: 0, stretchDamping: 0 } : {}),
  })
  if (scene === 'cape') pinRow(world, cloth, 0, hero)
  else if (scene === 'row') pinRow(world, cloth, 0)
  else {
    pinParticle(world, cloth, 0)
    pinParticle(world, cloth, N - 1)
  }
  return { world, cloth, hero }
}

/** Deterministic run around a 3 m circle, reaching 4 m/s in 0.5 s, with a 5 cm running bob. */
function moveHero(world: object, hero: number, frame: number, q: quat, state: { angle: number }): void {
  const t = frame / 60
  const speed = Math.min(1, t / 0.5)
  state.angle += (4 / 3) * speed / 60
  quat.setAxisAngle(q, [0, 1, 0], -state.angle)
  setTransform(world, hero, [3 * Math.cos(state.angle), 1.6 + 0.05 * speed * Math.sin(t * 12), 3 * Math.sin(state.angle)], q)
}

interface Trace {
  ms: number
  mean: number
  max: number
  lowest: number
  samples: Float64Array[]
}

/** Runs a scene for `steps` frames of 1/60 s; the cape samples its particles every 10 frames. */
function runScene(scene: SceneId, c: Config, steps: number): Trace {
  const { world, cloth, hero } = build(scene, c)
  const cs = getClothState(world, cloth)
  const q = quat.create()
  const motion = { angle: 0 }
  let time = 0, meanSum = 0, meanCount = 0, max = 0
  const samples: Float64Array[] = []
  for (let f = 0; f < steps; f++) {
    if (scene === 'cape') moveHero(world, hero, f, q, motion)
    const t0 = cpuMs()
    stepCloth(world, 1 / 60)
    time += cpuMs() - t0
    if (scene === 'cape') {
      if (f >= 60) {
        const s = getClothStretch(world, cloth)
        meanSum += s.mean
        meanCount++
        if (s.max > max) max = s.max
      }
      if (f % 10 === 9) samples.push(Float64Array.from(cs.pos.subarray(0, 3 * cs.count)))
    }
  }
  let lowest = Infinity
  for (let i = 0; i < cs.count; i++) lowest = Math.min(lowest, cs.pos[3 * i + 1])
  if (scene !== 'cape') {
    const s = getClothStretch(world, cloth)
    meanSum = s.mean
    meanCount = 1
    max = s.max
  }
  return { ms: time / steps, mean: meanSum / meanCount, max, lowest, samples }
}

/** Energy change of an undamped sheet released horizontal, after 10 s, per M·g·L. */
function energyDrift(scene: SceneId, c: Config): number {
  const { world, cloth } = build(scene, c, true)
  const cs = getClothState(world, cloth)
  const energy = () => {
    let e = 0
    for (let i = 0; i < cs.count; i++) {
      if (cs.invMass[i] === 0) continue
      const m = 1 / cs.baseInvMass[i]
      const v2 = cs.vel[3 * i] ** 2 + cs.vel[3 * i + 1] ** 2 + cs.vel[3 * i + 2] ** 2
      e += m * (0.5 * v2 + 9.81 * cs.pos[3 * i + 1])
    }
    return e
  }
  let M = 0
  for (let i = 0; i < cs.count; i++) M += 1 / cs.baseInvMass[i]
  const e0 = energy()
  for (let f = 0; f < 600; f++) stepCloth(world, 1 / 60)
  return (energy() - e0) / (M * 9.81 * 1)
}

function rmsDistance(a: Float64Array[], b: Float64Array[]): number {
  let sum = 0, n = 0
  for (let k = 0; k < Math.min(a.length, b.length); k++) {
    for (let i = 0; i < a[k].length; i += 3) {
      sum += (a[k][i] - b[k][i]) ** 2 + (a[k][i + 1] - b[k][i + 1]) ** 2 + (a[k][i + 2] - b[k][i + 2]) ** 2
      n++
    }
  }
  return Math.sqrt(sum / Math.max(1, n))
}

const LEVELS = [1, 2, 4, 8, 16, 32]
const MAX_SWEEPS = 64
const REFERENCE: Config = { substeps: 64, iterations: 4, tethers: true, solver: 'xpbd' }

export function accuracy(only?: SceneId[]): void {
  const rows: Row[] = []
  const scenes: SceneId[] = only ?? ['corners', 'row', 'cape']
  for (const scene of scenes) {
    const staticSteps = 300
    const ref = runScene(scene, REFERENCE, staticSteps)
    for (const solver of ['xpbd', 'pbd'] as const) {
      for (const tethers of [true, false]) {
        for (const substeps of LEVELS) {
          for (const iterations of LEVELS) {
            if (substeps * iterations > MAX_SWEEPS) continue
            const c: Config = { substeps, iterations, tethers, solver }
            const r = runScene(scene, c, staticSteps)
            rows.push({
              scene,
              ...c,
              msPerStep: r.ms,
              meanStretch: r.mean,
              maxStretch: r.max,
              shapeError: scene === 'cape' ? rmsDistance(r.samples, ref.samples) : Math.abs(r.lowest - ref.lowest),
              energyDrift: scene === 'cape' ? null : energyDrift(scene, c),
            })
          }
        }
      }
    }
  }
  mkdirSync(RESULTS, { recursive: true })
  writeFileSync(join(RESULTS, 'accuracy.json'), JSON.stringify({ cloth: `${N}x${N} cotton`, reference: REFERENCE, rows }, null, 1))
  writeFileSync(join(RESULTS, 'accuracy.svg'), chart(rows))
  const tiers = qualityTiers(rows)
  table('Recommended settings (cape on a running character, 24×24)', tiers.rows)
  updateReadme(tiers.markdown)
  summary(rows)
}

const SERIES: { name: string; solver: 'xpbd' | 'pbd'; tethers: boolean; color: string; marker: Series['marker'] }[] = [
  { name: 'XPBD + tethers', solver: 'xpbd', tethers: true, color: '#d9480f', marker: 'circle' },
  { name: 'XPBD', solver: 'xpbd', tethers: false, color: '#1c7ed6', marker: 'square' },
  { name: 'PBD + tethers', solver: 'pbd', tethers: true, color: '#2b8a3e', marker: 'triangle' },
  { name: 'PBD', solver: 'pbd', tethers: false, color: '#862e9c', marker: 'diamond' },
]

function chart(rows: Row[]): string {
  const titles: Record<SceneId, string> = {
    corners: 'Sheet hanging from two corners',
    row: 'Sheet hanging from its top row',
    cape: 'Cape on a running character',
  }
  const panels = (['corners', 'row', 'cape'] as SceneId[]).map((scene) => {
    const own = rows.filter((r) => r.scene === scene)
    const pts = own.map((r) => ({ x: r.msPerStep, y: Math.max(r.maxStretch * 100, 1e-4) }))
    return {
      title: titles[scene],
      xLabel: 'time per step (ms, one core)',
      yLabel: scene === 'cape' ? 'max edge stretch while running (%)' : 'max edge stretch at rest (%)',
      series: SERIES.map((s) => ({
        name: s.name,
        color: s.color,
        marker: s.marker,
        points: own.filter((r) => r.solver === s.solver && r.tethers === s.tethers).map((r) => ({
          x: r.msPerStep,
          y: Math.max(r.maxStretch * 100, 1e-4),
        })),
      })),
      front: paretoFront(pts),
    }
  })
  return scatterPanels(
    `What accuracy costs in time: ${N}×${N} cotton, substeps × iterations from 1 to 32 (≤ 64 sweeps per step)`,
    panels,
    'Each point is one setting (substeps × iterations); lower left is better. Regenerate: npm run bench:accuracy',
  )
}

/** Cheapest setting on the cape's front under each stretch budget. */
function qualityTiers(rows: Row[]) {
  const cape = rows.filter((r) => r.scene === 'cape')
  const tiers = [
    { tier: 'Background cloth', budget: 0.25 },
    { tier: 'Standard', budget: 0.1 },
    { tier: 'Close-up', budget: 0.05 },
    { tier: 'Hero cape', budget: 0.02 },
  ]
  const out: Record<string, string | number>[] = []
  const md = [
    '| Tier | Max stretch while running | Setting | ms per step (24×24) | Mean stretch | Shape error vs reference |',
    '|---|---|---|---|---|---|',
  ]
  for (const t of tiers) {
    const ok = cape.filter((r) => r.maxStretch <= t.budget).sort((a, b) => a.msPerStep - b.msPerStep)
    const best = ok[0]
    if (!best) {
      md.push(`| ${t.tier} | ≤ ${t.budget * 100} % | none within 64 sweeps | | | |`)
      continue
    }
    const setting = `${best.substeps} substeps × ${best.iterations} iteration${
      best.iterations > 1 ? 's' : ''
    }, ${best.solver.toUpperCase()}${best.tethers ? ' + tethers' : ''}`
    out.push({
      tier: t.tier,
      budget: `≤ ${t.budget * 100} %`,
      setting,
      'ms per step': fmt(best.msPerStep, 3),
      'max stretch (%)': fmt(best.maxStretch * 100, 2),
    })
    md.push(
      `| ${t.tier} | ≤ ${t.budget * 100} % | ${setting} | ${fmt(best.msPerStep, 3)} | ${fmt(best.meanStretch * 100, 3)} % | ${
        fmt(best.shapeError * 100, 1)
      } cm |`,
    )
  }
  return { rows: out, markdown: md.join('\n') }
}

function summary(rows: Row[]): void {
  const pick = (scene: SceneId, s: number, i: number, tethers: boolean, solver: 'xpbd' | 'pbd') =>
    rows.find((r) => r.scene === scene && r.substeps === s && r.iterations === i && r.tethers === tethers && r.solver === solver)
  const lines: Record<string, string | number>[] = []
  for (const scene of ['corners', 'row', 'cape'] as SceneId[]) {
    for (const [s, i] of [[1, 8], [8, 1], [2, 4], [4, 2], [16, 1], [32, 2]] as const) {
      for (const tethers of [true, false]) {
        const x = pick(scene, s, i, tethers, 'xpbd'), p = pick(scene, s, i, tethers, 'pbd')
        if (!x || !p) continue
        lines.push({
          scene,
          setting: `${s}×${i}${tethers ? ' +tethers' : ''}`,
          'ms per step': fmt(x.msPerStep, 3),
          'XPBD max stretch (%)': fmt(x.maxStretch * 100, 2),
          'PBD max stretch (%)': fmt(p.maxStretch * 100, 2),
          'XPBD shape error (cm)': fmt(x.shapeError * 100, 2),
          'energy drift': x.energyDrift === null ? 'n/a' : fmt(x.energyDrift, 3),
        })
      }
    }
  }
  table('Selected settings (full sweep in tests/bench/results/accuracy.json)', lines)
}

/** Replaces the table between the accuracy markers in README.md. */
function updateReadme(markdown: string): void {
  const path = 'README.md'
  if (!existsSync(path)) return
  const text = readFileSync(path, 'utf8')
  const start = '<!-- accuracy-table:start -->', end = '<!-- accuracy-table:end -->'
  const a = text.indexOf(start), b = text.indexOf(end)
  if (a < 0 || b < a) return
  writeFileSync(path, text.slice(0, a + start.length) + '\n' + markdown + '\n' + text.slice(b))
}
