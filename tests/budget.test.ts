import { addEntity, removeEntity } from 'bitecs'
import { describe, expect, it, onTestFinished, vi } from 'vitest'
import {
  ClothError,
  SUBSTEP_LADDER,
  createCloth,
  createWindZone,
  enableSelfCollision,
  getClothBudgetStats,
  getClothLod,
  getClothReference,
  getClothState,
  getClothStats,
  getClothStretch,
  pinParticle,
  pinRow,
  resetClothStats,
  setClothBudget,
  setClothInertia,
  setClothMotionConstraints,
  setClothQuality,
  setClothQualityTarget,
  setClothSkinning,
  setClothVisible,
  setTransform,
  stepCloth,
} from '../src/index'
import { CALIBRATION, hashBytes, makeWorld } from './helpers'

const DT = 1 / 60

/** A 1 m sheet of n×n hanging from its two top corners at x (or pinned along the top row to `anchor`). */
function sheet(world: object, x: number, n = 12, options: { substeps?: number; iterations?: number; anchor?: number } = {}) {
  const cloth = createCloth(world, {
    width: 1,
    height: 1,
    resolution: n,
    position: [x, 2, 0],
    substeps: options.substeps,
    iterations: options.iterations,
  })
  if (options.anchor !== undefined) pinRow(world, cloth, 0, options.anchor)
  else {
    pinParticle(world, cloth, 0)
    pinParticle(world, cloth, n - 1)
  }
  return cloth
}

/** A cape pinned to a character 5 m from the viewer, beyond `far`: a far cloth stepping every `every`-th step. */
function farCape(every: 2 | 4) {
  const world = makeWorld({ sleep: false })
  const viewer = addEntity(world)
  setTransform(world, viewer, [0, 0, 0])
  const hero = addEntity(world)
  setTransform(world, hero, [5, 1.6, 0])
  const cape = createCloth(world, { width: 0.6, height: 0.9, resolution: 10, position: [5, 1.6, -0.15] })
  pinRow(world, cape, 0, hero)
  setClothBudget(world, { viewer, near: 1, far: 2, farStepEvery: every, adapt: false, interval: 1, calibration: CALIBRATION })
  return { world, hero, cape, c: getClothState(world, cape) }
}

function steps(world: object, n: number): void {
  for (let f = 0; f < n; f++) stepCloth(world, DT)
}

describe('quality targets', () => {
  it('a stretch target raises the substeps until the stretch is under it, and lowers them when far under', () => {
    const world = makeWorld({ sleep: false })
    const loose = sheet(world, 0, 24, { substeps: 1 })
    steps(world, 120)
    const before = getClothStretch(world, loose).max
    expect(before).toBeGreaterThan(0.02) // one substep: the corners pull the sheet far out (2.9 %)
    setClothQualityTarget(world, loose, { maxStretch: 0.01 })
    steps(world, 240)
    const lod = getClothLod(world, loose)
    expect(lod.substeps).toBeGreaterThan(1)
    expect(SUBSTEP_LADDER).toContain(lod.substeps)
    expect(getClothStretch(world, loose).max).toBeLessThan(0.01)

    const stiff = sheet(world, 3, 16, { substeps: 32 })
    setClothQualityTarget(world, stiff, { maxStretch: 0.05 })
    steps(world, 600)
    const down = getClothLod(world, stiff)
    expect(down.substeps).toBeLessThan(32)
    expect(getClothStretch(world, stiff).max).toBeLessThan(0.05)
  })

  it('stretch falls about as 1/substeps² (what the ladder and the cost model assume)', () => {
    const world = makeWorld({ sleep: false })
    const cloths = [1, 2, 4].map((s, k) => sheet(world, 3 * k, 24, { substeps: s }))
    steps(world, 120)
    const stretch = cloths.map((c) => getClothStretch(world, c).max)
    console.log(`24×24 sheet from two corners, worst edge at 1, 2, 4 substeps: ${stretch.map((x) => (100 * x).toFixed(2)).join(', ')} %`)
    // measured 2.93, 0.73 and 0.19 % (README): ×3.99 and ×3.93 a doubling, 1/substeps² giving ×4
    expect(stretch[0]).toBeGreaterThan(0.025)
    expect(stretch[0]).toBeLessThan(0.034)
    for (const k of [0, 1]) {
      expect(stretch[k] / stretch[k + 1]).toBeGreaterThan(3.4)
      expect(stretch[k] / stretch[k + 1]).toBeLessThan(4.6)
    }
  })

  it('a time target picks the most substeps the cost model allows; the bounds hold', () => {
    const world = makeWorld({ sleep: false })
    const cloth = sheet(world, 0, 16)
    setClothQualityTarget(world, cloth, { msPerStep: 0.1, calibration: CALIBRATION })
    steps(world, 2)
    const lod = getClothLod(world, cloth)
    expect(lod.predictedMs).toBeLessThanOrEqual(0.1)
    // the next rung up would not fit
    const next = SUBSTEP_LADDER[SUBSTEP_LADDER.indexOf(lod.substeps) + 1]
    expect(lod.predictedMs * (next / lod.substeps)).toBeGreaterThan(0.1)
    setClothQualityTarget(world, cloth, { msPerStep: 100, maxSubsteps: 6, calibration: CALIBRATION })
    steps(world, 16)
    expect(getClothLod(world, cloth).substeps).toBe(6)
    setClothQualityTarget(world, cloth, { msPerStep: 1e-6, minSubsteps: 2, calibration: CALIBRATION })
    steps(world, 16)
    expect(getClothLod(world, cloth).substeps).toBe(2)
    setClothQualityTarget(world, cloth, null)
    setClothQuality(world, cloth, { substeps: 5 })
    steps(world, 16)
    expect(getClothLod(world, cloth).substeps).toBe(5)
  })

  it('the cost model counts the aerodynamics of a cloth a wind zone reaches (a flag in wind had run 1.6–2.1× its prediction, 76 % over its time target)', () => {
    const lodIn = (wind: boolean, calibration = CALIBRATION) => {
      const world = makeWorld({ sleep: false })
      const cloth = sheet(world, 0, 16)
      if (wind) createWindZone(world, { direction: [0, 0, 1], strength: 8, turbulence: 0.3 })
      setClothQualityTarget(world, cloth, { msPerStep: 0.2, calibration })
      steps(world, 16)
      return { lod: getClothLod(world, cloth), triangles: getClothState(world, cloth).topology.triangleCount }
    }
    const still = lodIn(false), windy = lodIn(true)
    expect(windy.lod.substeps).toBeLessThan(still.lod.substeps)
    expect(windy.lod.predictedMs).toBeLessThanOrEqual(0.2)
    // the wind term itself: triangles × nsPerWindTriangle per substep (6 × nsPerProjection when not given)
    const explicit = lodIn(true, { ...CALIBRATION, nsPerWindTriangle: 0 })
    expect(explicit.lod.substeps).toBe(still.lod.substeps)
    const s = windy.lod.substeps
    const withoutWind = (still.lod.predictedMs / still.lod.substeps) * s
    expect(windy.lod.predictedMs - withoutWind).toBeCloseTo((s * windy.triangles * 6 * CALIBRATION.nsPerProjection) / 1e6, 9)
    expect(() => lodIn(true, { ...CALIBRATION, nsPerWindTriangle: -1 })).toThrow(/nsPerWindTriangle/)
  })

  it('bad targets are rejected at the API edge', () => {
    const world = makeWorld()
    const cloth = sheet(world, 0)
    expect(() => setClothQualityTarget(world, cloth, {})).toThrow(ClothError)
    expect(() => setClothQualityTarget(world, cloth, { maxStretch: -0.1 })).toThrow(/target\.maxStretch/)
    expect(() => setClothQualityTarget(world, cloth, { msPerStep: NaN })).toThrow(/target\.msPerStep/)
    expect(() => setClothQualityTarget(world, cloth, { maxStretch: 0.01, minSubsteps: 8, maxSubsteps: 4 })).toThrow(/target\.maxSubsteps/)
    expect(() => setClothQualityTarget(world, cloth, { msPerStep: 1, calibration: { ...CALIBRATION, nsPerProjection: 0 } })).toThrow(
      /nsPerProjection/,
    )
    expect(() => setClothQualityTarget(world, 12345, { maxStretch: 0.01 })).toThrow(ClothError)
  })
})

describe('world budget and level of detail', () => {
  /** Cloths at 2, 8, 20, 60 and 200 m from a viewer at the origin. */
  function row(options: Parameters<typeof setClothBudget>[1]) {
    const world = makeWorld({ sleep: false })
    const viewer = addEntity(world)
    setTransform(world, viewer, [0, 2, 0])
    const cloths = [2, 8, 20, 60, 200].map((x) => sheet(world, x, 10, { substeps: 8, iterations: 2 }))
    setClothBudget(world, { viewer, near: 5, far: 50, cull: 150, calibration: CALIBRATION, farStepEvery: 2, ...options })
    return { world, viewer, cloths }
  }

  it('near cloths keep their quality, farther ones run fewer substeps, the farthest step every other step, beyond the cull they freeze', () => {
    const { world, cloths } = row({})
    steps(world, 2)
    const lods = cloths.map((c) => getClothLod(world, c))
    expect(lods[0]).toMatchObject({ substeps: 8, iterations: 2, stepEvery: 1, frozen: false })
    expect(lods[1].substeps).toBeLessThan(8)
    expect(lods[1].substeps).toBeGreaterThanOrEqual(4) // about 8 × 5/8.5
    expect(lods[2].substeps).toBeLessThan(lods[1].substeps)
    expect(lods[3]).toMatchObject({ substeps: 1, iterations: 1, stepEvery: 2, frozen: false })
    expect(lods[4].frozen).toBe(true)
    for (const l of lods) expect(l).toMatchObject({ wantSubsteps: 8, wantIterations: 2 })
    // the work follows: the frozen cloth is not integrated, the far one every other step
    const n = getClothState(world, cloths[0]).count
    resetClothStats(world)
    steps(world, 10)
    const perStep = n * (8 + lods[1].substeps + lods[2].substeps) + (n * 1) / 2
    expect(getClothStats(world).particlesIntegrated).toBe(10 * perStep)
    expect(getClothStats(world).lodSkippedSteps).toBe(10 + 5) // the frozen one every step, the far one every other
  })

  it('a time budget lowers the farthest cloths first and fits the prediction under it', () => {
    const world = makeWorld({ sleep: false })
    const viewer = addEntity(world)
    setTransform(world, viewer, [0, 2, 0])
    const cloths = [1, 3, 5, 7, 9, 11, 13, 15].map((x) => sheet(world, x, 16, { substeps: 16 }))
    setClothBudget(world, { viewer, near: 4, far: 1000, calibration: CALIBRATION })
    steps(world, 2)
    const unlimited = cloths.reduce((s, c) => s + getClothLod(world, c).predictedMs, 0)
    const budget = unlimited / 4
    setClothBudget(world, { viewer, near: 4, far: 1000, calibration: CALIBRATION, msPerFrame: budget, adapt: false })
    steps(world, 2)
    const lods = cloths.map((c) => getClothLod(world, c))
    const total = lods.reduce((s, l) => s + l.predictedMs, 0)
    expect(total).toBeLessThanOrEqual(budget)
    expect(total).toBeGreaterThan(0.6 * budget) // and uses most of it
    for (let k = 1; k < lods.length; k++) {
      expect(lods[k].substeps / lods[k].stepEvery).toBeLessThanOrEqual(lods[k - 1].substeps / lods[k - 1].stepEvery)
    }
    expect(lods[0].substeps).toBeGreaterThan(lods[lods.length - 1].substeps / lods[lods.length - 1].stepEvery)
    // removing the budget gives every cloth its own quality back
    setClothBudget(world, null)
    for (const c of cloths) expect(getClothLod(world, c)).toMatchObject({ substeps: 16, stepEvery: 1, frozen: false })
  })

  it('a time budget corrects a wrong cost model by the measured time, and then fits the measured time', () => {
    const world = makeWorld({ sleep: false })
    // a clock that runs with the work done (20 ps per particle integration and per projection), so
    // the test sees the same measurements however loaded the machine is
    const stats = getClothStats(world)
    const clock = vi.spyOn(performance, 'now').mockImplementation(() =>
      (stats.particlesIntegrated + stats.distanceProjections + stats.lineProjections) * 2e-5
    )
    onTestFinished(() => clock.mockRestore())
    const cloths = [0, 2, 4, 6].map((x) => sheet(world, x, 16, { substeps: 16 }))
    // a model 100 times too cheap: everything seems to fit at first
    const cheap = { nsPerParticle: 0.2, nsPerProjection: 0.12, nsPerColliderTest: 0.05, nsPerClothSubstep: 5 }
    steps(world, 30)
    const t0 = performance.now()
    steps(world, 30)
    const full = (performance.now() - t0) / 30 // ms per step at 16 substeps
    setClothBudget(world, { msPerFrame: full / 3, calibration: cheap, interval: 5 })
    steps(world, 2)
    expect(getClothLod(world, cloths[0]).substeps).toBe(16) // the model says it fits
    steps(world, 200)
    const budget = getClothBudgetStats(world)
    expect(budget.correction).toBeGreaterThan(10)
    expect(budget.measuredMs).toBeGreaterThan(0)
    expect(budget.predictedMs).toBeLessThanOrEqual(full / 3 + 1e-9)
    expect(cloths.every((c) => getClothLod(world, c).substeps < 16)).toBe(true)
  })

  it('a self-colliding cloth is never stepped every other step, nor below 6 substeps (see tests/collision/selfCollisionBudget.test.ts)', () => {
    const { world, cloths } = row({})
    enableSelfCollision(world, cloths[3])
    steps(world, 16)
    expect(getClothLod(world, cloths[3])).toMatchObject({ substeps: 6, stepEvery: 1 })
  })

  it('changing level causes no pop: a cape on a running character, the viewer walking away and cutting back', () => {
    // the largest change of any particle's velocity in one step, beyond the first half second
    const run = (budget: boolean) => {
      const world = makeWorld({ sleep: false })
      const viewer = addEntity(world)
      setTransform(world, viewer, [0, 2, 0])
      const hero = addEntity(world)
      setTransform(world, hero, [0, 1.6, 0])
      const cape = createCloth(world, { width: 0.6, height: 0.9, resolution: 12, position: [0, 1.6, -0.15], substeps: 16 })
      pinRow(world, cape, 0, hero)
      if (budget) setClothBudget(world, { viewer, near: 3, far: 20, interval: 5, calibration: CALIBRATION })
      const c = getClothState(world, cape)
      let prev = Float64Array.from(c.vel)
      let worst = 0
      const levels = new Set<number>()
      for (let f = 0; f < 480; f++) {
        const d = f < 240 ? f / 6 : 0 // 40 m away over 4 s, then a camera cut back
        setTransform(world, viewer, [d, 2, 0])
        setTransform(world, hero, [Math.sin(f / 30), 1.6, 0]) // running back and forth, up to 2 m/s
        stepCloth(world, DT)
        levels.add(getClothLod(world, cape).substeps)
        for (let i = 0; i < c.count && f > 30; i++) {
          worst = Math.max(
            worst,
            Math.hypot(c.vel[3 * i] - prev[3 * i], c.vel[3 * i + 1] - prev[3 * i + 1], c.vel[3 * i + 2] - prev[3 * i + 2]),
          )
        }
        prev = Float64Array.from(c.vel)
      }
      return { worst, levels: levels.size, stretch: getClothStretch(world, cape).max }
    }
    const fixed = run(false), lod = run(true)
    expect(lod.levels).toBeGreaterThanOrEqual(8) // 16 → 1 substep and back up, every rung
    expect(fixed.worst).toBeGreaterThan(0.5) // the running itself
    expect(lod.worst).toBeLessThan(1.2 * fixed.worst)
    expect(lod.stretch).toBeLessThan(0.01)
  })

  it('an invisible cape freezes, and thaws carried along with the character that walked on', () => {
    const world = makeWorld({ sleep: false })
    const hero = addEntity(world)
    setTransform(world, hero, [0, 1.6, 0])
    const cape = createCloth(world, { width: 0.6, height: 0.9, resolution: 10, position: [0, 1.6, -0.15] })
    pinRow(world, cape, 0, hero)
    setClothBudget(world, { calibration: CALIBRATION, interval: 1 })
    steps(world, 60)
    const c = getClothState(world, cape)
    const before = Float64Array.from(c.pos)
    setClothVisible(world, cape, false)
    steps(world, 1)
    expect(getClothLod(world, cape).frozen).toBe(true)
    const frozen = Float64Array.from(c.pos)
    resetClothStats(world)
    const q = [0, Math.sin(Math.PI / 4), 0, Math.cos(Math.PI / 4)] // turned 90° about y
    for (let f = 0; f < 60; f++) {
      setTransform(world, hero, [f * 0.1, 1.6, 0], q)
      stepCloth(world, DT)
    }
    expect(getClothStats(world).particlesIntegrated).toBe(0)
    expect(hashBytes(c.pos)).toBe(hashBytes(frozen))
    setClothVisible(world, cape, true)
    stepCloth(world, DT)
    expect(getClothLod(world, cape).frozen).toBe(false)
    // every particle where the cape was relative to the hero: hero moved 5.9 m and turned a quarter
    let worst = 0
    for (let i = 0; i < c.count; i++) {
      const lx = before[3 * i], ly = before[3 * i + 1] - 1.6, lz = before[3 * i + 2]
      // rotate (lx, lz) by 90° about y: x' = z, z' = −x
      const wx = 5.9 + lz, wy = 1.6 + ly, wz = -lx
      worst = Math.max(worst, Math.hypot(c.pos[3 * i] - wx, c.pos[3 * i + 1] - wy, c.pos[3 * i + 2] - wz))
    }
    expect(worst).toBeLessThan(0.05)
    expect(getClothStretch(world, cape).max).toBeLessThan(0.05)
  })

  it('a character cloth without pins (held by max distance 0 on its skin or frame) thaws carried along by its bones or frame: no yank', () => {
    // it was only carried by a pin: held by its skin instead, the frozen cloth stayed where it
    // froze, 20 m behind, and its held row yanked the rest across at the speed limit (250 m/s, 89 %)
    for (const by of ['skin', 'frame'] as const) {
      const world = makeWorld({ sleep: false })
      const b1 = addEntity(world), b2 = addEntity(world)
      setTransform(world, b1, [-0.3, 1.6, 0])
      setTransform(world, b2, [0.3, 1.6, 0])
      const cl = createCloth(world, { width: 0.6, height: 0.9, resolution: 8, position: [0, 1.6, -0.15] })
      if (by === 'skin') {
        const joints: number[] = [], weights: number[] = []
        for (let i = 0; i < 64; i++) {
          const u = (i % 8) / 7
          joints.push(0, 1, 0, 0)
          weights.push(1 - u, u, 0, 0)
        }
        setClothSkinning(world, cl, { bones: [b1, b2], joints, weights })
      } else setClothInertia(world, cl, { frame: b1, linear: 0.5, angular: 0.5, centrifugal: 0.5 })
      setClothMotionConstraints(world, cl, { maxDistance: Array.from({ length: 64 }, (_, i) => (i < 8 ? 0 : Infinity)) })
      setClothBudget(world, { calibration: CALIBRATION, adapt: false, interval: 1 })
      for (let f = 0; f < 60; f++) stepCloth(world, DT)
      setClothVisible(world, cl, false)
      stepCloth(world, DT)
      expect(getClothLod(world, cl).frozen).toBe(true)
      for (let f = 1; f <= 60; f++) {
        // (the frame also turns; the bones move together, so their skin stays the same shape)
        const a = by === 'frame' ? f / 120 : 0
        setTransform(world, b1, [-0.3 + f / 3, 1.6, 0], [0, Math.sin(a), 0, Math.cos(a)])
        setTransform(world, b2, [0.3 + f / 3, 1.6, 0])
        stepCloth(world, DT)
      }
      setClothVisible(world, cl, true)
      stepCloth(world, DT)
      const c = getClothState(world, cl)
      let v = 0
      for (let i = 0; i < c.count; i++) v = Math.max(v, Math.hypot(c.vel[3 * i], c.vel[3 * i + 1], c.vel[3 * i + 2]))
      expect(v, by).toBeLessThan(1)
      expect(getClothStretch(world, cl).max, by).toBeLessThan(0.05)
      expect(getClothStats(world).guardResets, by).toBe(0)
    }
  })

  it('a far cape that thaws steps at once: at the frame it becomes visible its particles lie within max distance of its reference', () => {
    for (const every of [2, 4] as const) {
      const { world, hero, cape, c } = farCape(every)
      setClothMotionConstraints(world, cape, { maxDistance: 0.05 })
      for (let f = 1; f <= 121; f++) {
        setTransform(world, hero, [f < 60 ? 5 : 5 + 0.05 * (f - 60), 1.6, 0]) // walks 3 m while invisible
        if (f === 60) setClothVisible(world, cape, false)
        if (f === 120) setClothVisible(world, cape, true)
        stepCloth(world, DT)
        if (f === 119) expect(getClothLod(world, cape).frozen).toBe(true)
        if (f < 120) continue
        const ref = getClothReference(world, cape)!
        let worst = 0
        for (let i = 0; i < c.count; i++) {
          worst = Math.max(
            worst,
            Math.hypot(c.pos[3 * i] - ref[3 * i], c.pos[3 * i + 1] - ref[3 * i + 1], c.pos[3 * i + 2] - ref[3 * i + 2]),
          )
        }
        // sitting out the thaw's step, it showed the reference of the freeze, 3 m behind
        expect(worst, `every ${every}, frame ${f}`).toBeLessThan(0.052)
      }
    }
  })

  it("a far cloth stepping every 2nd or 4th step handles its character's 30 m jump as a teleport on whichever step the jump lands", () => {
    for (const every of [2, 4] as const) {
      for (let at = 100; at < 100 + every; at++) {
        for (const character of [false, true]) {
          const { world, hero, cape, c } = farCape(every)
          if (character) setClothInertia(world, cape, { frame: hero, teleport: { mode: 'reset' } })
          let fastest = 0, farthest = 0
          for (let f = 1; f <= at + 30; f++) {
            setTransform(world, hero, [f >= at ? 35 : 5, 1.6, 0])
            stepCloth(world, DT)
            if (f === at - 1) {
              expect(getClothLod(world, cape).stepEvery).toBe(every)
              resetClothStats(world)
            }
            if (f < at) continue
            for (let i = 0; i < c.count; i++) {
              fastest = Math.max(fastest, Math.hypot(c.vel[3 * i], c.vel[3 * i + 1], c.vel[3 * i + 2]))
              farthest = Math.max(farthest, Math.hypot(c.pos[3 * i] - 35, c.pos[3 * i + 1] - 1.6, c.pos[3 * i + 2]))
            }
          }
          const what = `every ${every}, jump at ${at}${character ? ', reset by its frame' : ''}`
          // dragged across the gap by its next step, it flew at the world's speed limit (250 m/s)
          expect(getClothStats(world).teleports, what).toBe(1)
          expect(fastest, what).toBeLessThan(3)
          expect(farthest, what).toBeLessThan(1.2)
        }
      }
    }
  })

  it('with fixed cost numbers the levels, and so the run, are deterministic', () => {
    const run = () => {
      const { world, viewer, cloths } = row({ msPerFrame: 0.05, adapt: false })
      for (let f = 0; f < 120; f++) {
        setTransform(world, viewer, [f * 0.3, 2, 0])
        stepCloth(world, DT)
      }
      return cloths.map((c) => hashBytes(getClothState(world, c).pos)).join()
    }
    expect(run()).toBe(run())
  })

  it('bad budgets are rejected at the API edge; a removed viewer means no distances', () => {
    const world = makeWorld()
    const cloth = sheet(world, 0)
    const notTransformed = addEntity(world)
    expect(() => setClothBudget(world, { msPerFrame: -1 })).toThrow(/options\.msPerFrame/)
    expect(() => setClothBudget(world, { viewer: notTransformed })).toThrow(/options\.viewer/)
    expect(() => setClothBudget(world, { viewer: 99999 })).toThrow(ClothError)
    expect(() => setClothBudget(world, { near: 10, far: 5 })).toThrow(/options\.far/)
    expect(() => setClothBudget(world, { interval: 0 })).toThrow(/options\.interval/)
    expect(() => setClothBudget(world, { freezeInvisible: 'no' as never })).toThrow(/freezeInvisible/)
    expect(() => setClothVisible(world, cloth, 1 as never)).toThrow(/visible/)
    const viewer = addEntity(world)
    setTransform(world, viewer, [100, 0, 0])
    setClothBudget(world, { viewer, near: 1, far: 2, calibration: CALIBRATION })
    steps(world, 2)
    expect(getClothLod(world, cloth)).toMatchObject({ substeps: 1, iterations: 1 })
    expect(getClothLod(world, cloth).distance).toBeGreaterThan(99)
    removeEntity(world, viewer)
    steps(world, 16)
    expect(getClothLod(world, cloth)).toMatchObject({ substeps: 2, distance: 0 }) // back up, a rung per allocation
    expect(() => setClothBudget(world, { farStepEvery: 3 as never })).toThrow(/options\.farStepEvery/)
  })
})
