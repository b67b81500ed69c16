// Frame timing as games produce it: hitches longer than maxStepsPerFrame steps (the dropped time's
// motion is carried rigidly, not squeezed into the steps that run: a 0.5 s hitch at 4 m/s stretched
// the cape 114 % against 1.5 % without it), the teleport test over the frame's whole span, a frame
// refused at its sample keeping its step, display rates other than 60 Hz (the step lags its
// Transform by up to one fixed step: measured and documented), bad dt, variable rates, determinism.
import { addEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  gustWind,
  addSphereCollider,
  beginClothStep,
  ClothError,
  ClothSimulation,
  createCloth,
  createWindZone,
  endClothStep,
  getClothState,
  getClothStats,
  getClothStretch,
  grabParticle,
  moveGrab,
  pinRow,
  pinParticle,
  getClothComponents,
  getClothDrawTransform,
  saveClothState,
  restoreClothState,
  setClothInertia,
  setClothSkinning,
  setTransform,
  stepCloth,
  teleportCloth,
} from '../../src/index'
import { makeWorld } from '../helpers'
import { capeScene, yq } from './hitchScene'

type Pose = { p: [number, number, number]; yaw: number }

/** Run along +z at `speed` after 0.5 s standing (accelerating 10 m/s²), heading +z (yaw 0). */
const runZ = (speed: number) => (t: number): Pose => {
  const t0 = 0.5, ta = speed / 10
  if (t <= t0) return { p: [0, 0, 0], yaw: 0 }
  const u = t - t0
  const z = u < ta ? 5 * u * u : 5 * ta * ta + speed * (u - ta)
  return { p: [0, 0, z], yaw: 0 }
}
/** README quickstart: a 3 m circle at 3 m/s, facing where it goes. */
const circle = (t: number): Pose => {
  const a = t
  return { p: [3 - 3 * Math.cos(a), 0, 3 * Math.sin(a)], yaw: a }
}

/** Depth (m) of the deepest cape particle inside the torso capsule (negative: outside). */
function torsoDepth(world: object, cape: number, p: Pose): number {
  const c = getClothState(world, cape)
  let worst = -Infinity
  for (let i = 0; i < c.count; i++) {
    const x = c.pos[3 * i] - p.p[0], y = c.pos[3 * i + 1] - p.p[1], z = c.pos[3 * i + 2] - p.p[2]
    const cy = Math.max(1.15 - 0.22, Math.min(1.15 + 0.22, y))
    const d = 0.19 - Math.hypot(x, y - cy, z)
    if (d > worst) worst = d
  }
  return worst
}

interface RunResult {
  maxStretch: number[]
  steps: number[]
  finite: boolean
  resets: number
  teleports: number
  depth: number[]
}

/** Drives a scene: frame f has dt = dts[f]; game time advances by gameDt[f] (default dt). */
function run(
  scene: ReturnType<typeof capeScene>,
  dts: number[],
  motion: (t: number) => Pose,
  opts: { gameDts?: number[]; entry?: 'step' | 'begin' } = {},
): RunResult {
  const { world, hero, cape } = scene
  const r: RunResult = { maxStretch: [], steps: [], finite: true, resets: 0, teleports: 0, depth: [] }
  let t = 0
  const s0 = getClothStats(world)
  const resets0 = s0.guardResets, tel0 = s0.teleports
  for (let f = 0; f < dts.length; f++) {
    t += opts.gameDts ? opts.gameDts[f] : dts[f]
    const m = motion(t)
    setTransform(world, hero, m.p, yq(m.yaw))
    let n: number
    if (opts.entry === 'begin') {
      n = beginClothStep(world, dts[f])
      endClothStep(world)
    } else n = stepCloth(world, dts[f])
    r.steps.push(n)
    r.maxStretch.push(getClothStretch(world, cape).max)
    r.depth.push(torsoDepth(world, cape, m))
    const c = getClothState(world, cape)
    for (let i = 0; i < 3 * c.count; i++) if (!Number.isFinite(c.pos[i]) || !Number.isFinite(c.vel[i])) r.finite = false
  }
  const s = getClothStats(world)
  r.resets = s.guardResets - resets0
  r.teleports = s.teleports - tel0
  return r
}
const max = (a: number[], from = 0, to = a.length) => Math.max(...a.slice(from, to))
const fill = (n: number, dt: number) => Array.from({ length: n }, () => dt)

/** Max edge stretch in the second after a hitch of h s at frame 180 (3 s in), and the unhitched run's over the same frames. */
function hitchVsBaseline(speed: number, h: number, mk: () => ReturnType<typeof capeScene> = capeScene, motion = runZ(speed)) {
  const base = run(mk(), fill(240, 1 / 60), motion)
  const r = run(mk(), [...fill(180, 1 / 60), h, ...fill(59, 1 / 60)], motion)
  return { base: max(base.maxStretch, 180), hitched: max(r.maxStretch, 180), r, baseRun: base }
}
const pct = (x: number) => `${(100 * x).toFixed(1)} %`
/** What a hitch may add to the unhitched run's worst stretch: 2 points (the quickstart circle: 4.6 % against 3.3 %). */
const allowed = (base: number) => base + 0.02
/** Largest particle speed relative to a body moving at `v` along +z. */
function relSpeed(world: object, cape: number, v: number): number {
  const c = getClothState(world, cape)
  let m = 0
  for (let i = 0; i < c.count; i++) m = Math.max(m, Math.hypot(c.vel[3 * i], c.vel[3 * i + 1], c.vel[3 * i + 2] - v))
  return m
}

describe('a hitch: the motion of the dropped time is carried, not squeezed into the ≤ 4 steps that run', () => {
  it('250 ms hitch while running at 4 m/s: the cape stays within the unhitched run’s stretch', () => {
    const { base, hitched, r } = hitchVsBaseline(4, 0.25)
    console.log(`250 ms @ 4 m/s: ${r.steps[180]} steps, worst stretch in the next second ${pct(hitched)} vs ${pct(base)} unhitched`)
    expect(r.finite).toBe(true)
    expect(hitched).toBeLessThan(allowed(base)) // was 42.9 % against 1.5 %
  })

  it('500 ms hitch while running at 4 m/s: no edge doubled, no particle flung at tens of m/s', () => {
    const { base, hitched } = hitchVsBaseline(4, 0.5)
    const sc = capeScene()
    run(sc, [...fill(180, 1 / 60), 0.5], runZ(4))
    const v = relSpeed(sc.world, sc.cape, 4)
    const all = capeScene({ world: { maxStepsPerFrame: 64 } }) // the same hitch with every step simulated
    run(all, [...fill(180, 1 / 60), 0.5], runZ(4))
    const vAll = relSpeed(all.world, all.cape, 4)
    console.log(
      `500 ms @ 4 m/s: stretch ${pct(hitched)} vs ${pct(base)}; fastest particle relative to the body ${v.toFixed(1)} m/s (${
        vAll.toFixed(1)
      } m/s when all 30 steps run)`,
    )
    expect(hitched).toBeLessThan(allowed(base)) // was 114.3 % against 1.5 %
    expect(v).toBeLessThan(5) // was 37.1 m/s (1.6 m/s with every step run)
  })

  it('1 s hitch while walking at 1.5 m/s (below the teleport distance): the cape is not torn apart', () => {
    const { base, hitched, r } = hitchVsBaseline(1.5, 1)
    console.log(`1 s @ 1.5 m/s: stretch ${pct(hitched)} vs ${pct(base)}, teleports ${r.teleports}`)
    expect(hitched).toBeLessThan(allowed(base)) // was 115.4 % against 2.8 %
  })

  it('100 ms hitch while sprinting at 6.5 m/s', () => {
    const { base, hitched } = hitchVsBaseline(6.5, 0.1)
    console.log(`100 ms @ 6.5 m/s: stretch ${pct(hitched)} vs ${pct(base)}`)
    expect(hitched).toBeLessThan(allowed(base)) // was 40.5 % against 14.1 %
  })

  it('README quickstart (3 m circle at 3 m/s, no character settings), 500 ms hitch', () => {
    const mk = () => capeScene({ character: false })
    const { base, hitched } = hitchVsBaseline(3, 0.5, mk, circle)
    console.log(`quickstart circle, 500 ms: stretch ${pct(hitched)} vs ${pct(base)}`)
    expect(hitched).toBeLessThan(allowed(base)) // was 45.1 % against 3.3 %
  })

  it('a grabbed hem following the running character through a 250 ms hitch', () => {
    const grabbed = (h: number) => {
      const sc = capeScene()
      const hand = grabParticle(sc.world, sc.cape, 14 * 23 + 7, [0, 0.6, -0.5])
      const motion = runZ(4)
      const dts = [...fill(180, 1 / 60), ...(h ? [h] : [1 / 60]), ...fill(59, 1 / 60)]
      let t = 0, worst = 0
      for (let f = 0; f < dts.length; f++) {
        t += dts[f]
        const m = motion(t)
        setTransform(sc.world, sc.hero, m.p, yq(0))
        moveGrab(sc.world, hand, [m.p[0], 0.6, m.p[2] - 0.5])
        stepCloth(sc.world, dts[f])
        if (f >= 180) worst = Math.max(worst, getClothStretch(sc.world, sc.cape).max)
      }
      return worst
    }
    const base = grabbed(0), hitched = grabbed(0.25)
    console.log(`grab, 250 ms @ 4 m/s: stretch ${pct(hitched)} vs ${pct(base)}`)
    expect(hitched).toBeLessThan(allowed(base)) // was 74.0 % against 13.8 %
  })
})

/** Inertia 0.5 with teleports by distance or by a π/2 turn putting the cape on its reference ('reset'). */
const resetOnTeleports = (sc: ReturnType<typeof capeScene>) =>
  setClothInertia(sc.world, sc.cape, {
    frame: sc.hero,
    linear: 0.5,
    angular: 0.5,
    centrifugal: 0.5,
    teleport: { mode: 'reset', angle: Math.PI / 2 },
  })

describe("the teleport test extrapolates over the frame's whole span (dropped time too)", () => {
  it("a 0.75 s hitch at a steady 4 m/s lands where the character's velocity takes it: not a teleport", () => {
    const sc = capeScene()
    resetOnTeleports(sc)
    run(sc, fill(180, 1 / 60), runZ(4))
    const r = run(sc, [0.75], (t: number) => runZ(4)(t + 3))
    console.log(`0.75 s hitch at 4 m/s: teleports ${r.teleports} (predicted 4 × 6.7 cm = 0.27 m, moved 3 m)`)
    expect(r.teleports).toBe(0) // was 1 (reset onto the reference pose): the velocity was extrapolated over 4 steps only
  })

  it('a 0.75 s hitch while turning steadily at 3 rad/s (2.25 rad, beyond the π/2 teleport angle) is not a teleport; a 180° snap still is', () => {
    const turning = (snap: number) => (t: number): Pose => ({ p: [0, 0, 0], yaw: t < 3 ? 3 * t : 9 + 3 * (t - 3) + snap })
    for (const snap of [0, Math.PI]) {
      const sc = capeScene()
      resetOnTeleports(sc)
      const motion = turning(snap)
      run(sc, fill(180, 1 / 60), motion)
      const r = run(sc, [0.75], (t: number) => motion(t + 3))
      console.log(`0.75 s hitch turning at 3 rad/s, snapped ${snap.toFixed(2)} rad: teleports ${r.teleports}`)
      expect(r.teleports).toBe(snap === 0 ? 0 : 1) // was 1 without the snap: the angle was not extrapolated
    }
  })
})

describe('teleportCloth in a long frame: the pins follow the jump, the rest of the motion is simulated', () => {
  // a hero running at 4 m/s is moved 10 m sideways in a frame of dt; the game moves the cape by hand
  // by the hero's whole displacement (B − A, this frame's running included), by the jump alone, or
  // not at all (the jump is detected). The hand moves were taken as they were while the pins
  // interpolated the frame's running: 24.4 % stretch after a 0.1 s frame (8.4 % after a 1/60 s one)
  // against 5.6 % detected
  const teleported = (dt: number, hand: 'whole' | 'jump' | 'none') => {
    const sc = capeScene()
    let t = 0, z = 0
    for (let f = 0; f < 180; f++) {
      t += 1 / 60
      z = t < 0.5 ? 0 : 4 * (t - 0.5)
      setTransform(sc.world, sc.hero, [0, 0, z], yq(0))
      stepCloth(sc.world, 1 / 60)
    }
    t += dt
    const z2 = 4 * (t - 0.5)
    setTransform(sc.world, sc.hero, [10, 0, z2], yq(0))
    if (hand !== 'none') teleportCloth(sc.world, sc.cape, [10, 0, hand === 'whole' ? z2 - z : 0])
    stepCloth(sc.world, dt)
    let worst = getClothStretch(sc.world, sc.cape).max
    for (let f = 0; f < 60; f++) {
      t += 1 / 60
      setTransform(sc.world, sc.hero, [10, 0, 4 * (t - 0.5)], yq(0))
      stepCloth(sc.world, 1 / 60)
      worst = Math.max(worst, getClothStretch(sc.world, sc.cape).max)
    }
    return worst
  }
  for (const dt of [1 / 60, 0.1, 0.5]) {
    it(`a ${(1000 * dt).toFixed(0)} ms frame: moved by hand by the whole displacement or by the jump, as when detected`, () => {
      const detected = teleported(dt, 'none'), whole = teleported(dt, 'whole'), jump = teleported(dt, 'jump')
      console.log(
        `teleportCloth in a ${(1000 * dt).toFixed(0)} ms frame: whole ${pct(whole)}, jump ${pct(jump)}, detected ${pct(detected)}`,
      )
      // measured 5.6 % all three (README), for every frame length
      expect(detected).toBeGreaterThan(0.05)
      expect(detected).toBeLessThan(0.062)
      expect(Math.abs(whole - detected)).toBeLessThan(0.005) // was 8.4 % (1/60 s) and 24.4 % (0.1 s)
      expect(Math.abs(jump - detected)).toBeLessThan(0.005)
    })
  }
})

describe("display rates other than 60 Hz (documented in the README's frame table)", () => {
  it('144 Hz, running at 4 m/s: the pinned row is where the last fixed step left it, at most one fixed step of motion behind its Transform; drawn with getClothDrawTransform it is on it', () => {
    for (const hz of [144, 60]) {
      const sc = capeScene()
      const c = getClothState(sc.world, sc.cape)
      const rest = Array.from(c.pos.slice(0, 3 * 14))
      const motion = runZ(4)
      const m4 = new Float64Array(16)
      let t = 0, worst = 0, drawnWorst = 0, idle = 0, identity = true
      for (let f = 0; f < 4 * hz; f++) {
        t += 1 / hz
        const m = motion(t)
        setTransform(sc.world, sc.hero, m.p, yq(0))
        if (stepCloth(sc.world, 1 / hz) === 0) idle++
        getClothDrawTransform(sc.world, sc.cape, m4)
        for (let j = 0; j < 16; j++) identity &&= m4[j] === (j % 5 === 0 ? 1 : 0)
        if (t < 2) continue
        for (let i = 0; i < 14; i++) {
          const x = c.pos[3 * i], y = c.pos[3 * i + 1], z = c.pos[3 * i + 2]
          const want = [rest[3 * i] + m.p[0], rest[3 * i + 1] + m.p[1], rest[3 * i + 2] + m.p[2]]
          worst = Math.max(worst, Math.hypot(x - want[0], y - want[1], z - want[2]))
          const dx = m4[0] * x + m4[4] * y + m4[8] * z + m4[12]
          const dy = m4[1] * x + m4[5] * y + m4[9] * z + m4[13]
          const dz = m4[2] * x + m4[6] * y + m4[10] * z + m4[14]
          drawnWorst = Math.max(drawnWorst, Math.hypot(dx - want[0], dy - want[1], dz - want[2]))
        }
      }
      console.log(
        `${hz} Hz: collar off its Transform by up to ${(100 * worst).toFixed(2)} cm, drawn with the transform ${
          (100 * drawnWorst).toFixed(4)
        } cm; ${idle} of ${4 * hz} frames ran no step`,
      )
      if (hz === 60) {
        // whole steps: the cloth is on its Transform, and the transform is exactly the identity
        expect(worst).toBeLessThan(1e-9)
        expect(identity).toBe(true)
        expect(idle).toBe(0)
        continue
      }
      // 4 s at 144 Hz is 576 frames and 240 fixed steps: 336 frames run none (README)
      expect(idle).toBeGreaterThanOrEqual(335)
      expect(idle).toBeLessThanOrEqual(337)
      // measured 6.11 cm (mean 3.06 cm): a fixed step at 4 m/s is 6.67 cm
      expect(worst).toBeGreaterThan(0.03)
      expect(worst).toBeLessThan((4 * 1) / 60 + 1e-3)
      expect(drawnWorst).toBeLessThan(1e-6)
    }
  })
})

describe('a frame refused for a bad Transform keeps its step for the next frame', () => {
  it('after the error is fixed, the next frame simulates both frames of motion (it runs 2 steps, not 1)', () => {
    const sc = capeScene()
    run(sc, fill(180, 1 / 60), runZ(4))
    getClothComponents(sc.world).Transform.px[sc.hero] = NaN
    expect(() => stepCloth(sc.world, 1 / 60)).toThrow(ClothError)
    const r = run(sc, fill(60, 1 / 60), (t: number) => runZ(4)(t + 3 + 1 / 60))
    console.log(
      `after the refused frame: steps ${r.steps.slice(0, 3).join(', ')}; worst stretch ${pct(max(r.maxStretch))} (unhitched run 1.5 %)`,
    )
    expect(r.steps[0]).toBe(2) // was 1: the refused frame took a fixed step off the accumulator, and stretch went to 13.8 %
  })

  it('a refused hitch: the next frame carries the dropped time as an accepted hitch does', () => {
    // (the dropped time was forgotten at the refused sample, and what the 4 steps could not take of
    // the kept time was squeezed into them: 45.1 % against 2.6 %)
    const sc = capeScene()
    run(sc, fill(180, 1 / 60), runZ(4))
    getClothComponents(sc.world).Transform.px[sc.hero] = NaN
    expect(() => stepCloth(sc.world, 0.5)).toThrow(ClothError)
    const r = run(sc, fill(60, 1 / 60), (t: number) => runZ(4)(t + 3 + 0.5))
    const base = hitchVsBaseline(4, 0.5).base
    expect(max(r.maxStretch)).toBeLessThan(allowed(base))
  })
})

describe('hitches: what is carried and what sweeps', () => {
  it('a sheet pinned to the world and to a turning corner is not carried by the corner (it swung 0.7 rad about it: 39 % stretch)', () => {
    const sheet = (h: number) => {
      const world = makeWorld({ sleep: false })
      const corner = addEntity(world)
      setTransform(world, corner, [1, 2, 0])
      const cloth = createCloth(world, { width: 2, height: 1, resolution: [16, 8], position: [0, 2, 0] })
      for (let c = 0; c < 8; c++) pinParticle(world, cloth, c)
      pinParticle(world, cloth, 15, corner)
      const dts = [...fill(120, 1 / 60), h || 1 / 60, ...fill(60, 1 / 60)]
      let t = 0, worst = 0
      for (let f = 0; f < dts.length; f++) {
        t += dts[f]
        setTransform(world, corner, [1, 2, 0], yq(0.8 * Math.sin(2 * t)))
        stepCloth(world, dts[f])
        if (f >= 120) worst = Math.max(worst, getClothStretch(world, cloth).max)
      }
      return worst
    }
    const base = sheet(0), hitched = sheet(0.5)
    expect(hitched).toBeLessThan(allowed(base))
  })

  /**
   * The scene's cape skinned by the hero and a hip bone below it (the hip rigid with the hero or
   * swaying about x); with `tied`, an apron framed by and pinned to the hip, skinned to the hip and
   * a thigh, and a scarf hung between the hip and a chest entity. Runs along z at 4 m/s with a
   * hitch of h s at frame 180; per cloth, the worst stretch and largest one-frame velocity change after.
   */
  function skinnedRun(h: number, sway: number, tied = false, crouch = 0) {
    const s = capeScene()
    const { world, hero, cape } = s
    const bone = (p: [number, number, number]) => {
      const e = addEntity(world)
      setTransform(world, e, p)
      return e
    }
    const hip = bone([0, 0.95, 0]), thigh = bone([0, 0.5, 0.1]), chest = bone([0, 1.4, 0])
    const skin = (cloth: number, cols: number, bones: number[]) => {
      const c = getClothState(world, cloth)
      const joints: number[] = [], weights: number[] = []
      for (let i = 0; i < c.count; i++) {
        const u = Math.floor(i / cols) / (c.count / cols - 1)
        joints.push(0, 1, 0, 0)
        weights.push(1 - u, u, 0, 0)
      }
      setClothSkinning(world, cloth, { bones, joints, weights })
    }
    skin(cape, 14, [hero, hip])
    const cloths = [cape]
    if (tied) {
      const apron = createCloth(world, { width: 0.4, height: 0.5, resolution: [8, 10], position: [0, 1.0, 0.3], material: 'wool' })
      pinRow(world, apron, 0, hip)
      setClothInertia(world, apron, { frame: hip, linear: 0.5, angular: 0.5, centrifugal: 0.5 })
      skin(apron, 8, [hip, thigh])
      const scarf = createCloth(world, { width: 0.3, height: 0.3, resolution: [6, 6], position: [0.3, 1.2, 0.2], material: 'wool' })
      pinParticle(world, scarf, 0, hip)
      pinParticle(world, scarf, 5, chest)
      cloths.push(apron, scarf)
    }
    const motion = runZ(4)
    const dts = [...fill(180, 1 / 60), h || 1 / 60, ...fill(59, 1 / 60)]
    const last = cloths.map((e) => Float64Array.from(getClothState(world, e).vel))
    const stretch = cloths.map(() => 0), dv = cloths.map(() => 0)
    let t = 0
    for (let f = 0; f < dts.length; f++) {
      t += dts[f]
      const m = motion(t)
      setTransform(world, hero, m.p, yq(m.yaw))
      const a = sway * Math.sin(5 * t) // about x, in the hero's frame (yaw 0)
      // (with `crouch`, the hip drops that far over 3.0–3.5 s, in the hitch at 3 s)
      const down = crouch * Math.min(1, Math.max(0, (t - 3) / 0.5))
      setTransform(world, hip, [m.p[0], 0.95 - down, m.p[2]], [Math.sin(a / 2), 0, 0, Math.cos(a / 2)])
      setTransform(world, thigh, [m.p[0], 0.5, m.p[2] + 0.1])
      setTransform(world, chest, [m.p[0], 1.4, m.p[2]])
      stepCloth(world, dts[f])
      cloths.forEach((e, n) => {
        const c = getClothState(world, e)
        for (let i = 0; i < 3 * c.count; i += 3) {
          if (f >= 180)
            dv[n] = Math.max(dv[n], Math.hypot(c.vel[i] - last[n][i], c.vel[i + 1] - last[n][i + 1], c.vel[i + 2] - last[n][i + 2]))
        }
        last[n].set(c.vel)
        if (f >= 180) stretch[n] = Math.max(stretch[n], getClothStretch(world, e).max)
      })
    }
    return { stretch, dv }
  }

  it("a skinned cape is carried with its frame and sweeps only its bones' motion against it (a 250 ms hitch at 4 m/s changed its speed by 13 m/s in a frame: 39 % stretch)", () => {
    for (const sway of [0, 0.4]) {
      const base = skinnedRun(0, sway), hitched = skinnedRun(0.25, sway)
      console.log(
        `skinned cape, sway ${sway} rad: 250 ms hitch: stretch ${pct(hitched.stretch[0])}, largest 1-frame dv ${
          hitched.dv[0].toFixed(2)
        } m/s; unhitched ${pct(base.stretch[0])}, ${base.dv[0].toFixed(2)} m/s`,
      )
      if (sway === 0) {
        expect(hitched.stretch[0]).toBeLessThan(allowed(base.stretch[0])) // was 42.9 % against 1.5 %
        expect(hitched.dv[0]).toBeLessThan(base.dv[0] + 1) // was 16.7 m/s against 1.4
      } else {
        // the hip's sway in the dropped time is swept into the steps that run (measured 31 % and
        // 6.3 m/s against 13 % and 4.5 unhitched; swept with the whole motion, 62 % and 21 m/s)
        expect(hitched.stretch[0]).toBeLessThan(0.4)
        expect(hitched.dv[0]).toBeLessThan(base.dv[0] + 3)
      }
    }
  })

  it('a skinned cape whose hip crouches 40 cm in a 1 s hitch is carried with its frame, the crouch swept (the group swept whole: 132 % for a 30 cm crouch)', () => {
    const base = skinnedRun(0, 0, false, 0.4), hitched = skinnedRun(1, 0, false, 0.4)
    expect(hitched.stretch[0]).toBeLessThan(base.stretch[0] + 0.05)
  })

  it("cloths tied by shared entities are carried by one jump: an apron framed by the cape's hip bone and a scarf between the hip and the chest, through 0.25 and 1 s hitches (the apron was torn 133 %, the cape 17 %)", () => {
    const base = skinnedRun(0, 0, true)
    for (const h of [0.25, 1]) {
      const hitched = skinnedRun(h, 0, true)
      console.log(
        `tied cloths, ${h} s hitch: stretch ${hitched.stretch.map(pct).join(', ')} against ${base.stretch.map(pct).join(', ')} unhitched`,
      )
      hitched.stretch.forEach((x, n) => expect(x, `cloth ${n}`).toBeLessThan(allowed(base.stretch[n])))
      hitched.dv.forEach((x, n) => expect(x, `cloth ${n}`).toBeLessThan(base.dv[n] + 1))
    }
  })

  it('a banner between two carriers is carried by one of them when they move as one (circling together, facing their way), and sweeps when they do not (circling with unturned Transforms: carried with the first, the second swept twice its motion, 27 m/s)', () => {
    const yaw = (a: number): [number, number, number, number] => [0, Math.sin(a / 2), 0, Math.cos(a / 2)]
    const banner = (h: number, facing: boolean) => {
      const world = makeWorld({ sleep: false })
      const a = addEntity(world), b = addEntity(world)
      const at = (t: number) => {
        setTransform(world, a, [-Math.cos(2 * t), 1.5, -Math.sin(2 * t)], yaw(facing ? -2 * t : 0))
        setTransform(world, b, [Math.cos(2 * t), 1.5, Math.sin(2 * t)], yaw(facing ? -2 * t : 0))
      }
      at(0)
      const cloth = createCloth(world, { width: 2, height: 0.6, resolution: [8, 6], position: [0, 1.2, 0], material: 'wool' })
      pinParticle(world, cloth, 0, a)
      pinParticle(world, cloth, 7, b)
      const dts = [...fill(120, 1 / 60), h || 1 / 60, ...fill(60, 1 / 60)]
      const c = getClothState(world, cloth)
      const last = Float64Array.from(c.vel)
      let t = 0, dv = 0
      for (let f = 0; f < dts.length; f++) {
        t += dts[f]
        at(t)
        stepCloth(world, dts[f])
        for (let i = 0; i < 3 * c.count; i += 3) {
          if (f >= 120) dv = Math.max(dv, Math.hypot(c.vel[i] - last[i], c.vel[i + 1] - last[i + 1], c.vel[i + 2] - last[i + 2]))
        }
        last.set(c.vel)
      }
      return dv
    }
    // measured: 1.26 m/s facing (14.7 when both swept), 14.7 unturned (swept, as before grouping)
    expect(banner(0.25, true)).toBeLessThan(3)
    expect(banner(0.25, false)).toBeLessThan(20)
  })

  it('a ball nothing follows jumps with the dropped time, as a collider body does (documented): the curtain it crosses in that time is not pushed', () => {
    // (a collider on its own entity jumps so that legs stay with the carried cape they belong to)
    const curtain = (h: number) => {
      const world = makeWorld({ sleep: false })
      const cloth = createCloth(world, { width: 2, height: 2, resolution: 16, position: [0, 2.5, 0] })
      pinRow(world, cloth, 0)
      const ball = addEntity(world)
      setTransform(world, ball, [0, 1.5, -2.5])
      addSphereCollider(world, addEntity(world), { body: ball, radius: 0.3 })
      const dts = [...fill(30, 1 / 60), h || 1 / 60, ...fill(30, 1 / 60)]
      let t = 0, pushed = 0
      for (let f = 0; f < dts.length; f++) {
        t += dts[f]
        setTransform(world, ball, [0, 1.5, -2.5 + 3 * t])
        stepCloth(world, dts[f])
        const c = getClothState(world, cloth)
        for (let i = 0; i < c.count; i++) pushed = Math.max(pushed, c.pos[3 * i + 2])
      }
      return pushed
    }
    expect(curtain(0)).toBeGreaterThan(0.5)
    expect(curtain(0.5)).toBeLessThan(0.05)
  })
})

describe('variable frame times', () => {
  it('bad dt: a ClothError naming dt from stepCloth, beginClothStep and ClothSimulation.step', () => {
    const bad: unknown[] = [-1, -1e-9, NaN, Infinity, -Infinity, '0.016', undefined, null]
    const { world } = capeScene({ colliders: false, character: false })
    const sim = new ClothSimulation({ width: 1, height: 1, resolution: 8 })
    for (const dt of bad) {
      for (const call of [() => stepCloth(world, dt as number), () => beginClothStep(world, dt as number), () => sim.step(dt as number)]) {
        let e: unknown
        try {
          call()
        } catch (x) {
          e = x
        }
        expect(e).toBeInstanceOf(ClothError)
        expect((e as ClothError).argument).toBe('dt')
      }
    }
    // huge: clamped to maxStepsPerFrame, finite
    expect(stepCloth(world, 1e308)).toBe(4)
    expect(stepCloth(world, Number.MAX_VALUE)).toBe(4)
    expect(sim.step(5e-324)).toBe(0)
    expect(stepCloth(world, -0)).toBe(0)
  })

  it('variable rates, jitter, tiny and zero dt, slow motion, fast-forward: finite, bounded, no teleport, no guard reset, ≤ 4 steps a call', () => {
    const cases: [string, number[], number][] = [
      ['30→144', [...fill(90, 1 / 30), ...fill(432, 1 / 144)], 0.05],
      ['jitter 1/50–1/70', Array.from({ length: 240 }, (_, i) => (i % 2 ? 1 / 70 : 1 / 50)), 0.05],
      ['1e-4', [...fill(120, 1 / 60), ...fill(2000, 1e-4), ...fill(60, 1 / 60)], 0.05],
      ['dt 0 every other frame', Array.from({ length: 480 }, (_, i) => (i % 2 ? 0 : 1 / 60)), 0.05],
      ['×0.1', fill(1200, 1 / 600), 0.05],
      ['×4', fill(60, 4 / 60), 0.1],
    ]
    for (const [name, dts, lim] of cases) {
      const r = run(capeScene(), dts, runZ(4))
      console.log(
        `${name}: worst stretch (2nd half) ${pct(max(r.maxStretch, dts.length >> 1))}, deepest in torso ${
          (100 * max(r.depth)).toFixed(1)
        } cm`,
      )
      expect(r.finite).toBe(true)
      expect(r.resets).toBe(0)
      expect(r.teleports).toBe(0)
      expect(max(r.steps)).toBeLessThanOrEqual(4)
      expect(max(r.maxStretch, dts.length >> 1)).toBeLessThan(lim)
      expect(max(r.depth)).toBeLessThan(0) // never inside the torso capsule
    }
  })

  it('slow motion (1/600 frames) and 120 Hz give the 60 Hz run to 1e-9 m', () => {
    const shape = (dts: number[]) => {
      const sc = capeScene()
      run(sc, dts, runZ(4))
      const c = getClothState(sc.world, sc.cape)
      return Array.from(c.pos.slice(0, 3 * c.count))
    }
    const a = shape(fill(120, 1 / 60))
    for (const b of [shape(fill(1200, 1 / 600)), shape(fill(240, 1 / 120))])
      for (let j = 0; j < a.length; j++) expect(Math.abs(a[j] - b[j])).toBeLessThan(1e-9)
  })

  it('hitches never break the max-step clamp and stay finite, without guard resets; custom maxStepsPerFrame honoured', () => {
    for (const h of [0.1, 0.25, 1, 10]) {
      const r = run(capeScene(), [...fill(60, 1 / 60), h, ...fill(10, 1 / 60)], runZ(4))
      expect(r.steps[60]).toBe(4)
      expect(r.finite).toBe(true)
      expect(r.resets).toBe(0)
      expect(max(r.depth)).toBeLessThan(0)
    }
    const w = capeScene({ world: { maxStepsPerFrame: 2 } })
    expect(run(w, [1, 0.05, 0.03], runZ(1)).steps).toEqual([2, 2, 1]) // 0.03 s after an empty accumulator: 1 step, 0.013 s kept
  })

  it('determinism: same dt sequence twice, stepCloth vs begin/endClothStep, snapshot replay mid-accumulator', () => {
    const dts = [
      ...Array.from({ length: 60 }, (_, i) => (i % 2 ? 1 / 70 : 1 / 50)),
      0,
      1e-4,
      1e-4,
      0.25,
      ...fill(30, 1 / 144),
      1.0,
      ...fill(30, 1 / 30),
    ]
    const bytes = (entry: 'step' | 'begin') => {
      const sc = capeScene()
      run(sc, dts, runZ(4), { entry })
      const c = getClothState(sc.world, sc.cape)
      return Buffer.from(new Float64Array([...c.pos.slice(0, 3 * c.count), ...c.vel.slice(0, 3 * c.count)]).buffer).toString('base64')
    }
    const a = bytes('step')
    expect(bytes('step')).toBe(a)
    expect(bytes('begin')).toBe(a)
    const sc = capeScene()
    const first = dts.slice(0, 61), rest = dts.slice(61)
    run(sc, first, runZ(4))
    const saved = saveClothState(sc.world, sc.cape)
    const t0 = first.reduce((x, y) => x + y, 0)
    const m2 = (t: number) => runZ(4)(t + t0)
    run(sc, rest, m2)
    const c = getClothState(sc.world, sc.cape)
    const A = Array.from(c.pos.slice(0, 3 * c.count))
    setTransform(sc.world, sc.hero, runZ(4)(t0).p, yq(0))
    restoreClothState(sc.world, sc.cape, saved)
    run(sc, rest, m2)
    expect(Array.from(c.pos.slice(0, 3 * c.count))).toEqual(A)
  })

  it('a flag in gusty wind through a 1 s hitch, jitter and 0/1e-4 frames stays finite without resets', () => {
    const cases: number[][] = [
      [...fill(150, 1 / 60), 1, ...fill(150, 1 / 60)],
      Array.from({ length: 300 }, (_, i) => (i % 2 ? 1 / 70 : 1 / 50)),
      Array.from({ length: 900 }, (_, i) => (i % 3 === 0 ? 1 / 60 : i % 3 === 1 ? 0 : 1e-4)),
    ]
    for (const dts of cases) {
      const world = makeWorld({ sleep: false })
      const pole = addEntity(world)
      setTransform(world, pole, [0, 2, 0])
      const flag = createCloth(world, {
        width: 1.5,
        height: 1,
        resolution: [24, 16],
        position: [0.75, 2, 0],
        rotation: [Math.SQRT1_2, 0, 0, Math.SQRT1_2],
        material: 'nylon',
      })
      const c = getClothState(world, flag)
      const zone = createWindZone(world, { direction: [1, 0, 0.2], strength: 9, turbulence: 0.3 })
      for (let i = 0; i < c.count; i += 24) pinParticle(world, flag, i, pole)
      for (let f = 0; f < dts.length; f++) {
        if (f === 100) gustWind(world, zone, { strength: 10, duration: 1 })
        expect(stepCloth(world, dts[f])).toBeLessThanOrEqual(4)
      }
      for (let i = 0; i < 3 * c.count; i++) expect(Number.isFinite(c.pos[i])).toBe(true)
      expect(getClothStats(world).guardResets).toBe(0)
    }
  })
})
