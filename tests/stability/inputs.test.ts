// Torture suite, part 1: abusive inputs (frame times, pins, a long session). See harness.ts for
// what every case must show; one case per `it`: a scene, an abuse, a release.
import { addEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import { createCloth, pinParticle, setTransform } from '../../src/index'
import { rng } from '../helpers'
import { expectStable, expectStuck, runTorture, type Scene } from './harness'
import { heroWithCape, walk } from './scenes'

describe('frame times', () => {
  for (const dt of [0, 1e-6, 0.1, 1, 10]) {
    it(`frames of ${dt} s while the character walks`, () => {
      let t = 0
      expectStable(runTorture({
        build: (world) => heroWithCape(world),
        abuse: (s, f) => {
          t += dt
          walk(s, t)
          return f % 2 === 0 ? dt : 1 / 60 // alternate with normal frames: abuse between real motion
        },
        release: (s) => setTransform(s.world, s.hero, [0, 1.6, 0], [0, 0, 0, 1]),
        // 'drape' needs the hero back where it started, which walking does not promise
        recover: 'rest',
      }))
    })
  }

  it('a coarse fixed step: 0.1 s with one substep, character walking', () => {
    let t = 0
    expectStable(runTorture({
      world: { fixedTimeStep: 0.1 },
      build: (world) => heroWithCape(world, { substeps: 1 }),
      abuse: (s) => {
        t += 0.1
        walk(s, t)
        return 0.1
      },
      release: (s) => setTransform(s.world, s.hero, [0, 1.6, 0], [0, 0, 0, 1]),
      recover: 'rest',
    }))
  })
})

/** A 1 m sheet with particle 0 and `second` pinned to two target entities a and b. */
const sheetOnTwoTargets = (bending: 'distance' | 'both', second: 1 | 7, tethers = true) => (world: object) => {
  const a = addEntity(world), b = addEntity(world)
  setTransform(world, a, [-0.5, 2, 0])
  setTransform(world, b, [-0.5 + second / 7, 2, 0])
  const cloth = createCloth(world, { width: 1, height: 1, resolution: 8, position: [0, 2, 0], bending, tethers })
  pinParticle(world, cloth, 0, a)
  pinParticle(world, cloth, second, b)
  return { cloths: [cloth], a, b }
}
type TwoTargets = Scene<{ cloths: number[]; a: number; b: number }>

describe('pins', () => {
  // Skip-one ('distance') bending cannot tell a flap folded through the cloth in its own plane from
  // an unfolded one: abuse that moves a flat cloth exactly within its plane (the pins here, with no
  // out-of-plane component) can leave it tangled at rest. Dihedral hinges ('both') unfold it, and
  // so does any out-of-plane motion; the in-plane 'distance' variants are the known weakness below.

  for (const [bending, dz] of [['both', 0], ['distance', 0.3]] as const) {
    const how = dz === 0 ? 'in its plane' : 'partly out of its plane'
    it(`both ends of an edge pinned and pulled 10× apart ${how}, then back (${bending} bending, no tethers)`, () => {
      const L = 1 / 7
      expectStable(runTorture({
        build: sheetOnTwoTargets(bending, 1, false),
        abuse: (s: TwoTargets, f) => {
          const u = Math.min(1, f / 30) // pulled to 10× over half a second, held
          setTransform(s.world, s.b, [-0.5 + L * (1 + 9 * u), 2, dz * u])
        },
        release: (s: TwoTargets) => setTransform(s.world, s.b, [-0.5 + L, 2, 0]),
        settle: 900,
        // hanging from one short edge, the sheet may come to rest turned about it: no unique drape
        recover: 'rest',
      }))
    })

    it(`the two top corners pulled 10× the sheet apart ${how} in one frame, then back (${bending} bending)`, () => {
      expectStable(runTorture({
        build: sheetOnTwoTargets(bending, 7),
        abuse: (s: TwoTargets, f) => {
          if (f !== 10) return
          setTransform(s.world, s.a, [-5, 2, dz])
          setTransform(s.world, s.b, [5, 2, -dz])
        },
        release: (s: TwoTargets) => {
          setTransform(s.world, s.a, [-0.5, 2, 0])
          setTransform(s.world, s.b, [0.5, 2, 0])
        },
        settle: 900,
        drapeTolerance: 0.03,
      }))
    })
  }

  it('pin targets teleported 1 km (with a half turn) and back', () => {
    expectStable(runTorture({
      build: (world) => heroWithCape(world),
      abuse: (s, f) => {
        if (f === 30) setTransform(s.world, s.hero, [1000, 1.6, 0], [0, 1, 0, 0])
        if (f === 60) setTransform(s.world, s.hero, [1000, 1001.6, -1000])
      },
      release: (s) => setTransform(s.world, s.hero, [0, 1.6, 0], [0, 0, 0, 1]),
    }))
  })

  for (const [bending, target] of [['distance', [700, 1.6, 700]], ['both', [1000, 1.6, 0]]] as const) {
    it(`pin targets moved 1 km in one step with teleport detection off: the cloth is dragged (${bending} bending)`, () => {
      expectStable(runTorture({
        world: { teleportDistance: 1e6 },
        build: (world) => heroWithCape(world, { bending }),
        abuse: (s, f) => {
          if (f === 30) setTransform(s.world, s.hero, target)
        },
        release: (s) => setTransform(s.world, s.hero, [0, 1.6, 0]),
        settle: 600,
      }))
    })
  }

  it('pin targets spinning at 100 rad/s for two seconds', () => {
    expectStable(runTorture({
      build: (world) => heroWithCape(world),
      abuse: (s, f) => {
        const a = (100 * f) / 60
        setTransform(s.world, s.hero, [0, 1.6, 0], [0, Math.sin(a / 2), 0, Math.cos(a / 2)])
      },
      release: (s) => setTransform(s.world, s.hero, [0, 1.6, 0], [0, 0, 0, 1]),
      settle: 600,
    }))
  })
})

describe('known weakness: line and skip-one bending tangle under in-plane abuse', () => {
  // These document a limitation rather than a promise (`expectStuck`: the cloth stays finite and
  // bounded but tangled; the test fails if it blows up, and also once it recovers). A cape with the default line bending whose character moves 0.3 m
  // sideways in one frame, exactly in the cape's plane, rests 0.5 m too high with 15 % strain. When
  // the solver learns to untangle this, these turn red: move them up into the suite.
  it('a cape dragged 0.3 m within its own plane in one step stays tangled', () => {
    expectStuck(runTorture({
      build: (world) => heroWithCape(world),
      abuse: (s, f) => {
        if (f === 30) setTransform(s.world, s.hero, [0.3, 1.6, 0])
      },
      release: (s) => setTransform(s.world, s.hero, [0, 1.6, 0]),
    }))
  })
  it('two top corners pulled 10× apart within the sheet plane leave it tangled', () => {
    expectStuck(runTorture({
      build: sheetOnTwoTargets('distance', 7),
      abuse: (s: TwoTargets, f) => {
        if (f !== 10) return
        setTransform(s.world, s.a, [-5, 2, 0])
        setTransform(s.world, s.b, [5, 2, 0])
      },
      release: (s: TwoTargets) => {
        setTransform(s.world, s.a, [-0.5, 2, 0])
        setTransform(s.world, s.b, [0.5, 2, 0])
      },
      settle: 900,
    }))
  })
})

describe('a long game session', () => {
  it('a cape on a random-walking, randomly teleporting character for 10,000 steps', () => {
    const r = rng(2024)
    const p = [0, 1.6, 0]
    let yaw = 0
    const result = runTorture({
      build: (world) => heroWithCape(world, { resolution: [5, 6], substeps: 4 }),
      abuse: (s) => {
        p[0] += (r() - 0.5) * 0.4
        p[2] += (r() - 0.5) * 0.4
        yaw += (r() - 0.5) * 0.6
        if (r() < 0.01) {
          // teleports: far and near, with a turn
          p[0] += (r() - 0.5) * 200
          p[1] = 1.6 + (r() - 0.5) * 20
          yaw += r() * 6
        }
        setTransform(s.world, s.hero, p, [0, Math.sin(yaw / 2), 0, Math.cos(yaw / 2)])
        const u = r()
        return u < 0.02 ? 0 : u < 0.04 ? 0.25 : (0.5 + r()) / 60 // stalls, hitches, jittery frames
      },
      frames: 10_000,
      checkEvery: 10,
      release: (s) => setTransform(s.world, s.hero, [0, 1.6, 0], [0, 0, 0, 1]),
      settle: 600,
    })
    expectStable(result)
    expect(result.steps).toBeGreaterThanOrEqual(10_000)
  })
})
