import { addEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  buildGridMesh,
  createCloth,
  createRenderProxy,
  getClothMesh,
  grabParticle,
  makeTearable,
  moveGrab,
  pinRow,
  setTransform,
  stepCloth,
  updateRenderProxy,
} from '../../src/index'
import { makeWorld } from '../helpers'
import { edgeStretch } from './surface'

/**
 * A 14×24 cape on a swaying hero, drawn by a 4× render proxy, torn apart by two hands pulling its
 * hem out and down (`seed` picks the hands, the tear strain and so the cracks). Returns the worst
 * stretch of a drawn render edge between corners in different cloth triangles, and within one.
 */
function tornCape(seed: number) {
  const world = makeWorld()
  const hero = addEntity(world)
  setTransform(world, hero, [0, 1.5, 0])
  const cape = createCloth(world, { width: 0.55, height: 1.05, resolution: [14, 24], position: [0, 1.47, -0.2] })
  pinRow(world, cape, 0, hero)
  const fine = buildGridMesh({ width: 0.55, height: 1.05, resolution: [53, 93] })
  const proxy = createRenderProxy(world, cape, fine)
  makeTearable(world, cape, { strain: 0.25 + 0.05 * seed })
  const hands = [14 * 23 + 3 + seed, 14 * 23 + 10 - (seed % 3)].map((i) =>
    grabParticle(world, cape, i, getClothMesh(world, cape).positions.slice(3 * i, 3 * i + 3))
  )
  // which cloth triangle each render vertex rides in: the one nearest at rest (the proxy's binding)
  const tri = (proxy as unknown as { binding: { tri: Int32Array } }).binding.tri
  let spanning = 0, within = 0
  for (let f = 0; f < 240; f++) {
    const d = Math.min(1.2, f * 0.01)
    moveGrab(world, hands[0], [-0.3 - d, 0.4 - d * 0.5, -0.3 - 0.2 * Math.sin(f * 0.1)])
    moveGrab(world, hands[1], [0.3 + d, 0.4 - d * 0.3, -0.3])
    setTransform(world, hero, [0.1 * Math.sin(f * 0.05), 1.5, 0])
    stepCloth(world, 1 / 60)
    const m = updateRenderProxy(world, proxy)
    for (let t = 0; t < m.triangleCount; t++) {
      const a = m.indices[3 * t], b = m.indices[3 * t + 1], c = m.indices[3 * t + 2]
      if (a === b) continue // hidden
      for (const [p, q] of [[a, b], [b, c], [c, a]]) {
        const r = edgeStretch(m.positions, fine.positions, p, q)
        if (tri[a] === tri[b] && tri[b] === tri[c]) within = Math.max(within, r)
        else spanning = Math.max(spanning, r)
      }
    }
  }
  return { spanning, within, particles: getClothMesh(world, cape).vertexCount }
}

describe('render proxies of torn capes', () => {
  // measured: spanning 2.48 and 4.22, within 2.62 and 4.22 (before hiding the render triangles
  // across a crack's tip: spanning 4.45 with seed 1)
  it.each([1, 4])('no drawn render edge across cloth triangles stretches more than the cloth itself (seed %i)', (seed) => {
    const { spanning, within, particles } = tornCape(seed)
    expect(particles).toBeGreaterThan(14 * 24 + 10) // it tore
    expect(spanning).toBeLessThanOrEqual(within * 1.02)
  })
})
