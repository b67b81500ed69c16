// Teleports of a character cloth's frame: carried along ('keep') or put on the reference pose
// ('reset'), detected by distance and by angle; entity lifetimes of the frame.
import { addComponent, addEntity, removeEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  addSphereCollider,
  createCloth,
  getClothComponents,
  getClothReference,
  getClothState,
  getClothStats,
  getClothStretch,
  grabParticle,
  moveGrab,
  pinRow,
  removeCloth,
  setClothInertia,
  setClothMotionConstraints,
  setClothSkinning,
  setTransform,
  stepCloth,
  teleportCloth,
  type ClothInertiaOptions,
} from '../../src/index'
import { allFinite, makeWorld } from '../helpers'
import { capeBehind, DT, capeOnCharacter, carriedRest, drive, localShape, positionsNow, rms, woolCape, yawQuat } from './scenes'

/** A swinging cape: the character runs at 4 m/s along +x turning at 1 rad/s for 1 s (shares 0.5). */
function swinging(inertia: ClothInertiaOptions) {
  const scene = capeOnCharacter({ linear: 0.5, angular: 0.5, centrifugal: 0.5, ...inertia }, makeWorld({ sleep: false }))
  const rest = positionsNow(scene.world, scene.cape)
  setClothMotionConstraints(scene.world, scene.cape, { maxDistance: 1 }) // (keeps the reference pose updated)
  const motion = (t: number) => ({ p: [4 * t, 1.6, 0], yaw: t })
  drive(scene.world, scene.hero, motion, 1)
  return { ...scene, rest, at: motion(1) }
}

describe('teleport', () => {
  it("'keep' carries a swinging cape 10 m away with its shape in the character's frame unchanged", () => {
    const s = swinging({ teleport: { mode: 'keep' } })
    const before = localShape(s.world, s.cape, s.at.p, s.at.yaw)
    const to = [s.at.p[0] + 10, 1.6, 5]
    const teleports = getClothStats(s.world).teleports
    setTransform(s.world, s.hero, to, yawQuat(s.at.yaw))
    stepCloth(s.world, DT)
    expect(getClothStats(s.world).teleports).toBe(teleports + 1)
    // one step of its own swing later, in the frame: what it was, give or take one step's motion
    expect(rms(localShape(s.world, s.cape, to, s.at.yaw), before)).toBeLessThan(0.03)
    expect(allFinite(s.world, s.cape)).toBe(true)
  })

  it("'reset' lands the cape on its reference pose, at rest in the frame", () => {
    const s = swinging({ teleport: { mode: 'reset' } })
    const to = [s.at.p[0] + 10, 1.6, 5]
    setTransform(s.world, s.hero, to, yawQuat(s.at.yaw))
    const ref = carriedRest(s.rest, [0, 1.6, 0], 0, to, s.at.yaw)
    const c = getClothState(s.world, s.cape)
    const offBefore = rms(carriedRest(s.rest, [0, 1.6, 0], 0, s.at.p, s.at.yaw), c.pos.slice(0, 3 * c.count))
    stepCloth(s.world, DT)
    const offAfter = rms(ref, c.pos.slice(0, 3 * c.count))
    console.log(
      `teleport reset: RMS distance from the reference pose ${(1000 * offBefore).toFixed(1)} mm before, ${
        (1000 * offAfter).toExponential(2)
      } mm one step after`,
    )
    expect(offBefore).toBeGreaterThan(0.05) // it was swinging well away from it
    expect(offAfter).toBeLessThan(0.003) // one step of gravity from the reference: ½·g·(1/60 s)² = 1.4 mm
  })

  it('a 180° snap in one frame is a teleport with an angle threshold (kept: no whip); without one the cape whips round', () => {
    const whip = (angle: number | undefined) => {
      const s = capeOnCharacter({ teleport: angle === undefined ? {} : { angle } }, makeWorld({ sleep: false }))
      for (let f = 0; f < 120; f++) stepCloth(s.world, DT)
      const stand = localShape(s.world, s.cape, [0, 1.6, 0], 0)
      setTransform(s.world, s.hero, [0, 1.6, 0], yawQuat(Math.PI))
      let worst = 0
      for (let f = 0; f < 30; f++) {
        stepCloth(s.world, DT)
        worst = Math.max(worst, rms(localShape(s.world, s.cape, [0, 1.6, 0], Math.PI), stand))
      }
      return worst
    }
    const kept = whip(Math.PI / 2), whipped = whip(undefined)
    expect(kept).toBeLessThan(1e-6)
    expect(whipped).toBeGreaterThan(0.1)
  })

  it('a per-cloth distance threshold below the world one catches a 1 m jump the world lets the pins drag across', () => {
    const jump = (distance?: number) => {
      const s = capeOnCharacter({ teleport: distance === undefined ? {} : { distance } }, makeWorld({ sleep: false }))
      for (let f = 0; f < 60; f++) stepCloth(s.world, DT)
      const stand = localShape(s.world, s.cape, [0, 1.6, 0], 0)
      setTransform(s.world, s.hero, [0, 1.6, 1])
      stepCloth(s.world, DT)
      return { teleports: getClothStats(s.world).teleports, off: rms(localShape(s.world, s.cape, [0, 1.6, 1], 0), stand) }
    }
    const caught = jump(0.5), dragged = jump()
    expect(caught.teleports).toBe(1)
    expect(caught.off).toBeLessThan(1e-6)
    expect(dragged.teleports).toBe(0)
    expect(dragged.off).toBeGreaterThan(0.05)
  })

  it("teleportCloth by hand is neither reset nor carried a second time in 'reset' mode: the same bytes as 'keep'", () => {
    const run = (mode: 'keep' | 'reset') => {
      const s = swinging({ teleport: { mode, distance: 0.5 } })
      const c = getClothState(s.world, s.cape)
      const x0 = centroidX(c.pos, c.count)
      setTransform(s.world, s.hero, [s.at.p[0] + 3, 1.6, 0], yawQuat(s.at.yaw))
      teleportCloth(s.world, s.cape, [3, 0, 0])
      stepCloth(s.world, DT)
      expect(centroidX(c.pos, c.count) - x0).toBeGreaterThan(2.9)
      expect(centroidX(c.pos, c.count) - x0).toBeLessThan(3.2)
      expect(getClothStats(s.world).teleports).toBe(1)
      return c.pos.slice(0, 3 * c.count)
    }
    expect(run('reset')).toEqual(run('keep'))
  })

  it('a frame that carries a cloth without pins (held by max distance 0) carries it over a jump too', () => {
    const world = makeWorld({ sleep: false })
    const hero = addEntity(world)
    setTransform(world, hero, [0, 1.6, 0])
    const cape = capeBehind(world, [8, 12])
    setClothInertia(world, cape, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5 })
    setClothMotionConstraints(world, cape, { maxDistance: Array.from({ length: 96 }, (_, i) => (i < 8 ? 0 : Infinity)) })
    drive(world, hero, (t) => ({ p: [3 * t, 1.6, 0], yaw: 0 }), 1)
    const before = localShape(world, cape, [3, 1.6, 0], 0)
    setTransform(world, hero, [20, 1.6, 0])
    stepCloth(world, DT)
    expect(rms(localShape(world, cape, [20, 1.6, 0], 0), before)).toBeLessThan(0.03)
    expect(getClothStats(world).teleports).toBe(1)
  })
})

describe('entity lifetimes', () => {
  it('the frame entity removed and its id recycled: the cloth keeps simulating, let go (its constraints lifted), the new entity is not followed', () => {
    const s = swinging({})
    const c = getClothState(s.world, s.cape)
    setClothMotionConstraints(s.world, s.cape, { maxDistance: Array.from({ length: c.count }, (_, i) => (i < 8 ? 0 : 0.2)) })
    stepCloth(s.world, DT)
    const collar = c.pos.slice(0, 24)
    removeEntity(s.world, s.hero) // takes the pins with it, and the constraints: the collar is let go
    const recycled = addEntity(s.world)
    expect(recycled).toBe(s.hero)
    addComponent(s.world, recycled, getClothComponents(s.world).Transform)
    drive(s.world, recycled, (t) => ({ p: [5 + 3 * t, 4, 2], yaw: 2 * t }), 1)
    // it fell (0.4 m in that second, the cape's drag and its own swing on it), not toward the
    // recycled id's entity (4 m up); held on the frame's last reference, it stayed to 1e-6 m
    for (let j = 1; j < 24; j += 3) expect(c.pos[j]).toBeLessThan(collar[j] - 0.2)
    expect(c.character === null || c.character.frame === 0).toBe(true)
    expect(allFinite(s.world, s.cape)).toBe(true)
    // and a new frame can be given
    setClothInertia(s.world, s.cape, { frame: recycled, linear: 0 })
    stepCloth(s.world, DT)
    expect(allFinite(s.world, s.cape)).toBe(true)
  })

  it('removing a cloth, or every setting, stops tracking its frame', () => {
    const world = makeWorld()
    const hero = addEntity(world)
    setTransform(world, hero, [0, 1.6, 0])
    const cape = createCloth(world, { width: 0.5, height: 0.8, resolution: 4 })
    const k = () => getClothStateWorld(world).kinematics
    setClothInertia(world, cape, { frame: hero })
    expect(k().slotOf[hero]).toBeGreaterThanOrEqual(0)
    setClothInertia(world, cape, null)
    expect(getClothState(world, cape).character).toBeNull()
    expect(k().slotOf[hero]).toBe(-1)
    setClothMotionConstraints(world, cape, { maxDistance: 0.1 })
    setClothInertia(world, cape, { frame: hero })
    removeCloth(world, cape)
    expect(k().slotOf[hero]).toBe(-1)
  })
})

describe('teleportCloth of a cloth whose frame is the world', () => {
  // a sheet held by world pins, with max distance and a backstop around its rest pose in the world:
  // the reference moved with the cloth (it stayed behind: 4443 % stretch between the moved pins
  // and the particles held near the old place)
  for (const turned of [false, true]) {
    it(`takes its reference along${turned ? ', turned' : ''}: no stretch, every particle within its max distance`, () => {
      const world = makeWorld({ sleep: false })
      const cloth = createCloth(world, { width: 1, height: 1, resolution: 10, position: [0, 2, 0] })
      pinRow(world, cloth, 0)
      setClothMotionConstraints(world, cloth, { maxDistance: 0.2, backstop: { distance: 0.05, radius: 1 } })
      for (let f = 0; f < 60; f++) stepCloth(world, DT)
      const q = turned ? [0, Math.sin(0.5), 0, Math.cos(0.5)] : [0, 0, 0, 1]
      const refBefore = getClothReference(world, cloth)!.slice()
      teleportCloth(world, cloth, [5, 0, 0], q, [0, 2, 0])
      // the reference: rigidly moved as the cloth was (x' = pivot + t + R·(x − pivot))
      const moved = carriedRest(refBefore, [0, 2, 0], 0, [5, 2, 0], turned ? 1 : 0)
      const refNow = getClothReference(world, cloth)!
      for (let j = 0; j < refNow.length; j++) expect(refNow[j]).toBeCloseTo(moved[j], 5)
      let worst = 0
      for (let f = 0; f < 60; f++) {
        stepCloth(world, DT)
        worst = Math.max(worst, getClothStretch(world, cloth).max)
      }
      expect(worst).toBeLessThan(0.01)
      const ref = getClothReference(world, cloth)!
      const pos = getClothState(world, cloth).pos
      for (let j = 0; j < pos.length; j += 3) {
        expect(Math.hypot(pos[j] - ref[j], pos[j + 1] - ref[j + 1], pos[j + 2] - ref[j + 2])).toBeLessThan(0.2 + 0.002)
      }
    })
  }
})

describe('a hand holding the cape across a 10 m jump of its character', () => {
  // a cape held by its frame alone (top row at max distance 0, no pins) had its hand's new target
  // carried by the jump a second time (the grab advanced before the frame's jump carried the
  // cloth): 77 % stretch and 9.5 m/s at the hem against 8.3 % and 0.2 m/s pinned; with 'reset' the
  // targets were not carried at all and swept the gap (47 %, 12.9 m/s)
  const run = (mode: 'keep' | 'reset', pins: boolean) => {
    const world = makeWorld({ sleep: false })
    const hero = addEntity(world)
    setTransform(world, hero, [0, 0, 0])
    const cols = 14, rows = 24
    const cape = woolCape(world, cols, rows)
    if (pins) pinRow(world, cape, 0, hero)
    setClothInertia(world, cape, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5, teleport: { mode } })
    setClothMotionConstraints(world, cape, { maxDistance: Array.from({ length: cols * rows }, (_, i) => (i < cols ? 0 : Infinity)) })
    const c = getClothState(world, cape)
    const hem = cols * (rows - 1) + 4
    let hand = -1, speed = 0, stretch = 0
    for (let f = 1; f <= 80; f++) {
      const x = f >= 61 ? 10 : 0, z = (3 * f) / 60 // walking at 3 m/s, 10 m sideways at frame 61
      setTransform(world, hero, [x, 0, z])
      if (f === 30) hand = grabParticle(world, cape, hem, [x, 0.6, z - 0.6])
      if (f > 30) moveGrab(world, hand, [x, 0.6, z - 0.6])
      stepCloth(world, DT)
      if (f >= 61 && f < 66) {
        speed = Math.max(speed, Math.hypot(c.vel[3 * hem], c.vel[3 * hem + 1], c.vel[3 * hem + 2] - 3))
        stretch = Math.max(stretch, getClothStretch(world, cape).max)
      }
    }
    return { speed, stretch }
  }
  for (const mode of ['keep', 'reset'] as const) {
    it(`'${mode}': a cape held by its frame alone moves as a pinned one does`, () => {
      const pinned = run(mode, true), framed = run(mode, false)
      console.log(
        `'${mode}', hand across the jump: held by its frame ${(100 * framed.stretch).toFixed(1)} %, ${
          framed.speed.toFixed(2)
        } m/s; pinned ${(100 * pinned.stretch).toFixed(1)} %, ${pinned.speed.toFixed(2)} m/s`,
      )
      expect(framed.stretch).toBeLessThan(pinned.stretch + 0.02)
      expect(framed.speed).toBeLessThan(pinned.speed + 0.5)
      // measured (README), pinned or not: 'keep' 7.4 % and 0.12 m/s at the hem, as without the jump
      // (8.3 % and 0.20 m/s while the walk's start in the first frame was taken as steady); 'reset'
      // 44 % and 7.8 m/s, the hand pulling the hem back from the reference
      const [stretch, speed] = mode === 'keep' ? [0.074, 0.12] : [0.444, 7.81]
      for (const r of [pinned, framed]) {
        expect(r.stretch).toBeGreaterThan(0.85 * stretch)
        expect(r.stretch).toBeLessThan(1.15 * stretch)
        expect(r.speed).toBeGreaterThan(0.85 * speed)
        expect(r.speed).toBeLessThan(1.15 * speed)
      }
    })
  }
})

function centroidX(pos: Float64Array, n: number): number {
  let x = 0
  for (let i = 0; i < n; i++) x += pos[3 * i]
  return x / n
}

function getClothStateWorld(world: object) {
  return (world as Record<symbol, { kinematics: { slotOf: Int32Array } }>)[Symbol.for('bitecs-cloth')]
}

describe('a skinned cape whose skeleton is posed a frame after (or before) its root across a 10 m jump', () => {
  // the frame's jump carried the cape while its reference stayed with the bones 10 m back (or went
  // ahead a frame early), and the limits dragged it across the gap: 21,961 % stretch for a frame
  // (reset put it on the stale skeleton); now the limits rest for the step the bones are off
  const COLS = 14, ROWS = 24
  const run = (lag: -1 | 0 | 1, mode: 'keep' | 'reset', jump = 10, hz = 60) => {
    const world = makeWorld({ sleep: false })
    const hero = addEntity(world)
    const bones = [addEntity(world), addEntity(world)]
    const heroAt = (f: number) => [(4 * f) / hz + (f >= hz ? jump : 0), 0, 0]
    const pose = (f: number) => {
      const p = heroAt(f)
      setTransform(world, bones[0], [p[0], 1.4, 0])
      setTransform(world, bones[1], [p[0], 1.0, 0])
    }
    setTransform(world, hero, heroAt(0))
    pose(0)
    const cape = woolCape(world, COLS, ROWS)
    pinRow(world, cape, 0, hero)
    const n = COLS * ROWS
    const u = (i: number) => Math.floor(i / COLS) / (ROWS - 1)
    setClothSkinning(world, cape, {
      bones,
      joints: Array.from({ length: 4 * n }, (_, k) => (k % 4 === 1 ? 1 : 0)),
      weights: Array.from({ length: 4 * n }, (_, k) => (k % 4 === 0 ? 1 - u(k >> 2) : k % 4 === 1 ? u(k >> 2) : 0)),
    })
    setClothInertia(world, cape, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5, teleport: { mode } })
    const maxDistance = Array.from({ length: n }, (_, i) => (u(i) === 1 ? Infinity : 0.9 * u(i) ** 2))
    setClothMotionConstraints(world, cape, { maxDistance, backstop: { distance: 0.02, radius: 0.5 } })
    let stretch = 0
    for (let f = 1; f <= 1.5 * hz; f++) {
      setTransform(world, hero, heroAt(f))
      pose(f - lag)
      stepCloth(world, 1 / hz)
      if (f >= hz - 5) stretch = Math.max(stretch, getClothStretch(world, cape).max)
    }
    // after it: within the limits of its skeleton (but the pinned row)
    const pos = getClothState(world, cape).pos, ref = getClothReference(world, cape)!
    let over = 0
    for (let i = COLS; i < n; i++)
      over = Math.max(
        over,
        Math.hypot(pos[3 * i] - ref[3 * i], pos[3 * i + 1] - ref[3 * i + 1], pos[3 * i + 2] - ref[3 * i + 2]) - maxDistance[i],
      )
    return { stretch, over, teleports: getClothStats(world).teleports, finite: allFinite(world, cape) }
  }
  for (const mode of ['keep', 'reset'] as const) {
    // (at 30 Hz each frame runs two steps: the limits rested for the first alone dragged the cape
    // across the gap in the second, 16,954 %)
    it(`'${mode}': as whole as without the jump, at 60 and 30 Hz`, () => {
      for (const hz of [60, 30])
        for (const lag of [0, 1, -1] as const) {
          // (a skeleton a frame off its root at 4 m/s is 6.7 cm off the pins, and stretches the collar by that without any jump)
          const r = run(lag, mode, 10, hz), still = run(lag, mode, 0, hz)
          console.log(
            `'${mode}' at ${hz} Hz, bones ${['in step', 'a frame late', 'a frame early'].at(lag)}: ${
              (100 * r.stretch).toFixed(1)
            } % (without the jump ${(100 * still.stretch).toFixed(1)} %)`,
          )
          expect(r.finite).toBe(true)
          expect(r.teleports).toBe(1)
          expect(r.stretch).toBeLessThan(still.stretch * 1.2 + 0.05)
          expect(r.over).toBeLessThan(0.002)
        }
    })
  }
})

describe('a bone swung fast against its frame is motion, not a jump of the skeleton', () => {
  // A strip held at max distance 0 on an arm that swings ±0.3 m against a still hero at 4 m/s peak
  // (6.7 cm a frame), with a cloth teleport distance of 5 cm: the bone's motion is what its velocity
  // predicts, so the strip stays held to its skin (it was let go 0.42 m: every step the arm moved
  // more than 5 cm against its frame rested the limits).
  it('keeps a kinematic strip on its skinned pose', () => {
    const world = makeWorld({ sleep: false })
    const hero = addEntity(world), arm = addEntity(world)
    setTransform(world, hero, [0, 0, 0])
    setTransform(world, arm, [0.3, 1.5, 0])
    const cloth = createCloth(world, { width: 0.2, height: 0.4, resolution: [3, 5], position: [0.3, 1.3, 0] })
    const c = getClothState(world, cloth)
    setClothSkinning(world, cloth, {
      bones: [arm],
      joints: Array.from({ length: 4 * c.count }, () => 0),
      weights: Array.from({ length: 4 * c.count }, (_, k) => (k % 4 === 0 ? 1 : 0)),
    })
    setClothInertia(world, cloth, { frame: hero, teleport: { distance: 0.05 } })
    setClothMotionConstraints(world, cloth, { maxDistance: 0 })
    const w = 4 / 0.3
    let worst = 0
    for (let f = 1; f <= 120; f++) {
      setTransform(world, arm, [0.3 * Math.cos((w * f) / 60), 1.5, 0]) // from rest at the swing's end
      stepCloth(world, DT)
      const ref = getClothReference(world, cloth)!
      for (let i = 0; i < c.count; i++)
        worst = Math.max(worst, Math.hypot(c.pos[3 * i] - ref[3 * i], c.pos[3 * i + 1] - ref[3 * i + 1], c.pos[3 * i + 2] - ref[3 * i + 2]))
    }
    expect(worst).toBeLessThan(1e-6)
  })
})

describe("a bone's leap for one cloth is no jump for the world", () => {
  // A strip skinned to an arm with a 5 cm teleport distance; the arm starts a 7.2 m/s punch (12 cm
  // a frame) with a hand sphere on it, through another hanging sheet. The strip rests its limits
  // for that leap; the hand still sweeps (marked as the bone's jump for the whole world, it passed
  // through the sheet untouched: 0.000 m, against 0.163 m without the strip).
  const punch = (withStrip: boolean) => {
    const world = makeWorld({ sleep: false })
    const hero = addEntity(world), arm = addEntity(world)
    setTransform(world, hero, [0, 0, -1])
    let z = -0.06
    setTransform(world, arm, [0, 1.0, z])
    addSphereCollider(world, addEntity(world), { body: arm, radius: 0.04 })
    const sheet = createCloth(world, { width: 0.6, height: 0.6, resolution: 16, position: [0, 1.3, 0] })
    pinRow(world, sheet, 0)
    if (withStrip) {
      const strip = createCloth(world, { width: 0.1, height: 0.2, resolution: [3, 5], position: [0.5, 1.0, z] })
      const n = getClothState(world, strip).count
      setClothSkinning(world, strip, {
        bones: [arm],
        joints: Array.from({ length: 4 * n }, () => 0),
        weights: Array.from({ length: 4 * n }, (_, k) => (k % 4 === 0 ? 1 : 0)),
      })
      setClothInertia(world, strip, { frame: hero, teleport: { distance: 0.05 } })
      setClothMotionConstraints(world, strip, { maxDistance: 0 })
    }
    const s = getClothState(world, sheet)
    for (let f = 0; f < 60; f++) stepCloth(world, DT)
    let pushed = 0
    for (let f = 1; f <= 6; f++) {
      z += 7.2 * DT
      setTransform(world, arm, [0, 1.0, z])
      stepCloth(world, DT)
      for (let i = 0; i < s.count; i++) pushed = Math.max(pushed, s.pos[3 * i + 2])
    }
    return pushed
  }

  it('a hand sphere on the bone sweeps through another sheet as without the strip', () => {
    const without = punch(false), withStrip = punch(true)
    expect(without).toBeGreaterThan(0.1) // measured 0.163 m
    expect(withStrip).toBeCloseTo(without, 6)
  })
})
