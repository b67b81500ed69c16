// The threaded step gives the same bytes as the single-threaded one: every feature, 600 frames,
// threads 0, 1 and 2, with the workers' copies checked against the main thread's every step.
import { describe, expect, it } from 'vitest'
import { disposeClothWorld, getClothStats } from '../../src/index'
import { getClothWorld } from '../../src/world/access'
import { buildRun } from './scene'

describe('threaded step: bitwise identical to the single-threaded one', () => {
  it(
    '600 frames of capes on running characters, colliders, wind, a tearing curtain, self-collision, sleep, a budget and a guard reset: same bytes with 0, 1, 2 and 3 workers (other partitions) after every frame',
    { timeout: 300_000 },
    () => {
      const runs = [buildRun(0), buildRun(1), buildRun(2), buildRun(3)]
      let handed = 0
      try {
        for (let f = 0; f < 600; f++) {
          for (const r of runs) r.frame(f)
          const h0 = runs[0].hash()
          expect(runs[1].hash(), `frame ${f}, 1 worker`).toBe(h0)
          expect(runs[2].hash(), `frame ${f}, 2 workers`).toBe(h0)
          expect(runs[3].hash(), `frame ${f}, 3 workers`).toBe(h0)
        }
        handed = getClothWorld(runs[2].world).threads!.step
        // the scene did what it is for
        const stats = getClothStats(runs[0].world)
        expect(stats.tears).toBeGreaterThan(3)
        expect(stats.guardResets).toBeGreaterThan(0)
        expect(stats.wakes).toBeGreaterThan(0)
        expect(stats.sleepingSteps).toBeGreaterThan(50)
        expect(stats.selfCollisionTests).toBeGreaterThan(0)
        expect(stats.lodSkippedSteps + stats.windTriangles).toBeGreaterThan(0)
        expect(runs[0].events.some((e) => e.startsWith('reset'))).toBe(true)
        expect(runs[1].events).toEqual(runs[0].events)
        expect(runs[2].events).toEqual(runs[0].events)
        expect(runs[3].events).toEqual(runs[0].events)
      } finally {
        for (const r of runs) disposeClothWorld(r.world)
      }
      // every step went to the workers (none ran on the main thread)
      expect(handed).toBeGreaterThan(550)
    },
  )
})
