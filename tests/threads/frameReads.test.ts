// The pipelined frame (endClothStep → animate → beginClothStep → draw): between begin and end the
// game reads meshes and render proxies, and gets the last finished step's, the same bytes with and
// without workers as a world stepped with stepCloth and read after each step.
import { addEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  beginClothStep,
  buildGridMesh,
  ClothError,
  createCloth,
  createRenderProxy,
  disposeClothWorld,
  endClothStep,
  endClothStepAsync,
  getClothMesh,
  getClothStretch,
  getClothTearCount,
  getGrabForce,
  grabParticle,
  pinRow,
  setTransform,
  stepCloth,
  updateRenderProxy,
} from '../../src/index'
import { createClothMesh, createProxyMesh, updateClothGeometry, updateProxyGeometry } from '../../src/three/index'
import { getClothWorld } from '../../src/world/access'
import { hashBytes } from '../helpers'
import { sheetOnHands, threadedWorld } from './scene'

const FRAMES = 12

/** A cape on a running hero (drawn as a three.js mesh, and through a finer proxy) and a sheet torn by two hands. */
function scene(threads: number) {
  const world = threadedWorld(threads)
  const hero = addEntity(world)
  setTransform(world, hero, [0, 1.6, 0])
  const cape = createCloth(world, { width: 0.6, height: 0.9, resolution: [8, 10], position: [0, 1.5, -0.15] })
  pinRow(world, cape, 0, hero)
  const { hands, sheet } = sheetOnHands(world, 0.15)
  const mesh = createClothMesh(world, cape)
  const sheetMesh = createClothMesh(world, sheet)
  const proxy = createRenderProxy(world, cape, buildGridMesh({ width: 0.6, height: 0.9, resolution: [15, 19] }))
  const proxyMesh = createProxyMesh(world, proxy)
  const animate = (f: number) => {
    setTransform(world, hero, [f / 60, 1.6, 0.02 * f])
    const spread = Math.min(1, 0.04 * f)
    setTransform(world, hands[0], [2.5 - spread, 2, 0])
    setTransform(world, hands[1], [3.5 + spread, 2, 0])
  }
  /** What is drawn: the geometries' bytes, as updated now (positions, normals, indices, draw range). */
  const draw = () => {
    const g = updateClothGeometry(world, cape, mesh.geometry)
    const s = updateClothGeometry(world, sheet, sheetMesh.geometry)
    const p = updateProxyGeometry(world, proxy, proxyMesh.geometry)
    const m = getClothMesh(world, sheet)
    return [
      hashBytes(g.getAttribute('position').array as Float32Array),
      hashBytes(g.getAttribute('normal').array as Float32Array),
      hashBytes((s.getAttribute('position').array as Float32Array).subarray(0, 3 * m.vertexCount)),
      hashBytes((s.getAttribute('normal').array as Float32Array).subarray(0, 3 * m.vertexCount)),
      hashBytes((s.getIndex()!.array as Uint32Array).subarray(0, 3 * m.triangleCount)),
      `${s.drawRange.count}`,
      hashBytes(p.getAttribute('position').array as Float32Array),
      hashBytes(p.getAttribute('normal').array as Float32Array),
      hashBytes(p.getIndex()!.array as Uint32Array),
    ].join(' ')
  }
  return { world, cape, sheet, proxy, animate, draw }
}

describe('reads between beginClothStep and endClothStep', () => {
  it('the pipelined frame draws the last finished step, with 0 and 2 workers, blocking or awaited, the same bytes as reading after stepCloth', async () => {
    const ref = scene(0)
    const runs = [scene(0), scene(2), scene(2)]
    try {
      // the reference: stepped and read after each step
      const expected: string[] = []
      for (let f = 0; f <= FRAMES; f++) {
        ref.animate(f)
        stepCloth(ref.world, 1 / 60)
        expected.push(ref.draw())
      }
      expect(new Set(expected).size).toBe(expected.length) // every step moved the cloths
      for (let k = 0; k < runs.length; k++) {
        const r = runs[k]
        r.animate(0)
        beginClothStep(r.world, 1 / 60)
        for (let f = 0; f < FRAMES; f++) {
          if (k === 2) await endClothStepAsync(r.world)
          else endClothStep(r.world)
          r.animate(f + 1)
          beginClothStep(r.world, 1 / 60)
          // drawn while step f + 1 runs: step f's cloth, twice (the second read changes nothing)
          expect(r.draw(), `run ${k}, frame ${f}`).toBe(expected[f])
          expect(r.draw(), `run ${k}, frame ${f}, again`).toBe(expected[f])
        }
        endClothStep(r.world)
        expect(r.draw()).toBe(expected[FRAMES]) // and after the end, the frame's own step
      }
      // the sheet tore meanwhile: its index (read between the calls) followed the tears
      const m = getClothMesh(ref.world, ref.sheet)
      expect(m.vertexCount).toBeGreaterThan(64)
    } finally {
      for (const r of [ref, ...runs]) disposeClothWorld(r.world)
    }
  })

  for (const threads of [0, 2]) {
    it(`a mesh or proxy never read before the frame began has no finished step to give then (${threads} workers): a ClothError in every mode`, () => {
      const world = threadedWorld(threads)
      try {
        const cloth = createCloth(world, { width: 1, height: 1, resolution: 6, position: [0, 2, 0] })
        pinRow(world, cloth, 0)
        stepCloth(world, 1 / 60)
        const proxy = createRenderProxy(world, cloth, buildGridMesh({ width: 1, height: 1, resolution: 11 }))
        beginClothStep(world, 1 / 60)
        expect(() => getClothMesh(world, cloth)).toThrow(ClothError)
        expect(() => updateRenderProxy(world, proxy)).toThrow(/never read before this frame began/)
        endClothStep(world)
        // read once outside a frame, they can be read within one from the next frame on
        const positions = Float32Array.from(getClothMesh(world, cloth).positions)
        const proxied = Float32Array.from(updateRenderProxy(world, proxy).positions)
        beginClothStep(world, 1 / 60)
        expect(getClothMesh(world, cloth).positions).toEqual(positions)
        expect(updateRenderProxy(world, proxy).positions).toEqual(proxied)
        endClothStep(world)
        expect(getClothMesh(world, cloth).positions).not.toEqual(positions)
      } finally {
        disposeClothWorld(world)
      }
    })
  }
})

describe('counters read between begin and end', () => {
  /** A sheet torn by two hands while a grab pulls it: what getClothTearCount and getGrabForce give mid-frame, per frame. */
  function run(threads: number): string[] {
    const world = threadedWorld(threads)
    const th = getClothWorld(world).threads
    if (th !== null) th.verify = false
    const reads: string[] = []
    try {
      const { hands, sheet } = sheetOnHands(world, 0.05)
      const hand = grabParticle(world, sheet, 60, [3, 1.5, 0.3])
      for (let f = 0; f < 60; f++) {
        const spread = Math.min(0.9, 0.02 * f)
        setTransform(world, hands[0], [2.5 - spread, 2, 0])
        setTransform(world, hands[1], [3.5 + spread, 2, 0])
        const before = `${getClothTearCount(world, sheet)} ${Array.from(getGrabForce(world, hand)).join(' ')}`
        beginClothStep(world, 1 / 60)
        // the game reads them while the workers step: the last finished step's, as without workers
        const mid = `${getClothTearCount(world, sheet)} ${Array.from(getGrabForce(world, hand)).join(' ')}`
        expect(mid).toBe(before)
        endClothStep(world)
        reads.push(mid)
      }
      expect(getClothTearCount(world, sheet)).toBeGreaterThan(0)
    } finally {
      disposeClothWorld(world)
    }
    return reads
  }

  it('getClothTearCount and getGrabForce give the last finished step, the same with 0 and 2 workers', () => {
    const plain = run(0)
    expect(run(2)).toEqual(plain)
  })
})

describe('getClothStretch reads the particles, which the step in flight moves', () => {
  it('between begin and end: a ClothError naming the world that says to read after endClothStep (it said to change cloths there), with 0 and 2 workers; after end, the measure', () => {
    for (const threads of [0, 2]) {
      const world = threadedWorld(threads)
      const cape = createCloth(world, { width: 0.6, height: 0.9, resolution: [8, 10], position: [0, 1.5, 0] })
      pinRow(world, cape, 0)
      stepCloth(world, 1 / 60)
      const before = getClothStretch(world, cape).max
      beginClothStep(world, 1 / 60)
      let err: unknown
      try {
        getClothStretch(world, cape)
      } catch (e) {
        err = e
      }
      endClothStep(world)
      expect(err).toBeInstanceOf(ClothError)
      expect((err as ClothError).argument).toBe('world')
      expect((err as Error).message).toMatch(/getClothStretch after endClothStep/)
      expect((err as Error).message).not.toMatch(/change cloths/)
      const after = getClothStretch(world, cape).max
      expect(after).toBeGreaterThan(0)
      expect(after).not.toBe(before) // (the step moved the sheet: measured anew)
      disposeClothWorld(world)
    }
  })
})
