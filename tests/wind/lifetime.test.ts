import { addEntity, createWorld, removeComponent, removeEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  createCloth,
  createWindZone,
  getClothComponents,
  getClothState,
  getWindZones,
  gustWind,
  installClothPlugin,
  removeWindZone,
  restoreClothState,
  sampleWind,
  saveClothState,
  stepCloth,
  type ClothSnapshot,
} from '../../src/index'
import { rejects } from '../helpers'

/** A world with a cloth and a calm zone given a 20 m/s gust, one second in (the gust at its hold). */
function gustyWorld() {
  const world = installClothPlugin(createWorld())
  const cloth = createCloth(world, { width: 1, height: 1, resolution: 6, position: [0, 2, 0] })
  const zone = createWindZone(world, { direction: [1, 0, 0], strength: 0 })
  gustWind(world, zone, { strength: 20, duration: 10 })
  for (let f = 0; f < 60; f++) stepCloth(world, 1 / 60)
  return { world, cloth, zone }
}

describe('wind zone lifetimes', () => {
  it("a restore leaves alone a new zone that reused a removed zone's id, and still rewinds a zone that lived on", () => {
    const { world, cloth, zone: old } = gustyWorld()
    const saved = saveClothState(world, cloth)
    removeWindZone(world, old)
    const calm = createWindZone(world, { direction: [1, 0, 0], strength: 0 })
    expect(calm).toBe(old) // bitECS gave the id back
    restoreClothState(world, cloth, saved)
    stepCloth(world, 1 / 60)
    expect(sampleWind(world, [0, 2, 0])[0]).toBe(0) // the removed zone's gust stays removed

    // the zone that lived on gets its gust back
    const b = gustyWorld()
    const kept = saveClothState(b.world, b.cloth)
    const before = sampleWind(b.world, [0, 2, 0])[0]
    expect(before).toBeGreaterThan(5)
    gustWind(b.world, b.zone, { strength: 0, duration: 0.01 }) // calm it
    for (let f = 0; f < 10; f++) stepCloth(b.world, 1 / 60)
    expect(sampleWind(b.world, [0, 2, 0])[0]).toBe(0)
    restoreClothState(b.world, b.cloth, kept)
    expect(sampleWind(b.world, [0, 2, 0])[0]).toBe(before)
  })

  it('a snapshot from before zone generations were saved still restores; a malformed one throws ClothError(snapshot)', () => {
    const { world, cloth, zone } = gustyWorld()
    const saved = saveClothState(world, cloth)
    const older = structuredClone(saved) as ClothSnapshot
    delete older.windGenerations
    const before = sampleWind(world, [0, 2, 0])[0]
    gustWind(world, zone, { strength: 0, duration: 0.01 })
    for (let f = 0; f < 10; f++) stepCloth(world, 1 / 60)
    restoreClothState(world, cloth, older)
    expect(sampleWind(world, [0, 2, 0])[0]).toBe(before)
    for (const bad of [new Uint32Array(3), Array.from(saved.windGenerations!), new Int32Array(1), null]) {
      const s = structuredClone(saved) as ClothSnapshot
      s.windGenerations = bad as never
      rejects(() => restoreClothState(world, cloth, s), 'snapshot')
    }
  })

  it('a zone whose entity loses its Transform is removed, as if its entity were', () => {
    const run = (lose: 'transform' | 'entity') => {
      const world = installClothPlugin(createWorld())
      const { Transform } = getClothComponents(world)
      const cloth = createCloth(world, { width: 1, height: 1, resolution: 6, position: [0, 2, 0] })
      const fan = createWindZone(world, { shape: 'sphere', position: [0, 2, 0], size: 2, direction: [1, 0, 0], strength: 10 })
      const breeze = createWindZone(world, { direction: [0, 0, 1], strength: 1 })
      for (let f = 0; f < 10; f++) stepCloth(world, 1 / 60)
      expect(sampleWind(world, [0, 2, 0])[0]).toBeCloseTo(10, 9)
      if (lose === 'transform') removeComponent(world, fan, Transform)
      else removeWindZone(world, fan)
      expect(getWindZones(world)).toEqual([breeze])
      expect(sampleWind(world, [0, 2, 0])[0]).toBe(0)
      for (let f = 0; f < 30; f++) stepCloth(world, 1 / 60)
      return { world, fan, breeze, pos: Array.from(getClothState(world, cloth).pos) }
    }
    const removed = run('entity'), lost = run('transform')
    expect(lost.pos).toEqual(removed.pos) // the cloth moves as if the zone were removed
    // the entity itself stays (only its zone went); removing it afterwards changes nothing
    removeEntity(lost.world, lost.fan)
    expect(getWindZones(lost.world)).toEqual([lost.breeze])
    removeEntity(lost.world, lost.breeze)
    expect(getWindZones(lost.world)).toEqual([])
    expect(addEntity(lost.world)).toBeGreaterThan(0)
  })
})
