import { addEntity, createWorld } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  ClothError,
  createCloth,
  getClothMesh,
  getClothState,
  getClothStretch,
  installClothPlugin,
  makeTearable,
  pinParticle,
  pinRow,
  setTransform,
  stepCloth,
} from '../../src/index'
import { allFinite, makeWorld } from '../helpers'
import { meshPieces, pieceCount } from './util'

describe('tearing with tethers on a moving character', () => {
  it('a cape snagged on a nail tears free of it without an explosion', () => {
    const world = makeWorld()
    const hero = addEntity(world)
    setTransform(world, hero, [0, 0, 0])
    const cols = 12, rows = 18
    const cape = createCloth(world, { width: 0.55, height: 1.0, resolution: [cols, rows], position: [0, 1.45, -0.2], material: 'silk' })
    pinRow(world, cape, 0, hero)
    makeTearable(world, cape, { maxTearsPerStep: 3 })
    const c = getClothState(world, cape)
    // the bottom-left corner is caught on a nail where it hangs now
    pinParticle(world, cape, (rows - 1) * cols)
    let maxSpeed = 0
    for (let f = 0; f < 240; f++) {
      // the hero runs off at 4 m/s along +z, turning
      const t = f / 60
      setTransform(world, hero, [Math.sin(t) * 0.5, 0, 4 * t], [0, Math.sin(0.3 * t), 0, Math.cos(0.3 * t)])
      stepCloth(world, 1 / 60)
      for (let i = 0; i < c.count; i++) maxSpeed = Math.max(maxSpeed, Math.hypot(c.vel[3 * i], c.vel[3 * i + 1], c.vel[3 * i + 2]))
    }
    expect(allFinite(world, cape)).toBe(true)
    expect(c.count).toBeGreaterThan(cols * rows) // it tore
    expect(maxSpeed).toBeLessThan(40) // no explosion: the fastest particle stays near the run speed
    const mesh = getClothMesh(world, cape)
    const label = meshPieces(mesh.indices, mesh.vertexCount)
    expect(pieceCount(label)).toBeGreaterThanOrEqual(2)
    // the piece on the shoulders follows the hero, and is not torn to rags: little stretch left in it
    const heroZ = 4 * 4
    const shoulders = label[0]
    let far = 0
    for (let i = 0; i < c.count; i++) if (label[i] === shoulders) far = Math.max(far, Math.abs(c.pos[3 * i + 2] - heroZ))
    expect(far).toBeLessThan(1.5)
    expect(getClothStretch(world, cape).max).toBeLessThan(0.6)
  })

  it('validates makeTearable and reserves its capacity once', () => {
    const world = installClothPlugin(createWorld())
    const cloth = createCloth(world, { width: 1, height: 1, resolution: 4 })
    expect(() => makeTearable(world, cloth, { strain: 0 })).toThrow(ClothError)
    expect(() => makeTearable(world, cloth, { strain: NaN })).toThrow(/options.strain/)
    expect(() => makeTearable(world, cloth, { maxTearsPerStep: 0 })).toThrow(/maxTearsPerStep/)
    expect(() => makeTearable(world, cloth, { capacity: -1 })).toThrow(/capacity/)
    expect(() => makeTearable(world, cloth, { minPiece: 0 })).toThrow(/options.minPiece/)
    expect(() => makeTearable(world, cloth, { minPiece: 2.5 })).toThrow(/options.minPiece/)
    expect(() => makeTearable(world, 999, {})).toThrow(/cloth/)
    makeTearable(world, cloth, { capacity: 8 })
    expect(getClothState(world, cloth).pos.length).toBe(3 * (16 + 8))
    makeTearable(world, cloth, { strain: 0.5 }) // settings change, capacity stays
    expect(() => makeTearable(world, cloth, { capacity: 100 })).toThrow(/capacity/)
  })
})
