import { createWorld } from 'bitecs'
import { checkClothHealth } from '../../src/kernels/guard'
import {
  clothFixedStep,
  clothGuard,
  createCloth,
  getClothState,
  installClothPlugin,
  pinParticle,
  restoreClothState,
  saveClothState,
  stepCloth,
  type ClothGuardOptions,
} from '../../src/index'
import { fmt, saveJson, table, timeIt } from './harness'

/** A 1 m sheet of n×n particles hanging from its two top corners, warmed up. */
function sheet(n: number, substeps: number, guard: boolean | ClothGuardOptions) {
  const world = installClothPlugin(createWorld(), { guard, sleep: false })
  const cloth = createCloth(world, { width: 1, height: 1, resolution: n, substeps, material: 'cotton' })
  pinParticle(world, cloth, 0)
  pinParticle(world, cloth, n - 1)
  for (let f = 0; f < 100; f++) stepCloth(world, 1 / 60)
  return { world, cloth }
}

/**
 * What the explosion guard costs: the step with the guard on and off, and the guard phase alone
 * (health check plus copy of the pose) as a share of the step. Runs alternate so both see the same
 * machine load.
 */
export function guardCost(): void {
  const rows: Record<string, string | number>[] = []
  for (const [n, substeps] of [[32, 8], [64, 2], [64, 8], [128, 2], [128, 8]]) {
    const on = sheet(n, substeps, true)
    const off = sheet(n, substeps, false)
    const sparse = sheet(n, substeps, { snapshotInterval: 10 })
    const c = getClothState(on.world, on.cloth)
    const g = c.guard.params
    let tOn = 0, tOff = 0, tPhase = 0, tSparse = 0, tCheck = 0, tCopy = 0
    let sink = 0
    for (let rep = 0; rep < 5; rep++) {
      tOn += timeIt(() => clothFixedStep(on.world), 40, 5)
      tOff += timeIt(() => clothFixedStep(off.world), 40, 5)
      tPhase += timeIt(() => clothGuard(on.world), 400, 20)
      tSparse += timeIt(() => clothGuard(sparse.world), 400, 20)
      tCheck += timeIt(
        () => {
          sink += checkClothHealth(c.pos, c.vel, c.invMass, c.count, g)
        },
        400,
        20,
      )
      tCopy += timeIt(() => c.guard.safe.set(c.pos), 400, 20)
    }
    if (sink !== 0) throw new Error('a healthy sheet failed its check')
    rows.push({
      sheet: `${n}×${n}`,
      substeps,
      'step, guard off (ms)': fmt(tOff / 5, 3),
      'step, guard on (ms)': fmt(tOn / 5, 3),
      'guard phase (µs)': fmt((tPhase / 5) * 1000, 1),
      'share of step': `${fmt((tPhase / tOn) * 100, 1)} %`,
      'check (µs)': fmt((tCheck / 5) * 1000, 1),
      'pose copy (µs)': fmt((tCopy / 5) * 1000, 1),
      'phase, copy every 10 steps (µs)': fmt((tSparse / 5) * 1000, 1),
    })
  }
  table('Explosion guard: cost per step (check: the health kernel; pose copy: the last-good copy)', rows)
  saveJson('stability-guard', rows)
}

/** Saving into a reused snapshot, restoring, and a guard reset, against the step they sit next to. */
export function snapshotCost(): void {
  const rows: Record<string, string | number>[] = []
  for (const n of [32, 64, 128]) {
    const { world, cloth } = sheet(n, 8, true)
    const snap = saveClothState(world, cloth)
    const step = timeIt(() => clothFixedStep(world), 100, 10)
    const save = timeIt(() => saveClothState(world, cloth, snap), 400, 50)
    const restore = timeIt(() => restoreClothState(world, cloth, snap), 400, 50)
    const c = getClothState(world, cloth)
    // a reset every step: the fault is written before each step, the guard restores after it
    const reset = timeIt(
      () => {
        c.pos[3 * (n + 1)] = NaN
        clothFixedStep(world)
      },
      100,
      10,
    )
    rows.push({
      sheet: `${n}×${n}, 8 substeps`,
      'step (ms)': fmt(step, 3),
      'save into a snapshot (µs)': fmt(save * 1000, 1),
      'restore (µs)': fmt(restore * 1000, 1),
      'step with a guard reset (ms)': fmt(reset, 3),
    })
  }
  table('Snapshots and resets', rows)
  saveJson('stability-snapshots', rows)
}
