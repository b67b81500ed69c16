// Character cloth in the threaded step: the same bytes as the single-threaded step (positions,
// velocities, stats, events, snapshots) with the workers' copies checked against the main
// thread's every step (verify mode), and snapshots that restore across modes.
import { addEntity, removeEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  beginClothStep,
  createCloth,
  disposeClothWorld,
  endClothStep,
  getClothState,
  getClothStats,
  pinRow,
  setClothInertia,
  setClothMotionConstraints,
  setClothSkinning,
  setTransform,
} from '../../src/index'
import { hashBytes } from '../helpers'
import { getClothWorld } from '../../src/world/access'
import { buildCharacterRun } from './characterScene'
import { threadedWorld } from './scene'

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

  it('a frame or bone entity removed between beginClothStep and endClothStep is let go of as without workers (the cloths keep its last pose)', () => {
    const scene = (threads: number) => {
      const world = threadedWorld(threads)
      const hero = addEntity(world), torso = addEntity(world), arm = addEntity(world)
      const place = (f: number) => {
        const a = 0.05 * f
        setTransform(world, hero, [Math.cos(a), 1.6, Math.sin(a)], [0, Math.sin(-a / 2), 0, Math.cos(-a / 2)])
        if (f > 30) return // (removed)
        setTransform(world, torso, [Math.cos(a), 1.3, Math.sin(a)], [0, Math.sin(-a / 2), 0, Math.cos(-a / 2)])
        setTransform(world, arm, [Math.cos(a), 1.3, Math.sin(a) + 0.3], [Math.sin(a), 0, 0, Math.cos(a)])
      }
      place(0)
      const capes = [0, 1].map((k) => {
        const cape = createCloth(world, { width: 0.5, height: 0.6, resolution: [6, 7], position: [1 + 0.6 * k, 1.5, -0.15] })
        pinRow(world, cape, 0, hero)
        return cape
      })
      setClothInertia(world, capes[0], { frame: torso, linear: 0.5, angular: 0.5, centrifugal: 0.5 })
      setClothMotionConstraints(world, capes[0], { maxDistance: 0.2, every: 2 })
      const n = getClothState(world, capes[1]).count
      setClothSkinning(world, capes[1], {
        bones: [torso, arm],
        joints: new Array(4 * n).fill(0).map((_, k) => (k % 4 === 1 ? 1 : 0)),
        weights: Array.from({ length: 4 * n }, (_, k) => (k % 4 === 0 ? 0.5 : k % 4 === 1 ? 0.5 : 0)),
      })
      setClothMotionConstraints(world, capes[1], { maxDistance: 0.1, drive: 0.3 })
      const hash = () => capes.map((e) => hashBytes(getClothState(world, e).pos) + hashBytes(getClothState(world, e).vel)).join('')
      return { world, torso, arm, capes, place, hash }
    }
    const runs = [scene(0), scene(2)]
    try {
      for (let f = 1; f < 90; f++) {
        for (const s of runs) {
          s.place(f)
          beginClothStep(s.world, 1 / 60)
          if (f === 30) {
            removeEntity(s.world, s.torso) // the first cape's frame, a bone of the second
            removeEntity(s.world, s.arm)
          }
          endClothStep(s.world)
        }
        expect(runs[1].hash(), `frame ${f}`).toBe(runs[0].hash())
      }
      for (const s of runs) {
        const ch = getClothState(s.world, s.capes[0]).character!
        expect([ch.frame, ch.frameSlot]).toEqual([0, -1])
        expect(Array.from(getClothState(s.world, s.capes[1]).character!.skin!.slots)).toEqual([-1, -1])
      }
    } finally {
      for (const s of runs) disposeClothWorld(s.world)
    }
  })
})
