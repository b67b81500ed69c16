// Torture suite, part 4: colliders. Colliders jumping 100 m in one step, colliders spawned inside
// the cloth (every shape), a cape's own body teleporting, and a long session of a cape with body
// colliders on a random-walking, randomly teleporting character. See harness.ts for what every
// case must show.
import { addEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  addBoxCollider,
  addCapsuleCollider,
  addConvexHullCollider,
  addPlaneCollider,
  addSphereCollider,
  removeCollider,
  setTransform,
} from '../../src/index'
import { rng } from '../helpers'
import { expectStable, expectStuck, hangingSheet, runTorture, type Scene } from './harness'
import { heroWithBody, poseLegs } from './scenes'

type Ball = Scene<{ cloths: number[]; ball: number }>

/** A 1 m sheet hanging from its top row (y 1…2, in the plane z = 0) and a collider entity at `at`. */
function sheetAndCollider(add: (world: object, e: number) => void, at: number[], sheet: Parameters<typeof hangingSheet>[1] = {}) {
  return (world: object) => {
    const cloth = hangingSheet(world, sheet)
    const ball = addEntity(world)
    setTransform(world, ball, at)
    add(world, ball)
    return { cloths: [cloth], ball }
  }
}
const sphere = (radius: number) => (w: object, e: number) => addSphereCollider(w, e, { radius })
const capsule = (w: object, e: number) => addCapsuleCollider(w, e, { radius: 0.15, halfHeight: 0.3, axis: [1, 0.2, 0] })

describe('colliders moving 100 m in one step', () => {
  it('a sphere jumping 100 m through a hanging sheet lands beyond it without sweeping it', () => {
    expectStable(runTorture({
      build: sheetAndCollider(sphere(0.2), [0, 1.5, -50]),
      abuse: (s: Ball, f) => {
        if (f === 30) setTransform(s.world, s.ball, [0, 1.5, 50])
      },
      release: (s: Ball) => setTransform(s.world, s.ball, [0, 1.5, -50]),
    }))
  })

  it('a capsule jumping 100 m back and forth through the sheet every step for two seconds', () => {
    expectStable(runTorture({
      build: sheetAndCollider(capsule, [0, 1.5, -50]),
      abuse: (s: Ball, f) => setTransform(s.world, s.ball, [0.1 * Math.sin(f), 1.5 + 0.3 * Math.cos(f), f % 2 ? 50 : -50]),
      release: (s: Ball) => setTransform(s.world, s.ball, [0, 1.5, -50]),
    }))
  })

  it('a sphere jumping 100 m into the middle of the sheet, and away again', () => {
    expectStable(runTorture({
      build: sheetAndCollider(sphere(0.2), [0, 1.5, -100]),
      abuse: (s: Ball, f) => {
        if (f === 30) setTransform(s.world, s.ball, [0.05, 1.5, 0.03])
      },
      release: (s: Ball) => setTransform(s.world, s.ball, [0, 1.5, -100]),
    }))
  })

  it('with teleport detection off, a sphere sweeping 100 m through the sheet in one step drags what it meets: the guard resets the sheet, which recovers', () => {
    // A collider never lets a particle pass through it, and the pins never let go: at 6,000 m/s
    // the particles it meets are carried along, metres out of the sheet's bounds (48 m without the
    // guard). The guard's bounds test puts the sheet back; once the sphere has passed, it hangs as
    // before. (With teleport detection on, the default, the same motion is a jump: the case above.)
    const r = runTorture({
      world: { teleportDistance: 1e6 },
      build: sheetAndCollider(sphere(0.2), [0, 1.5, -50]),
      abuse: (s: Ball, f) => {
        if (f === 30) setTransform(s.world, s.ball, [0, 1.5, 50])
      },
      release: (s: Ball) => setTransform(s.world, s.ball, [0, 1.5, -50]),
      resets: 4,
    })
    expectStable(r)
    expect(r.resets).toBeGreaterThan(0)
  })
})

describe('a cape’s body colliders teleporting', () => {
  type Hero = Scene<ReturnType<typeof heroWithBody>>
  it('a character with body colliders teleported 100 m with its cape, and back', () => {
    expectStable(runTorture({
      build: (world) => heroWithBody(world),
      abuse: (s: Hero, f) => {
        if (f === 30) setTransform(s.world, s.hero, [100, 1.6, 0], [0, 1, 0, 0])
        if (f === 31) poseLegs(s, [100, 1.6, 0], Math.PI, 0)
        if (f === 60) setTransform(s.world, s.hero, [0, 1.6, 0])
        if (f === 61) poseLegs(s, [0, 1.6, 0], 0, 0)
      },
      release: (s: Hero) => setTransform(s.world, s.hero, [0, 1.6, 0], [0, 0, 0, 1]),
    }))
  })

  it('one body collider (a leg bone) teleported 100 m away, then back inside the cape', () => {
    expectStable(runTorture({
      build: (world) => heroWithBody(world),
      abuse: (s: Hero, f) => {
        if (f === 30) setTransform(s.world, s.legs[0], [0, 0.8, 100])
        if (f === 60) setTransform(s.world, s.legs[0], [0, 1.2, -0.2]) // where the cape hangs
      },
      release: (s: Hero) => setTransform(s.world, s.legs[0], [0, 0.8, 0]),
    }))
  })
})

describe('a collider spawned inside the cloth', () => {
  // spawned where the sheet hangs, its centre 3 cm off the sheet's plane (see the known weakness
  // below for exactly in the plane)
  const shapes: [string, (w: object, e: number) => void][] = [
    ['sphere', sphere(0.25)],
    ['capsule', capsule],
    ['box', (w, e) => addBoxCollider(w, e, { halfExtents: [0.3, 0.2, 0.25], rotation: [0.1, 0.2, 0, 1] })],
    [
      'convex hull',
      (w, e) => addConvexHullCollider(w, e, { points: [0, 0.3, 0, 0.3, 0, 0, -0.3, 0, 0, 0, 0, 0.3, 0, 0, -0.3, 0, -0.3, 0] }),
    ],
    ['plane (tilted floor through the sheet)', (w, e) => addPlaneCollider(w, e, { normal: [0, 1, 0.3] })],
    ['plane (wall through the sheet)', (w, e) => addPlaneCollider(w, e, { normal: [0.2, 0, 1] })],
  ]
  for (const [name, add] of shapes) {
    it(`a ${name} appears in the middle of a hanging sheet, then goes away`, () => {
      expectStable(runTorture({
        build: (world) => ({ cloths: [hangingSheet(world)], ball: addEntity(world) }),
        abuse: (s: Ball, f) => {
          if (f !== 30) return
          setTransform(s.world, s.ball, [0.07, 1.5, 0.03])
          add(s.world, s.ball)
        },
        release: (s: Ball) => removeCollider(s.world, s.ball),
      }))
    })
  }

  it('a box appears around the whole sheet, its pins inside: the sheet is pushed out to the faces, and falls back when it goes', () => {
    // over-constrained: the pins hold the top row inside the box, so the cloth is stretched out to
    // the faces, 2.6 m from its pins; allowed that much (dihedral hinges: see the weakness below)
    expectStable(runTorture({
      build: (world) => ({ cloths: [hangingSheet(world, { bending: 'both' })], ball: addEntity(world) }),
      abuse: (s: Ball, f) => {
        if (f !== 30) return
        setTransform(s.world, s.ball, [0.07, 1.5, 0])
        addBoxCollider(s.world, s.ball, { halfExtents: [2, 2, 2] })
      },
      release: (s: Ball) => removeCollider(s.world, s.ball),
      margin: 1,
    }))
  })
})

describe('known weakness: a collider pushing a flat sheet within its own plane', () => {
  // A sphere or capsule spawned with its centre exactly in the plane of a flat, resting sheet
  // pushes the particles it covers outward within that plane; the lower rows fold up in the plane,
  // and line bending cannot tell the folded rows from straight ones (the in-plane tangle above).
  // Dihedral hinges unfold it. When the solver learns to, these turn red: move them up.
  for (const [name, add] of [['sphere', sphere(0.25)], ['capsule', capsule]] as const) {
    it(`a ${name} spawned exactly in the sheet's plane leaves it folded (line bending)`, () => {
      expectStuck(runTorture({
        build: (world) => ({ cloths: [hangingSheet(world)], ball: addEntity(world) }),
        abuse: (s: Ball, f) => {
          if (f !== 30) return
          setTransform(s.world, s.ball, [0.07, 1.5, 0])
          add(s.world, s.ball)
        },
        release: (s: Ball) => removeCollider(s.world, s.ball),
      }))
    })
    it(`the same with dihedral hinges (${name}) unfolds`, () => {
      expectStable(runTorture({
        build: (world) => ({ cloths: [hangingSheet(world, { bending: 'both' })], ball: addEntity(world) }),
        abuse: (s: Ball, f) => {
          if (f !== 30) return
          setTransform(s.world, s.ball, [0.07, 1.5, 0])
          add(s.world, s.ball)
        },
        release: (s: Ball) => removeCollider(s.world, s.ball),
      }))
    })
  }
})

describe('a long game session with body colliders', () => {
  it('a cape with body colliders on a random-walking, randomly teleporting character for 10,000 steps', () => {
    const r = rng(7)
    const p = [0, 1.6, 0]
    let yaw = 0, t = 0
    const result = runTorture({
      build: (world) => heroWithBody(world, { resolution: [5, 6], substeps: 4 }),
      abuse: (s: Scene<ReturnType<typeof heroWithBody>>) => {
        p[0] += (r() - 0.5) * 0.4
        p[2] += (r() - 0.5) * 0.4
        yaw += (r() - 0.5) * 0.6
        if (r() < 0.01) {
          // teleports: far and near, with a turn
          p[0] += (r() - 0.5) * 200
          p[1] = 1.6 + (r() - 0.5) * 20
          yaw += r() * 6
        }
        const u = r()
        const dt = u < 0.02 ? 0 : u < 0.04 ? 0.25 : (0.5 + r()) / 60 // stalls, hitches, jittery frames
        t += dt
        setTransform(s.world, s.hero, p, [0, Math.sin(yaw / 2), 0, Math.cos(yaw / 2)])
        poseLegs(s, p, yaw, t)
        return dt
      },
      frames: 10_000,
      checkEvery: 10,
      release: (s) => {
        setTransform(s.world, s.hero, [0, 1.6, 0], [0, 0, 0, 1])
        poseLegs(s, [0, 1.6, 0], 0, 0)
      },
      settle: 600,
      // a cape thrown over the shoulders may rest there, on the body: no unique drape
      recover: 'rest',
    })
    expectStable(result)
    expect(result.steps).toBeGreaterThanOrEqual(10_000)
    expect(result.stats.colliderTests).toBeGreaterThan(0)
  })
})
