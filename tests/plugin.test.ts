import { addEntity, createWorld, removeEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  ClothError,
  clothFixedStep,
  clothPhases,
  clothSubstepCount,
  clothSync,
  clothGuard,
  clothEvents,
  createCloth,
  setClothSubstep,
  setClothInertia,
  setClothMotionConstraints,
  addCapsuleCollider,
  addSphereCollider,
  addPlaneCollider,
  createWindZone,
  makeTearable,
  onClothTear,
  grabParticle,
  moveGrab,
  setClothQuality,
  enableSelfCollision,
  getClothComponents,
  getClothMesh,
  getClothState,
  getClothStats,
  installClothPlugin,
  pinParticle,
  pinRow,
  setTransform,
  stepCloth,
} from '../src/index'
import { hashBytes, makeWorld, rng } from './helpers'

/** A small scene driven by a seeded random walk: a cape on a character plus a free sheet. */
function runScene(world: object, seed: number, steps: number) {
  const r = rng(seed)
  const hero = addEntity(world)
  setTransform(world, hero, [0, 1.6, 0])
  const cape = createCloth(world, { width: 0.5, height: 0.8, resolution: 10, position: [0, 1.5, -0.1], material: 'silk' })
  pinRow(world, cape, 0, hero)
  const sheet = createCloth(world, { width: 1, height: 1, resolution: 12, position: [2, 2, 0], bending: 'both' })
  pinParticle(world, sheet, 0)
  const p = [0, 1.6, 0]
  for (let s = 0; s < steps; s++) {
    p[0] += (r() - 0.5) * 0.1
    p[2] += (r() - 0.5) * 0.1
    setTransform(world, hero, p, [0, Math.sin(s * 0.01), 0, Math.cos(s * 0.01)])
    stepCloth(world, 1 / 60 + (r() - 0.5) * 0.004)
  }
  return [getClothState(world, cape).pos, getClothState(world, sheet).pos]
}

describe('plugin', () => {
  it('two worlds built and stepped the same way give byte-identical positions', () => {
    const a = runScene(makeWorld(), 42, 300)
    const b = runScene(makeWorld(), 42, 300)
    expect(hashBytes(a[0])).toBe(hashBytes(b[0]))
    expect(hashBytes(a[1])).toBe(hashBytes(b[1]))
    expect(Buffer.from(a[0].buffer).equals(Buffer.from(b[0].buffer))).toBe(true)
  })

  it('results do not depend on the world’s entity history (ids differ, bytes do not)', () => {
    const w1 = makeWorld()
    const w2 = makeWorld()
    // churn entities in the second world so every id differs and queries are reordered
    const junk = Array.from({ length: 17 }, () => addEntity(w2))
    for (const e of junk.filter((_, i) => i % 3 !== 0)) removeEntity(w2, e)
    const extra = createCloth(w2, { width: 1, height: 1, resolution: 3 })
    removeEntity(w2, extra)
    const a = runScene(w1, 7, 200)
    const b = runScene(w2, 7, 200)
    expect(hashBytes(a[0])).toBe(hashBytes(b[0]))
    expect(hashBytes(a[1])).toBe(hashBytes(b[1]))
  })

  it('keeps all state per world: stepping one world leaves another untouched', () => {
    const w1 = makeWorld(), w2 = makeWorld()
    const c1 = createCloth(w1, { width: 1, height: 1, resolution: 4 })
    const c2 = createCloth(w2, { width: 1, height: 1, resolution: 4 })
    expect(c1).toBe(c2) // same entity id in both worlds...
    const before = Float64Array.from(getClothState(w2, c2).pos)
    stepCloth(w1, 1 / 60)
    expect(Array.from(getClothState(w2, c2).pos)).toEqual(Array.from(before)) // ...separate stores
    expect(getClothComponents(w1).Transform).not.toBe(getClothComponents(w2).Transform)
  })

  it('installing twice is a no-op; stepping without the plugin is a clear error', () => {
    const world = makeWorld()
    const comps = getClothComponents(world)
    installClothPlugin(world)
    installClothPlugin(world, {})
    expect(getClothComponents(world)).toBe(comps)
    // options apply at the first install only: a second install with any names them (it kept the first's, silently)
    expect(() => installClothPlugin(world, { sleep: false })).toThrow(/options.*first install/)
    expect(() => installClothPlugin(world, { fixedTimeStep: -1 })).toThrow(ClothError)
    expect(() => stepCloth(createWorld(), 1 / 60)).toThrow(ClothError)
  })

  it('runs whole fixed steps from the accumulator and clamps a huge frame', () => {
    const world = makeWorld({ fixedTimeStep: 1 / 60, maxStepsPerFrame: 4 })
    createCloth(world, { width: 1, height: 1, resolution: 3 })
    expect(stepCloth(world, 0)).toBe(0)
    expect(stepCloth(world, 1 / 120)).toBe(0)
    expect(stepCloth(world, 1 / 120)).toBe(1)
    let total = 0
    for (let f = 0; f < 600; f++) total += stepCloth(world, 1 / 60)
    expect(total).toBe(600) // no drift into skipped or doubled steps
    expect(stepCloth(world, 10)).toBe(4) // a 10 s hitch runs 4 steps, not 600 or one giant one
    expect(stepCloth(world, 1 / 60)).toBe(1)
    expect(getClothStats(world).steps).toBe(606)
  })

  it('by default keeps up with frames of up to 1/15 s at any fixed step: a free sheet falls ½gt² at 30 Hz with 1/240 s steps (it ran at half speed, 1.23 m instead of 4.9)', () => {
    for (const [fixedTimeStep, hz] of [[1 / 240, 30], [1 / 240, 15], [1 / 120, 20], [1 / 60, 15], [1 / 20, 10]]) {
      const world = makeWorld({ fixedTimeStep, gravity: [0, -9.81, 0], sleep: false, guard: false })
      const sheet = createCloth(world, { width: 0.2, height: 0.2, resolution: 3, damping: 0 })
      const c = getClothState(world, sheet)
      const y0 = c.pos[1]
      let steps = 0
      for (let f = 0; f < hz; f++) steps += stepCloth(world, 1 / hz)
      const t = steps * fixedTimeStep
      expect(t, `${1 / fixedTimeStep} Hz steps, ${hz} Hz frames: simulated time`).toBeCloseTo(1, 6)
      // (symplectic Euler: ½g·t·(t + h))
      expect(y0 - c.pos[1], `${1 / fixedTimeStep} Hz steps, ${hz} Hz frames`).toBeCloseTo(
        0.5 * 9.81 * t * (t + fixedTimeStep / c.substeps),
        3,
      )
    }
    // a frame longer than 1/15 s still drops the rest, and an explicit cap is kept
    expect(stepCloth(makeWorld({ fixedTimeStep: 1 / 240 }), 0.5)).toBe(16)
    expect(stepCloth(makeWorld({ fixedTimeStep: 1 / 240, maxStepsPerFrame: 4 }), 0.5)).toBe(4)
    // at most the option's own limit, 1000, at the shortest steps
    expect(stepCloth(makeWorld({ fixedTimeStep: 2e-5 }), 10)).toBe(1000)
  })

  it('grows its stores when entity ids exceed the initial capacity', () => {
    const world = installClothPlugin(createWorld(), { capacity: 4 })
    const cloth = createCloth(world, { width: 1, height: 1, resolution: 4 })
    const targets = Array.from({ length: 40 }, (_, i) => {
      const e = addEntity(world)
      setTransform(world, e, [i * 0.01, 0, 0])
      return e
    })
    const pins = targets.slice(0, 16).map((t, i) => pinParticle(world, cloth, i, t))
    expect(Math.max(...pins)).toBeGreaterThan(40)
    stepCloth(world, 1 / 60)
    const c = getClothState(world, cloth)
    const x15 = c.pos[3 * 15]
    setTransform(world, targets[15], [15 * 0.01 + 1, 0, 0]) // the highest target moves 1 m
    stepCloth(world, 1 / 60)
    expect(c.pos[3 * 15] - x15).toBeCloseTo(1, 12)
  })
})

/** One fixed step through the public phase systems, phase by phase, as an engine's own scheduler runs them. */
function stepByPhases(w: object): void {
  clothSync(w)
  for (let s = 0; s < clothSubstepCount(w); s++) {
    setClothSubstep(w, s)
    for (const phase of clothPhases) phase(w)
  }
  clothGuard(w)
  clothEvents(w)
}

describe('stepping by hand', () => {
  it('clothFixedStep and the phase systems run in pipeline order give the bytes of stepCloth at the fixed step', () => {
    const scene = () => {
      const world = makeWorld()
      const hero = addEntity(world)
      setTransform(world, hero, [0, 2, 0])
      const cloth = createCloth(world, { width: 1, height: 1, resolution: 10, position: [0, 2, 0] })
      pinRow(world, cloth, 0, hero)
      return { world, hero, c: getClothState(world, cloth) }
    }
    const runs = [scene(), scene(), scene()]
    for (let f = 0; f < 90; f++) {
      for (const r of runs) setTransform(r.world, r.hero, [Math.sin(f / 10), 2, 0.2 * f / 60])
      stepCloth(runs[0].world, 1 / 60)
      clothFixedStep(runs[1].world)
      stepByPhases(runs[2].world)
    }
    const bytes = runs.map((r) => hashBytes(r.c.pos.subarray(0, 3 * r.c.count)))
    expect(bytes[1]).toBe(bytes[0])
    expect(bytes[2]).toBe(bytes[0])
    // and the same counts (a step run by hand counted no substeps; found by a hunt)
    const counts = runs.map((r) => JSON.stringify(getClothStats(r.world)))
    expect(counts[1]).toBe(counts[0])
    expect(counts[2]).toBe(counts[0])
  })
  it('a world of many kinds of cloth (character, wind, tearing, self-collision, grabs, colliders, fewer substeps) gives the same bytes and tear events stepped by the pipeline, cloth by cloth, and by the phase systems, phase by phase', () => {
    const scene = () => {
      const world = makeWorld()
      const hero = addEntity(world)
      setTransform(world, hero, [0, 1.6, 0])
      const cape = createCloth(world, { width: 0.5, height: 0.9, resolution: 10, position: [0, 1.6, -0.2], material: 'wool' })
      pinRow(world, cape, 0, hero)
      setClothInertia(world, cape, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5 })
      setClothMotionConstraints(world, cape, { maxDistance: 0.3, backstop: { distance: 0.02, radius: 0.4 } })
      addCapsuleCollider(world, addEntity(world), { body: hero, offset: [0, -0.3, 0], radius: 0.17, halfHeight: 0.3 })
      // self-colliding and tearable, created before the other tearable sheet: the pipeline runs it
      // after the others, and its tears must still come first
      const folded = createCloth(world, { width: 1, height: 1, resolution: 12, position: [-6, 2, 0] })
      makeTearable(world, folded, { strain: 0.05 })
      enableSelfCollision(world, folded)
      pinRow(world, folded, 0)
      const ball2 = addEntity(world)
      setTransform(world, ball2, [-6, 1.5, -2])
      addSphereCollider(world, ball2, { radius: 0.35 })
      const flag = createCloth(world, { width: 1, height: 0.6, resolution: 12, position: [3, 2, 0] })
      pinRow(world, flag, 0)
      setClothQuality(world, flag, { substeps: 3, iterations: 2 })
      createWindZone(world, { direction: [0.3, 0, 1], strength: 9, turbulence: 0.4, seed: 3 })
      const sheet = createCloth(world, { width: 1, height: 1, resolution: 12, position: [-3, 2, 0] })
      makeTearable(world, sheet, { strain: 0.1 })
      pinRow(world, sheet, 0)
      const ball = addEntity(world)
      setTransform(world, ball, [-3, 1.5, -2])
      addSphereCollider(world, ball, { radius: 0.35 })
      const ground = addEntity(world)
      setTransform(world, ground, [0, 0, 0])
      addPlaneCollider(world, ground, { distance: 0 })
      const rag = createCloth(world, {
        width: 0.5,
        height: 0.5,
        resolution: 8,
        position: [6, 1, 0],
        rotation: [Math.SQRT1_2, 0, 0, Math.SQRT1_2],
      })
      const grab = grabParticle(world, rag, 40, [6, 1.5, 0])
      const tears: number[] = []
      onClothTear(world, (e) => tears.push(e.cloth, e.particle, e.newParticle, e.strain))
      return { world, hero, ball, ball2, grab, cloths: [cape, folded, flag, sheet, rag], tears }
    }
    const runs = [scene(), scene()]
    for (let f = 0; f < 150; f++) {
      for (const r of runs) {
        const a = f / 20
        setTransform(r.world, r.hero, [Math.sin(a), 1.6, 2 * Math.cos(a)], [0, Math.sin(a / 2), 0, Math.cos(a / 2)])
        setTransform(r.world, r.ball, [-3, 1.5, -2 + f / 8])
        setTransform(r.world, r.ball2, [-6, 1.5, -2 + f / 8])
        moveGrab(r.world, r.grab, [6 + 0.5 * Math.sin(a), 1.5, 0])
      }
      stepCloth(runs[0].world, 1 / 60)
      stepByPhases(runs[1].world)
    }
    // both tearable sheets tore, in some step both at once
    expect(new Set(runs[0].tears.filter((_, i) => i % 4 === 0)).size).toBe(2)
    expect(runs[1].tears).toEqual(runs[0].tears)
    for (let k = 0; k < 5; k++) {
      const [a, b] = runs.map((r) => getClothState(r.world, r.cloths[k]))
      expect(a.count).toBe(b.count)
      expect(hashBytes(b.pos.subarray(0, 3 * b.count)), `cloth ${k}`).toBe(hashBytes(a.pos.subarray(0, 3 * a.count)))
      expect(hashBytes(b.vel.subarray(0, 3 * b.count)), `cloth ${k}`).toBe(hashBytes(a.vel.subarray(0, 3 * a.count)))
    }
  })
})

describe('clothFixedStep, then stepCloth', () => {
  it('the first stepCloth frame after steps outside frames samples the Transforms (its pins stood still for a step)', () => {
    // a scene warmed up with clothFixedStep, then run at 4 m/s in stepCloth frames: the first frame
    // took no sample, its pinned corner 6.7 cm behind its target
    for (const warmUp of ['stepCloth', 'clothFixedStep'] as const) {
      const world = makeWorld({ sleep: false })
      const hero = addEntity(world)
      setTransform(world, hero, [0, 1.5, 0])
      const cape = createCloth(world, { width: 0.55, height: 1.05, resolution: [14, 24], position: [0, 1.5, -0.2], material: 'wool' })
      pinRow(world, cape, 0, hero)
      for (let i = 0; i < 60; i++) {
        if (warmUp === 'stepCloth') stepCloth(world, 1 / 60)
        else clothFixedStep(world)
      }
      const c = getClothState(world, cape)
      for (let f = 1; f <= 5; f++) {
        const x = (4 * f) / 60
        setTransform(world, hero, [x, 1.5, 0])
        stepCloth(world, 1 / 60)
        expect(Math.abs(c.pos[0] - (x - 0.275)), warmUp).toBeLessThan(1e-9) // the pinned corner on its target
      }
    }
  })
})

describe('getClothMesh', () => {
  it('returns GPU-ready arrays sized to the live cloth, the same arrays every call', () => {
    const world = makeWorld()
    const cloth = createCloth(world, { width: 1, height: 1, resolution: 5 })
    const a = getClothMesh(world, cloth)
    expect(a.positions).toBeInstanceOf(Float32Array)
    expect(a.normals).toBeInstanceOf(Float32Array)
    expect(a.indices).toBeInstanceOf(Uint32Array)
    expect(a.positions.length).toBe(3 * 25)
    expect(a.normals.length).toBe(3 * 25)
    expect(a.indices.length).toBe(3 * 2 * 16)
    stepCloth(world, 1 / 60)
    const b = getClothMesh(world, cloth)
    expect(b.positions).toBe(a.positions)
    expect(b.normals).toBe(a.normals)
    const c = getClothState(world, cloth)
    for (let i = 0; i < 3 * c.count; i++) expect(b.positions[i]).toBe(Math.fround(c.pos[i]))
    // a flat sheet facing +z has +z normals
    for (let i = 0; i < 25; i++) expect(b.normals[3 * i + 2]).toBeCloseTo(1, 5)
  })
})
