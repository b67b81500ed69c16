// Snapshots under quality targets and level of detail: save, step on (with other inputs), restore,
// step again, and the run is byte for byte that of a twin world that never restored: the budget's
// allocation countdown, its timing, the quality controller's counters and wanted substeps, each
// cloth's level, its every-n-th-step phase and its freeze are part of the state (rollback netcode
// needs byte identity with every feature on).
import { addEntity, createWorld } from 'bitecs'
import { CAL, budgetCape } from '../fixtures/budgetCape'
import { describe, expect, it } from 'vitest'
import {
  createCloth,
  getClothBudgetStats,
  getClothLod,
  getClothState,
  getClothStretch,
  installClothPlugin,
  pinRow,
  restoreClothState,
  saveClothState,
  setClothBudget,
  setClothInertia,
  setClothMotionConstraints,
  setClothQualityTarget,
  setClothVisible,
  setTransform,
  stepCloth,
  type ClothBudgetOptions,
  type ClothSnapshot,
} from '../../src/index'
import { CHEAP_CALIBRATION, hashBytes } from '../helpers'

interface Setup {
  budget?: ClothBudgetOptions
  /** Quality target on the first cape. */
  target?: boolean
  /** Toggle the capes' visibility with the frames. */
  visibility?: boolean
  /** Character cloth on every cape: inertia in its character's frame, painted max distance (every 2nd substep on one), a backstop, a drive on another. */
  character?: boolean
}

/** Three capes on three running characters, a viewer walking away and back. */
function build(setup: Setup) {
  const world = installClothPlugin(createWorld(), { sleep: false })
  const heroes: number[] = [], capes: number[] = []
  for (let k = 0; k < 3; k++) {
    const hero = addEntity(world)
    setTransform(world, hero, [4 * k, 1.6, 0])
    const cape = createCloth(world, {
      width: 0.5,
      height: 0.8,
      resolution: [6, 9],
      position: [4 * k, 1.5, -0.15],
      substeps: 8,
      iterations: 2,
    })
    pinRow(world, cape, 0, hero)
    if (setup.character) {
      setClothInertia(world, cape, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5, teleport: { angle: Math.PI / 2 } })
      const maxDistance = Array.from({ length: 54 }, (_, i) => (i < 6 ? 0 : 0.05 * Math.floor(i / 6)))
      setClothMotionConstraints(world, cape, {
        maxDistance,
        backstop: { distance: 0.02, radius: 0.4 },
        every: k === 1 ? 2 : 1,
        drive: k === 2 ? 0.05 : 0,
      })
    }
    heroes.push(hero)
    capes.push(cape)
  }
  const viewer = addEntity(world)
  setTransform(world, viewer, [0, 2, 5])
  if (setup.budget) setClothBudget(world, { viewer, calibration: CHEAP_CALIBRATION, adapt: false, ...setup.budget })
  if (setup.target) setClothQualityTarget(world, capes[0], { maxStretch: 0.004, calibration: CHEAP_CALIBRATION })
  return { world, heroes, capes, viewer }
}
type Scene = ReturnType<typeof build>

/** The host's inputs of frame f (absolute: applying them again sets the same state). */
function inputs(s: Scene, setup: Setup, f: number, variant = 0): number {
  const t = f / 60 + 7 * variant
  for (let k = 0; k < 3; k++) {
    const a = 2 * t + k
    setTransform(s.world, s.heroes[k], [4 * k + Math.sin(a), 1.6, Math.cos(1.3 * a)], [0, Math.sin(a / 2), 0, Math.cos(a / 2)])
  }
  // the viewer walks away to 60 m and back, so the levels move through every rung
  setTransform(s.world, s.viewer, [0, 2, 5 + 60 * Math.abs(Math.sin(t / 4))])
  if (setup.visibility) setClothVisible(s.world, s.capes[2], Math.floor(f / 25 + variant) % 3 !== 2)
  return (0.7 + 0.6 * ((f * 7919) % 13) / 13) / 60
}

function hash(s: Scene): string {
  return s.capes
    .map((cl) => {
      const c = getClothState(s.world, cl)
      const n = 3 * c.count
      const lod = getClothLod(s.world, cl)
      return hashBytes(c.pos.subarray(0, n)) + hashBytes(c.vel.subarray(0, n)) + JSON.stringify(lod)
    })
    .join('|') + JSON.stringify(getClothBudgetStats(s.world))
}

/** Runs `at` frames, saves, runs 37 frames of other inputs, restores, runs on; compares with a twin that never restored. */
function rollback(setup: Setup, at: number, after = 90) {
  const a = build(setup), b = build(setup)
  for (let f = 0; f < at; f++) {
    stepCloth(a.world, inputs(a, setup, f))
    stepCloth(b.world, inputs(b, setup, f))
  }
  const saved: ClothSnapshot[] = a.capes.map((cl) => saveClothState(a.world, cl))
  for (let f = 0; f < 37; f++) stepCloth(a.world, inputs(a, setup, at + f, 1))
  a.capes.forEach((cl, k) => restoreClothState(a.world, cl, saved[k]))
  if (at > 0) inputs(a, setup, at - 1) // the host restores its own state too (Transforms, visibility)
  const lods = new Set<string>()
  for (let f = at; f < at + after; f++) {
    stepCloth(a.world, inputs(a, setup, f))
    stepCloth(b.world, inputs(b, setup, f))
    expect(hash(a), `frame ${f} (saved at ${at})`).toBe(hash(b))
    for (const cl of b.capes)
      lods.add(JSON.stringify([getClothLod(b.world, cl).substeps, getClothLod(b.world, cl).stepEvery, getClothLod(b.world, cl).frozen]))
  }
  return lods
}

describe('snapshots under quality targets and level of detail: a rollback replays byte for byte', () => {
  const saves = [1, 13, 29, 44, 60]

  it('a quality target (maxStretch): the controller’s counters and wanted substeps are restored', () => {
    const setup: Setup = { target: true }
    const levels = new Set<string>()
    for (const at of [1, 29, 44]) for (const l of rollback(setup, at, 60)) levels.add(l)
    expect(levels.size).toBeGreaterThan(1) // the target moved the substeps
  })

  for (const farStepEvery of [2, 4] as const) {
    it(`a budget with farStepEvery ${farStepEvery}: the allocation countdown and the every-n-th-step phase are restored`, () => {
      const setup: Setup = { budget: { near: 6, far: 25, farStepEvery, interval: 7 } }
      const levels = new Set<string>()
      for (const at of saves) for (const l of rollback(setup, at, 150)) levels.add(l)
      expect([...levels].some((l) => JSON.parse(l)[1] === farStepEvery)).toBe(true)
    })
  }

  it('a time budget (msPerFrame, fixed cost numbers) with a quality target and frozen invisible cloths', () => {
    const setup: Setup = { budget: { near: 6, far: 40, farStepEvery: 2, msPerFrame: 0.02, interval: 5 }, target: true, visibility: true }
    const levels = new Set<string>()
    for (const at of saves) for (const l of rollback(setup, at, 120)) levels.add(l)
    expect([...levels].some((l) => JSON.parse(l)[2] === true)).toBe(true) // some cape froze
  })

  it('character cloth (inertia in the frame, painted limits, every 2nd substep, a drive) under a budget with farStepEvery 2 and frozen invisible cloths', () => {
    const setup: Setup = { budget: { near: 6, far: 30, farStepEvery: 2, interval: 7 }, visibility: true, character: true }
    const levels = new Set<string>()
    for (const at of saves) for (const l of rollback(setup, at, 120)) levels.add(l)
    expect([...levels].some((l) => JSON.parse(l)[1] === 2)).toBe(true)
    expect(levels.size).toBeGreaterThan(2)
  })

  it('saved between a far cloth’s catch-up step and its freeze (farStepEvery 4, cull 40)', () => {
    const setup: Setup = { budget: { near: 6, far: 25, cull: 40, farStepEvery: 4, interval: 7 } }
    const s = build(setup)
    const ats: number[] = []
    for (let f = 0; f < 900 && ats.length < 2; f++) {
      stepCloth(s.world, inputs(s, setup, f))
      if (s.capes.some((cl) => getClothState(s.world, cl).budget.freezing)) ats.push(f + 1)
    }
    expect(ats.length).toBeGreaterThan(0) // (the scene reaches the window)
    for (const at of ats) rollback(setup, at, 60)
  })

  it('a snapshot saved without the budget section (older versions) still restores', () => {
    const s = build({ budget: { interval: 5 } })
    for (let f = 0; f < 20; f++) stepCloth(s.world, inputs(s, {}, f))
    const saved = saveClothState(s.world, s.capes[0]) as ClothSnapshot & { budget?: Float64Array }
    delete saved.budget
    for (let f = 0; f < 20; f++) stepCloth(s.world, inputs(s, {}, f))
    restoreClothState(s.world, s.capes[0], saved)
    stepCloth(s.world, 1 / 60)
  })

  for (const character of [false, true]) {
    it(`a ${character ? 'character ' : ''}cape's snapshot saved while frozen, restored once the budget is gone, thaws onto its pins as removing the budget thaws it`, () => {
      // frozen from frame 60 (the viewer 100 m away) while its hero walks on at 3 m/s; saved at
      // frame 150 and restored right after setClothBudget(null) (a game saved under a budget, loaded
      // without one). Restored still frozen with no budget to thaw it, it started where it froze,
      // its pins metres ahead: 3.8 m/s and 10 % (plain), 111 m/s and 463 % (character)
      const run = (restore: boolean) => {
        const { world, hero, viewer, cape } = budgetCape(character, [2, 2, 0])
        setClothBudget(world, { viewer, near: 5, far: 26, cull: 42, calibration: CAL, adapt: false, interval: 1 })
        const c = getClothState(world, cape)
        let snap: ClothSnapshot | null = null
        const before = new Float64Array(3 * c.count)
        let dv = 0, stretch = 0
        for (let f = 0; f < 200; f++) {
          setTransform(world, hero, [0, 0, (3 * f) / 60])
          setTransform(world, viewer, [f >= 60 ? 100 : 2, 2, (3 * f) / 60])
          if (f === 150) {
            expect(getClothLod(world, cape).frozen).toBe(true)
            snap = saveClothState(world, cape)
            setClothBudget(world, null)
            if (restore) restoreClothState(world, cape, snap!)
          }
          stepCloth(world, 1 / 60)
          if (f >= 150) {
            for (let i = 0; i < c.count; i++) {
              if (c.invMass[i] === 0) continue
              const j = 3 * i
              dv = Math.max(dv, Math.hypot(c.vel[j] - before[j], c.vel[j + 1] - before[j + 1], c.vel[j + 2] - before[j + 2]))
            }
            stretch = Math.max(stretch, getClothStretch(world, cape).max)
          }
          before.set(c.vel.subarray(0, 3 * c.count))
        }
        return { dv, stretch }
      }
      const removed = run(false), restored = run(true)
      expect(removed.dv).toBeLessThan(1)
      expect(restored.dv).toBeLessThan(removed.dv + 0.05)
      expect(restored.stretch).toBeLessThan(removed.stretch + 0.005)
    })
  }
})
