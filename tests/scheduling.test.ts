// The phases run by hand (an engine with its own scheduler), and listeners: cloths may not change
// between a step's clothSync and its clothGuard (motion constraints switched on there ran against a
// reference the sync had not set up: 491 % stretch; a pin made there took the target's pose at the
// step's end for its start: 0.2 m off for good), and a step's listeners may change the world but
// not step it (a nested clothFixedStep in a tear listener lost two of the outer step's events and
// delivered two of its own twice; the phase systems ran in a stepCloth listener).
import { addEntity, createWorld } from 'bitecs'
import { describe, expect, it } from 'vitest'
import * as C from '../src/index'

const frame = 1 / 60

function refusal(fn: () => unknown): string {
  try {
    fn()
    return 'ran'
  } catch (e) {
    return e instanceof C.ClothError ? `ClothError(${e.argument})` : String(e)
  }
}

/** A 1 m sheet pinned by its top row to a hero, 5 frames in; then one step run phase by phase with `op` called at `when`. */
function handStep(
  when: 'before sync' | 'after sync' | 'mid substeps' | 'after guard',
  op: (world: object, cloth: number, hero: number) => void,
) {
  const world = C.installClothPlugin(createWorld())
  const hero = addEntity(world)
  C.setTransform(world, hero, [0, 1.6, 0])
  const cl = C.createCloth(world, { width: 1, height: 1, resolution: 5, position: [0, 1.6, 0] })
  C.pinRow(world, cl, 0, hero)
  for (let f = 0; f < 5; f++) C.stepCloth(world, frame)
  C.setTransform(world, hero, [0.2, 1.6, 0]) // the hero moves 0.2 m in this step
  let result = 'not called'
  const call = () => (result = refusal(() => op(world, cl, hero)))
  if (when === 'before sync') call()
  C.clothSync(world)
  if (when === 'after sync') call()
  const n = C.clothSubstepCount(world)
  for (let s = 0; s < n; s++) {
    if (when === 'mid substeps' && s === n >> 1) call()
    C.setClothSubstep(world, s)
    for (const phase of C.clothPhases) phase(world)
  }
  C.clothGuard(world)
  if (when === 'after guard') call()
  C.clothEvents(world)
  for (let f = 0; f < 5; f++) C.stepCloth(world, frame)
  return { result, stretch: C.getClothStretch(world, cl).max }
}

describe('phases run by hand', () => {
  const ops: [string, (world: object, cloth: number, hero: number) => void][] = [
    ['setClothMotionConstraints', (world, cloth) => C.setClothMotionConstraints(world, cloth, { maxDistance: 0.2, drive: 0.3 })],
    ['pinParticle', (world, cloth, hero) => C.pinParticle(world, cloth, 24, hero)],
    ['createCloth', (world) => C.createCloth(world, { width: 0.2, height: 0.2, resolution: 2 })],
  ]
  for (const [name, op] of ops) {
    it(`${name} between clothSync and clothGuard is refused (ClothError naming the world); before the sync and after the guard it runs, and the cloth stays calm`, () => {
      expect(handStep('after sync', op).result).toBe('ClothError(world)')
      expect(handStep('mid substeps', op).result).toBe('ClothError(world)')
      for (const when of ['before sync', 'after guard'] as const) {
        const r = handStep(when, op)
        expect(r.result).toBe('ran')
        expect(r.stretch).toBeLessThan(0.1)
      }
    })
  }
  it('the substep phases run once per step instead of once per substep: the guard throws a ClothError naming the world; the full loop gives the bytes of clothFixedStep', () => {
    // (piped once each per fixed step, as a system list reads, every cloth fell at 1/8 of g with 8
    // substeps, silently; found by a hunt)
    const make = () => {
      const world = C.installClothPlugin(createWorld(), { sleep: false })
      const cloth = C.createCloth(world, { width: 1, height: 1, resolution: 6, position: [0, 2, 0] })
      return { world, cloth }
    }
    const once = make()
    C.clothSync(once.world)
    for (const phase of C.clothPhases) phase(once.world)
    let error: unknown = null
    try {
      C.clothGuard(once.world)
    } catch (e) {
      error = e
    }
    expect(error).toBeInstanceOf(C.ClothError)
    expect((error as C.ClothError).argument).toBe('world')
    // the step is abandoned: the world may change again, and steps on
    C.createCloth(once.world, { width: 0.5, height: 0.5, resolution: 3, position: [3, 2, 0] })
    C.clothFixedStep(once.world)
    // the recipe, and the guard alone after a step run otherwise, are fine
    const byHand = make(), fixed = make()
    for (let f = 0; f < 30; f++) {
      C.clothSync(byHand.world)
      for (let s = 0; s < C.clothSubstepCount(byHand.world); s++) {
        C.setClothSubstep(byHand.world, s)
        for (const phase of C.clothPhases) phase(byHand.world)
      }
      C.clothGuard(byHand.world)
      C.clothEvents(byHand.world)
      C.clothFixedStep(fixed.world)
      C.clothGuard(fixed.world)
    }
    const a = C.getClothState(byHand.world, byHand.cloth).pos, b = C.getClothState(fixed.world, fixed.cloth).pos
    expect(Array.from(a)).toEqual(Array.from(b))
  })

  it('a step abandoned after its sync leaves the world changeable once the next step finishes', () => {
    const world = C.installClothPlugin(createWorld())
    const cl = C.createCloth(world, { width: 1, height: 1, resolution: 5 })
    C.clothSync(world)
    expect(refusal(() => C.pinParticle(world, cl, 0))).toBe('ClothError(world)')
    C.stepCloth(world, frame)
    expect(refusal(() => C.pinParticle(world, cl, 0))).toBe('ran')
  })
})

/** A sheet hanging by its top row that tears 3 edges per step from its second step on. */
function tearing() {
  const world = C.installClothPlugin(createWorld())
  const cl = C.createCloth(world, { width: 1, height: 1, resolution: 6, position: [0, 2, 0] })
  C.pinRow(world, cl, 0)
  C.makeTearable(world, cl, { strain: 1e-6, maxTearsPerStep: 3, hysteresis: 1 })
  C.clothFixedStep(world) // one tear; three per step from here
  return { world, cl }
}

describe('listeners may change the world but not step it', () => {
  for (const how of ['stepCloth', 'clothFixedStep', 'the phases by hand'] as const) {
    it(`in a tear listener of ${how}: every step and phase is refused`, () => {
      const { world, cl } = tearing()
      const got: Record<string, string> = {}
      C.onClothTear(world, () => {
        if (Object.keys(got).length > 0) return
        got.clothFixedStep = refusal(() => C.clothFixedStep(world))
        got.stepCloth = refusal(() => C.stepCloth(world, frame))
        got.beginClothStep = refusal(() => C.beginClothStep(world, frame))
        got.clothSync = refusal(() => C.clothSync(world))
        got.clothForces = refusal(() => C.clothForces(world))
        got.clothGuard = refusal(() => C.clothGuard(world))
        got.clothEvents = refusal(() => C.clothEvents(world))
        got.change = refusal(() => C.setClothQuality(world, cl, { substeps: 4 }))
      })
      if (how === 'stepCloth') C.stepCloth(world, frame)
      else if (how === 'clothFixedStep') C.clothFixedStep(world)
      else {
        C.clothSync(world)
        for (let s = 0; s < C.clothSubstepCount(world); s++) {
          C.setClothSubstep(world, s)
          for (const phase of C.clothPhases) phase(world)
        }
        C.clothGuard(world)
        C.clothEvents(world)
      }
      const refused = 'ClothError(world)'
      expect(got).toEqual({
        clothFixedStep: refused,
        stepCloth: refused,
        beginClothStep: refused,
        clothSync: refused,
        clothForces: refused,
        clothGuard: refused,
        clothEvents: refused,
        change: 'ran',
      })
    })
  }
  it("a listener that tries a nested step leaves the outer step's events intact, each delivered once", () => {
    const plain = tearing()
    const expected: string[] = []
    C.onClothTear(plain.world, (e) => expected.push(`${e.particle}->${e.newParticle}`))
    C.clothFixedStep(plain.world)
    expect(expected).toHaveLength(3)
    const { world } = tearing()
    const outer: string[] = []
    C.onClothTear(world, (e) => {
      outer.push(`${e.particle}->${e.newParticle}`)
      if (outer.length === 1) refusal(() => C.clothFixedStep(world))
    })
    C.clothFixedStep(world)
    expect(outer).toEqual(expected)
  })
})
