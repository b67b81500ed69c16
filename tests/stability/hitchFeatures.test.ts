// Hitches with the other features: leg colliders on their own entities jump with the carried
// cape (swept while the cape was carried, they ran through it: 347 %), a snapshot saved after a
// refused hitch frame replays (it forgot the pending dropped time: 0.17 m apart), workers give the
// same positions through hitches, a sleeping cape woken by a hitch frame is carried.
import { addEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  addCapsuleCollider,
  beginClothStep,
  createCloth,
  createWindZone,
  getClothComponents,
  getClothState,
  getClothStats,
  getClothStretch,
  pinRow,
  restoreClothState,
  saveClothState,
  setClothInertia,
  setClothMotionConstraints,
  setTransform,
  stepCloth,
  disposeClothWorld,
  isClothSleeping,
} from '../../src/index'
import { makeWorld } from '../helpers'
import { capeScene, yq } from './hitchScene'

type V3 = [number, number, number]

const runZ = (speed: number) => (t: number): V3 => {
  const t0 = 0.5, ta = speed / 10
  if (t <= t0) return [0, 0, 0]
  const u = t - t0
  return [0, 0, u < ta ? 5 * u * u : 5 * ta * ta + speed * (u - ta)]
}

/** deepest penetration of any cape particle into a leg capsule at hero position p (m; negative: outside) */
function legDepth(world: object, cape: number, p: V3): number {
  const c = getClothState(world, cape)
  let worst = -Infinity
  for (let i = 0; i < c.count; i++) {
    for (const lx of [-0.1, 0.1]) {
      const x = c.pos[3 * i] - p[0] - lx, y = c.pos[3 * i + 1] - p[1], z = c.pos[3 * i + 2] - p[2]
      const cy = Math.max(0.15, Math.min(0.75, y))
      worst = Math.max(worst, 0.09 - Math.hypot(x, y - cy, z))
    }
  }
  return worst
}
/** particles in front of the body plane (z > hero + 0.2), at hem heights */
function inFront(world: object, cape: number, p: V3): number {
  const c = getClothState(world, cape)
  let n = 0
  for (let i = 0; i < c.count; i++) if (c.pos[3 * i + 2] - p[2] > 0.1) n++
  return n
}

describe('hitch: carried cape vs uncarried leg colliders on bone entities', () => {
  it('a 0.5 s hitch at 4 m/s: the carried cape is not swept through by the legs (stretch within 2 points of the unhitched run, no particle in front of the body)', () => {
    const res: Record<string, { stretch: number; front: number; depth: number }> = {}
    for (const [speed, hitch] of [[4, 0], [4, 0.5], [1.5, 0], [1.5, 1]]) {
      const s = capeScene({ legs: true, height: 1.35, behind: -0.14 })
      const mot = runZ(speed)
      let t = 0, worstStretch = 0, worstDepth = -1, front = 0
      for (let f = 0; f < 120; f++) {
        const dt = f === 80 && hitch > 0 ? hitch : 1 / 60
        t += dt
        const p = mot(t)
        setTransform(s.world, s.hero, p)
        s.legs.forEach((l, i) => setTransform(s.world, l, [p[0] + (i ? 0.1 : -0.1), 0.45, p[2]]))
        stepCloth(s.world, dt)
        if (f >= 80) {
          worstStretch = Math.max(worstStretch, getClothStretch(s.world, s.cape).max)
          worstDepth = Math.max(worstDepth, legDepth(s.world, s.cape, p))
          front = Math.max(front, inFront(s.world, s.cape, p))
        }
      }
      console.log(
        'speed',
        speed,
        'hitch',
        hitch,
        'stretch',
        worstStretch.toFixed(3),
        'legDepth',
        worstDepth.toFixed(4),
        'inFront',
        front,
        'resets',
        getClothStats(s.world).guardResets,
      )
      res[`${speed}/${hitch}`] = { stretch: worstStretch, front, depth: worstDepth }
    }
    // measured: 4 m/s unhitched 14.8 %, 0 in front, 26 cm outside the legs; 0.5 s hitch 347 %, 75 particles in front, 2.9 cm inside a leg
    // 1.5 m/s: unhitched 15.3 %; 1 s hitch 75.3 %
    expect(res['4/0.5'].front).toBe(0)
    expect(res['4/0.5'].stretch).toBeLessThan(res['4/0'].stretch + 0.02)
    expect(res['4/0.5'].depth).toBeLessThan(0)
    expect(res['1.5/1'].stretch).toBeLessThan(res['1.5/0'].stretch + 0.02)
  })
})

describe('snapshot after a refused hitch frame', () => {
  it('restoring a snapshot saved after a refused 0.5 s frame replays byte for byte', () => {
    const s = capeScene({ height: 1.35, behind: -0.14 })
    const mot = runZ(4)
    let t = 0
    const _frames: number[] = []
    for (let f = 0; f < 60; f++) {
      t += 1 / 60
      setTransform(s.world, s.hero, mot(t))
      stepCloth(s.world, 1 / 60)
    }
    // a hitch frame refused by a bad Transform
    t += 0.5
    getClothComponents(s.world).Transform.px[s.hero] = NaN
    let threw = false
    try {
      stepCloth(s.world, 0.5)
    } catch {
      threw = true
    }
    expect(threw).toBe(true)
    setTransform(s.world, s.hero, mot(t))
    const saved = saveClothState(s.world, s.cape)
    const t0 = t
    const runOn = () => {
      let tt = t0
      for (let f = 0; f < 30; f++) {
        tt += 1 / 60
        setTransform(s.world, s.hero, mot(tt))
        stepCloth(s.world, 1 / 60)
      }
      return Array.from(getClothState(s.world, s.cape).pos)
    }
    setTransform(s.world, s.hero, mot(t0))
    const a = runOn()
    restoreClothState(s.world, s.cape, saved)
    setTransform(s.world, s.hero, mot(t0))
    const b = runOn()
    let diff = 0
    for (let i = 0; i < a.length; i++) diff = Math.max(diff, Math.abs(a[i] - b[i]))
    console.log('replay max diff', diff)
    expect(diff).toBe(0) // measured 0.173 m: K_DROPPED is not in the snapshot (set to 0 on restore)
  })
})
import { workerUrl } from '../threads/helpers'
import { installClothPlugin } from '../../src/index'
import { createWorld } from 'bitecs'

describe('threads through hitches', () => {
  it('hitches of 0.5, 0.2, 1.3 s with two capes (keep / reset), legs: 0 and 2 workers give the same positions', async () => {
    const hashes: string[][] = []
    for (const threads of [0, 2]) {
      const world = installClothPlugin(createWorld(), { sleep: false, threads, workerUrl: workerUrl(), threadMinStepMs: 0 })
      const hero = addEntity(world)
      setTransform(world, hero, [0, 0, 0])
      const torso = addEntity(world)
      addCapsuleCollider(world, torso, { body: hero, offset: [0, 1.15, 0], radius: 0.19, halfHeight: 0.22 })
      const leg = addEntity(world)
      setTransform(world, leg, [0, 0.45, 0])
      addCapsuleCollider(world, leg, { radius: 0.09, halfHeight: 0.3 })
      const capes: number[] = []
      for (const x of [-0.15, 0.15]) {
        const cape = createCloth(world, {
          width: 0.3,
          height: 1.0,
          resolution: [8, 14],
          position: [x, 1.47, -0.2],
          rotation: [0, 1, 0, 0],
          material: 'wool',
        })
        pinRow(world, cape, 0, hero)
        setClothInertia(world, cape, {
          frame: hero,
          linear: 0.5,
          angular: 0.5,
          centrifugal: 0.5,
          teleport: { mode: x < 0 ? 'reset' : 'keep', angle: Math.PI / 2 },
        })
        setClothMotionConstraints(world, cape, { maxDistance: 0.5, backstop: { distance: 0.02, radius: 0.5 } })
        capes.push(cape)
      }
      createWindZone(world, { direction: [1, 0, 0], strength: 0 })
      const out: string[] = []
      let t = 0
      for (let f = 0; f < 90; f++) {
        const dt = f === 40 ? 0.5 : f === 60 ? 0.2 : f === 70 ? 1.3 : 1 / 60
        t += dt
        const p: V3 = [Math.sin(t), 0, 3 * t]
        setTransform(world, hero, p, yq(2 * t))
        setTransform(world, leg, [p[0], 0.45, p[2]])
        beginClothStep(world, dt)
        await (await import('../../src/index')).endClothStepAsync(world)
        let h = 0
        for (const c of capes) {
          const pos = getClothState(world, c).pos
          for (let i = 0; i < pos.length; i++) h = (h * 31 + Math.round(pos[i] * 1e9)) % 1e12
        }
        out.push(String(h))
      }
      disposeClothWorld(world)
      hashes.push(out)
    }
    let first = -1
    for (let f = 0; f < hashes[0].length; f++)
      if (hashes[0][f] !== hashes[1][f]) {
        first = f
        break
      }
    console.log('first diff frame', first)
    expect(first).toBe(-1)
  }, 60000)
})

describe('a sleeping cape through a hitch', () => {
  it('a sleeping cape whose character starts walking in a 0.5 s hitch frame stretches as without the hitch', () => {
    const r: number[] = []
    for (const hitch of [0, 0.5]) {
      const world = makeWorld({ sleep: { speed: 0.01, delay: 0.5 } })
      const hero = addEntity(world)
      setTransform(world, hero, [0, 0, 0])
      const cape = createCloth(world, {
        width: 0.55,
        height: 1.05,
        resolution: [14, 24],
        position: [0, 1.47, -0.2],
        rotation: [0, 1, 0, 0],
        material: 'wool',
      })
      pinRow(world, cape, 0, hero)
      for (let f = 0; f < 300; f++) stepCloth(world, 1 / 60)
      expect(isClothSleeping(world, cape)).toBe(true)
      let t = 0, worst = 0
      for (let f = 0; f < 60; f++) {
        const dt = f === 0 && hitch > 0 ? hitch : 1 / 60
        t += dt
        setTransform(world, hero, [0, 0, 3 * t])
        stepCloth(world, dt)
        worst = Math.max(worst, getClothStretch(world, cape).max)
      }
      r.push(worst)
    }
    console.log('sleep stretch', r)
    expect(r[1]).toBeLessThan(r[0] + 0.02)
  })
})
