// beginClothStep / endClothStep: a frame that does not wait. Same bytes as stepCloth in every mode;
// between the two calls the game writes Transforms and reads finished results, and cannot change cloths.
import { addEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  ClothError,
  beginClothStep,
  clothEvents,
  clothGuard,
  clothPhases,
  clothSync,
  createCloth,
  createWindZone,
  disposeClothWorld,
  endClothStep,
  endClothStepAsync,
  getClothComponents,
  getClothMesh,
  getClothState,
  getClothStats,
  gustWind,
  onClothTear,
  pinParticle,
  pinRow,
  removeCloth,
  setClothInertia,
  setClothMotionConstraints,
  setClothQuality,
  setClothSkinning,
  setTransform,
  setWindZone,
  stepCloth,
  unpin,
} from '../../src/index'
import { hashBytes } from '../helpers'
import { sheetOnHands, threadedWorld } from './scene'

/** Two capes on a running character and a tearable sheet pulled apart by its corners. */
function scene(threads: number) {
  const world = threadedWorld(threads)
  const hero = addEntity(world)
  setTransform(world, hero, [2, 1.6, 0]) // where animate(0) puts it
  const capes = [0, 1].map((k) => {
    const c = createCloth(world, { width: 0.5, height: 0.8, resolution: [7, 9], position: [2 + 0.6 * k, 1.5, -0.15] })
    pinRow(world, c, 0, hero)
    return c
  })
  const { hands, sheet } = sheetOnHands(world, 0.2)
  const tears: number[] = []
  onClothTear(world, (e) => tears.push(e.particle))
  const cloths = [...capes, sheet]
  /** Writes frame f's transforms. */
  const animate = (f: number) => {
    const a = 0.05 * f
    setTransform(world, hero, [2 * Math.cos(a), 1.6, 2 * Math.sin(a)], [0, Math.sin(-a / 2), 0, Math.cos(-a / 2)])
    const spread = Math.min(0.9, 0.02 * f)
    setTransform(world, hands[0], [2.5 - spread, 2, 0])
    setTransform(world, hands[1], [3.5 + spread, 2, 0])
  }
  const hash = () =>
    cloths.map((e) => {
      const c = getClothState(world, e)
      return hashBytes(c.pos.subarray(0, 3 * c.count)) + hashBytes(c.vel.subarray(0, 3 * c.count))
    }).join('') + JSON.stringify(getClothStats(world))
  return { world, hero, capes, sheet, cloths, tears, animate, hash }
}

/** Frame times: mostly one fixed step, some with none, some with two or three. */
const DT = [1 / 60, 1 / 60, 0.5 / 60, 1.5 / 60, 1 / 60, 3 / 60, 1 / 60, 0.2 / 60]

describe('beginClothStep / endClothStep', () => {
  it('give the same bytes as stepCloth, with and without workers, blocking or awaited, the next frame’s Transforms written in between', async () => {
    const ref = scene(0)
    const runs = [scene(0), scene(2), scene(2)]
    try {
      ref.animate(0)
      for (const r of runs) r.animate(0)
      for (let f = 0; f < 120; f++) {
        const dt = DT[f % DT.length]
        stepCloth(ref.world, dt)
        ref.animate(f + 1)
        for (let k = 0; k < runs.length; k++) {
          const r = runs[k]
          beginClothStep(r.world, dt)
          r.animate(f + 1) // read at the next begin
          if (k === 2) await endClothStepAsync(r.world)
          else endClothStep(r.world)
        }
        for (const r of runs) expect(r.hash(), `frame ${f}`).toBe(ref.hash())
      }
      expect(ref.tears.length).toBeGreaterThan(0)
      for (const r of runs) expect(r.tears).toEqual(ref.tears)
    } finally {
      for (const r of [ref, ...runs]) disposeClothWorld(r.world)
    }
  })

  for (const threads of [0, 2]) {
    it(`between the two calls (${threads} workers): changes throw a ClothError, meshes and stats are the last finished step's, events arrive at the end`, () => {
      const s = scene(threads)
      try {
        s.animate(0)
        const zone = createWindZone(s.world, { direction: [0, 0, 1], strength: 2 })
        stepCloth(s.world, 1 / 60)
        const mesh = getClothMesh(s.world, s.capes[0])
        const before = Float32Array.from(mesh.positions)
        const steps = getClothStats(s.world).steps
        s.animate(1)
        expect(beginClothStep(s.world, 1 / 60)).toBe(1)
        // what the game may do meanwhile
        setTransform(s.world, s.hero, [0, 1.6, 0])
        expect(Float32Array.from(getClothMesh(s.world, s.capes[0]).positions)).toEqual(before) // read since the last step
        expect(() => getClothMesh(s.world, s.capes[1])).toThrow(ClothError) // never read: would need positions mid-step
        expect(getClothStats(s.world).steps).toBe(steps + 1) // the sync phase ran at begin
        // what it may not
        expect(() => createCloth(s.world, { width: 1, height: 1, resolution: 4 })).toThrow(ClothError)
        expect(() => pinParticle(s.world, s.capes[0], 10)).toThrow(ClothError)
        expect(() => setClothQuality(s.world, s.capes[0], { substeps: 2 })).toThrow(ClothError)
        expect(() => setClothInertia(s.world, s.capes[0], { frame: s.hero, linear: 0.5 })).toThrow(ClothError)
        expect(() => setClothMotionConstraints(s.world, s.capes[0], { maxDistance: 0.2 })).toThrow(ClothError)
        const n = getClothState(s.world, s.capes[0]).count
        const skinning = {
          bones: [s.hero],
          joints: new Array(4 * n).fill(0),
          weights: Array.from({ length: 4 * n }, (_, k) => (k % 4 === 0 ? 1 : 0)),
        }
        expect(() => setClothSkinning(s.world, s.capes[0], skinning)).toThrow(ClothError)
        expect(() => removeCloth(s.world, s.sheet)).toThrow(ClothError)
        // a zone changed now would reach this step without workers and the next one with them
        expect(() => setWindZone(s.world, zone, { strength: 6 })).toThrow(ClothError)
        expect(() => gustWind(s.world, zone, { strength: 3 })).toThrow(ClothError)
        // a custom scheduler's phases would race the workers for the particles
        for (const phase of [clothSync, ...clothPhases, clothGuard, clothEvents])
          expect(() => phase(s.world), phase.name).toThrow(ClothError)
        expect(() => stepCloth(s.world, 1 / 60)).toThrow(ClothError)
        expect(() => beginClothStep(s.world, 1 / 60)).toThrow(ClothError)
        expect(endClothStep(s.world)).toBe(1)
        expect(endClothStep(s.world)).toBe(0) // nothing open
        expect(Float32Array.from(getClothMesh(s.world, s.capes[0]).positions)).not.toEqual(before)
        // a listener may change the world when its events arrive
        let removed = false
        onClothTear(s.world, () => {
          if (!removed) {
            unpin(s.world, getClothState(s.world, s.sheet).pins.list[0])
            removed = true
          }
        })
        for (let f = 2; f < 90 && !removed; f++) {
          s.animate(f)
          beginClothStep(s.world, 1 / 60)
          expect(removed).toBe(false)
          endClothStep(s.world)
        }
        expect(removed).toBe(true)
      } finally {
        disposeClothWorld(s.world)
      }
    })
  }

  it('pipelined by one frame, the cloth drawn is one step behind its pins (8.3 cm at 5 m/s); moved by the pin target’s motion since that step, its pinned row is back on the target', () => {
    const s = scene(2)
    try {
      const pin = getClothState(s.world, s.capes[0]).pins.list[0]
      const P = getClothComponents(s.world).Pin
      let x = 2
      const step = 5 / 60 // 5 m/s
      s.animate(0)
      stepCloth(s.world, 1 / 60)
      for (let f = 0; f < 30; f++) {
        // frame f: start this frame's step after animating, finish it at the start of the next frame
        const heroAtStep = x
        setTransform(s.world, s.hero, [x, 1.6, 0])
        beginClothStep(s.world, 1 / 60)
        endClothStep(s.world) // (at the start of the next frame, before it animates)
        x += step // the next frame's animation: this is where the hero is when the pose above is drawn
        const drawn = getClothState(s.world, s.capes[0]).pos[3 * P.particle[pin]]
        const held = x + P.ox[pin] // where the pin holds the particle at the moment it is drawn
        if (f < 3) continue
        expect(held - drawn).toBeCloseTo(step, 9) // 8.3 cm behind
        expect(drawn + (x - heroAtStep)).toBeCloseTo(held, 9) // moved with the target since the step: on it
      }
    } finally {
      disposeClothWorld(s.world)
    }
  })

  it('while endClothStepAsync is pending, the frame stays locked: no other end, no dispose, no changes', async () => {
    const s = scene(2)
    try {
      s.animate(0)
      stepCloth(s.world, 1 / 60)
      beginClothStep(s.world, 1 / 60)
      const ending = endClothStepAsync(s.world)
      expect(() => endClothStep(s.world)).toThrow(ClothError)
      expect(() => disposeClothWorld(s.world)).toThrow(ClothError)
      expect(() => pinParticle(s.world, s.capes[0], 10)).toThrow(ClothError)
      expect(await ending).toBe(1)
      expect(await endClothStepAsync(s.world)).toBe(0)
    } finally {
      disposeClothWorld(s.world)
    }
  })
})
