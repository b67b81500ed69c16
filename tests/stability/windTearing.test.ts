// Torture suite, part 5: wind of 1000 m/s (global, zones, gusts; switched off again) and tearing
// (every edge over its threshold at once, the capacity running out, pieces landing on colliders).
// See harness.ts for what every case must show.
import { addEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  addBoxCollider,
  addCapsuleCollider,
  addConvexHullCollider,
  addSphereCollider,
  createCloth,
  createWindZone,
  getClothTearCount,
  gustWind,
  makeTearable,
  pinParticle,
  removeWindZone,
  setTransform,
  setWindZone,
  type TearableOptions,
} from '../../src/index'
import { expectStable, expectStuck, hangingSheet, runTorture, type Scene } from './harness'
import { heroWithCape, walk } from './scenes'
import { ground as groundPlane } from '../collision/scenes'

type Zoned = Scene<{ cloths: number[]; zone: number }>

describe('wind of 1000 m/s', () => {
  for (const material of ['silk', 'cotton', 'leather'] as const) {
    for (const turbulence of [0, 0.5]) {
      it(`a global wind of 1000 m/s (turbulence ${turbulence}) on a hanging ${material} sheet for two seconds, then calm`, () => {
        expectStable(runTorture({
          build: (world) => ({
            cloths: [hangingSheet(world, { material })],
            zone: createWindZone(world, { direction: [0.3, 0.2, 1], strength: 0, turbulence }),
          }),
          abuse: (s: Zoned, f) => {
            if (f === 0) setWindZone(s.world, s.zone, { strength: 1000 })
          },
          release: (s: Zoned) => setWindZone(s.world, s.zone, { strength: 0 }),
          // heavy leather flung about by the storm swings for a long time in still air (0.5 m/s
          // after 3 s, 0.1 after 10, 0.01 after 20)
          settle: material === 'leather' ? 1200 : 600,
        }))
      })
    }
  }

  it('a box zone of 1000 m/s switched on around the sheet, then removed', () => {
    expectStable(runTorture({
      build: (world) => ({ cloths: [hangingSheet(world)], zone: -1 }),
      abuse: (s: Zoned, f) => {
        if (f === 10)
          s.zone = createWindZone(s.world, {
            shape: 'box',
            position: [0, 1.5, 0],
            size: [1.2, 1.2, 1.2],
            direction: [0.2, 0, -1],
            strength: 1000,
            turbulence: 0.3,
          })
      },
      release: (s: Zoned) => removeWindZone(s.world, s.zone),
    }))
  })

  it('a sphere zone of 1000 m/s sweeping across the sheet', () => {
    expectStable(runTorture({
      build: (world) => ({
        cloths: [hangingSheet(world)],
        zone: createWindZone(world, { shape: 'sphere', position: [-3, 1.5, 0.5], size: 0.6, direction: [0, 0.3, 1], strength: 1000 }),
      }),
      abuse: (s: Zoned, f) => setTransform(s.world, s.zone, [-3 + f / 20, 1.5 + 0.3 * Math.sin(f / 5), 0.5]),
      release: (s: Zoned) => setTransform(s.world, s.zone, [-3, 1.5, 0.5]),
    }))
  })

  it('a gust of 1000 m/s on a light breeze', () => {
    // a light breeze (2 m/s, Beaufort 2) lifts the cotton sheet to ~55° and holds it still there; at
    // 5 m/s it blows it out nearly level, where it flutters and never comes to rest to compare with
    expectStable(runTorture({
      build: (world) => ({ cloths: [hangingSheet(world)], zone: createWindZone(world, { direction: [1, 0, 1], strength: 2 }) }),
      abuse: (s: Zoned, f) => {
        if (f === 10) gustWind(s.world, s.zone, { strength: 1000, duration: 0.5 })
      },
      // the gust dies away by itself; the breeze blows on, as in the twin
    }))
  })

  it('in-plane wind of 1000 m/s on a sheet with dihedral hinges (line bending may fold it within its plane, see inputs)', () => {
    expectStable(runTorture({
      build: (world) => ({
        cloths: [hangingSheet(world, { bending: 'both' })],
        zone: createWindZone(world, { direction: [1, 0, 0], strength: 0 }),
      }),
      abuse: (s: Zoned, f) => {
        if (f === 10) setWindZone(s.world, s.zone, { strength: 1000 })
      },
      release: (s: Zoned) => setWindZone(s.world, s.zone, { strength: 0 }),
    }))
  })

  it('known weakness: the same in-plane wind folds a sheet with line bending within its plane', () => {
    // line bending cannot tell rows folded within the sheet's plane from straight ones (see
    // inputs.test.ts); when the solver learns to unfold them this turns red: move it up
    expectStuck(runTorture({
      build: (world) => ({ cloths: [hangingSheet(world)], zone: createWindZone(world, { direction: [1, 0, 0], strength: 0 }) }),
      abuse: (s: Zoned, f) => {
        if (f === 10) setWindZone(s.world, s.zone, { strength: 1000 })
      },
      release: (s: Zoned) => setWindZone(s.world, s.zone, { strength: 0 }),
    }))
  })

  it('a cape on a walking character in a turbulent storm of 1000 m/s', () => {
    expectStable(runTorture({
      build: (world) => ({
        ...heroWithCape(world),
        zone: createWindZone(world, { direction: [1, 0, 0.2], strength: 1000, turbulence: 0.5 }),
      }),
      abuse: (s: Scene<ReturnType<typeof heroWithCape> & { zone: number }>, f) => walk(s, f / 60),
      release: (s: Scene<ReturnType<typeof heroWithCape> & { zone: number }>) => {
        setTransform(s.world, s.hero, [0, 1.6, 0], [0, 0, 0, 1])
        removeWindZone(s.world, s.zone)
      },
      recover: 'rest',
    }))
  })
})

/** A ground plane at y = 0, and optionally colliders on it for falling pieces to land on. */
function ground(world: object, colliders: boolean) {
  groundPlane(world)
  if (!colliders) return
  const ball = addEntity(world)
  setTransform(world, ball, [0, 0.5, 0.1])
  addSphereCollider(world, ball, { radius: 0.4 })
  const box = addEntity(world)
  setTransform(world, box, [0.6, 0.3, -0.2], [0, 0.38, 0, 0.92])
  addBoxCollider(world, box, { halfExtents: [0.3, 0.3, 0.3] })
  const rock = addEntity(world)
  setTransform(world, rock, [-0.6, 0, 0])
  addConvexHullCollider(world, rock, { points: [0, 0.6, 0, 0.4, 0, 0.4, -0.4, 0, 0.4, 0.4, 0, -0.4, -0.4, 0, -0.4] })
  const log = addEntity(world)
  setTransform(world, log, [0, 0.15, -0.6], [0, 0, Math.SQRT1_2, Math.SQRT1_2])
  addCapsuleCollider(world, log, { radius: 0.15, halfHeight: 0.5 })
}

/** Every edge of a tearable sheet over its threshold (1e-6 strain, any number of tears per step, any piece size). */
const everything = (capacity?: number): TearableOptions => ({ strain: 1e-6, maxTearsPerStep: 4096, hysteresis: 1, capacity, minPiece: 1 })

describe('every edge torn at once', () => {
  for (
    const [name, capacity, colliders] of [
      ['the capacity runs out (the default: as many particles again)', undefined, false],
      ['room for every split: it comes apart crack by crack', 2000, false],
      ['pieces falling onto a sphere, a box, a convex hull and a capsule', 2000, true],
    ] as const
  ) {
    it(`a sheet hanging 4 m up with every edge over its threshold: ${name}`, () => {
      let tears = 0
      const r = runTorture({
        build: (world) => {
          ground(world, colliders)
          return { cloths: [hangingSheet(world, { position: [0, 4, 0] })] }
        },
        abuse: (s, f) => {
          if (f === 20) makeTearable(s.world, s.cloths[0], everything(capacity))
          tears = getClothTearCount(s.world, s.cloths[0])
        },
        pieces: true,
        floor: 0,
        recover: 'rest',
      })
      expectStable(r)
      expect(tears).toBeGreaterThanOrEqual(capacity === undefined ? 64 : 150)
    })
  }

  // The pins' targets jump 4.5 m each (a teleport): the piece the first one holds is carried
  // along, and the pieces torn off before stay where they are. When the carry took every piece
  // along, one of them landed with a particle squeezed between the convex hull's base and the
  // ground (inside the hull's margin, whose nearest face is the base) and rested with an edge held
  // at about 3× its length; this scene no longer puts a piece there.
  for (
    const [label, tear] of [['a tiny threshold (every edge over it)', everything()], ['a 20 % threshold, 64 tears a step', {
      strain: 0.2,
      maxTearsPerStep: 64,
    }]] as const
  ) {
    it(`a tearable sheet with ${label} whose two top corners are pulled 10× the sheet apart in one frame, pieces landing on colliders`, () => {
      const r = runTorture({
        build: (world) => {
          ground(world, true)
          const a = addEntity(world), b = addEntity(world)
          setTransform(world, a, [-0.5, 3, 0])
          setTransform(world, b, [0.5, 3, 0])
          const cloth = createCloth(world, { width: 1, height: 1, resolution: 8, position: [0, 3, 0], bending: 'both' })
          pinParticle(world, cloth, 0, a)
          pinParticle(world, cloth, 7, b)
          makeTearable(world, cloth, tear)
          return { cloths: [cloth], a, b }
        },
        abuse: (s: Scene<{ cloths: number[]; a: number; b: number }>, f) => {
          if (f !== 10) return
          setTransform(s.world, s.a, [-5, 3, 0.3])
          setTransform(s.world, s.b, [5, 3, -0.3])
        },
        release: (s: Scene<{ cloths: number[]; a: number; b: number }>) => {
          setTransform(s.world, s.a, [-0.5, 3, 0])
          setTransform(s.world, s.b, [0.5, 3, 0])
        },
        pieces: true,
        floor: 0,
        recover: 'rest',
      })
      expectStable(r)
      expect(r.stats.tears).toBeGreaterThan(0) // it did tear
    })
  }

  it('torn pieces blown away by 50 m/s wind, then left to land', () => {
    const r = runTorture({
      build: (world) => {
        ground(world, true)
        const cloth = hangingSheet(world, { position: [0, 4, 0] })
        makeTearable(world, cloth, { strain: 0.05, maxTearsPerStep: 16 })
        return { cloths: [cloth], zone: createWindZone(world, { direction: [1, 0.2, 0.5], strength: 0, turbulence: 0.5 }) }
      },
      abuse: (s: Zoned, f) => {
        if (f === 10) setWindZone(s.world, s.zone, { strength: 50 })
      },
      release: (s: Zoned) => setWindZone(s.world, s.zone, { strength: 0 }),
      pieces: true,
      floor: 0,
      // blown far away, pieces may still be fluttering down when the run ends
      recover: 'bounded',
    })
    expectStable(r)
    expect(r.stats.tears).toBeGreaterThan(0) // the wind tore it
  })

  // A known weakness: from about 70 m/s (measured: 50 m/s stays inside, 70–1000 m/s leave it by
  // 0.2–0.9 m), turbulent wind stretches free pieces of a dozen triangles or more (tearing cuts off
  // nothing smaller than `minPiece`) wider than the allowed region while they fly. The guard
  // measures speed within each piece, so pieces flying apart at their own speeds are not reset
  // (measured: at most one reset at 400 m/s, none at 1000). The cloth stays finite. When the
  // solver learns to hold such pieces together, this turns red: move it up into the suite.
  it('torn pieces blown away by 1000 m/s wind are stretched past the allowed region while they fly; nothing goes non-finite', () => {
    const r = runTorture({
      build: (world) => {
        ground(world, true)
        const cloth = hangingSheet(world, { position: [0, 4, 0] })
        makeTearable(world, cloth, { strain: 0.05, maxTearsPerStep: 16 })
        return { cloths: [cloth], zone: createWindZone(world, { direction: [1, 0.2, 0.5], strength: 0, turbulence: 0.5 }) }
      },
      abuse: (s: Zoned, f) => {
        if (f === 10) setWindZone(s.world, s.zone, { strength: 1000 })
      },
      release: (s: Zoned) => setWindZone(s.world, s.zone, { strength: 0 }),
      pieces: true,
      floor: 0,
      recover: 'bounded',
    })
    expect(r.finite).toBe(true)
    expect(r.worstExcess).toBeGreaterThan(0)
    expect(r.resets).toBeLessThanOrEqual(2)
  })
})
