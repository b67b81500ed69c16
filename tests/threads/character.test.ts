// Character cloth in the threaded step: the same bytes as the single-threaded step (positions,
// velocities, stats, events, snapshots) with the workers' copies checked against the main
// thread's every step (verify mode), and snapshots that restore across modes.
import { describe, expect, it } from 'vitest'
import { disposeClothWorld, getClothState, getClothStats } from '../../src/index'
import { getClothWorld } from '../../src/world/access'
import { buildCharacterRun } from './characterScene'

const FRAMES = 400

describe('threaded step with character cloth', () => {
  it(
    'capes with inertia shares, painted motion constraints, a skinned sleeve, teleports, a guard reset, options changed between steps: same bytes and snapshots with 0, 1 and 2 workers',
    { timeout: 300_000 },
    () => {
      const runs = [buildCharacterRun(0), buildCharacterRun(1), buildCharacterRun(2)]
      try {
        for (let f = 0; f < FRAMES; f++) {
          for (const r of runs) r.frame(f)
          const h0 = runs[0].hash()
          expect(runs[1].hash(), `frame ${f}, 1 worker`).toBe(h0)
          expect(runs[2].hash(), `frame ${f}, 2 workers`).toBe(h0)
          if (f % 20 === 19) {
            const s0 = runs[0].snapshots()
            expect(runs[1].snapshots(), `frame ${f}, 1 worker`).toBe(s0)
            expect(runs[2].snapshots(), `frame ${f}, 2 workers`).toBe(s0)
          }
        }
        const stats = getClothStats(runs[0].world)
        expect(stats.guardResets).toBeGreaterThan(0)
        expect(stats.teleports).toBeGreaterThan(2)
        expect(stats.tears).toBeGreaterThan(0)
        expect(runs[0].events.some((e) => e.startsWith('reset'))).toBe(true)
        // tears split held particles (on the workers): the split-off particles are held too
        const held = runs.map((r) => getClothState(r.world, r.curtain).character!.heldCount)
        expect(held[0]).toBeGreaterThan(9) // (9 held at the start)
        expect(held).toEqual([held[0], held[0], held[0]])
        expect(runs[1].events).toEqual(runs[0].events)
        expect(runs[2].events).toEqual(runs[0].events)
        expect(getClothWorld(runs[2].world).threads!.step).toBeGreaterThan(FRAMES - 20)
      } finally {
        for (const r of runs) disposeClothWorld(r.world)
      }
    },
  )

  it(
    'snapshots of character cloths saved in one mode restore in the other and replay byte for byte (character state, skin and drive restored onto cloths that lost or regained them)',
    { timeout: 300_000 },
    () => {
      const one = buildCharacterRun(0), two = buildCharacterRun(2), ref = buildCharacterRun(0)
      const runs = [one, two, ref]
      // (the stats count on: compare the cloths only)
      const cloths = (h: string) => h.slice(0, h.lastIndexOf(' '))
      let f = 0
      try {
        // saved at 150 (every cape has character state), restored at 265 (the third cape has none, the
        // sleeve was unskinned and skinned again); saved at 268 (none), restored at 290 (it has again)
        for (const [from, to] of [[150, 265], [268, 290]]) {
          for (; f < from; f++) for (const r of runs) r.frame(f)
          const fromOne = one.save(), fromTwo = two.save(), fromRef = ref.save()
          const saved = ref.hash()
          for (; f < to; f++) for (const r of runs) r.frame(f)
          const reached = ref.hash()
          expect(cloths(reached)).not.toBe(cloths(saved))
          one.restore(fromTwo)
          two.restore(fromOne)
          ref.restore(fromRef)
          expect(cloths(one.hash())).toBe(cloths(saved))
          expect(cloths(two.hash())).toBe(cloths(saved))
          for (f = from; f < to; f++) {
            for (const r of runs) r.frame(f)
            expect(cloths(two.hash()), `frame ${f}`).toBe(cloths(ref.hash()))
            expect(cloths(one.hash()), `frame ${f}`).toBe(cloths(ref.hash()))
          }
          expect(cloths(ref.hash())).toBe(cloths(reached))
        }
      } finally {
        for (const r of runs) disposeClothWorld(r.world)
      }
    },
  )
})
