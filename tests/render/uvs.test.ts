import { describe, expect, it } from 'vitest'
import {
  createCloth,
  createClothFromMesh,
  getClothMesh,
  getClothState,
  makeTearable,
  onClothTear,
  setTransform,
  stepCloth,
} from '../../src/index'
import { pinSidesToBars } from '../fixtures/bars'
import { makeWorld, rejects } from '../helpers'

/** The uv a point of a w × h sheet's rest frame should carry: u left to right, v bottom to top. */
function sheetUv(rest: ArrayLike<number>, i: number, w: number, h: number): [number, number] {
  return [(rest[3 * i] + w / 2) / w, 1 + rest[3 * i + 1] / h]
}

describe('texture coordinates', () => {
  it('a grid cloth: u along the columns, v from 1 at the top row to 0 at the bottom, the same view every call', () => {
    const world = makeWorld()
    const cloth = createCloth(world, { width: 2, height: 1, resolution: [5, 3], position: [0, 2, 0], rotation: [0, 0.38, 0, 0.92] })
    const mesh = getClothMesh(world, cloth)
    expect(mesh.uvs).toBeInstanceOf(Float32Array)
    expect(mesh.uvs.length).toBe(2 * 15)
    for (let r = 0; r < 3; r++) {
      for (let col = 0; col < 5; col++) {
        const i = r * 5 + col
        expect(mesh.uvs[2 * i]).toBe(Math.fround(col / 4))
        expect(mesh.uvs[2 * i + 1]).toBe(Math.fround(1 - r / 2))
      }
    }
    // seen from the front (+z before the rotation), u grows to the right and v upwards, as on
    // THREE.PlaneGeometry: (u, v) is an affine function of the rest position
    const rest = getClothState(world, cloth).topology.restPositions
    for (let i = 0; i < 15; i++) {
      const [u, v] = sheetUv(rest, i, 2, 1)
      expect(mesh.uvs[2 * i]).toBeCloseTo(u, 6)
      expect(mesh.uvs[2 * i + 1]).toBeCloseTo(v, 6)
    }
    for (let f = 0; f < 30; f++) stepCloth(world, 1 / 60)
    const again = getClothMesh(world, cloth)
    expect(again.uvs).toBe(mesh.uvs)
    expect(again.uvs[2 * 14]).toBe(1)
    expect(again.uvs[2 * 14 + 1]).toBe(0)
  })

  it('a mesh cloth takes its uvs option; without it, a planar projection seen from its front', () => {
    const world = makeWorld()
    const positions = [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0]
    const uvs = [0.1, 0.2, 3, 0.2, 3, 4.5, 0.1, 4.5]
    const front = createClothFromMesh(world, { positions, indices: [0, 1, 2, 0, 2, 3], uvs })
    expect(Array.from(getClothMesh(world, front).uvs)).toEqual(uvs.map(Math.fround))

    // default: facing +z, u along +x and v along +y, each over 0..1
    const plain = createClothFromMesh(world, { positions, indices: [0, 1, 2, 0, 2, 3] })
    expect(Array.from(getClothMesh(world, plain).uvs)).toEqual([0, 0, 1, 0, 1, 1, 0, 1])
    // the same square wound the other way faces −z: seen from there, +x is to the left
    const back = createClothFromMesh(world, { positions, indices: [0, 2, 1, 0, 3, 2] })
    expect(Array.from(getClothMesh(world, back).uvs)).toEqual([1, 0, 0, 0, 0, 1, 1, 1])
    // lying flat, facing up: seen from above, u along +x and v along −z
    const flat = [0, 0, 0, 2, 0, 0, 2, 0, -1, 0, 0, -1]
    const floor = createClothFromMesh(world, { positions: flat, indices: [0, 1, 2, 0, 2, 3] })
    expect(Array.from(getClothMesh(world, floor).uvs)).toEqual([0, 0, 1, 0, 1, 1, 0, 1])
    // a mesh with a grid cloth's rest shape gets that grid's uvs
    const grid = createCloth(world, { width: 1.5, height: 1, resolution: [4, 6] })
    const t = getClothState(world, grid).topology
    const copy = createClothFromMesh(world, { positions: t.restPositions, indices: t.triangles })
    const a = getClothMesh(world, grid).uvs, b = getClothMesh(world, copy).uvs
    for (let k = 0; k < a.length; k++) expect(b[k]).toBeCloseTo(a[k], 6)
  })

  it('tearing: every vertex a split makes carries the uv of the particle it was split from', () => {
    const world = makeWorld()
    const n = 12
    const cloth = createCloth(world, { width: 1, height: 1, resolution: n, position: [0, 2, 0] })
    const [left, right] = pinSidesToBars(world, cloth, n)
    makeTearable(world, cloth)
    const splits: [number, number][] = []
    onClothTear(world, (e) => splits.push([e.particle, e.newParticle]))
    const before = Float32Array.from(getClothMesh(world, cloth).uvs)
    for (let f = 0; f < 200; f++) {
      const d = Math.min(0.5, (f + 1) * 0.004)
      setTransform(world, left, [-d, 0, 0])
      setTransform(world, right, [d, 0, 0])
      stepCloth(world, 1 / 60)
    }
    const c = getClothState(world, cloth)
    const mesh = getClothMesh(world, cloth)
    expect(splits.length).toBeGreaterThan(5)
    expect(mesh.vertexCount).toBe(n * n + splits.length)
    expect(mesh.uvs.length).toBe(2 * mesh.vertexCount)
    // the original particles keep theirs; each new one has its source's (a source may itself be new)
    for (let k = 0; k < 2 * n * n; k++) expect(mesh.uvs[k]).toBe(before[k])
    for (const [src, nv] of splits) {
      expect(mesh.uvs[2 * nv]).toBe(mesh.uvs[2 * src])
      expect(mesh.uvs[2 * nv + 1]).toBe(mesh.uvs[2 * src + 1])
    }
    // so every vertex's uv is still the texture's point at its rest position
    for (let i = 0; i < c.count; i++) {
      const [u, v] = sheetUv(c.topology.restPositions, i, 1, 1)
      expect(mesh.uvs[2 * i]).toBeCloseTo(u, 6)
      expect(mesh.uvs[2 * i + 1]).toBeCloseTo(v, 6)
    }
  })

  it('bad uvs are a ClothError naming them', () => {
    const world = makeWorld()
    const square = { positions: [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0], indices: [0, 1, 2, 0, 2, 3] }
    rejects(() => createClothFromMesh(world, { ...square, uvs: [0, 0, 1, 0, 1, 1] }), 'options.uvs', '8')
    rejects(() => createClothFromMesh(world, { ...square, uvs: [0, 0, 1, 0, 1, 1, 0] }), 'options.uvs', 'multiple of 2')
    rejects(() => createClothFromMesh(world, { ...square, uvs: [0, 0, 1, 0, 1, NaN, 0, 1] }), 'options.uvs[5]', 'NaN')
    rejects(() => createClothFromMesh(world, { ...square, uvs: [0, 0, 1, 0, 1, 1, 0, Infinity] }), 'options.uvs[7]')
    rejects(() => createClothFromMesh(world, { ...square, uvs: [0, 0, 1e300, 0, 1, 1, 0, 1] }), 'options.uvs[2]')
    rejects(() => createClothFromMesh(world, { ...square, uvs: 'uv' as never }), 'options.uvs')
  })
})
