import { createWorld } from 'bitecs'
import { createCloth, createWindZone, getClothStats, installClothPlugin, pinParticle, resetClothStats, stepCloth } from '../../src/index'
import { fmt, saveJson, table, timeIt } from './harness'

/** A flag of n×(2n/3) particles pinned along its hoist, optionally in a wind zone. */
function flag(n: number, wind: 'none' | 'steady' | 'turbulent' | 'elsewhere') {
  const world = installClothPlugin(createWorld(), { sleep: false })
  const rows = Math.round((2 * n) / 3)
  const cloth = createCloth(world, { width: 1.5, height: 1, resolution: [n, rows], position: [0.75, 3, 0], material: 'nylon', substeps: 8 })
  for (let r = 0; r < rows; r++) pinParticle(world, cloth, r * n)
  if (wind === 'steady') createWindZone(world, { direction: [0.3, 0, 1], strength: 8 })
  if (wind === 'turbulent') createWindZone(world, { direction: [0.3, 0, 1], strength: 8, turbulence: 0.4 })
  if (wind === 'elsewhere')
    createWindZone(world, { shape: 'sphere', position: [20, 0, 0], size: 3, direction: [1, 0, 0], strength: 8, turbulence: 0.4 })
  return { world, cloth }
}

/**
 * Aerodynamics cost: ms per step of a flag without wind, in a steady and in a turbulent global
 * zone, and with a zone elsewhere in the world (which must cost nothing); the wind's share per
 * triangle and substep from the difference. Ratios are from one run, interleaved.
 */
export function windCost(): void {
  const rows: Record<string, string | number>[] = []
  for (const n of [24, 48]) {
    const scenes = (['none', 'elsewhere', 'steady', 'turbulent'] as const).map((w) => ({ w, ...flag(n, w) }))
    for (const s of scenes) for (let f = 0; f < 120; f++) stepCloth(s.world, 1 / 60)
    const ms = new Map<string, number>()
    for (let round = 0; round < 3; round++) {
      for (const s of scenes) {
        const t = timeIt(() => stepCloth(s.world, 1 / 60), 100, 10)
        ms.set(s.w, Math.min(ms.get(s.w) ?? Infinity, t))
      }
    }
    for (const s of scenes) {
      resetClothStats(s.world)
      stepCloth(s.world, 1 / 60)
    }
    const tris = getClothStats(scenes[2].world).windTriangles // per step (8 substeps)
    const base = ms.get('none')!
    for (const s of scenes) {
      const t = ms.get(s.w)!
      rows.push({
        flag: `${n}×${Math.round((2 * n) / 3)}`,
        wind: s.w,
        'ms per step': fmt(t, 3),
        'ratio to no wind': fmt(t / base, 2),
        'wind triangles per step': getClothStats(s.world).windTriangles,
        'ns per triangle and substep': s.w === 'steady' || s.w === 'turbulent' ? fmt(((t - base) * 1e6) / tris, 1) : '-',
      })
    }
  }
  table('Wind: a nylon flag, 8 substeps (min of 3 interleaved rounds of 100 steps)', rows)
  saveJson('wind', rows)
}
