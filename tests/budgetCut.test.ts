import { addEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  getClothLod,
  getClothState,
  getClothStretch,
  restoreClothState,
  saveClothState,
  setClothBudget,
  setClothSleep,
  setClothSkinning,
  setTransform,
  stepCloth,
} from '../src/index'
import { CAL, budgetCape } from './fixtures/budgetCape'

/**
 * A 7×11 wool cape on a hero walking +z at 3 m/s away from a camera at the origin; at frame 1000 the
 * camera cuts to the hero (2 m beside it). Returns the cape's worst stretch and largest one-step
 * velocity change (any particle) from the cut on, and its stretch before.
 */
function cameraCut(character: boolean, cull: number, farStepEvery: 1 | 2 | 4) {
  const { world, hero, viewer, cape } = budgetCape(character, [0, 2, 0])
  setClothBudget(world, { viewer, near: 5, far: 26, cull, farStepEvery, calibration: CAL, adapt: false })
  const c = getClothState(world, cape)
  const prev = new Float64Array(3 * c.count)
  let before = 0, after = 0, dvBefore = 0, dvAfter = 0, frozenAtCut = false
  for (let f = 0; f < 1200; f++) {
    setTransform(world, hero, [0, 0, (3 * f) / 60])
    if (f === 1000) {
      frozenAtCut = getClothLod(world, cape).frozen
      setTransform(world, viewer, [2, 2, (3 * f) / 60]) // the camera cuts to the hero
    }
    stepCloth(world, 1 / 60)
    const s = getClothStretch(world, cape).max
    let dv = 0
    for (let i = 0; i < 3 * c.count; i += 3) {
      dv = Math.max(dv, Math.hypot(c.vel[i] - prev[i], c.vel[i + 1] - prev[i + 1], c.vel[i + 2] - prev[i + 2]))
    }
    prev.set(c.vel.subarray(0, 3 * c.count))
    if (f > 600 && f < 1000) {
      before = Math.max(before, s)
      dvBefore = Math.max(dvBefore, dv)
    }
    if (f >= 1000) {
      after = Math.max(after, s)
      dvAfter = Math.max(dvAfter, dv)
    }
  }
  return { before, after, dvBefore, dvAfter, frozenAtCut }
}

describe('a camera cut to a far cape', () => {
  it('farStepEvery 1: a frozen character cape thawed by the cut does not pop (0.01 m/s, 0.1 %)', () => {
    const r = cameraCut(true, 42, 1)
    expect(r.frozenAtCut).toBe(true)
    expect(r.dvAfter).toBeLessThan(0.1)
    expect(r.after).toBeLessThan(0.02)
  })

  // The first step back at full rate covers the steps the cloth sat out: before, it was one fixed
  // step long and took two steps' motion of the pins (a 3.0 m/s velocity change at a 3 m/s walk),
  // and a thaw's step at farStepEvery 4 was four steps long for one step's motion (67 % stretch).
  it.each([2, 4] as const)('farStepEvery %i: a far cape back at full rate does not pop', (every) => {
    const r = cameraCut(false, 1e6, every)
    expect(r.frozenAtCut).toBe(false)
    expect(r.dvBefore).toBeLessThan(0.1)
    expect(r.dvAfter).toBeLessThan(0.1)
    expect(r.after).toBeLessThan(Math.max(0.02, 1.2 * r.before))
  })

  // A far cloth chosen to freeze while it sat steps out takes its step first, and freezes where its
  // pins and frame are: frozen with the lag, the thaw undid it at once (7.9 m/s, 71 % at 4 with
  // the step fix above alone; 3.1 m/s, 67 % before either). Measured now: 0.13 m/s, 0.4 %.
  it.each([2, 4] as const)('farStepEvery %i: a frozen character cape thawed by the cut does not pop', (every) => {
    const r = cameraCut(true, 42, every)
    expect(r.frozenAtCut).toBe(true)
    expect(r.dvAfter).toBeLessThan(0.25)
    expect(r.after).toBeLessThan(0.02)
  })
})

/**
 * A cape on a hero walking +z at 3 m/s, the camera 60 m off (farStepEvery 4: the cape steps every
 * 4th step at 1 substep); `k` steps after the cape's last step (k = 0..3) the budget is removed, and
 * the cape steps at once at its own 4 substeps. Returns the largest one-step velocity change of any
 * particle and the worst stretch over the 10 frames after, and in frames 200–300 (steady, far).
 */
function budgetRemoved(k: number, character: boolean) {
  const { world, hero, viewer, cape } = budgetCape(character, [60, 2, 0])
  setClothBudget(world, { viewer, near: 5, far: 26, farStepEvery: 4, calibration: CAL, adapt: false })
  const c = getClothState(world, cape)
  const prev = new Float64Array(3 * c.count)
  let dvBefore = 0, stBefore = 0, dvAfter = 0, stAfter = 0
  for (let f = 0; f < 330; f++) {
    setTransform(world, hero, [0, 0, (3 * f) / 60])
    setTransform(world, viewer, [60, 2, (3 * f) / 60])
    if (f === 300 + k) setClothBudget(world, null)
    stepCloth(world, 1 / 60)
    let dv = 0
    for (let i = 0; i < 3 * c.count; i += 3) {
      dv = Math.max(dv, Math.hypot(c.vel[i] - prev[i], c.vel[i + 1] - prev[i + 1], c.vel[i + 2] - prev[i + 2]))
    }
    prev.set(c.vel.subarray(0, 3 * c.count))
    const s = getClothStretch(world, cape).max
    if (f >= 200 && f < 300) {
      dvBefore = Math.max(dvBefore, dv)
      stBefore = Math.max(stBefore, s)
    }
    if (f >= 300 + k && f < 310 + k) {
      dvAfter = Math.max(dvAfter, dv)
      stAfter = Math.max(stAfter, s)
    }
  }
  expect(getClothLod(world, cape).stepEvery).toBe(1)
  return { dvBefore, stBefore, dvAfter, stAfter }
}

describe('the budget removed while a far cape sits steps out', () => {
  // Its step then runs 4 substeps over the steps it sat out: the pins moved over this fixed step
  // only, taking the waited motion at the first substep, and the pinned row left at 1/(waited + 1)
  // of its speed (1.5, 2.0, 3.1 m/s at 1, 2, 3 waited; found by a hunt). They now move over the span.
  it.each([0, 1, 2, 3])('plain cape, %i steps after its last: no pop', (k) => {
    const r = budgetRemoved(k, false)
    expect(r.dvAfter).toBeLessThan(Math.max(0.2, 1.5 * r.dvBefore))
    expect(r.stAfter).toBeLessThan(Math.max(0.05, 1.5 * r.stBefore))
  })

  it.each([1, 3])('character cape, %i steps after its last: no pop', (k) => {
    const r = budgetRemoved(k, true)
    expect(r.dvAfter).toBeLessThan(Math.max(0.2, 1.5 * r.dvBefore))
    expect(r.stAfter).toBeLessThan(Math.max(0.05, 1.5 * r.stBefore))
  })
})

describe('a character cape frozen while its character turns 90°, thawed walking the new way', () => {
  /**
   * The hero walks +z at 3 m/s; the camera goes 100 m off at frame 120 (cull 42: the cape freezes),
   * the hero turns 90° over frames 150–170 and walks +x; the camera is back at 240. Returns the worst
   * gap between a particle's velocity and the hero's over the 5 steps after the thaw, and over 30
   * steps before the freeze.
   */
  function turnWhileFrozen(farStepEvery: 1 | 4) {
    const { world, hero, viewer, cape } = budgetCape(true, [2, 2, 0])
    setClothBudget(world, { viewer, near: 5, far: 26, cull: 42, farStepEvery, calibration: CAL, adapt: false, interval: 1 })
    const c = getClothState(world, cape)
    let x = 0, z = 0, heading = 0, before = 0, after = 0, thawAt = -1, frozen = false
    for (let f = 0; f < 300; f++) {
      if (f >= 150 && f < 170) heading += Math.PI / 40
      x += (3 / 60) * Math.sin(heading)
      z += (3 / 60) * Math.cos(heading)
      setTransform(world, hero, [x, 0, z], [0, Math.sin(heading / 2), 0, Math.cos(heading / 2)])
      setTransform(world, viewer, f >= 120 && f < 240 ? [x + 100, 2, z] : [x + 2, 2, z])
      stepCloth(world, 1 / 60)
      const lod = getClothLod(world, cape)
      if (lod.frozen) frozen = true
      if (frozen && !lod.frozen && thawAt < 0) thawAt = f
      const vx = 3 * Math.sin(heading), vz = 3 * Math.cos(heading)
      let gap = 0
      for (let i = 0; i < 3 * c.count; i += 3) gap = Math.max(gap, Math.hypot(c.vel[i] - vx, c.vel[i + 1], c.vel[i + 2] - vz))
      if (f >= 90 && f < 120) before = Math.max(before, gap)
      if (thawAt >= 0 && f < thawAt + 5) after = Math.max(after, gap)
    }
    expect(thawAt).toBeGreaterThanOrEqual(240)
    return { before, after }
  }

  // The thaw turned the cloth's velocities with the carry, but not the frame's last velocities, so
  // its first step felt the turn as the frame's whole change of velocity (2.4 m/s off the hero's;
  // found by a hunt). Measured now: 0.10 m/s, 0.11 before the freeze.
  it.each([1, 4] as const)('farStepEvery %i: it thaws moving with the hero', (every) => {
    const r = turnWhileFrozen(every)
    expect(r.after).toBeLessThan(Math.max(0.3, 3 * r.before))
  })
})

describe('a snapshot saved under a budget, restored after the budget was removed', () => {
  // The level it held was restored with it, and with no budget nothing set it back: the cape ran
  // 1 substep every 4th step for good (found by a hunt).
  it('the cape runs its own quality again', () => {
    const { world, hero, viewer, cape } = budgetCape(false, [60, 2, 0])
    setClothBudget(world, { viewer, near: 5, far: 26, farStepEvery: 4, calibration: CAL, adapt: false })
    for (let f = 0; f < 100; f++) {
      setTransform(world, hero, [0, 0, (3 * f) / 60])
      stepCloth(world, 1 / 60)
    }
    expect(getClothLod(world, cape)).toMatchObject({ substeps: 1, stepEvery: 4 })
    const saved = saveClothState(world, cape)
    setClothBudget(world, null)
    restoreClothState(world, cape, saved)
    for (let f = 100; f < 130; f++) {
      setTransform(world, hero, [0, 0, (3 * f) / 60])
      stepCloth(world, 1 / 60)
    }
    expect(getClothLod(world, cape)).toMatchObject({ substeps: 4, stepEvery: 1 })
    expect(getClothStretch(world, cape).max).toBeLessThan(0.05)
  })
})

describe('a skinned character cape frozen while its back bone leans or sways, thawed', () => {
  /**
   * A 7×11 wool cape pinned to a hero walking at 3 m/s, skinned to the hero (collar) and a back bone
   * (hem: 90 %), painted max distance and a backstop; culled over frames 60–180 while the back bone
   * moves by `swing`. Returns the largest one-step velocity change of any particle and the worst
   * stretch from frame 150 on.
   */
  function swingWhileFrozen(budget: boolean, swing: (f: number) => number) {
    const { world, hero, viewer, cape } = budgetCape(true, [2, 2, 0])
    const bone = addEntity(world)
    setTransform(world, bone, [0, 1.2, 0])
    const joints: number[] = [], weights: number[] = []
    for (let i = 0; i < 77; i++) {
      const u = Math.floor(i / 7) / 10
      joints.push(0, 1, 0, 0)
      weights.push(1 - u, u, 0, 0)
    }
    setClothSkinning(world, cape, { bones: [hero, bone], joints, weights })
    if (budget) setClothBudget(world, { viewer, near: 5, far: 26, cull: 42, calibration: CAL, adapt: false, interval: 1 })
    const c = getClothState(world, cape)
    const prev = new Float64Array(3 * c.count)
    let dv = 0, stretch = 0, frozen = false
    for (let f = 0; f < 260; f++) {
      const a = swing(f), z = (3 * f) / 60
      setTransform(world, hero, [0, 0, z])
      setTransform(world, bone, [0, 1.2, z], [Math.sin(a / 2), 0, 0, Math.cos(a / 2)])
      setTransform(world, viewer, f >= 60 && f < 180 ? [100, 2, z] : [2, 2, z])
      stepCloth(world, 1 / 60)
      frozen ||= getClothLod(world, cape).frozen
      let d = 0
      for (let i = 0; i < 3 * c.count; i += 3)
        d = Math.max(d, Math.hypot(c.vel[i] - prev[i], c.vel[i + 1] - prev[i + 1], c.vel[i + 2] - prev[i + 2]))
      prev.set(c.vel.subarray(0, 3 * c.count))
      if (f >= 150) {
        dv = Math.max(dv, d)
        stretch = Math.max(stretch, getClothStretch(world, cape).max)
      }
    }
    expect(frozen).toBe(budget)
    return { dv, stretch }
  }

  // The thaw carries the cape rigidly by its pins' target, while its skinned reference moved on:
  // the backstop then pushed it out of the body in one substep. Corrections in the step after a gap
  // are placements, without velocity (found by a hunt). Measured: a lean toward the body 4.5 m/s and
  // 8.8 % (24.4 m/s and 33 % before; 0.20 m/s and 5.2 % never frozen). Known limit: the rest.
  it('a back bone leaning 0.5 rad toward the body while frozen', () => {
    const lean = (f: number) => (f < 100 ? 0 : f < 130 ? (-0.5 * (f - 100)) / 30 : -0.5)
    const r = swingWhileFrozen(true, lean)
    expect(r.dv).toBeLessThan(8)
    expect(r.stretch).toBeLessThan(0.15)
  })

  // Measured: 1.1–3.2 m/s over 8 phases of the sway, 1.4–1.7 never frozen (10–19 m/s before).
  it('a back bone swaying 0.3 rad at 5 rad/s: within 2.5× of the cape never frozen, at any phase', () => {
    for (let k = 0; k < 8; k += 2) {
      const sway = (f: number) => 0.3 * Math.sin((5 * f) / 60 + (k * Math.PI) / 4)
      const r = swingWhileFrozen(true, sway), base = swingWhileFrozen(false, sway)
      expect(r.dv).toBeLessThan(2.5 * Math.max(base.dv, 0.3))
    }
  })
})

/**
 * A plain cape far-stepped every 4th step, its hero standing then walking off at 3 m/s (or walking
 * then stopping) on the very frame the budget goes, when the cape has waited `k` steps: the
 * largest one-step velocity change, edge stretch and backward speed over the next 5 steps.
 */
function startOrStop(budget: boolean, k: number, mode: 'start' | 'stop') {
  const { world, hero, viewer, cape } = budgetCape(false, [60, 2, 0])
  if (budget) setClothBudget(world, { viewer, near: 5, far: 26, farStepEvery: 4, calibration: CAL, adapt: false })
  setClothSleep(world, cape, false)
  const c = getClothState(world, cape)
  const before = new Float64Array(3 * c.count)
  const S = 300 + k
  let back = 0, dv = 0, stretch = 0, z = 0
  for (let f = 0; f < S + 5; f++) {
    if (mode === 'start' ? f >= S : f < S) z += 3 / 60
    setTransform(world, hero, [0, 0, z])
    if (f === S && budget) {
      expect(c.budget.waited).toBe(k)
      setClothBudget(world, null)
    }
    stepCloth(world, 1 / 60)
    if (f >= S) {
      for (let i = 0; i < c.count; i++) {
        if (c.invMass[i] === 0) continue
        const j = 3 * i
        dv = Math.max(dv, Math.hypot(c.vel[j] - before[j], c.vel[j + 1] - before[j + 1], c.vel[j + 2] - before[j + 2]))
        back = Math.min(back, c.vel[j + 2])
      }
      stretch = Math.max(stretch, getClothStretch(world, cape).max)
    }
    before.set(c.vel.subarray(0, 3 * c.count))
  }
  return { back, dv, stretch }
}

describe('a far cape whose hero starts or stops walking on the frame the budget goes', () => {
  // its first step spans the steps it waited; its pins go straight from where they stand to their
  // targets at the step's end. Extrapolated back along the last fixed step's motion, they went
  // where the hero never was: a start after 3 waited steps gave 3.06 m/s and 12.4 % stretch (never
  // budgeted: 1.46 m/s, 6.9 %) and particles moving backwards at 0.54 m/s (found by a hunt)
  for (const mode of ['start', 'stop'] as const) {
    for (const k of [2, 3]) {
      it(`${mode}, after ${k} waited steps: within 1.3× the velocity change and 1.1× the stretch of the cape never budgeted, nothing moving back`, () => {
        const b = startOrStop(true, k, mode), n = startOrStop(false, k, mode)
        expect(b.dv).toBeLessThan(1.3 * n.dv)
        expect(b.stretch).toBeLessThan(1.1 * n.stretch)
        expect(b.back).toBeGreaterThan(n.back - 0.05)
      })
    }
  }
})

describe('setClothBudget with the options the budget runs', () => {
  // It reset the allocation countdown and timing: a game setting its options again (each frame, or
  // after a restore) ran 2.19 m off the run without the call from 9 frames later (found by a hunt)
  it('changes nothing: the run equals the run without the call, byte for byte (options changed do change it)', () => {
    const run = (again: 'none' | 'same' | 'changed') => {
      const { world, hero, viewer, cape } = budgetCape(false, [3, 2, 0])
      const opts = { viewer, near: 5, far: 26, farStepEvery: 4 as const, calibration: CAL, adapt: false }
      setClothBudget(world, opts)
      const c = getClothState(world, cape)
      const out: number[][] = []
      for (let f = 0; f < 200; f++) {
        setTransform(world, hero, [0, 0, (3 * f) / 60])
        setTransform(world, viewer, [3 + 40 * (0.5 - 0.5 * Math.cos(f / 40)), 2, 0]) // walks away and back
        if (f === 81 && again !== 'none') setClothBudget(world, { ...opts, calibration: { ...CAL }, near: again === 'same' ? 5 : 6 })
        stepCloth(world, 1 / 60)
        out.push(Array.from(c.pos))
      }
      return out
    }
    const none = run('none')
    expect(run('same')).toEqual(none)
    expect(run('changed')).not.toEqual(none)
  })
})
