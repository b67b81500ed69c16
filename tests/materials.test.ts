import { describe, expect, it } from 'vitest'
import {
  buildGridMesh,
  ClothMaterial,
  createCloth,
  createClothFromMesh,
  defineMaterial,
  getClothState,
  pinParticle,
  pinRow,
  resolveMaterial,
  stepCloth,
} from '../src/index'
import { delaunaySheet, type Mesh } from './fixtures/delaunay'
import { lowestY, makeWorld } from './helpers'

describe('materials', () => {
  it('presets are physical, frozen and resolvable by name in any case', () => {
    for (const [key, m] of Object.entries(ClothMaterial)) {
      expect(Object.isFrozen(m)).toBe(true)
      expect(resolveMaterial(key.toLowerCase())).toBe(m)
      expect(resolveMaterial(key)).toBe(m)
      expect(m.density).toBeGreaterThan(0)
      expect(m.tearStrain).toBeGreaterThan(0)
    }
    expect(ClothMaterial.SILK.density).toBeLessThan(ClothMaterial.COTTON.density)
    expect(ClothMaterial.COTTON.density).toBeLessThan(ClothMaterial.LEATHER.density)
    expect(ClothMaterial.LEATHER.bendCompliance).toBeLessThan(ClothMaterial.SILK.bendCompliance)
  })

  it('custom materials inherit from a base and validate', () => {
    const m = defineMaterial({ name: 'oilcloth', density: 0.5 }, 'canvas')
    expect(m.density).toBe(0.5)
    expect(m.bendCompliance).toBe(ClothMaterial.CANVAS.bendCompliance)
    expect(Object.isFrozen(m)).toBe(true)
  })

  it('a plain material object is copied and frozen: editing it later cannot reach the solver', () => {
    const plain = { ...ClothMaterial.COTTON, name: 'mine' }
    const world = makeWorld()
    const cloth = createCloth(world, { width: 1, height: 1, resolution: 4, material: plain })
    plain.friction = NaN
    plain.density = -1
    const held = getClothState(world, cloth).material
    expect(Object.isFrozen(held)).toBe(true)
    expect(held.friction).toBe(ClothMaterial.COTTON.friction)
    expect(held.density).toBe(ClothMaterial.COTTON.density)
    expect(() => resolveMaterial(plain)).toThrow(/friction|density/)
  })

  it('rubber stretches visibly more than leather under the same load', () => {
    const drop = (material: string) => {
      const world = makeWorld()
      const cloth = createCloth(world, { width: 1, height: 1, resolution: 10, material, substeps: 16, tethers: false })
      pinRow(world, cloth, 0)
      for (let f = 0; f < 300; f++) stepCloth(world, 1 / 60)
      return -lowestY(world, cloth) - 1
    }
    expect(drop('rubber')).toBeGreaterThan(3 * drop('leather'))
  })

  it('a heavier material gives heavier particles for the same sheet', () => {
    const world = makeWorld()
    const silk = getClothState(world, createCloth(world, { width: 1, height: 1, resolution: 5, material: 'silk' }))
    const denim = getClothState(world, createCloth(world, { width: 1, height: 1, resolution: 5, material: 'denim' }))
    expect(1 / denim.invMass[12] / (1 / silk.invMass[12])).toBeCloseTo(ClothMaterial.DENIM.density / ClothMaterial.SILK.density, 9)
  })
})

describe('triangulations (documented in the README: Materials and accuracy)', () => {
  // a 1 m cotton sheet held level at its four corners, tethers off, 400 steps at the default 8
  // substeps: its sag against the grid sheet's. A mesh whose triangles pair into quads gets shear
  // compliance on the quads' diagonals as the grid does; an irregular one (Delaunay) gets stretch
  // compliance on every edge, so it resists shear more and sags less.
  const level = (m: Mesh): Mesh => {
    const p = m.positions.slice()
    for (let i = 0; i < p.length; i += 3) {
      const y = p[i + 1]
      p[i + 1] = 1
      p[i + 2] = y + 0.5
    }
    return { positions: p, indices: m.indices }
  }
  const nearest = (m: Mesh, x: number, y: number) => {
    let best = -1, bd = Infinity
    for (let i = 0; i < m.positions.length / 3; i++) {
      const d = Math.hypot(m.positions[3 * i] - x, m.positions[3 * i + 1] - y)
      if (d < bd) (bd = d), (best = i)
    }
    return best
  }
  const sag = (m: Mesh) => {
    const world = makeWorld()
    const cloth = createClothFromMesh(world, { ...level(m), tethers: false })
    for (const [x, y] of [[-0.5, 0], [0.5, 0], [-0.5, -1], [0.5, -1]]) pinParticle(world, cloth, nearest(m, x, y))
    for (let f = 0; f < 400; f++) stepCloth(world, 1 / 60)
    return 1 - lowestY(world, cloth)
  }
  it('a grid as a mesh sags as the grid sheet; an irregular mesh 12–19 % less (measured 14–16 %)', () => {
    const grid = buildGridMesh({ width: 1, height: 1, resolution: 16 })
    const asMesh = { positions: Array.from(grid.positions), indices: Array.from(grid.indices) }
    const reference = sag(asMesh)
    const world = makeWorld()
    const sheet = createCloth(world, {
      width: 1,
      height: 1,
      resolution: 16,
      rotation: [-Math.SQRT1_2, 0, 0, Math.SQRT1_2],
      position: [0, 1, 0.5],
      tethers: false,
    })
    for (const i of [0, 15, 240, 255]) pinParticle(world, sheet, i)
    for (let f = 0; f < 400; f++) stepCloth(world, 1 / 60)
    const gridSag = 1 - lowestY(world, sheet)
    expect(Math.abs(reference / gridSag - 1)).toBeLessThan(0.03)
    const irregular = [1, 2, 3].map((seed) => sag(delaunaySheet(1, 1, 16, 196, seed)) / gridSag)
    console.log(
      `sag against the grid sheet (${(100 * gridSag).toFixed(1)} cm): grid as a mesh ${(reference / gridSag).toFixed(3)}, Delaunay ${
        irregular.map((r) => r.toFixed(3)).join(', ')
      }`,
    )
    // measured 0.854, 0.836 and 0.857: 14–16 % less (README)
    for (const r of irregular) {
      expect(r).toBeGreaterThan(0.81)
      expect(r).toBeLessThan(0.88)
    }
  })
})
