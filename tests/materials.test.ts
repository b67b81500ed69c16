import { describe, expect, it } from 'vitest'
import { ClothMaterial, createCloth, defineMaterial, getClothState, pinRow, resolveMaterial, stepCloth } from '../src/index'
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
