// Character cloth at its seams with the budget, frame changes and entity lifetimes (found by a hunt;
// each failed before its fix: 30 m/s at the thaw, a reference 5 cm off its pins for good at 16 %
// stretch, 2174 % stretch).
import { addEntity, createWorld, removeComponent, removeEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  createCloth,
  getClothComponents,
  getClothLod,
  getClothReference,
  getClothState,
  getClothStretch,
  installClothPlugin,
  pinParticle,
  pinRow,
  setClothBudget,
  setClothInertia,
  setClothMotionConstraints,
  setClothSkinning,
  setClothVisible,
  setTransform,
  stepCloth,
} from '../../src/index'

const DT = 1 / 60
const yaw = (a: number): number[] => [0, Math.sin(a / 2), 0, Math.cos(a / 2)]
const COLS = 8, ROWS = 12
const CAL = { nsPerParticle: 20, nsPerProjection: 12, nsPerColliderTest: 5, nsPerClothSubstep: 500 }

/** 0 on the collar row, 0.5·u² m below, free at the hem. */
function painted(): number[] {
  return Array.from({ length: COLS * ROWS }, (_, i) => {
    const u = Math.floor(i / COLS) / (ROWS - 1)
    return i < COLS ? 0 : u === 1 ? Infinity : 0.5 * u * u
  })
}

function cape(world: object, hero: number, pinned: boolean): number {
  const c = createCloth(world, {
    width: 0.5,
    height: 0.8,
    resolution: [COLS, ROWS],
    position: [-0.15, 1.55, 0],
    rotation: yaw(-Math.PI / 2),
    iterations: 2,
  })
  if (pinned) pinRow(world, c, 0, hero)
  return c
}

function fastest(world: object, cloth: number): number {
  const c = getClothState(world, cloth)
  let v = 0
  for (let i = 0; i < c.count; i++) v = Math.max(v, Math.hypot(c.vel[3 * i], c.vel[3 * i + 1], c.vel[3 * i + 2]))
  return v
}

/** Two bones, at the collar (1.6 m) and the hip (1.2 m), the cape blended from the first to the second down its rows. */
function skinToTwoBones(world: object, c: number): number[] {
  const bones = [addEntity(world), addEntity(world)]
  setTransform(world, bones[0], [0, 1.6, 0])
  setTransform(world, bones[1], [0, 1.2, 0])
  const joints: number[] = [], weights: number[] = []
  for (let i = 0; i < COLS * ROWS; i++) {
    const u = Math.floor(i / COLS) / (ROWS - 1)
    joints.push(0, 1, 0, 0)
    weights.push(1 - u, u, 0, 0)
  }
  setClothSkinning(world, c, { bones, joints, weights })
  return bones
}

describe('character cloth: frames changed and bones removed while it runs', () => {
  it('a frozen cape held by its frame (max distance 0, no pins) given a new frame while frozen thaws carried, as without the change', () => {
    const thawSpeed = (change: boolean): number => {
      const world = installClothPlugin(createWorld())
      const hero = addEntity(world), child = addEntity(world)
      setTransform(world, hero, [0, 1.6, 0])
      setTransform(world, child, [0, 1.7, 0]) // a bone 10 cm up: moves rigidly with the hero
      const c = cape(world, hero, false)
      setClothInertia(world, c, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5 })
      setClothMotionConstraints(world, c, { maxDistance: painted() })
      setClothBudget(world, { calibration: CAL, adapt: false, interval: 1 })
      for (let f = 0; f < 120; f++) stepCloth(world, DT) // settled
      setClothVisible(world, c, false)
      stepCloth(world, DT) // frozen
      if (change) setClothInertia(world, c, { frame: child, linear: 0.5, angular: 0.5, centrifugal: 0.5 })
      for (let f = 1; f <= 100; f++) { // walks 10 m, stops
        const x = Math.min(10, 0.1 * f)
        setTransform(world, hero, [x, 1.6, 0])
        setTransform(world, child, [x, 1.7, 0])
        stepCloth(world, DT)
      }
      setClothVisible(world, c, true)
      let v = 0
      for (let f = 0; f < 4; f++) {
        stepCloth(world, DT)
        v = Math.max(v, fastest(world, c))
      }
      return v
    }
    const plain = thawSpeed(false), changed = thawSpeed(true)
    // measured: 0.000 and 0.000 m/s (30.0 before the fix)
    expect(changed).toBeLessThan(Math.max(0.5, 1.2 * plain))
  })

  it('a pinned cape whose frame is the world for one frame, then its pin target again, keeps its reference on its pins (no lasting stretch)', () => {
    const runCape = (detour: boolean) => {
      const world = installClothPlugin(createWorld())
      const hero = addEntity(world)
      setTransform(world, hero, [0, 1.6, 0])
      const c = cape(world, hero, true)
      const shares = { linear: 0.5, angular: 0.5, centrifugal: 0.5 }
      setClothInertia(world, c, shares)
      setClothMotionConstraints(world, c, { maxDistance: painted() })
      let worst = 0
      for (let f = 1; f <= 240; f++) {
        setTransform(world, hero, [3 * f * DT, 1.6, 0]) // walking at 3 m/s
        if (detour && f === 60) setClothInertia(world, c, { ...shares, frame: null }) // e.g. a ragdoll moment
        if (detour && f === 61) setClothInertia(world, c, shares) // back to the default frame: the pins' target
        stepCloth(world, DT)
        if (f > 180) worst = Math.max(worst, getClothStretch(world, c).max)
      }
      // the reference's collar against the pinned collar
      const ref = getClothReference(world, c)!, s = getClothState(world, c)
      let off = 0
      for (let i = 0; i < COLS; i++)
        off = Math.max(off, Math.hypot(ref[3 * i] - s.pos[3 * i], ref[3 * i + 1] - s.pos[3 * i + 1], ref[3 * i + 2] - s.pos[3 * i + 2]))
      return { worst, off }
    }
    const plain = runCape(false), detour = runCape(true)
    // measured: 0.22 % and 0.32 %, the collar 7e-9 m off both times (5.0 cm and 15.7 % before)
    expect(detour.off).toBeLessThan(1e-4)
    expect(detour.worst).toBeLessThan(plain.worst + 0.02)
  })

  it("a skin bone removed while the character runs keeps its last pose in the cloth's frame: its part of the cape runs on with the character", () => {
    const world = installClothPlugin(createWorld())
    const hero = addEntity(world)
    setTransform(world, hero, [0, 1.6, 0])
    const c = cape(world, hero, true)
    const bones = skinToTwoBones(world, c)
    setClothInertia(world, c, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5 })
    setClothMotionConstraints(world, c, { maxDistance: painted() })
    let before = 0, after = 0
    for (let f = 1; f <= 120; f++) {
      const x = 3 * f * DT // walking at 3 m/s
      setTransform(world, hero, [x, 1.6, 0])
      setTransform(world, bones[0], [x, 1.6, 0])
      if (f < 60) setTransform(world, bones[1], [x, 1.2, 0])
      if (f === 60) removeEntity(world, bones[1]) // the hip bone goes (a dismembered or swapped skeleton part)
      stepCloth(world, DT)
      const s = getClothStretch(world, c).max
      if (f < 60) before = Math.max(before, s)
      else after = Math.max(after, s)
    }
    // measured: 1.6 % and 0.7 % (2174 % after, before the fix)
    expect(after).toBeLessThan(Math.max(0.05, 2 * before))
  })

  it("the removed bone's kept pose jumps with its frame: a 10 m teleport, a 180° snap and a 0.25 s hitch after it (the part weighted on it was held behind: 16,954 %, 33,592 %, 18 %)", () => {
    const run = (event: 'move' | 'snap' | 'hitch') => {
      const world = installClothPlugin(createWorld())
      const hero = addEntity(world)
      setTransform(world, hero, [0, 1.6, 0])
      const c = cape(world, hero, true)
      const bones = skinToTwoBones(world, c)
      setClothInertia(world, c, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5, teleport: { angle: Math.PI / 2 } })
      setClothMotionConstraints(world, c, { maxDistance: painted() })
      let before = 0, after = 0
      for (let f = 1; f <= 120; f++) {
        let p = [3 * f * DT, 1.6, 0], q = [0, 0, 0, 1] // walking at 3 m/s
        if (f >= 70 && event === 'move') p = [p[0] + 10, 1.6, 0]
        if (f >= 70 && event === 'snap') {
          q = yaw(Math.PI)
          p = [-p[0], 1.6, 0]
        }
        setTransform(world, hero, p, q)
        setTransform(world, bones[0], p, q)
        if (f < 60) setTransform(world, bones[1], [p[0], 1.2, 0])
        if (f === 60) removeEntity(world, bones[1])
        stepCloth(world, f === 70 && event === 'hitch' ? 0.25 : DT)
        const s = getClothStretch(world, c).max
        if (f < 60) before = Math.max(before, s)
        else after = Math.max(after, s)
      }
      return { before, after }
    }
    for (const event of ['move', 'snap', 'hitch'] as const) {
      const r = run(event)
      expect(r.after, event).toBeLessThan(Math.max(0.05, 2 * r.before))
    }
  })

  it('an unpinned skinned cape whose frame (its first bone, the default) is removed while it runs takes the next bone as its frame', () => {
    const world = installClothPlugin(createWorld())
    const c = cape(world, 0, false) // held by max distance 0 at the collar
    const bones = skinToTwoBones(world, c)
    setClothInertia(world, c, { linear: 0.5, angular: 0.5, centrifugal: 0.5 })
    setClothMotionConstraints(world, c, { maxDistance: painted() })
    let before = 0, after = 0
    for (let f = 1; f <= 120; f++) {
      const x = 3 * f * DT // walking at 3 m/s
      if (f < 60) setTransform(world, bones[0], [x, 1.6, 0])
      setTransform(world, bones[1], [x, 1.2, 0])
      if (f === 60) removeEntity(world, bones[0]) // the spine bone goes; the hip walks on
      stepCloth(world, DT)
      const s = getClothStretch(world, c).max
      if (f < 60) before = Math.max(before, s)
      else after = Math.max(after, s)
    }
    // measured: 1.6 % and 0.7 % (2174 % after, when the frame became the world)
    expect(after).toBeLessThan(Math.max(0.05, 2 * before))
  })

  // Found by a hunt (a death: the character entity goes, its ragdoll's bones slide on): given as the
  // frame explicitly, the removed first bone made the world the frame, which kept the bone's pose
  // where it went, and the collar with it: 12,702 % stretch, the collar 8.2 m behind the bones at
  // 4 m/s (1.17 m and 32 % when they slowed to rest). Here, slowing to rest: 34 % after, the collar
  // 0.93 m from where it hangs on the bone; measured now 0.6 % (0.7 % before the removal), 0.15 m
  // (its place on the bone).
  it.each([false, true])('the same with that bone given as the frame explicitly (pinned to it: %s): the next bone carries it', (pinned) => {
    const world = installClothPlugin(createWorld())
    const c = cape(world, 0, false)
    const bones = skinToTwoBones(world, c)
    if (pinned) pinRow(world, c, 0, bones[0])
    setClothInertia(world, c, { frame: bones[0], linear: 0.5, angular: 0.5, centrifugal: 0.5 })
    setClothMotionConstraints(world, c, { maxDistance: painted() })
    let before = 0, after = 0, x = 0
    for (let f = 1; f <= 150; f++) {
      x += (f < 60 ? 3 : Math.max(0, 3 - 6 * (f - 60) * DT)) * DT // walking at 3 m/s, then slowing to rest over 0.5 s
      if (f < 60) setTransform(world, bones[0], [x, 1.6, 0])
      setTransform(world, bones[1], [x, 1.2, 0])
      if (f === 60) removeEntity(world, bones[0])
      stepCloth(world, DT)
      const s = getClothStretch(world, c).max
      if (f < 60) before = Math.max(before, s)
      else after = Math.max(after, s)
    }
    expect(after).toBeLessThan(Math.max(0.05, 2 * before))
    // the collar stays with the bone that lives on (it stayed where the first bone went)
    expect(Math.abs(getClothState(world, c).pos[0] - x)).toBeLessThan(0.3)
  })
})

describe('a skinned cape with the world as its frame (frame: null) whose skeleton jumps 10 m', () => {
  // Its teleports are its first bone's jumps: before, nothing carried it, and its limits dragged it
  // across the 10 m (27 m/s, 12 % stretch); a reset left it at rest in the world under a walking
  // skeleton (swinging up to 7.4 m/s). Measured now: keep 1.2 %, 4.2 m/s; reset 0.6 %, 3.8 m/s.
  it.each(['keep', 'reset'] as const)("teleport '%s': carried or reset, as with its first bone as the frame", (mode) => {
    const run = (frame: 'bone' | 'world') => {
      const world = installClothPlugin(createWorld())
      const c = cape(world, 0, false) // held by max distance 0 at the collar
      const bones = skinToTwoBones(world, c)
      setClothInertia(world, c, frame === 'world' ? { frame: null, teleport: { mode } } : { teleport: { mode } })
      setClothMotionConstraints(world, c, { maxDistance: painted() })
      let stretch = 0, speed = 0
      for (let f = 1; f <= 120; f++) {
        const x = 3 * f * DT + (f >= 60 ? 10 : 0) // walking at 3 m/s, 10 m on at frame 60
        setTransform(world, bones[0], [x, 1.6, 0])
        setTransform(world, bones[1], [x, 1.2, 0])
        stepCloth(world, DT)
        if (f >= 60) {
          stretch = Math.max(stretch, getClothStretch(world, c).max)
          speed = Math.max(speed, fastest(world, c))
        }
      }
      return { stretch, speed }
    }
    const world = run('world'), bone = run('bone')
    expect(world.stretch).toBeLessThan(Math.max(0.03, 2 * bone.stretch))
    expect(world.speed).toBeLessThan(1.5 * Math.max(bone.speed, 3))
  })
})

describe('an explicit frame entity removed while the cape runs at a steady 5 m/s', () => {
  // The frame became the world, but kept its motion history, which the next step took for the frame
  // stopping dead: the free particles' mean velocity jumped by 4.4 m/s at shares 0, 2.4 at 0.5
  // (found by a hunt). A frame changed by a call already started afresh.
  it.each([0, 0.5])('shares %s: no jolt (the entity removed, or its Transform)', (share) => {
    for (const how of ['entity', 'transform'] as const) {
      const world = installClothPlugin(createWorld())
      const hero = addEntity(world), chest = addEntity(world)
      setTransform(world, hero, [0, 1.6, 0])
      setTransform(world, chest, [0, 1.6, 0])
      const c = cape(world, hero, true)
      setClothInertia(world, c, { frame: chest, linear: share, angular: share, centrifugal: share })
      const st = getClothState(world, c)
      for (let i = 0; i < st.count; i++) st.vel[3 * i] = 5 // moving with the hero from the start
      const mean: number[] = []
      for (let f = 1; f <= 100; f++) {
        setTransform(world, hero, [5 * f * DT, 1.6, 0])
        if (f < 90) setTransform(world, chest, [5 * f * DT, 1.6, 0])
        if (f === 90) {
          if (how === 'entity') removeEntity(world, chest)
          else removeComponent(world, chest, getClothComponents(world).Transform)
        }
        stepCloth(world, DT)
        let v = 0, n = 0
        for (let i = 0; i < st.count; i++) {
          if (st.invMass[i] === 0) continue
          v += st.vel[3 * i]
          n++
        }
        mean.push(v / n)
      }
      expect(Math.abs(mean[89] - mean[88]), how).toBeLessThan(0.1)
    }
  })
})

/**
 * A skinned cape with no pins on two bones (the first its default frame), held at the collar by
 * max distance 0, walking at 3 m/s under a budget that freezes it while its viewer is 60 m away
 * (frames 30–100). Its first or its hip bone is removed before or during the freeze. Returns the
 * worst edge stretch from frame 35 on.
 */
function frozenWithoutBone(removeAt: number, which: number): number {
  const world = installClothPlugin(createWorld())
  const eye = addEntity(world)
  setTransform(world, eye, [2, 1.5, 0])
  const c = cape(world, 0, false)
  const bones = skinToTwoBones(world, c)
  setClothInertia(world, c, { linear: 0.5, angular: 0.5, centrifugal: 0.5 })
  setClothMotionConstraints(world, c, { maxDistance: painted() })
  setClothBudget(world, { viewer: eye, near: 5, far: 26, cull: 42, farStepEvery: 4, calibration: CAL, adapt: false, interval: 1 })
  let stretch = 0
  const alive = [true, true]
  for (let f = 1; f <= 160; f++) {
    const x = (3 * f) / 60
    if (f === removeAt) {
      removeEntity(world, bones[which])
      alive[which] = false
    }
    if (alive[0]) setTransform(world, bones[0], [x, 1.6, 0])
    if (alive[1]) setTransform(world, bones[1], [x, 1.2, 0])
    setTransform(world, eye, [x + (f < 30 || f >= 100 ? 2 : 60), 1.5, 0])
    stepCloth(world, DT)
    if (f === 60) expect(getClothLod(world, c).frozen).toBe(true)
    if (f >= 35) stretch = Math.max(stretch, getClothStretch(world, c).max)
  }
  return stretch
}

describe('a frozen skinned cape whose bone is removed before or during the freeze', () => {
  // the removed bone's pose is kept in the terms of the frame's pose at the cloth's last step, and
  // carried over the gap by the frame's motion: kept as it was and not carried over the gap, the
  // part weighted on it stayed where the freeze left it, 1667–2720 % stretch for good
  const kept = frozenWithoutBone(-1, 0)
  for (
    const [name, at, which] of [
      ['the first bone (its frame) removed before the freeze', 20, 0],
      ['the first bone (its frame) removed while frozen', 60, 0],
      ['the hip bone removed before the freeze', 20, 1],
      ['the hip bone removed while frozen', 60, 1],
    ] as const
  ) {
    it(`${name}: thaws as the cape whose bones all stay (edge stretch within 1.2×, under 30 %)`, () => {
      const s = frozenWithoutBone(at, which)
      expect(kept).toBeLessThan(0.3)
      expect(s).toBeLessThan(Math.max(1.2 * kept, 0.05))
    })
  }
})

describe('a constrained cape whose character is removed while it runs', () => {
  // its frame became the still world with the reference where the character vanished, and the
  // max distance 0 at its collar nailed it there, in mid-air (a banner on a truck at 50 m/s, a
  // caped runner at 5 m/s); without the constraints it was let go with its pins, and flew on
  const run = (constrained: boolean, explicit: boolean) => {
    const world = installClothPlugin(createWorld(), { sleep: false })
    const hero = addEntity(world)
    setTransform(world, hero, [0, 1.6, 0])
    const cape = createCloth(world, { width: 0.6, height: 1, resolution: [8, 12], position: [0, 1.6, -0.2], rotation: [0, 1, 0, 0] })
    pinRow(world, cape, 0, hero)
    setClothInertia(world, cape, { ...(explicit ? { frame: hero } : {}), linear: 0.5, angular: 0.5, centrifugal: 0.5 })
    const maxDistance = Array.from({ length: 96 }, (_, i) => 0.6 * (Math.floor(i / 8) / 11) ** 2)
    if (constrained) setClothMotionConstraints(world, cape, { maxDistance, backstop: { distance: 0.02, radius: 0.5 } })
    const c = getClothState(world, cape)
    for (let f = 1; f <= 150; f++) {
      if (f < 90) setTransform(world, hero, [0, 1.6, zAt(f)], [0, 1, 0, 0])
      if (f === 90) removeEntity(world, hero)
      stepCloth(world, DT)
    }
    return { y: c.pos[1], z: c.pos[2] }
  }
  /** Along +z, reaching 5 m/s in 1 s. */
  const zAt = (f: number) => (f <= 60 ? (2.5 * (f / 60) ** 2) : 2.5 + 5 * ((f - 60) / 60))
  for (const explicit of [true, false]) {
    it(`is let go as its pins are: it flies on and falls as without the constraints (${explicit ? 'explicit' : 'default'} frame)`, () => {
      const free = run(false, explicit), held = run(true, explicit)
      // 1 s after: the collar fell (½·g·t² = 4.9 m without drag) from 1.6 m and flew on past where
      // the character vanished (z = 4.9 m); nailed, it stayed at 1.6 m, z 5.1 m
      for (const r of [free, held]) {
        expect(r.y).toBeLessThan(-1)
        expect(r.z).toBeGreaterThan(zAt(89) + 1)
      }
    })
  }
})

describe('an awning with world-space limits (frame null) pinned to two poles, one removed', () => {
  // Its frame is the world by choice: the pole that went was never its frame, so its limits stay
  // (they were lifted with the pole, and the awning fell 2.08 m in 1 s).
  it('keeps its motion constraints: every particle within its max distance of where it lay', () => {
    const world = installClothPlugin(createWorld(), { sleep: false })
    const poleA = addEntity(world), poleB = addEntity(world)
    setTransform(world, poleA, [-0.5, 2, 0])
    setTransform(world, poleB, [0.5, 2, 0])
    const cloth = createCloth(world, {
      width: 1,
      height: 1,
      resolution: 8,
      position: [0, 2, 0],
      rotation: [-Math.SQRT1_2, 0, 0, Math.SQRT1_2],
    })
    const c = getClothState(world, cloth)
    const rest = c.pos.slice(0, 3 * c.count)
    for (let i = 0; i < 8; i++) pinParticle(world, cloth, i, i < 4 ? poleA : poleB)
    setClothInertia(world, cloth, { frame: null })
    setClothMotionConstraints(world, cloth, { maxDistance: 0.05 })
    for (let f = 0; f < 30; f++) stepCloth(world, DT)
    removeEntity(world, poleA)
    expect(getClothReference(world, cloth)).not.toBeNull()
    for (let f = 0; f < 60; f++) stepCloth(world, DT)
    let worst = 0
    for (let i = 0; i < c.count; i++)
      worst = Math.max(
        worst,
        Math.hypot(c.pos[3 * i] - rest[3 * i], c.pos[3 * i + 1] - rest[3 * i + 1], c.pos[3 * i + 2] - rest[3 * i + 2]),
      )
    expect(worst).toBeLessThan(0.05 + 2e-3)
  })
})
