import { addEntity, createWorld } from 'bitecs'
import {
  addPlaneCollider,
  addSphereCollider,
  createCloth,
  createWindZone,
  getClothMesh,
  getClothStretch,
  getClothTearCount,
  installClothPlugin,
  makeTearable,
  pinParticle,
  setTransform,
  stepCloth,
} from '../../src/index'
import { fmt, saveJson, table } from './harness'

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
    const chain = createCloth(world, { ...q, material: 'chainmail', width: 0.06, height: 1.2, resolution: [2, 30], position: [-0.85, 2.55, 0] })
    pinParticle(world, chain, 0)
    pinParticle(world, chain, 1)
    for (let i = 0; i < 120; i++) stepCloth(world, 1 / 60)
    const steps = 600
    let mean = 0, max = 0, ms = 0
    for (let i = 0; i < steps; i++) {
      const t0 = performance.now()
      stepCloth(world, 1 / 60)
      ms += performance.now() - t0
      const a = getClothStretch(world, patch), b = getClothStretch(world, chain)
      mean += (a.mean + b.mean) / 2 / steps
      max += Math.max(a.max, b.max) / steps
    }
    const plural = (n: number, w: string) => `${n} ${w}${n === 1 ? '' : 's'}`
    rows.push({ setting: `${plural(substeps, 'substep')} × ${plural(iterations, 'iteration')}`, 'mean stretch %': fmt(100 * mean, 2), 'max stretch %': fmt(100 * max, 1), 'ms/step': fmt(ms / steps, 3) })
  }
  return rows
}

/**
 * The demo's curtain scene without a browser: four balls thrown in turn at the points the Throw
 * button aims at, 1.5 s apart. After each: tears so far, triangles still connected to a hook, and
 * the pieces that came free (triangle counts).
 */
function curtainThrows(): Record<string, string | number>[] {
  const world = installClothPlugin(createWorld(), { sleep: false })
  const ground = addEntity(world as never)
  setTransform(world, ground, [0, 0, 0])
  addPlaneCollider(world, ground)
  const cols = 36, rows = 30
  const curtain = createCloth(world, { width: 2, height: 1.8, resolution: [cols, rows], position: [0, 2.3, 0], substeps: 8, iterations: 1, tethers: false })
  const hooks: number[] = []
  for (let c = 0; c < cols; c += 2) hooks.push(c)
  hooks.push(cols - 1)
  for (const h of hooks) pinParticle(world, curtain, h)
  makeTearable(world, curtain, { strain: 0.12, maxTearsPerStep: 32, hysteresis: 1 })
  for (let i = 0; i < 48; i++) stepCloth(world, 1 / 60)
  const out: Record<string, string | number>[] = []
  const radius = 0.22, speed = 9, g = 9.81
  for (const [k, [x, y]] of [[-0.1, 1.05], [0.45, 1.35], [-0.5, 1.5], [0.2, 0.85]].entries()) {
    const p = [x + 0.6, 0.9, 3.2]
    const t = Math.hypot(x - p[0], y - p[1], -p[2]) / speed
    const v = [(x - p[0]) / t, (y - p[1]) / t + 0.5 * g * t, -p[2] / t]
    const ball = addEntity(world as never)
    setTransform(world, ball, p)
    addSphereCollider(world, ball, { radius, friction: 0 })
    let ms = 0
    for (let f = 0; f < 90; f++) {
      v[1] -= g / 60
      for (let j = 0; j < 3; j++) p[j] += v[j] / 60
      if (p[1] < radius) {
        p[1] = radius
        v[1] = -0.4 * v[1]
      }
      setTransform(world, ball, p)
      const t0 = performance.now()
      stepCloth(world, 1 / 60)
      ms = Math.max(ms, performance.now() - t0)
    }
    // connected pieces of the triangle mesh (union-find over triangle corners)
    const m = getClothMesh(world, curtain)
    const parent = Int32Array.from({ length: m.vertexCount }, (_, i) => i)
    const find = (i: number): number => {
      while (parent[i] !== i) i = parent[i] = parent[parent[i]]
      return i
    }
    for (let tri = 0; tri < m.triangleCount; tri++) {
      const a = find(m.indices[3 * tri])
      parent[find(m.indices[3 * tri + 1])] = a
      parent[find(m.indices[3 * tri + 2])] = a
    }
    const hooked = new Set(hooks.map(find))
    let attached = 0
    const free = new Map<number, number>()
    for (let tri = 0; tri < m.triangleCount; tri++) {
      const r = find(m.indices[3 * tri])
      if (hooked.has(r)) attached++
      else free.set(r, (free.get(r) ?? 0) + 1)
    }
    const sizes = [...free.values()].sort((a, b) => b - a)
    out.push({
      throw: k + 1,
      tears: getClothTearCount(world, curtain),
      'triangles on hooks': attached,
      'free pieces ≥ 20 triangles': sizes.filter((s) => s >= 20).join(' ') || '-',
      'smaller shreds': sizes.filter((s) => s < 20).length,
      'slowest step ms': fmt(ms, 1),
    })
  }
  return out
}

/** `npm run bench -- demo`: the numbers behind the demo's accuracy and curtain scenes. */
export function demoScenes(): void {
  const sides = accuracySides()
  table('Accuracy scene: patch + chain in a breeze (stretch averaged over 10 s)', sides)
  const throws = curtainThrows()
  table('Curtain scene: four throws (cotton, tear strain 12 %, tethers off)', throws)
  saveJson('demo', { sides, throws })
}
