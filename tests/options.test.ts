// Bad input the product rule covers (a ClothError naming the argument), found by a hunt: misspelt
// option keys were ignored, 'false' turned tethers on, frozen out arrays threw TypeErrors, integer
// transform stores rounded positions away, huge calibrations and kernel positions made Infinity and
// NaN, and the exported substep ladder could be rewritten. Each test failed before its fix.
import { addEntity, createWorld } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  ClothError,
  ClothSimulation,
  SUBSTEP_LADDER,
  addSphereCollider,
  createCloth,
  createWindZone,
  getClothBudgetStats,
  getClothDrawTransform,
  getClothLod,
  getClothState,
  getClothStretch,
  getColliderPose,
  getGrabForce,
  getTransform,
  grabParticle,
  installClothPlugin,
  makeTearable,
  pinParticle,
  sampleWind,
  saveClothState,
  setClothBudget,
  setClothGuard,
  setClothInertia,
  setClothMotionConstraints,
  setClothQuality,
  setClothSleep,
  setClothTethers,
  setTransform,
  setWindZone,
  solveDistances,
  spreadInverseMasses,
  stepCloth,
} from '../src/index'

const sheet = { width: 1, height: 1, resolution: 4 }

/** What `fn` did: the ClothError's argument, or 'no error', or the other error's name. */
function outcome(fn: () => unknown): string {
  try {
    fn()
    return 'no error'
  } catch (e) {
    return e instanceof ClothError ? `ClothError(${e.argument})` : `${(e as Error).name}`
  }
}

function scene() {
  const world = installClothPlugin(createWorld())
  const hero = addEntity(world)
  setTransform(world, hero, [0, 2, 0])
  const cloth = createCloth(world, { ...sheet, position: [0, 2, 0] })
  return { world, hero, cloth }
}

describe('bad input: options, out arrays, host stores, calibration, kernels', () => {
  it('unknown option keys (typos) are rejected with a ClothError naming the key, in 16 options objects across the API (top-level and nested)', () => {
    // [call, the argument the error should name]
    const cases: [string, () => unknown, string][] = [
      [
        'installClothPlugin {fixedTimestep}',
        () => installClothPlugin(createWorld(), { fixedTimestep: 1 / 120 } as never),
        'options.fixedTimestep',
      ],
      ['createCloth {substep}', () => createCloth(scene().world, { ...sheet, substep: 4 } as never), 'options.substep'],
      [
        'createCloth {guard:{enable}}',
        () => createCloth(scene().world, { ...sheet, guard: { enable: false } } as never),
        'options.guard.enable',
      ],
      ['setClothQuality {substep}', () => {
        const s = scene()
        setClothQuality(s.world, s.cloth, { substep: 4 } as never)
      }, 'quality.substep'],
      ['setClothGuard {enable}', () => {
        const s = scene()
        setClothGuard(s.world, s.cloth, { enable: false } as never)
      }, 'options.enable'],
      ['setClothSleep {enable}', () => {
        const s = scene()
        setClothSleep(s.world, s.cloth, { enable: false } as never)
      }, 'options.enable'],
      ['pinParticle {blendtime}', () => {
        const s = scene()
        pinParticle(s.world, s.cloth, 0, s.hero, [0, 0, 0], { blendtime: 1 } as never)
      }, 'options.blendtime'],
      ['grabParticle {maxforce}', () => {
        const s = scene()
        grabParticle(s.world, s.cloth, 0, [0, 0, 0], { maxforce: 1 } as never)
      }, 'options.maxforce'],
      ['setClothInertia {linearScale}', () => {
        const s = scene()
        setClothInertia(s.world, s.cloth, { linearScale: 0.5 } as never)
      }, 'options.linearScale'],
      ['setClothMotionConstraints {maxDistances}', () => {
        const s = scene()
        setClothMotionConstraints(s.world, s.cloth, { maxDistances: 0 } as never)
      }, 'constraints.maxDistances'],
      ['addSphereCollider {offest}', () => {
        const s = scene()
        addSphereCollider(s.world, s.hero, { radius: 0.1, offest: [0, 1, 0] } as never)
      }, 'options.offest'],
      [
        'createWindZone {turbulance}',
        () => createWindZone(scene().world, { direction: [1, 0, 0], strength: 1, turbulance: 0.5 } as never),
        'options.turbulance',
      ],
      ['setWindZone {position} (not settable: silently ignored)', () => {
        const { world } = scene()
        setWindZone(world, createWindZone(world, { direction: [1, 0, 0], strength: 1 }), { position: [5, 0, 0] } as never)
      }, 'options.position'],
      ['makeTearable {strian}', () => {
        const s = scene()
        makeTearable(s.world, s.cloth, { strian: 0.1 } as never)
      }, 'options.strian'],
      ['setClothBudget {msPerframe}', () => setClothBudget(scene().world, { msPerframe: 4 } as never), 'options.msPerframe'],
      ['new ClothSimulation {materal}', () => new ClothSimulation({ ...sheet, materal: 'silk' } as never), 'options.materal'],
    ]
    const wrong = cases
      .map(([what, fn, arg]) => [what, outcome(fn), `ClothError(${arg})`])
      .filter(([, got, want]) => got !== want)
      .map(([what, got]) => `${what}: ${got}`)
    expect(wrong).toEqual([])
  })

  it('tethers.enabled must be a boolean ({enabled: "false"} turned tethers on)', () => {
    const { world, cloth } = scene()
    setClothTethers(world, cloth, false)
    expect(outcome(() => setClothTethers(world, cloth, { enabled: 'false' } as never))).toBe('ClothError(tethers.enabled)')
    expect(getClothState(world, cloth).tethers.enabled).toBe(false) // it is true now
  })

  it('a read-only out array gets a ClothError naming it, not a TypeError', () => {
    const { world, cloth, hero } = scene()
    const ball = addEntity(world)
    setTransform(world, ball, [0, 0, 0])
    addSphereCollider(world, ball, { radius: 0.1 })
    const grab = grabParticle(world, cloth, 0, [0, 2, 0])
    const ro3 = () => Object.freeze([0, 0, 0]) as never
    const cases: [string, () => unknown, string][] = [
      ['sampleWind', () => sampleWind(world, [0, 0, 0], ro3()), 'out'],
      ['getTransform', () => getTransform(world, hero, ro3()), 'outPosition'],
      ['getColliderPose', () => getColliderPose(world, ball, ro3()), 'outPosition'],
      ['getGrabForce', () => getGrabForce(world, grab, ro3()), 'out'],
      ['getClothDrawTransform', () => getClothDrawTransform(world, cloth, Object.freeze(new Array(16).fill(0)) as never), 'out'],
      ['getClothStretch', () => getClothStretch(world, cloth, Object.freeze({ mean: 0, max: 0 }) as never), 'out'],
      ['saveClothState(into frozen)', () => saveClothState(world, cloth, Object.freeze(saveClothState(world, cloth))), 'into'],
    ]
    const wrong = cases
      .map(([what, fn, arg]) => [what, outcome(fn), `ClothError(${arg})`])
      .filter(([, got, want]) => got !== want)
      .map(([what, got]) => `${what}: ${got}`)
    expect(wrong).toEqual([])
  })

  it('host transform stores of integers are refused (setTransform rounded 0.5, 1.7, -0.25 to 0, 1, 0 and a 90° turn to identity)', () => {
    const t: Record<string, unknown> = { component: {} }
    for (const k of ['px', 'py', 'pz', 'qx', 'qy', 'qz', 'qw']) t[k] = new Int32Array(64)
    expect(outcome(() => installClothPlugin(createWorld(), { transforms: t as never }))).toBe('ClothError(options.transforms.px)')
  })

  it('host scale arrays come as a set (sx and sy without sz made setTransform ignore the scale silently)', () => {
    const t: Record<string, unknown> = { component: {} }
    for (const k of ['px', 'py', 'pz', 'qx', 'qy', 'qz', 'qw', 'sx', 'sy'])
      t[k] = new Float64Array(64).fill(k[0] === 's' || k === 'qw' ? 1 : 0)
    expect(outcome(() => installClothPlugin(createWorld(), { transforms: t as never }))).toBe('ClothError(options.transforms.sz)')
  })

  it('cost calibration is bounded (beyond ~1e306 ns the predicted cost was Infinity and the budget ran the cloth at full quality)', () => {
    const { world, cloth } = scene()
    const calibration = { nsPerParticle: 1e307, nsPerProjection: 1, nsPerColliderTest: 1, nsPerClothSubstep: 1 }
    expect(outcome(() => setClothBudget(world, { msPerFrame: 4, calibration }))).toBe('ClothError(options.calibration.nsPerParticle)')
    // a second per particle is still taken, and its cost stays finite: the budget drops to 1 substep
    setClothBudget(world, { msPerFrame: 4, calibration: { ...calibration, nsPerParticle: 1e9 } })
    for (let f = 0; f < 40; f++) stepCloth(world, 1 / 60)
    expect(Number.isFinite(getClothBudgetStats(world).predictedMs)).toBe(true)
    expect(getClothLod(world, cloth).substeps).toBe(1)
  })

  it('checked kernel solveDistances refuses positions of 1e300 (they made NaN silently)', () => {
    const inv = Float64Array.from([1, 1])
    const inv3 = new Float64Array(6)
    spreadInverseMasses(inv, inv3, 2)
    const p = new Float64Array(12).fill(1)
    const pos = Float64Array.from([0, 0, 0, 1e300, 1e300, 0])
    const r = outcome(() => solveDistances(pos, inv3, Int32Array.from([0, 3]), Float64Array.from([1]), Float64Array.from([0]), p, 0, 1))
    expect(r).toBe('ClothError(pos[3])') // it made [NaN, NaN, 0, NaN, NaN, 0]
  })

  it('SUBSTEP_LADDER is frozen, as ClothMaterial is (the budget reads it; SUBSTEP_LADDER.reverse() rewrote it)', () => {
    expect(Object.isFrozen(SUBSTEP_LADDER)).toBe(true)
  })
})
