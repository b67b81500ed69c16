import { addEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  ClothError,
  addCapsuleCollider,
  createCloth,
  createWindZone,
  getClothState,
  getClothStretch,
  getGrabForce,
  getGrabParticle,
  getGrabs,
  grabParticle,
  getClothLod,
  gustWind,
  isClothSleeping,
  isGrabActive,
  makeTearable,
  moveGrab,
  pinParticle,
  pinRow,
  releaseGrab,
  removeCloth,
  restoreClothState,
  saveClothState,
  setClothInertia,
  setClothVisible,
  setClothBudget,
  setClothMotionConstraints,
  setTransform,
  stepCloth,
  unpin,
} from '../src/index'
import { getClothWorld } from '../src/world/access'
import { RUN_COLS, RUN_ROWS, runningCape as capeOnRunner } from './character/scenes'
import { allFinite, hashBytes, makeWorld, momentum } from './helpers'

const DT = 1 / 60

const G0 = 9.81

function clothMass(world: object, cloth: number): number {
  const c = getClothState(world, cloth)
  let m = 0
  for (let i = 0; i < c.count; i++) m += 1 / c.baseInvMass[i]
  return m
}

function at(world: object, cloth: number, i: number): number[] {
  const c = getClothState(world, cloth)
  return [c.pos[3 * i], c.pos[3 * i + 1], c.pos[3 * i + 2]]
}

/**
 * A character running along +x (accelerating to 5 m/s in the first second), a wool cape pinned to
 * its shoulders and a torso capsule. After 1 s a hand takes particle `index` where it is and holds
 * that point still for 4 s: with a grab, or (`pin`) with a world pin, as the demo's mouse did.
 * Returns the largest edge stretch seen while held.
 */
function runningCape(index: number, hold: 'grab' | 'pin', tethers = true) {
  const world = makeWorld({ sleep: false })
  const hero = addEntity(world)
  setTransform(world, hero, [0, 0, 0])
  addCapsuleCollider(world, addEntity(world), { body: hero, offset: [0, 1.15, 0], radius: 0.19, halfHeight: 0.22 })
  const facingX = [0, Math.SQRT1_2, 0, Math.SQRT1_2]
  const cape = createCloth(world, {
    width: 0.55,
    height: 1.05,
    resolution: [14, 24],
    position: [-0.2, 1.47, 0],
    rotation: facingX,
    material: 'wool',
    substeps: 8,
    iterations: 1,
    tethers,
  })
  pinRow(world, cape, 0, hero)
  let x = 0, v = 0, max = 0, grab = -1, maxForce = 0
  for (let f = 0; f < 300; f++) {
    v = Math.min(5, v + 5 / 60)
    x += v / 60
    setTransform(world, hero, [x, 0, 0])
    if (f === 60) {
      if (hold === 'grab') grab = grabParticle(world, cape, index, at(world, cape, index))
      else pinParticle(world, cape, index)
    }
    stepCloth(world, 1 / 60)
    if (f < 60) continue
    max = Math.max(max, getClothStretch(world, cape).max)
    if (grab > 0) {
      const F = getGrabForce(world, grab)
      maxForce = Math.max(maxForce, Math.hypot(F[0], F[1], F[2]))
    }
  }
  return { world, cape, max, maxForce, x }
}

describe('grab: a hand on a moving cloth', () => {
  it('holding a running cape (5 m/s) still stretches it at most 23–31 %; a pin there stretches it to hundreds of times its size', () => {
    const seen: Record<string, string> = {}
    // measured 27.7, 31.3 and 23.1 % (README: 23–31 %); bound about 20 % above each
    for (const [row, bound] of [[5, 0.33], [12, 0.37], [23, 0.28]]) {
      const index = row * 14 + 7
      const held = runningCape(index, 'grab')
      seen[`row ${row}`] = `${(100 * held.max).toFixed(1)} %`
      expect(held.max, `row ${row}`).toBeLessThan(bound)
      expect(held.max, `row ${row}`).toBeGreaterThan(0.1) // the hand does pull
      expect(allFinite(held.world, held.cape)).toBe(true)
      // the cape slipped out of the hand and ran on with the character: its grabbed particle is
      // within a cape's length of the shoulders, not back where the hand is
      const p = at(held.world, held.cape, index)
      expect(held.x - p[0]).toBeLessThan(1.3)
      // the grip pulled as hard as it may (twice the cape's weight) and no harder
      const limit = 2 * clothMass(held.world, held.cape) * G0
      expect(held.maxForce).toBeGreaterThan(0.99 * limit)
      expect(held.maxForce).toBeLessThanOrEqual(limit * (1 + 1e-9))
    }
    const pinned = runningCape(23 * 14 + 7, 'pin').max
    seen.pin = `${(100 * pinned).toFixed(0)} %`
    console.log('largest stretch holding a running cape', seen)
    // measured 22,834 % (README)
    expect(pinned).toBeGreaterThan(180)
    expect(pinned).toBeLessThan(275)
  })

  it('without tethers too: at most 36–41 %', () => {
    const seen: Record<string, string> = {}
    // measured 39.6, 41.4 and 36.0 % (README: 36–41 %); bound about 15 % above each
    for (const [row, bound] of [[5, 0.46], [12, 0.48], [23, 0.42]]) {
      const max = runningCape(row * 14 + 7, 'grab', false).max
      seen[`row ${row}`] = `${(100 * max).toFixed(1)} %`
      expect(max, `row ${row}`).toBeLessThan(bound)
      expect(max, `row ${row}`).toBeGreaterThan(0.1)
    }
    console.log('largest stretch holding a running cape without tethers', seen)
  })

  it('a flag in gusty wind held at its fly end, or dragged 2 m away, keeps a bounded stretch, 41 and 35 % (a pin dragged there: tens of times its size)', () => {
    const flag = (hold: 'grab' | 'pin', dx: number) => {
      const world = makeWorld({ sleep: false })
      const cols = 30, rows = 20
      const cloth = createCloth(world, {
        width: 1.5,
        height: 1,
        resolution: [cols, rows],
        position: [0.75, 3.4, 0],
        material: 'nylon',
        substeps: 8,
        iterations: 3,
      })
      for (let r = 0; r < rows; r++) pinParticle(world, cloth, r * cols)
      const wind = createWindZone(world, { direction: [0.4, 0, -1], strength: 9, turbulence: 0.35, turbulenceScale: 1.5, seed: 7 })
      const index = 10 * cols + cols - 1
      let max = 0
      for (let f = 0; f < 420; f++) {
        if (f === 120) {
          const p = at(world, cloth, index)
          const target = [p[0] + dx, p[1] - dx, p[2] + dx]
          if (hold === 'grab') grabParticle(world, cloth, index, target)
          else pinParticle(world, cloth, index, null, target)
        }
        if (f % 150 === 0) gustWind(world, wind, { strength: 9, duration: 1.6 })
        stepCloth(world, 1 / 60)
        if (f >= 120) max = Math.max(max, getClothStretch(world, cloth).max)
      }
      expect(allFinite(world, cloth)).toBe(true)
      return max
    }
    const seen: Record<string, string> = {}
    // measured 40.7 and 34.5 % (README: 41 and 35 %); bound about 15 % above each
    for (const [dx, bound] of [[0, 0.47], [2, 0.4]]) {
      const max = flag('grab', dx)
      seen[`grab ${dx} m`] = `${(100 * max).toFixed(1)} %`
      expect(max, `${dx} m`).toBeLessThan(bound)
      expect(max, `${dx} m`).toBeGreaterThan(0.1)
    }
    const pinned = flag('pin', 2)
    seen['pin 2 m'] = `${(100 * pinned).toFixed(0)} %`
    console.log('largest stretch holding a flag in gusty wind', seen)
    // measured 3,439 % (README)
    expect(pinned).toBeGreaterThan(27.5)
    expect(pinned).toBeLessThan(41)
  })
})

describe('grab: across a teleport', () => {
  it('a hand that follows its character across a 10 m teleport does not drag the carried cape back over the gap', () => {
    // the cape is carried by the teleport; the grab's target glided from where it was before the
    // jump, pulling the hem back across the gap (5.3 m/s relative to the character, 9.7 % stretch,
    // against 0.5 m/s and 6.5 % in the same run without the jump)
    const run = (jump: boolean, inertia: boolean) => {
      const { world, hero, cape } = capeOnRunner(null)
      if (!inertia) setClothInertia(world, cape, null)
      const c = getClothState(world, cape)
      const hem = RUN_COLS * (RUN_ROWS - 1) + 4
      let grab = -1, relative = 0, stretch = 0
      for (let f = 1; f <= 70; f++) {
        const x = jump && f >= 61 ? 10 : 0, z = (3 * f) / 60
        setTransform(world, hero, [x, 0, z])
        if (f === 30) grab = grabParticle(world, cape, hem, [x, 0.6, z - 0.6])
        if (f > 30) moveGrab(world, grab, [x, 0.6, z - 0.6])
        stepCloth(world, DT)
        if (f === 61) {
          relative = Math.hypot(c.vel[3 * hem], c.vel[3 * hem + 1], c.vel[3 * hem + 2] - 3)
          stretch = getClothStretch(world, cape).max
        }
      }
      expect(allFinite(world, cape)).toBe(true)
      return { relative, stretch }
    }
    for (const inertia of [false, true]) {
      const still = run(false, inertia), jumped = run(true, inertia)
      console.log(
        `${inertia ? 'inertia 0.5' : 'world space'}: hem ${jumped.relative.toFixed(2)} m/s relative to the character at the teleport (${
          still.relative.toFixed(2)
        } without it), stretch ${(100 * jumped.stretch).toFixed(1)} % (${(100 * still.stretch).toFixed(1)} %)`,
      )
      expect(jumped.relative).toBeLessThan(still.relative + 0.1)
      expect(jumped.stretch).toBeLessThan(still.stretch + 0.01)
    }
  })

  /**
   * A 1 m sheet held by its top row (pinned to a pole entity, or held by its character frame at max
   * distance 0 with a teleport mode), a hand tears its lower middle off and then holds that piece
   * still 1.5 m below; the holder jumps 10 m or not. Returns the held particle's top speed after.
   */
  function heldPieceAcrossJump(holder: 'pole' | 'keep' | 'reset', jump: boolean, maxForce?: number): number {
    const world = makeWorld({ sleep: false })
    const pole = addEntity(world)
    setTransform(world, pole, [0, 2, 0])
    const n = 12
    const cloth = createCloth(world, { width: 1, height: 1, resolution: n, position: [0, 2, 0], iterations: 2, tethers: false })
    if (holder === 'pole') pinRow(world, cloth, 0, pole)
    else {
      setClothInertia(world, cloth, { frame: pole, linear: 1, angular: 1, centrifugal: 1, teleport: { mode: holder } })
      setClothMotionConstraints(world, cloth, { maxDistance: Array.from({ length: n * n }, (_, i) => (i < n ? 0 : Infinity)) })
      for (let f = 0; f < 30; f++) stepCloth(world, DT)
    }
    makeTearable(world, cloth, { strain: 0.15, maxTearsPerStep: 16 })
    const c = getClothState(world, cloth)
    const index = (n - 1) * n + n / 2
    const s = Array.from(c.pos.subarray(3 * index, 3 * index + 3))
    const hand = [s[0], s[1] - 1.5, s[2]]
    const tear = grabParticle(world, cloth, index, s, { maxForce: 60 })
    for (let f = 1; f <= 120; f++) {
      moveGrab(world, tear, [s[0], s[1] - Math.min(1.5, f / 40), s[2]])
      stepCloth(world, DT)
    }
    releaseGrab(world, tear)
    const hold = grabParticle(world, cloth, index, hand, { maxForce })
    for (let f = 0; f < 60; f++) stepCloth(world, DT)
    expect(Array.from(c.detached.subarray(1, 1 + c.detached[0]))).toContain(index) // (torn off: a loose piece)
    if (jump) setTransform(world, pole, [10, 2, 0])
    let fastest = 0
    for (let f = 0; f < 30; f++) {
      moveGrab(world, hold, hand)
      stepCloth(world, DT)
      fastest = Math.max(fastest, Math.hypot(c.vel[3 * index], c.vel[3 * index + 1], c.vel[3 * index + 2]))
    }
    return fastest
  }

  it('a hand holding a piece torn off a banner keeps it still when the pole jumps 10 m: the teleport leaves the piece, and its hand, where they are', () => {
    // (the hand's glide was carried with the banner while its piece was put back: the piece was
    // dragged 0.34 m toward the pole at 17.8 m/s, 117 m/s with a 60 N grip; found by a hunt)
    for (const maxForce of [undefined, 60]) {
      const still = heldPieceAcrossJump('pole', false, maxForce)
      expect(heldPieceAcrossJump('pole', true, maxForce), `maxForce ${maxForce}`).toBeLessThan(still + 0.05)
    }
  })

  it("likewise on a character cloth held by its frame, in both teleport modes ('reset' puts the rest on its reference, not the piece)", () => {
    // (the reset carried every hand's glide with the frame: 17.5 m/s, 119 at a 60 N grip; a review hunt)
    for (const mode of ['keep', 'reset'] as const) {
      expect(heldPieceAcrossJump(mode, true, 60), mode).toBeLessThan(heldPieceAcrossJump(mode, false, 60) + 0.05)
    }
  })
})

describe('grab: the force', () => {
  /** A free sheet in zero gravity, no damping, yanked by a grab toward a point 5 m away. */
  function yank(maxForce: number | undefined, iterations = 1) {
    const world = makeWorld({ sleep: false, gravity: [0, 0, 0] })
    const cloth = createCloth(world, {
      width: 1,
      height: 1,
      resolution: 12,
      position: [0, 2, 0],
      substeps: 8,
      iterations,
      damping: 0,
      stretchDamping: 0,
      tethers: false,
    })
    const grab = grabParticle(world, cloth, 6 * 12 + 6, [0, 2, 5], { maxForce })
    return { world, cloth, grab }
  }

  it("is the rate of change of the cloth's momentum (F = dp/dt), never above maxForce, saturated when the target is far", () => {
    for (const iterations of [1, 4]) {
      const { world, cloth, grab } = yank(0.3, iterations)
      let before = momentum(world, cloth)
      for (let f = 0; f < 40; f++) {
        stepCloth(world, 1 / 60)
        const now = momentum(world, cloth)
        const dp = Math.hypot(now[0] - before[0], now[1] - before[1], now[2] - before[2]) * 60
        const F = getGrabForce(world, grab)
        const reported = Math.hypot(F[0], F[1], F[2])
        // internal constraints conserve momentum: the grab is the only external force
        expect(dp).toBeLessThanOrEqual(0.3 * (1 + 1e-6))
        expect(Math.abs(dp - reported)).toBeLessThan(1e-6)
        if (f > 0) expect(dp).toBeGreaterThan(0.3 * 0.999) // 5 m away: the grip pulls as hard as it may
        before = now
      }
      // and the cloth, pulled toward +z (a little sideways as it folds), gained at most F·t of
      // momentum, nearly all of it along z (Newton's second law: the centre of mass at F/M)
      const p = momentum(world, cloth)
      expect(Math.hypot(p[0], p[1], p[2])).toBeLessThanOrEqual(0.3 * (40 / 60) * (1 + 1e-6))
      expect(p[2]).toBeGreaterThan(0.3 * (40 / 60) * 0.98)
    }
  })

  it("the default grip is twice the cloth's weight", () => {
    const { world, cloth, grab } = yank(undefined)
    stepCloth(world, 1 / 60)
    const F = getGrabForce(world, grab)
    expect(Math.hypot(F[0], F[1], F[2]) / (2 * clothMass(world, cloth) * G0)).toBeCloseTo(1, 5)
  })

  it('a still grab on a swinging cloth never adds energy: it damps the swing out', () => {
    const world = makeWorld({ sleep: false })
    const n = 10
    const cloth = createCloth(world, {
      width: 1,
      height: 1,
      resolution: n,
      position: [0, 2, 0],
      substeps: 8,
      iterations: 2,
      tethers: false,
    })
    pinParticle(world, cloth, 0)
    pinParticle(world, cloth, n - 1)
    const c = getClothState(world, cloth)
    // give it a swing: the whole sheet moving sideways at 1 m/s
    for (let i = 0; i < c.count; i++) if (c.invMass[i] > 0) c.vel[3 * i + 2] = 1
    const energy = () => {
      let e = 0
      for (let i = 0; i < c.count; i++) {
        if (c.invMass[i] === 0) continue
        const m = 1 / c.invMass[i]
        e += 0.5 * m * (c.vel[3 * i] ** 2 + c.vel[3 * i + 1] ** 2 + c.vel[3 * i + 2] ** 2) + m * G0 * c.pos[3 * i + 1]
      }
      return e
    }
    const index = (n - 1) * n + n / 2
    const grab = grabParticle(world, cloth, index, at(world, cloth, index), { compliance: 1e-3, maxForce: 50 })
    const e0 = energy()
    let peak = -Infinity, last = 0
    for (let f = 0; f < 600; f++) {
      stepCloth(world, 1 / 60)
      const F = getGrabForce(world, grab)
      // the grip's own spring energy, ½·α·F²
      last = energy() + 0.5 * 1e-3 * (F[0] ** 2 + F[1] ** 2 + F[2] ** 2)
      peak = Math.max(peak, last)
    }
    expect(peak).toBeLessThanOrEqual(e0 + 1e-6)
    let ke = 0
    for (let i = 0; i < c.count; i++) ke += c.vel[3 * i] ** 2 + c.vel[3 * i + 1] ** 2 + c.vel[3 * i + 2] ** 2
    expect(Math.sqrt(ke / c.count)).toBeLessThan(0.01)
    expect(last).toBeLessThan(e0)
  })
})

describe('grab: moving, releasing', () => {
  it('a hand moving at a steady speed drags a free cloth along at that speed; released, the particle keeps its velocity (no pop)', () => {
    const world = makeWorld({ sleep: false, gravity: [0, 0, 0] })
    const cloth = createCloth(world, {
      width: 0.5,
      height: 0.5,
      resolution: 8,
      position: [0, 2, 0],
      substeps: 8,
      iterations: 2,
      damping: 0,
      tethers: false,
    })
    const index = 0
    const start = at(world, cloth, index)
    const grab = grabParticle(world, cloth, index, start, { maxForce: 100 })
    const c = getClothState(world, cloth)
    for (let f = 1; f <= 120; f++) {
      moveGrab(world, grab, [start[0] + (2 * f) / 60, start[1], start[2]])
      stepCloth(world, 1 / 60)
    }
    const vBefore = c.vel[3 * index]
    expect(vBefore).toBeGreaterThan(1.8)
    expect(vBefore).toBeLessThan(2.2)
    expect(releaseGrab(world, grab)).toBe(true)
    stepCloth(world, 1 / 60)
    // no gravity, no damping: only the cloth's internal constraints change its velocity now, and
    // they had been carrying it along at the hand's speed
    expect(Math.abs(c.vel[3 * index] - vBefore)).toBeLessThan(0.1)
    // the cloth as a whole keeps the momentum the hand gave it
    const p = momentum(world, cloth)
    expect(p[0] / clothMass(world, cloth)).toBeGreaterThan(1.8)
  })

  it('the target glides over the frame: 30 fps frames give the path of 60 fps frames', () => {
    const path = (fps: number) => {
      const world = makeWorld({ sleep: false })
      const cloth = createCloth(world, { width: 0.5, height: 0.5, resolution: 8, position: [0, 2, 0], substeps: 4 })
      pinParticle(world, cloth, 0)
      const grab = grabParticle(world, cloth, 63, at(world, cloth, 63))
      const start = at(world, cloth, 63)
      for (let f = 1; f <= fps; f++) {
        moveGrab(world, grab, [start[0] + (0.5 * f) / fps, start[1], start[2] + (0.5 * f) / fps])
        stepCloth(world, 1 / fps)
      }
      return at(world, cloth, 63)
    }
    const a = path(60), b = path(30)
    expect(Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2])).toBeLessThan(1e-9)
  })

  it('the glide keeps pace with a steady hand at frames that are not whole steps (59.94 Hz, 1/50 and 1/70 s, 144 Hz)', () => {
    // (the glide started where the last step left the target, short of the last frame sample by
    // the time still in the accumulator: each step fell behind by a share of the gap, and the frame
    // running two steps snapped the target onto the hand: 1.01 m behind at 59.94 Hz, found by a hunt)
    const path = (frames: number[]) => {
      const world = makeWorld({ sleep: false, gravity: [0, 0, 0] })
      const cloth = createCloth(world, { width: 0.5, height: 0.5, resolution: 8, position: [0, 2, 0], damping: 0 })
      const start = at(world, cloth, 27)
      const hand = (t: number) => [start[0] + 2 * t, start[1], start[2]] // 2 m/s along x
      const grab = grabParticle(world, cloth, 27, hand(0))
      const state = getClothWorld(world)
      let t = 0, worst = 0
      for (let f = 0; t < 17; f++) {
        const dt = frames[f % frames.length]
        t += dt
        moveGrab(world, grab, hand(t))
        if (stepCloth(world, dt) === 0 || t < 1) continue
        // the hand where the last step ended
        worst = Math.max(worst, Math.abs(at(world, cloth, 27)[0] - hand(t - state.accumulator)[0]))
      }
      return worst
    }
    const steady = path([1 / 60])
    // (17 s: at 59.94 Hz the accumulator's phase takes about that long to drift by a whole step)
    for (const frames of [[1 / 59.94], [1 / 50, 1 / 70], [1 / 144]]) {
      const off = path(frames)
      expect(off, `${frames.map((d) => (1 / d).toFixed(2)).join('/')} Hz`).toBeLessThan(steady + 0.005)
    }
  })

  it('a grab wakes a sleeping cloth when it moves', () => {
    const world = makeWorld()
    const cloth = createCloth(world, { width: 0.5, height: 0.5, resolution: 6, position: [0, 2, 0] })
    pinRow(world, cloth, 0)
    const grab = grabParticle(world, cloth, 33, at(world, cloth, 33))
    for (let f = 0; f < 600 && !isClothSleeping(world, cloth); f++) stepCloth(world, 1 / 60)
    expect(isClothSleeping(world, cloth)).toBe(true)
    const p = at(world, cloth, 33)
    moveGrab(world, grab, [p[0], p[1], p[2] + 0.3])
    expect(isClothSleeping(world, cloth)).toBe(false)
    for (let f = 0; f < 60; f++) stepCloth(world, 1 / 60)
    expect(at(world, cloth, 33)[2] - p[2]).toBeGreaterThan(0.2)
  })
})

describe('grab: which particles, which lifetimes', () => {
  it('a pinned particle stays on its pin; unpinned, the grab pulls it', () => {
    const world = makeWorld({ sleep: false })
    const cloth = createCloth(world, { width: 0.5, height: 0.5, resolution: 6, position: [0, 2, 0] })
    const pin = pinParticle(world, cloth, 0)
    pinParticle(world, cloth, 5)
    const p = at(world, cloth, 0)
    const target = [p[0] + 0.2, p[1] - 0.2, p[2] + 0.2]
    const grab = grabParticle(world, cloth, 0, target)
    for (let f = 0; f < 30; f++) stepCloth(world, 1 / 60)
    expect(at(world, cloth, 0)).toEqual(p)
    expect(getGrabForce(world, grab)).toEqual([0, 0, 0])
    unpin(world, pin)
    for (let f = 0; f < 120; f++) stepCloth(world, 1 / 60)
    const q = at(world, cloth, 0)
    expect(Math.hypot(q[0] - target[0], q[1] - target[1], q[2] - target[2])).toBeLessThan(0.02)
  })

  it('a torn cloth: the grab keeps its particle, which stays on the piece the hand holds', () => {
    const world = makeWorld({ sleep: false })
    const n = 12
    const cloth = createCloth(world, {
      width: 1,
      height: 1,
      resolution: n,
      position: [0, 2, 0],
      substeps: 8,
      iterations: 2,
      tethers: false,
    })
    pinRow(world, cloth, 0)
    makeTearable(world, cloth, { strain: 0.15, maxTearsPerStep: 8 })
    const index = (n - 1) * n + n / 2
    const start = at(world, cloth, index)
    const grab = grabParticle(world, cloth, index, start, { maxForce: 60 })
    for (let f = 1; f <= 180; f++) {
      moveGrab(world, grab, [start[0], start[1] - Math.min(3, f / 30), start[2]])
      stepCloth(world, 1 / 60)
    }
    const c = getClothState(world, cloth)
    expect(c.pieceCount).toBeGreaterThan(1) // the hand tore a piece off
    expect(getGrabParticle(world, grab)).toBe(index)
    expect(allFinite(world, cloth)).toBe(true)
    // the torn-off piece follows the hand down
    expect(at(world, cloth, index)[1]).toBeLessThan(start[1] - 1.5)
  })

  it('removing the cloth ends its grabs; a recycled cloth id never picks up an old grab', () => {
    const world = makeWorld()
    const a = createCloth(world, { width: 0.5, height: 0.5, resolution: 4, position: [0, 2, 0] })
    const grab = grabParticle(world, a, 5, [0, 3, 0])
    removeCloth(world, a)
    expect(isGrabActive(world, grab)).toBe(false)
    expect(releaseGrab(world, grab)).toBe(false)
    expect(() => moveGrab(world, grab, [0, 0, 0])).toThrow(ClothError)
    // bitECS recycles the entity id
    let b = -1
    for (let k = 0; k < 2000 && b !== a; k++) b = createCloth(world, { width: 0.5, height: 0.5, resolution: 4, position: [0, 2, 0] })
    expect(b).toBe(a)
    expect(getGrabs(world, b)).toEqual([])
    expect(isGrabActive(world, grab)).toBe(false)
    const fresh = grabParticle(world, b, 5, [0, 3, 0])
    expect(fresh).not.toBe(grab)
    expect(() => getGrabForce(world, grab)).toThrow(/not an active grab/)
  })

  it('released grabs are gone; several grabs on one cloth keep their order', () => {
    const world = makeWorld()
    const cloth = createCloth(world, { width: 0.5, height: 0.5, resolution: 4, position: [0, 2, 0] })
    const g = [1, 2, 3].map((i) => grabParticle(world, cloth, i, [0, 2, 0]))
    expect(getGrabs(world, cloth)).toEqual(g)
    expect(releaseGrab(world, g[1])).toBe(true)
    expect(releaseGrab(world, g[1])).toBe(false)
    expect(getGrabs(world, cloth)).toEqual([g[0], g[2]])
    expect(getGrabParticle(world, g[2])).toBe(3)
  })
})

describe('grab: bad input', () => {
  const world = makeWorld()
  const cloth = createCloth(world, { width: 0.5, height: 0.5, resolution: 4, position: [0, 2, 0] })
  const cases: [string, () => unknown, string][] = [
    ['cloth', () => grabParticle(world, 9999, 0, [0, 0, 0]), 'cloth'],
    ['index out of range', () => grabParticle(world, cloth, 16, [0, 0, 0]), 'index'],
    ['index not an integer', () => grabParticle(world, cloth, 1.5, [0, 0, 0]), 'index'],
    ['target NaN', () => grabParticle(world, cloth, 0, [0, NaN, 0]), 'target'],
    ['target short', () => grabParticle(world, cloth, 0, [0, 0] as never), 'target'],
    ['options', () => grabParticle(world, cloth, 0, [0, 0, 0], null as never), 'options'],
    ['maxForce 0', () => grabParticle(world, cloth, 0, [0, 0, 0], { maxForce: 0 }), 'options.maxForce'],
    ['maxForce Infinity', () => grabParticle(world, cloth, 0, [0, 0, 0], { maxForce: Infinity }), 'options.maxForce'],
    ['compliance negative', () => grabParticle(world, cloth, 0, [0, 0, 0], { compliance: -1 }), 'options.compliance'],
    ['compliance 1e308', () => grabParticle(world, cloth, 0, [0, 0, 0], { compliance: 1e308 }), 'options.compliance'],
    ['grab handle garbage', () => moveGrab(world, 'x' as never, [0, 0, 0]), 'grab'],
    ['grab handle 0', () => releaseGrab(world, 0), 'grab'],
    ['grab never made', () => moveGrab(world, 123456, [0, 0, 0]), 'grab'],
    ['moveGrab target', () => moveGrab(world, grabParticle(world, cloth, 0, [0, 0, 0]), [Infinity, 0, 0]), 'target'],
    ['getGrabForce out', () => getGrabForce(world, grabParticle(world, cloth, 0, [0, 0, 0]), {} as never), 'out'],
  ]
  for (const [name, call, argument] of cases) {
    it(`${name}: ClothError naming ${argument}`, () => {
      let error: unknown
      try {
        call()
      } catch (e) {
        error = e
      }
      expect(error).toBeInstanceOf(ClothError)
      expect((error as ClothError).argument).toBe(argument)
    })
  }
})

describe('grab: determinism and snapshots', () => {
  function scene() {
    const world = makeWorld({ sleep: false })
    const cloth = createCloth(world, { width: 1, height: 1, resolution: 10, position: [0, 2, 0], substeps: 6, iterations: 2 })
    pinRow(world, cloth, 0)
    const grab = grabParticle(world, cloth, 95, at(world, cloth, 95))
    let f = 0
    const frame = () => {
      f++
      moveGrab(world, grab, [0.5 * Math.sin(f * 0.05), 1 + 0.3 * Math.cos(f * 0.07), 0.4 * Math.sin(f * 0.03)])
      stepCloth(world, [1 / 60, 1 / 45, 1 / 90][f % 3])
    }
    return { world, cloth, grab, frame }
  }
  const hash = (world: object, cloth: number) => {
    const c = getClothState(world, cloth)
    return hashBytes(c.pos) + hashBytes(c.vel)
  }

  it('same inputs, same bytes', () => {
    const a = scene(), b = scene()
    for (let k = 0; k < 200; k++) {
      a.frame()
      b.frame()
    }
    expect(hash(a.world, a.cloth)).toBe(hash(b.world, b.cloth))
  })

  it('a snapshot taken while grabbed restores identically (the same handle, the same run), also after the grab was released', () => {
    const a = scene()
    for (let k = 0; k < 50; k++) a.frame()
    const saved = saveClothState(a.world, a.cloth)
    // the inputs from frame 50 on, as often as needed
    const replay = () => {
      let f = 50
      const out: string[] = []
      for (let k = 0; k < 60; k++) {
        f++
        moveGrab(a.world, a.grab, [0.5 * Math.sin(f * 0.05), 1 + 0.3 * Math.cos(f * 0.07), 0.4 * Math.sin(f * 0.03)])
        stepCloth(a.world, [1 / 60, 1 / 45, 1 / 90][f % 3])
        out.push(hash(a.world, a.cloth))
      }
      return out
    }
    const first = replay()
    restoreClothState(a.world, a.cloth, saved)
    expect(replay()).toEqual(first)
    // released, and another grab made since: restoring brings back the saved grab under its handle
    releaseGrab(a.world, a.grab)
    const other = grabParticle(a.world, a.cloth, 3, [0, 0, 0])
    restoreClothState(a.world, a.cloth, saved)
    expect(getGrabs(a.world, a.cloth)).toEqual([a.grab])
    expect(isGrabActive(a.world, other)).toBe(false)
    expect(replay()).toEqual(first)
    // a new grab after the restore never reuses a restored handle
    expect(grabParticle(a.world, a.cloth, 3, [0, 0, 0])).toBeGreaterThan(a.grab)
  })

  it('a snapshot of the version before the frame sample (26 numbers per grab) still restores, with the sample taken as the target asked for', () => {
    const a = scene()
    for (let k = 0; k < 50; k++) a.frame()
    const saved = saveClothState(a.world, a.cloth) as unknown as { grabs: Int32Array; grabData: Float64Array }
    const count = saved.grabs.length / 2, stride = saved.grabData.length / count
    expect(stride).toBe(29)
    // the old layout: each grab's first 26 numbers (the sample equals the target asked for at a step's end)
    const old = { ...saved, grabData: new Float64Array(26 * count) }
    for (let g = 0; g < count; g++) old.grabData.set(saved.grabData.subarray(stride * g, stride * g + 26), 26 * g)
    const replay = (snapshot: object) => {
      restoreClothState(a.world, a.cloth, snapshot as never)
      for (let f = 51; f <= 80; f++) {
        moveGrab(a.world, a.grab, [0.5 * Math.sin(f * 0.05), 1 + 0.3 * Math.cos(f * 0.07), 0.4 * Math.sin(f * 0.03)])
        stepCloth(a.world, 1 / 60)
      }
      return hash(a.world, a.cloth)
    }
    expect(replay(old)).toBe(replay(saved))
    // (a truncated section is still refused)
    expect(() => restoreClothState(a.world, a.cloth, { ...saved, grabData: new Float64Array(27 * count) } as never)).toThrow(ClothError)
  })

  it("a grabbed cape frozen by the budget while its character walks on, then thawed: the hand's target is where the hand is (144 and 100 Hz)", () => {
    // (sampled while frozen and then carried by the 6 m walk the thaw carries the cloth by, the
    // glide started 1.2 m ahead of the hand: the hem yanked at 2 m/s; found by a hunt)
    const CAL = { nsPerParticle: 20, nsPerProjection: 12, nsPerColliderTest: 5, nsPerClothSubstep: 500 }
    for (const hz of [144, 100]) {
      const world = makeWorld({ sleep: false })
      const hero = addEntity(world), viewer = addEntity(world)
      setTransform(world, hero, [0, 1.6, 0])
      setTransform(world, viewer, [0, 1.6, 3])
      const cloth = createCloth(world, { width: 0.5, height: 0.8, resolution: [6, 9], position: [0, 1.55, -0.15] })
      pinRow(world, cloth, 0, hero)
      setClothBudget(world, { viewer, near: 4, far: 40, calibration: CAL, adapt: false })
      const c = getClothState(world, cloth), hem = 8 * 6 + 3
      const off = [c.pos[3 * hem], c.pos[3 * hem + 1] - 1.6, c.pos[3 * hem + 2]]
      const heroAt = (t: number) => [3 * Math.max(0, t - 0.5), 1.6, 0]
      const handAt = (t: number) => heroAt(t).map((h, a) => h + off[a])
      const g = grabParticle(world, cloth, hem, handAt(0))
      const data = getClothWorld(world).cloths[0].grab.data
      let t = 0, steps = 0, worst = 0
      const freezeF = Math.round(1.5 * hz), thawF = Math.round(3.5 * hz) + 1
      for (let f = 1; f <= 4 * hz; f++) {
        t += 1 / hz
        if (f === freezeF) setClothVisible(world, cloth, false)
        if (f === thawF) setClothVisible(world, cloth, true)
        setTransform(world, hero, heroAt(t))
        setTransform(world, viewer, [heroAt(t)[0], 1.6, 3])
        moveGrab(world, g, handAt(t))
        const n = stepCloth(world, 1 / hz)
        steps += n
        if (f >= thawF && n > 0 && !getClothLod(world, cloth).frozen) {
          const want = handAt(steps / 60) // where the hand is at the step's end
          worst = Math.max(worst, Math.hypot(data[9] - want[0], data[10] - want[1], data[11] - want[2])) // (G_STEP_TO)
        }
      }
      expect(worst, `${hz} Hz`).toBeLessThan(0.01) // measured 1.7 and 3.3 mm (1.21 and 1.01 m before)
    }
  })

  it('a snapshot whose grab another cloth holds now is refused with a ClothError', () => {
    const a = scene()
    a.frame()
    const saved = saveClothState(a.world, a.cloth)
    const other = createCloth(a.world, { width: 1, height: 1, resolution: 10, position: [3, 2, 0], substeps: 6, iterations: 2 })
    expect(() => restoreClothState(a.world, other, saved)).toThrow(/another cloth/)
    releaseGrab(a.world, a.grab)
    restoreClothState(a.world, other, saved)
    expect(getGrabs(a.world, other)).toEqual([a.grab])
  })
})
