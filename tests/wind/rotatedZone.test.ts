// A box zone turned in the world reaches what its box (and falloff band) reaches, not everything
// inside its world-axis bounds: a sheet beside a diagonal bar of wind sleeps and costs no
// aerodynamics; the same sheet on the bar is blown.
import { addEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  createCloth,
  createWindZone,
  getClothStats,
  isClothSleeping,
  pinRow,
  resetClothStats,
  sampleWind,
  setTransform,
  stepCloth,
} from '../../src/index'
import { makeWorld } from '../helpers'

const DT = 1 / 60
const s = Math.sin(Math.PI / 8), co = Math.cos(Math.PI / 8)

/** A bar of wind 4 m long and 0.4 m thick along the (1, 1, 0) diagonal (turned 45° about z), and a small sheet hanging at `at`. */
function scene(at: [number, number, number]) {
  const world = makeWorld()
  createWindZone(world, {
    shape: 'box',
    position: [0, 0, 0],
    rotation: [0, 0, s, co],
    size: [4, 0.4, 0.4],
    falloff: 0.1,
    direction: [0, 0, 1],
    strength: 8,
  })
  const anchor = addEntity(world)
  setTransform(world, anchor, at)
  const cloth = createCloth(world, { width: 0.4, height: 0.4, resolution: 6, position: at })
  pinRow(world, cloth, 0, anchor)
  return { world, cloth }
}

describe('a box zone turned 45°', () => {
  it('leaves a sheet beside it, inside its world bounds, asleep and free of aerodynamics', () => {
    const { world, cloth } = scene([1.2, -1.0, 0]) // 1.4–1.7 m from the bar's axis
    for (const p of [[1.2, -1.0, 0], [1.0, -1.2, 0], [1.4, -1.4, 0], [1.0, -1.4, 0]] as const) {
      expect(sampleWind(world, [...p])).toEqual([0, 0, 0])
    }
    let asleep = false
    for (let f = 0; f < 600 && !asleep; f++) {
      stepCloth(world, DT)
      asleep = isClothSleeping(world, cloth)
    }
    expect(asleep).toBe(true)
    resetClothStats(world)
    for (let f = 0; f < 60; f++) stepCloth(world, DT)
    expect(getClothStats(world).windTriangles).toBe(0)
  })
  it('blows a sheet hanging on its axis', () => {
    const { world, cloth } = scene([0.8, 0.8, 0])
    for (let f = 0; f < 120; f++) stepCloth(world, DT)
    expect(isClothSleeping(world, cloth)).toBe(false)
    expect(getClothStats(world).windTriangles).toBeGreaterThan(0)
  })
})
