import { createWorld } from 'bitecs'
import {
  createCloth,
  createWindZone,
  getClothStretch,
  installClothPlugin,
  pinParticle,
  stepCloth,
  type TearableOptions,
} from '../../src/index'
import { cpuMs, fmt, saveJson, table } from './harness'
import { CURTAIN_TEARING, curtainScene } from '../tearing/curtain'

/**
 * The demo's accuracy scene without a browser: its cotton patch (20×20, compression-only
 * diagonals, top row pinned) and chain-mail chain (2×30) in the 0.8 m/s breeze, at 1 substep ×
 * 1 iteration, 1 × 12 and 12 × 1: stretch averaged over 10 s after 2 s of settling (mean of the
 * two objects' mean stretch, larger of their max, as the scene's labels show it) and ms per step.
 */
function accuracySides(): Record<string, string | number>[] {
  const rows: Record<string, string | number>[] = []
  for (const [substeps, iterations] of [[1, 1], [1, 12], [12, 1]]) {
    const world = installClothPlugin(createWorld(), { sleep: false })
    createWindZone(world, { direction: [0.3, 0, -1], strength: 0.8, turbulence: 0.35, turbulenceScale: 20, turbulencePeriod: 1.5, seed: 3 })
    const q = { substeps, iterations, tethers: false }
    const patch = createCloth(world, { ...q, width: 1, height: 1, resolution: 20, position: [0, 2.55, 0], shear: 'compression' })
    for (let c = 0; c < 20; c++) pinParticle(world, patch, c)
    const chain = createCloth(world, {
      ...q,
      material: 'chainmail',
      width: 0.06,
      height: 1.2,
      resolution: [2, 30],
      position: [-0.85, 2.55, 0],
    })
    pinParticle(world, chain, 0)
    pinParticle(world, chain, 1)
    for (let i = 0; i < 120; i++) stepCloth(world, 1 / 60)
    const steps = 600
    let mean = 0, max = 0, ms = 0
    for (let i = 0; i < steps; i++) {
      const t0 = cpuMs()
      stepCloth(world, 1 / 60)
      ms += cpuMs() - t0
      const a = getClothStretch(world, patch), b = getClothStretch(world, chain)
      mean += (a.mean + b.mean) / 2 / steps
      max += Math.max(a.max, b.max) / steps
    }
    const plural = (n: number, w: string) => `${n} ${w}${n === 1 ? '' : 's'}`
    rows.push({
      setting: `${plural(substeps, 'substep')} × ${plural(iterations, 'iteration')}`,
      'mean stretch (%)': fmt(100 * mean, 2),
      'max stretch (%)': fmt(100 * max, 1),
      'ms per step': fmt(ms / steps, 3),
    })
  }
  return rows
}

/**
 * The demo's curtain scene without a browser (tests/tearing/curtain.ts): twelve balls thrown in
 * turn, 1.5 s apart, each at the next aim or at the intact cloth nearest to it. After each: tears,
 * the share of the curtain still hanging, the pieces that came free (triangles), the smallest piece
 * of the mesh, the throw's openings (new torn edges, grouped by connection) and the slowest step.
 */
function curtainThrows(tearing: TearableOptions): Record<string, string | number>[] {
  const scene = curtainScene(tearing)
  const total = 35 * 29 * 2
  const out: Record<string, string | number>[] = []
  for (let k = 0; k < 12; k++) {
    const r = scene.throwBall()
    out.push({
      throw: k + 1,
      tears: r.tears,
      'hanging %': fmt((100 * r.hanging) / total, 0),
      'free pieces (triangles)': r.fallen.join(' ') || '-',
      'smallest piece': r.smallest,
      'openings (torn edges)': r.openings.join(' ') || '-',
      'slowest step, ms': fmt(r.slowest, 1),
    })
  }
  return out
}

/** `npm run bench -- demo`: the numbers behind the demo's accuracy and curtain scenes. */
export function demoScenes(): void {
  const sides = accuracySides()
  table('Accuracy scene: patch + chain in a breeze (stretch averaged over 10 s)', sides)
  const throws = curtainThrows(CURTAIN_TEARING)
  table('Curtain scene: twelve throws (cotton, tear strain 25 %, hysteresis 1, tethers off)', throws)
  const brittle = curtainThrows({ strain: 0.12, maxTearsPerStep: 32, hysteresis: 1 })
  table("The same with the demo's settings before crack tearing (tear strain 12 %)", brittle)
  saveJson('demo', { sides, throws, brittle })
}
