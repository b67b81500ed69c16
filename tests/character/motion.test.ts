// Motion constraints around a reference pose: max distance, backstop, drive, and particles held
// kinematic by max distance 0. The reference is recomputed here from the character's poses (the
// rest shape carried rigidly by the character), not read from the library.
import { addEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  addCapsuleCollider,
  ClothError,
  type ClothMotionConstraints,
  createCloth,
  createClothFromMesh,
  getClothReference,
  getClothState,
  getClothStats,
  getClothStretch,
  pinRow,
  setClothInertia,
  setClothMotionConstraints,
  setClothQuality,
  setClothSkinning,
  setTransform,
  stepCloth,
} from '../../src/index'
import { allFinite, hashBytes, makeWorld } from '../helpers'
import {
  DT,
  capeOnCharacter,
  carriedRest,
  drive,
  expectClothErrors,
  paintRows,
  positionsNow,
  RUN_COLS,
  RUN_ROWS,
  runningCape,
  sprintTurnStopJump,
  yawQuat,
} from './scenes'

const ROWS = 12, COLS = 8

/** The cape of `capeOnCharacter` (scenes.ts) at the default iterations, without pins: behind a character at [0, 1.6, 0]. */
const CAPE = {
  width: 0.5,
  height: 0.8,
  resolution: [COLS, ROWS] as [number, number],
  position: [-0.15, 1.55, 0],
  rotation: yawQuat(-Math.PI / 2),
}

/** Max distance painted by row: 0 at the collar, growing linearly to `hem` m at the hem. */
function painted(hem: number): number[] {
  return Array.from({ length: ROWS * COLS }, (_, i) => (hem * Math.floor(i / COLS)) / (ROWS - 1))
}

/**
 * The violent run (world-space cape: sprint, turn, dead stop, jump) with motion constraints;
 * `check(x, ref, i)` sees every particle after every frame. Returns the cape's world.
 */
function run(
  constraints: ClothMotionConstraints | undefined,
  check: (pos: Float64Array, ref: Float64Array, i: number, yaw: number) => void,
) {
  const { world, hero, cape } = capeOnCharacter(undefined, makeWorld({ sleep: false }))
  const rest = positionsNow(world, cape)
  if (constraints) setClothMotionConstraints(world, cape, constraints)
  drive(world, hero, sprintTurnStopJump, 4, (_, t) => {
    const m = sprintTurnStopJump(t)
    const ref = carriedRest(rest, [0, 1.6, 0], 0, m.p, m.yaw)
    const c = getClothState(world, cape)
    for (let i = 0; i < c.count; i++) check(c.pos, ref, i, m.yaw)
  })
  expect(allFinite(world, cape)).toBe(true)
  return { world, cape }
}

/**
 * Where particle i lies against its backstop sphere (radius `radius`, its centre `distance` +
 * `radius` behind the reference): how far behind the reference it is (toward the body), how far
 * off the sphere's axis, and how deep inside the sphere (≤ 0: outside). The rest normal is −x
 * (away from the body) in the character's frame, turned by its yaw.
 */
function backstopOf(pos: Float64Array, ref: Float64Array, i: number, yaw: number, distance: number, radius: number) {
  const nx = -Math.cos(yaw), nz = Math.sin(yaw)
  const dx = pos[3 * i] - ref[3 * i], dy = pos[3 * i + 1] - ref[3 * i + 1], dz = pos[3 * i + 2] - ref[3 * i + 2]
  const depth = -(dx * nx + dz * nz)
  const lateral = Math.sqrt(Math.max(0, dx * dx + dy * dy + dz * dz - depth * depth))
  return { depth, lateral, inside: radius - Math.hypot(lateral, distance + radius - depth) }
}

const dist = (a: ArrayLike<number>, b: ArrayLike<number>, i: number) =>
  Math.hypot(a[3 * i] - b[3 * i], a[3 * i + 1] - b[3 * i + 1], a[3 * i + 2] - b[3 * i + 2])

describe('max distance', () => {
  it('no particle ever ends a step farther from its reference than its painted max distance (+1 µm) through a sprint, a turn, a dead stop and a jump', () => {
    const md = painted(0.15)
    let worst = -Infinity
    run({ maxDistance: md }, (pos, ref, i) => {
      worst = Math.max(worst, dist(pos, ref, i) - md[i])
    })
    console.log(`max distance: worst excess ${(1000 * worst).toExponential(2)} mm`)
    // measured 2.2e-5 mm: rounding (the reference is float32 offsets from the frame)
    expect(worst).toBeLessThan(1e-6)
    // the same run unconstrained goes far beyond those distances
    let free = -Infinity
    run(undefined, (pos, ref, i) => {
      free = Math.max(free, dist(pos, ref, i) - md[i])
    })
    expect(free).toBeGreaterThan(0.1)
  })

  it('max distance 0 holds particles on the reference (within 1 µm), kinematic (inverse mass 0) and anchoring tethers, with no pins at all', () => {
    const world = makeWorld({ sleep: false })
    const hero = addEntity(world)
    setTransform(world, hero, [0, 1.6, 0])
    const cape = createCloth(world, CAPE)
    const rest = positionsNow(world, cape)
    setClothInertia(world, cape, { frame: hero, linear: 0.3, angular: 0.3, centrifugal: 0.3 })
    const md = Array.from({ length: ROWS * COLS }, (_, i) => (i < COLS ? 0 : Infinity))
    setClothMotionConstraints(world, cape, { maxDistance: md })
    const c = getClothState(world, cape)
    for (let i = 0; i < COLS; i++) expect(c.invMass[i]).toBe(0)
    let worst = 0
    drive(world, hero, sprintTurnStopJump, 4, (_, t) => {
      const m = sprintTurnStopJump(t)
      const ref = carriedRest(rest, [0, 1.6, 0], 0, m.p, m.yaw)
      for (let i = 0; i < COLS; i++) worst = Math.max(worst, dist(c.pos, ref, i))
    })
    expect(worst).toBeLessThan(1e-6) // (the reference is kept as float32 offsets from the frame: ~0.1 µm)
    expect(c.tethers.set.count).toBeGreaterThan(0)
    expect(Math.min(...Array.from(c.pos).filter((_, j) => j % 3 === 1))).toBeGreaterThan(0.5) // it hangs, not falls
    // releasing them gives the particles their mass back
    setClothMotionConstraints(world, cape, null)
    for (let i = 0; i < COLS; i++) expect(c.invMass[i]).toBe(c.baseInvMass[i])
    expect(c.character!.inertia).toBe(true) // inertia stays
  })
})

describe('a scaled reference', () => {
  it('a character scaled 3× carries the reference with it: the cloth follows within max distance (+2 mm) and the explosion guard does not take that for flying off', () => {
    // the guard allowed twice the cloth's size around its pins only: from a scale of 3 on, the
    // limits pulled the cloth out of that every step and the guard put it back every step
    // (90 resets in 90 steps, 1.4 m past max distance)
    const { world, hero, cape } = capeOnCharacter(undefined, makeWorld({ sleep: false }))
    const md = painted(0.3)
    setClothMotionConstraints(world, cape, { maxDistance: md, backstop: { distance: 0.02, radius: 0.5 } })
    const c = getClothState(world, cape)
    let worst = 0
    for (let f = 0; f < 120; f++) {
      setTransform(world, hero, [0, 1.6, 0], [0, 0, 0, 1], f >= 30 ? [3, 3, 3] : [1, 1, 1])
      stepCloth(world, DT)
      const ref = getClothReference(world, cape)!
      for (let i = 0; i < c.count; i++) worst = Math.max(worst, dist(c.pos, ref, i) - md[i])
    }
    expect(getClothStats(world).guardResets).toBe(0)
    expect(worst).toBeLessThan(0.002)
    expect(allFinite(world, cape)).toBe(true)
  })
})

describe('held and pinned', () => {
  it('a particle pinned and held by max distance 0 stays on its pin after an explosion-guard reset, when the pin target moves apart from the frame', () => {
    // the frame is the character's root, the pins follow its chest, which bobs: a pin wins over
    // max distance 0 at every substep, and a reset once put such particles back on the reference
    const world = makeWorld({ sleep: false })
    const root = addEntity(world), chest = addEntity(world)
    setTransform(world, root, [0, 0, 0])
    setTransform(world, chest, [0, 1.6, 0])
    // a speed limit low enough that the bobbing trips it now and then
    const cape = createCloth(world, { ...CAPE, guard: { speed: 0.5 } })
    const rest = positionsNow(world, cape)
    pinRow(world, cape, 0, chest)
    setClothInertia(world, cape, { frame: root, linear: 0.5, angular: 0.5, centrifugal: 0.5 })
    setClothMotionConstraints(world, cape, { maxDistance: painted(0.5) })
    const c = getClothState(world, cape)
    let worst = 0
    for (let f = 1; f <= 60; f++) {
      const dy = 0.1 * Math.sin(f / 4)
      setTransform(world, chest, [0, 1.6 + dy, 0])
      stepCloth(world, DT)
      for (let i = 0; i < COLS; i++)
        worst = Math.max(
          worst,
          Math.hypot(c.pos[3 * i] - rest[3 * i], c.pos[3 * i + 1] - rest[3 * i + 1] - dy, c.pos[3 * i + 2] - rest[3 * i + 2]),
        )
    }
    expect(getClothStats(world).guardResets).toBeGreaterThan(5)
    expect(worst).toBeLessThan(1e-9) // (was up to the chest's 100 mm off the root)
  })
})

describe('a frame or bone chosen mid-run', () => {
  it("switching a running cape to a new frame, or skinning it to a new bone, after this frame's Transforms were written keeps its held row by its pinned row (no lasting stretch)", () => {
    // a new entity had no history: bound at the coming frame's pose against the last step's
    // reference, the held row stayed one frame of running (10 cm) off the pinned row: 74 % stretch for good
    const paint = paintRows(0.9)
    const worstAfter = (how: 'frame' | 'bone' | 'none') => {
      const { world, hero, cape } = runningCape(paint)
      const chest = addEntity(world)
      setTransform(world, chest, [0, 1.3, 0])
      let worst = 0
      for (let f = 1; f <= 60; f++) {
        const z = (6 * f) / 60
        setTransform(world, hero, [0, 0, z])
        setTransform(world, chest, [0, 1.3, z]) // the chest moves rigidly with the hero
        if (f === 41 && how === 'frame') setClothInertia(world, cape, { frame: chest, linear: 0.5, angular: 0.5, centrifugal: 0.5 })
        if (f === 41 && how === 'bone') {
          setClothSkinning(world, cape, {
            bones: [chest],
            joints: paint.flatMap(() => [0, 0, 0, 0]),
            weights: paint.flatMap(() => [1, 0, 0, 0]),
          })
        }
        stepCloth(world, DT)
        if (f > 41) worst = Math.max(worst, getClothStretch(world, cape).max)
      }
      expect(allFinite(world, cape)).toBe(true)
      return worst
    }
    const none = worstAfter('none'), frame = worstAfter('frame'), bone = worstAfter('bone')
    console.log(
      `worst stretch after the switch: new frame ${(100 * frame).toFixed(1)} %, new bone ${(100 * bone).toFixed(1)} %, no switch ${
        (100 * none).toFixed(1)
      } %`,
    )
    expect(frame).toBeLessThan(none + 0.02)
    expect(bone).toBeLessThan(none + 0.02)
  })
})

describe('limits changed mid-run', () => {
  it("tightening a swinging cape's painted max distance holds the new limits at once, with the kick the README's known limits give (every substep, and every 4th)", () => {
    for (const every of [1, 4]) {
      const { world, hero, cape } = runningCape(paintRows(0.9), every)
      const c = getClothState(world, cape)
      const fastest = () => {
        let v = 0
        for (let j = 0; j < 3 * c.count; j += 3) v = Math.max(v, Math.hypot(c.vel[j], c.vel[j + 1], c.vel[j + 2]))
        return v
      }
      let before = 0, after = 0, stretchBefore = 0, stretchAfter = 0, worst = 0
      const tight = paintRows(0.2)
      for (let f = 1; f <= 100; f++) {
        setTransform(world, hero, [0, 0, (6 * Math.min(f, 60)) / 60]) // runs at 6 m/s, stops dead
        if (f === 91) setClothMotionConstraints(world, cape, { maxDistance: tight, every })
        stepCloth(world, DT)
        if (f >= 85 && f <= 90) {
          before = Math.max(before, fastest())
          stretchBefore = Math.max(stretchBefore, getClothStretch(world, cape).max)
        }
        if (f > 90) {
          after = Math.max(after, fastest())
          stretchAfter = Math.max(stretchAfter, getClothStretch(world, cape).max)
          const ref = getClothReference(world, cape)!
          for (let i = 0; i < c.count; i++) worst = Math.max(worst, dist(c.pos, ref, i) - tight[i])
        }
      }
      console.log(
        `every ${every}: fastest ${before.toFixed(1)} m/s before, ${after.toFixed(1)} after; stretch ${
          (100 * stretchBefore).toFixed(1)
        } % before, ${(100 * stretchAfter).toFixed(1)} % after`,
      )
      expect(worst).toBeLessThan(0.002)
      expect(allFinite(world, cape)).toBe(true)
      // the known limit: what the new limits take back becomes velocity (measured 20.5 and 11.8 m/s
      // against 3.3 before; how much depends on the swing's phase: 17 and 59 m/s while the run's
      // start was taken as steady)
      expect(after).toBeGreaterThan(3 * before)
      expect(after).toBeLessThan(60)
    }
  })
})

describe('limits that limit nothing', () => {
  it('max distance Infinity everywhere, no backstop, no drive: the plain velocity update runs (the same bytes), until a limit is set', () => {
    // (it ran the constrained writeback over every particle for the same bytes: 1.11× the step)
    const free = runningCape(null), unlimited = runningCape(Array(RUN_COLS * RUN_ROWS).fill(Infinity))
    const start = getClothState(unlimited.world, unlimited.cape).character!.start
    start.fill(NaN) // where the limits run, the predict records each substep's start here
    for (let f = 0; f < 60; f++) {
      for (const r of [free, unlimited]) {
        setTransform(r.world, r.hero, [0.05 * f, 0, 0], yawQuat(0.03 * f))
        stepCloth(r.world, DT)
      }
    }
    expect(hashBytes(getClothState(unlimited.world, unlimited.cape).pos)).toBe(hashBytes(getClothState(free.world, free.cape).pos))
    expect(start.every((v) => Number.isNaN(v))).toBe(true)
    // one limit anywhere: the limits run again
    setClothMotionConstraints(unlimited.world, unlimited.cape, { maxDistance: [0.5, ...Array(RUN_COLS * RUN_ROWS - 1).fill(Infinity)] })
    stepCloth(unlimited.world, DT)
    expect(start.some((v) => Number.isNaN(v))).toBe(false)
  })
})

describe('every n-th substep', () => {
  it('with constraints every 3rd substep (and the last), every step still ends within max distance (+1 µm) and outside the backstop; every: 1 is the default, byte for byte', () => {
    const md = painted(0.3)
    const distance = 0.02, radius = 0.5
    let worst = -Infinity, inside = -Infinity
    const { world, cape } = run({ maxDistance: md, backstop: { distance, radius }, every: 3 }, (pos, ref, i, yaw) => {
      worst = Math.max(worst, dist(pos, ref, i) - md[i])
      inside = Math.max(inside, backstopOf(pos, ref, i, yaw, distance, radius).inside)
    })
    // the same run every 3rd substep without a backstop goes into the sphere: the check above has something to hold
    let unheld = -Infinity
    run({ maxDistance: md, every: 3 }, (pos, ref, i, yaw) => {
      unheld = Math.max(unheld, backstopOf(pos, ref, i, yaw, distance, radius).inside)
    })
    expect(unheld).toBeGreaterThan(0.02)
    console.log(
      `every 3rd substep: worst excess ${(1000 * worst).toExponential(2)} mm, deepest in the backstop ${
        (1000 * inside).toExponential(2)
      } mm`,
    )
    expect(getClothState(world, cape).substeps % 3).not.toBe(0) // (the last substep is not a 3rd one: it runs anyway)
    // measured 3.0e-5 and 1.7e-5 mm: rounding
    expect(worst).toBeLessThan(1e-6)
    expect(inside).toBeLessThan(1e-6)
    // it is not every substep: the same run at every substep differs
    const final = (constraints: ClothMotionConstraints) => {
      const r = run(constraints, () => {})
      return getClothState(r.world, r.cape).pos.slice()
    }
    const every1 = final({ maxDistance: md, backstop: { distance, radius }, every: 1 })
    const byDefault = final({ maxDistance: md, backstop: { distance, radius } })
    const every3 = final({ maxDistance: md, backstop: { distance, radius }, every: 3 })
    expect(byDefault).toEqual(every1)
    expect(every3).not.toEqual(every1)
  })

  it("checked at only a step's last two substeps (every: 8 of 8), the cape stays whole through the violent run: what a check takes back is the drift of the substeps since the last one, not one substep's motion", () => {
    // the demo's painting: 0 at the collar, 0.9·u² m below, free at the hem
    const md = Array.from({ length: ROWS * COLS }, (_, i) => {
      const u = Math.floor(i / COLS) / (ROWS - 1)
      return u === 1 ? Infinity : 0.9 * u * u
    })
    const worstStretch = (every: number, inertia: boolean) => {
      const { world, hero, cape } = capeOnCharacter(undefined, makeWorld({ sleep: false }))
      if (inertia) setClothInertia(world, cape, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5 })
      setClothMotionConstraints(world, cape, { maxDistance: md, backstop: { distance: 0.02, radius: 0.5 }, every })
      expect(getClothState(world, cape).substeps).toBe(8)
      let worst = 0
      drive(world, hero, sprintTurnStopJump, 4, () => {
        worst = Math.max(worst, getClothStretch(world, cape).max)
      })
      expect(allFinite(world, cape)).toBe(true)
      return worst
    }
    const rows = [1, 4, 8].flatMap((every) => [false, true].map((inertia) => ({ every, inertia, worst: worstStretch(every, inertia) })))
    console.log(
      rows.map((r) => `every ${r.every}${r.inertia ? ', inertia 0.5' : ''}: worst edge stretch ${(100 * r.worst).toFixed(1)} %`).join('; '),
    )
    // taken back as one substep's velocity, 7 substeps of drift flung the cape to 866 % (826 % with
    // inertia); checked at the step's last substep alone, 26 % (5.5 %); now 8.1 % (7.0 %)
    for (const r of rows) expect(r.worst).toBeLessThan(0.15)
  })
})

describe('limits against a collider', () => {
  it("a torso capsule reaching behind the cape's reference (the two disagree) leaves a standing cape still: no phantom velocity", () => {
    // the README cape, its capsule 2, 5 and 10 cm behind the rest plane: the collider pushes the
    // upper rows out, max distance pulls them back each substep. Undoing a push-out is no motion:
    // it once became 8.4, 22.8 and 54.7 m/s of stored velocity
    const fastest = (reach: number, constrained: boolean) => {
      const world = makeWorld()
      const hero = addEntity(world)
      setTransform(world, hero, [0, 0, 0])
      addCapsuleCollider(world, addEntity(world), { body: hero, offset: [0, 1.15, -0.01 - reach], radius: 0.19, halfHeight: 0.22 })
      const cape = createCloth(world, {
        width: 0.55,
        height: 1.05,
        resolution: [14, 24],
        position: [0, 1.47, -0.2],
        rotation: [0, 1, 0, 0],
        material: 'wool',
      })
      pinRow(world, cape, 0, hero)
      if (constrained) {
        const md = Array.from({ length: 14 * 24 }, (_, i) => {
          const u = Math.floor(i / 14) / 23
          return u === 1 ? Infinity : 0.9 * u * u
        })
        setClothMotionConstraints(world, cape, { maxDistance: md })
      }
      for (let f = 0; f < 300; f++) stepCloth(world, DT)
      const v = getClothState(world, cape).vel
      let top = 0
      for (let j = 0; j < v.length; j += 3) top = Math.max(top, Math.hypot(v[j], v[j + 1], v[j + 2]))
      expect(allFinite(world, cape)).toBe(true)
      return top
    }
    // measured 0.019, 0.191 and 0.182 m/s (0.027, 0.134 and 0.329 without constraints; README)
    for (const [reach, bound] of [[0.02, 0.025], [0.05, 0.24], [0.1, 0.23]]) {
      const on = fastest(reach, true), off = fastest(reach, false)
      console.log(`capsule ${100 * reach} cm behind: fastest particle ${on.toFixed(3)} m/s (${off.toFixed(3)} without motion constraints)`)
      expect(on).toBeLessThan(bound)
      expect(on).toBeLessThan(Math.max(0.05, 2 * off))
    }
  })
})

describe('backstop', () => {
  it('where max distance reaches into the backstop sphere, a particle pushed out of the sphere and clamped back ends on neither wrong side (checked every substep, and with every: 8 of 8 and every: 16 of 16)', () => {
    // max distance growing 6 cm a row, a 30 cm sphere 5 mm behind the reference: the straight way
    // back from the sphere's surface to the max-distance sphere cuts into it again
    const distance = 0.005, radius = 0.3
    const deepest = (substeps: number, every: number) => {
      const { world, hero, cape } = capeOnCharacter({ linear: 0.7 }, makeWorld({ sleep: false }))
      setClothQuality(world, cape, { substeps })
      const c = getClothState(world, cape)
      const md = Array.from({ length: c.count }, (_, i) => 0.06 * Math.floor(i / COLS))
      setClothMotionConstraints(world, cape, { maxDistance: md, every, backstop: { distance, radius } })
      const rest = positionsNow(world, cape)
      let inside = -Infinity, excess = -Infinity
      drive(world, hero, sprintTurnStopJump, 4, (_, t) => {
        const m = sprintTurnStopJump(t)
        const ref = carriedRest(rest, [0, 1.6, 0], 0, m.p, m.yaw)
        for (let i = COLS; i < c.count; i++) {
          inside = Math.max(inside, backstopOf(c.pos, ref, i, m.yaw, distance, radius).inside)
          excess = Math.max(excess, dist(c.pos, ref, i) - md[i])
        }
      })
      return { inside, excess }
    }
    const runs = [[1, 1], [8, 1], [8, 8], [16, 16]].map(([substeps, every]) => ({ substeps, every, ...deepest(substeps, every) }))
    console.log(
      runs.map((r) =>
        `${r.substeps} substeps, every ${r.every}: deepest in the sphere ${(1000 * r.inside).toExponential(2)} mm, worst excess ${
          (1000 * r.excess).toExponential(2)
        } mm`
      )
        .join('; '),
    )
    // one push and one clamp left particles 0.5 mm (1 substep) to 7.5 mm (every 16th of 16) inside;
    // now measured at most 1.4e-5 mm inside and 4.8e-5 mm past max distance: rounding
    for (const r of runs) {
      expect(r.inside).toBeLessThan(1e-6)
      expect(r.excess).toBeLessThan(1e-6)
    }
  })

  it('keeps every particle out of its backstop sphere when a dead stop flings the cape into the body; without it the cape goes deep', () => {
    const md = painted(0.3)
    const distance = 0.02, radius = 0.5
    let inside = -Infinity, worstDepth = -Infinity
    run({ maxDistance: md, backstop: { distance, radius } }, (pos, ref, i, yaw) => {
      const { depth, lateral, inside: deep } = backstopOf(pos, ref, i, yaw, distance, radius)
      inside = Math.max(inside, deep)
      // within the sphere's footprint its surface lies at depth distance + radius − √(radius² − lateral²)
      if (lateral < radius) worstDepth = Math.max(worstDepth, depth - (distance + radius - Math.sqrt(radius * radius - lateral * lateral)))
    })
    console.log(
      `backstop: deepest inside the sphere ${(1000 * inside).toExponential(2)} mm, beyond the surface depth ${
        (1000 * worstDepth).toExponential(2)
      } mm`,
    )
    // measured 1.2e-5 mm both: rounding
    expect(inside).toBeLessThan(1e-6)
    expect(worstDepth).toBeLessThan(1e-6)
    let deepest = -Infinity
    run({ maxDistance: md }, (pos, ref, i, yaw) => {
      deepest = Math.max(deepest, backstopOf(pos, ref, i, yaw, distance, radius).depth)
    })
    expect(deepest).toBeGreaterThan(distance + 0.05)
  })
})

describe('drive', () => {
  it('pulls toward the reference: drive 1 follows it (within 1 µm), more drive stays closer, none swings free', () => {
    const meanGap = (drive?: number) => {
      let sum = 0, n = 0
      run(drive === undefined ? undefined : { drive }, (pos, ref, i) => {
        sum += dist(pos, ref, i)
        n++
      })
      return sum / n
    }
    const free = meanGap(), weak = meanGap(0.05), strong = meanGap(0.5), full = meanGap(1)
    expect(full).toBeLessThan(1e-6)
    expect(strong).toBeLessThan(weak)
    expect(weak).toBeLessThan(free)
  })

  it('is a critically damped spring: an offset of 10 cm closes as e(t) = e₀·(1 + ωt)·e^(−ωt), nearly the same at 4 and 16 substeps, whatever the mass', () => {
    const f = 0.2 // closes 20 % of an offset in 1/60 s from rest
    // ω from f = 1 − (1 + ωT)·e^(−ωT), T = 1/60 s (bisection)
    let lo = 0, hi = 100
    for (let k = 0; k < 60; k++) {
      const u = (lo + hi) / 2
      if (1 - (1 + u) * Math.exp(-u) < f) lo = u
      else hi = u
    }
    const omega = lo * 60
    const gaps = (substeps: number, material = 'cotton') => {
      const world = makeWorld({ gravity: [0, 0, 0], sleep: false })
      const cloth = createCloth(world, { width: 0.2, height: 0.2, resolution: 2, substeps, damping: 0, material })
      setClothMotionConstraints(world, cloth, { drive: f })
      const c = getClothState(world, cloth)
      for (let i = 0; i < c.count; i++) c.pos[3 * i] += 0.1 // displaced 10 cm from the reference, at rest
      c.prev.set(c.pos)
      const out: number[] = []
      for (let frame = 1; frame <= 12; frame++) {
        stepCloth(world, DT)
        out.push(c.pos[0] - getClothReference(world, cloth)![0])
      }
      return out
    }
    const coarse = gaps(4), fine = gaps(16)
    for (let frame = 1; frame <= 12; frame++) {
      const t = frame * DT
      const exact = 0.1 * (1 + omega * t) * Math.exp(-omega * t)
      expect(Math.abs(fine[frame - 1] - exact), `frame ${frame}`).toBeLessThan(0.0015)
      expect(Math.abs(coarse[frame - 1] - exact), `frame ${frame}`).toBeLessThan(0.004)
      expect(fine[frame - 1]).toBeGreaterThan(0) // critically damped: no overshoot
    }
    expect(fine[0] / 0.1).toBeCloseTo(1 - f, 1)
    const heavy = gaps(16, 'chainmail') // 40 times cotton's density: the same motion
    for (let k = 0; k < fine.length; k++) expect(Math.abs(heavy[k] - fine[k])).toBeLessThan(1e-9)
  })
})

describe('setClothMotionConstraints input', () => {
  it('rejects negative or non-finite distances, arrays of the wrong length, bad drives with a ClothError naming the argument', () => {
    const { world, cape } = capeOnCharacter()
    const n = getClothState(world, cape).count
    const bad: [object, string][] = [
      [{ maxDistance: -0.1 }, 'constraints.maxDistance'],
      [{ maxDistance: NaN }, 'constraints.maxDistance'],
      [{ maxDistance: new Array(n - 1).fill(0.1) }, 'constraints.maxDistance'],
      [{ maxDistance: Array.from({ length: n }, (_, i) => (i === 3 ? -1 : 0.1)) }, 'constraints.maxDistance[3]'],
      [{ backstop: { distance: 0.1 } }, 'constraints.backstop.radius'],
      [{ backstop: { distance: -0.1, radius: 1 } }, 'constraints.backstop.distance'],
      [{ backstop: { distance: 0.1, radius: 0 } }, 'constraints.backstop.radius'],
      [{ backstop: { distance: 0.1, radius: new Float64Array(3) } }, 'constraints.backstop.radius'],
      [{ backstop: 'behind' }, 'constraints.backstop'],
      [{ drive: 1.5 }, 'constraints.drive'],
      [{ drive: -0.5 }, 'constraints.drive'],
      [{ every: 0 }, 'constraints.every'],
      [{ every: 1.5 }, 'constraints.every'],
      [{ every: NaN }, 'constraints.every'],
      [{ every: '2' }, 'constraints.every'],
    ]
    expectClothErrors(bad, (constraints) => setClothMotionConstraints(world, cape, constraints as never))
    expect(() => setClothMotionConstraints(world, cape, 5 as never)).toThrow(ClothError)
    expect(getClothState(world, cape).character).toBeNull()
  })
})

describe("limits every n-th substep never run only at a step's last", () => {
  // A skirt skinned to a hip and two thighs swinging ±40° at 1.5 Hz, walking at 1.4 m/s, with
  // painted max distance and a backstop, 8 substeps. With `every: 8` the limits ran once a step,
  // at its last substep: the whole step's drift taken back after the last solve, particle by
  // particle, showed in every frame (median edge stretch 28 %, against 7 % at every substep). The
  // step's last run now always has one before it.
  const skirt = (every: number) => {
    const world = makeWorld({ sleep: false })
    const hip = addEntity(world), thighL = addEntity(world), thighR = addEntity(world)
    const rows = 10, cols = 24, n = rows * cols
    const positions: number[] = [], indices: number[] = []
    for (let r = 0; r < rows; r++) {
      const v = r / (rows - 1), rad = 0.17 + 0.28 * v, y = 1 - 0.55 * v
      for (let k = 0; k < cols; k++) positions.push(rad * Math.sin((2 * Math.PI * k) / cols), y, rad * Math.cos((2 * Math.PI * k) / cols))
    }
    for (let r = 0; r + 1 < rows; r++) {
      for (let k = 0; k < cols; k++) {
        const a = r * cols + k, b = a + cols, d = r * cols + ((k + 1) % cols), e = d + cols
        indices.push(a, b, d, d, b, e)
      }
    }
    const pose = (t: number) => {
      const swing = ((40 * Math.PI) / 180) * Math.sin(2 * Math.PI * 1.5 * t)
      const hy = 1 + 0.03 * Math.abs(Math.sin(2 * Math.PI * 1.5 * t)), hz = 1.4 * t
      setTransform(world, hip, [0, hy, hz])
      setTransform(world, thighL, [0.09, hy - 0.06, hz], [Math.sin(-swing / 2), 0, 0, Math.cos(-swing / 2)])
      setTransform(world, thighR, [-0.09, hy - 0.06, hz], [Math.sin(swing / 2), 0, 0, Math.cos(swing / 2)])
    }
    pose(0)
    for (const thigh of [thighL, thighR]) {
      addCapsuleCollider(world, addEntity(world), { body: thigh, offset: [0, -0.4, 0], radius: 0.07, halfHeight: 0.33 })
    }
    const cloth = createClothFromMesh(world, { positions, indices, material: 'cotton', substeps: 8 })
    const joints: number[] = [], weights: number[] = [], maxDistance: number[] = []
    for (let i = 0; i < n; i++) {
      const v = Math.floor(i / cols) / (rows - 1)
      const s = positions[3 * i] / Math.hypot(positions[3 * i], positions[3 * i + 2])
      const wl = v * 0.5 * (1 + s), wr = v * 0.5 * (1 - s)
      joints.push(0, 1, 2, 0)
      weights.push(Math.max(0, 1 - wl - wr), wl, wr, 0)
      maxDistance.push(0.25 * v * v)
    }
    setClothInertia(world, cloth, { frame: hip, linear: 0.5, angular: 0.5, centrifugal: 0.5 })
    setClothSkinning(world, cloth, { bones: [hip, thighL, thighR], joints, weights })
    setClothMotionConstraints(world, cloth, { maxDistance, backstop: { distance: 0.02, radius: 0.15 }, every })
    const stretch: number[] = []
    for (let f = 1; f <= 240; f++) {
      pose(f / 60)
      stepCloth(world, 1 / 60)
      stretch.push(getClothStretch(world, cloth).max)
    }
    stretch.sort((a, b) => a - b)
    return { median: stretch[120], p95: stretch[228] }
  }

  it('a walking skirt at every: 8 of 8 substeps stretches about as at every substep', () => {
    const one = skirt(1), last = skirt(8)
    console.log('skirt median / p95 edge stretch: every 1', one, 'every 8', last)
    expect(last.median).toBeLessThan(1.5 * one.median) // measured before: 28 % against 7 %
    expect(last.p95).toBeLessThan(1.5 * one.p95)
  })
})
