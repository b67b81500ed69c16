import { describe, expect, it } from 'vitest'
import { buildGridTopology, buildMeshTopology } from '../src/model/builders'
import { BEND, SHEAR, STRETCH } from '../src/model/topology'
import { ClothMaterial, createCloth, createClothFromMesh, getClothState } from '../src/index'
import { makeWorld } from './helpers'

const count = (kinds: Uint8Array, n: number, kind: number) => kinds.subarray(0, n).reduce((s, k) => s + (k === kind ? 1 : 0), 0)

describe('grid topology', () => {
  it('has rows, columns, both diagonals and skip-one bending, row-major from the top-left', () => {
    const t = buildGridTopology(2, 1, 5, 4, ClothMaterial.COTTON, 'quad', { bending: 'distance' })
    expect(t.particleCount).toBe(20)
    expect(count(t.distKind, t.distCount, STRETCH)).toBe(4 * 4 + 5 * 3)
    expect(count(t.distKind, t.distCount, SHEAR)).toBe(2 * 4 * 3)
    expect(count(t.distKind, t.distCount, BEND)).toBe(4 * 3 + 5 * 2)
    expect(t.triangleCount).toBe(2 * 4 * 3)
    // index = row·columns + column; row 0 at the top, the sheet centred on x
    const p = t.restPositions
    expect([p[0], p[1]]).toEqual([-1, 0])
    expect([p[3 * 4], p[3 * 4 + 1]]).toEqual([1, 0])
    expect(p[3 * 15 + 1]).toBeCloseTo(-1, 12)
  })

  it('line bending (the default) puts a triple on every row and column run of three', () => {
    const t = buildGridTopology(2, 1, 5, 4, ClothMaterial.COTTON, 'quad')
    expect(t.lineCount).toBe(4 * 3 + 5 * 2)
    expect(count(t.distKind, t.distCount, BEND)).toBe(0)
    for (let k = 0; k < t.lineCount; k++) {
      const [a, v, b] = [t.lineIds[3 * k], t.lineIds[3 * k + 1], t.lineIds[3 * k + 2]]
      expect(v - a).toBe(b - v) // a straight run: consecutive in a row (1) or a column (5)
      expect([1, 5]).toContain(v - a)
      expect(t.lineRest[k]).toBeCloseTo(0, 12) // flat
    }
    // a mesh gets the same triples from its nearly opposite edge pairs (quad diagonals excluded)
    const m = buildGridTopology(1, 1, 3, 3, ClothMaterial.COTTON, 'triangle')
    expect(m.lineCount).toBe(6)
  })

  it('every constraint appears once and the solve order sweeps from the top down', () => {
    const t = buildGridTopology(1, 1, 8, 8, ClothMaterial.COTTON, 'quad')
    const seen = new Set<string>()
    let lastLevel = 0
    let clashes = 0
    for (let k = 0; k < t.distCount; k++) {
      // position offsets: particle index × 3, exactly
      expect(t.distOffsets[2 * k] % 3).toBe(0)
      expect(t.distOffsets[2 * k + 1] % 3).toBe(0)
      const a = t.distOffsets[2 * k] / 3, b = t.distOffsets[2 * k + 1] / 3
      const key = `${Math.min(a, b)}-${Math.max(a, b)}`
      expect(seen.has(key)).toBe(false)
      seen.add(key)
      // the interleave may pull a constraint up to one row early, never more
      const level = Math.floor(Math.min(a, b) / 8)
      expect(level).toBeGreaterThanOrEqual(lastLevel - 1)
      lastLevel = Math.max(lastLevel, level)
      // neighbours in the sweep rarely share a particle (instruction-level parallelism); only
      // at the tail, when nothing independent is left, can they
      if (k > 0) {
        const c = t.distOffsets[2 * k - 2] / 3, d = t.distOffsets[2 * k - 1] / 3
        if (c === a || c === b || d === a || d === b) clashes++
      }
    }
    expect(clashes).toBeLessThan(0.02 * t.distCount)
  })

  it('masses come from the areal density and add up to density × area', () => {
    const t = buildGridTopology(2, 1.5, 9, 7, ClothMaterial.DENIM, 'quad')
    const total = t.masses.reduce((s, m) => s + m, 0)
    expect(total).toBeCloseTo(ClothMaterial.DENIM.density * 3, 9)
  })

  it('stretch compliance does not depend on resolution (membrane stiffness, not per edge)', () => {
    const a = buildGridTopology(1, 1, 8, 8, ClothMaterial.COTTON, 'quad')
    const b = buildGridTopology(1, 1, 32, 32, ClothMaterial.COTTON, 'quad')
    const first = (t: typeof a) => t.distCompliance[Array.from(t.distKind).indexOf(STRETCH)]
    expect(first(a)).toBeCloseTo(first(b), 12)
  })
})

describe('mesh topology', () => {
  it('derives edges, quad shear pairs, cross-edge bending pairs and hinges from triangles', () => {
    // a 3×3 vertex grid as triangles: 8 triangles, 16 edges, 4 quad diagonals
    const t = buildGridTopology(1, 1, 3, 3, ClothMaterial.COTTON, 'triangle', { bending: 'distance' })
    expect(t.edgeCount).toBe(16)
    expect(count(t.distKind, t.distCount, SHEAR)).toBe(8) // 4 diagonals + 4 cross diagonals
    expect(count(t.distKind, t.distCount, STRETCH)).toBe(12)
    expect(count(t.distKind, t.distCount, BEND)).toBe(4) // interior non-diagonal edges
    const d = buildGridTopology(1, 1, 3, 3, ClothMaterial.COTTON, 'triangle', { bending: 'dihedral' })
    expect(d.hingeCount).toBe(16 - 8) // interior edges
  })

  it('builds a cloth from an arbitrary mesh (a pyramid cap) with matching counts', () => {
    const world = makeWorld()
    const positions = [0, 1, 0, -1, 0, -1, 1, 0, -1, 1, 0, 1, -1, 0, 1]
    const indices = [0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1]
    const cloth = createClothFromMesh(world, { positions, indices, material: 'leather', bending: 'both' })
    const c = getClothState(world, cloth)
    expect(c.count).toBe(5)
    expect(c.topology.edgeCount).toBe(8)
    expect(c.topology.hingeCount).toBe(4)
    expect(c.topology.hingeRest.every((a) => Number.isFinite(a) && Math.abs(a) > 0.1)).toBe(true)
  })

  it('keeps a non-manifold edge (three triangles) without a hinge or bending pair', () => {
    const positions = [0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -1, 0, 0.5, 0, 1]
    const indices = [0, 1, 2, 1, 0, 3, 0, 1, 4]
    const t = buildMeshTopology(positions, indices, ClothMaterial.COTTON, { bending: 'both' })
    expect(t.hingeCount).toBe(0)
    expect(t.edgeCount).toBe(7)
  })

  it('accepts zero-area triangles and coincident vertices, giving every particle a sane mass', () => {
    const positions = [0, 0, 0, 1, 0, 0, 2, 0, 0, 1, 1, 0, 1, 1, 0]
    const indices = [0, 1, 2, 0, 1, 3, 1, 3, 4]
    const t = buildMeshTopology(positions, indices, ClothMaterial.COTTON, { bending: 'both' })
    const mean = t.masses.reduce((s, m) => s + m, 0) / t.particleCount
    for (const m of t.masses) expect(m).toBeGreaterThanOrEqual(0.05 * mean)
    expect(Math.max(...t.masses) / Math.min(...t.masses)).toBeLessThan(20)
  })
})

describe('createCloth placement', () => {
  it('places the top edge centred on position and applies the rotation', () => {
    const world = makeWorld()
    const s = Math.SQRT1_2
    const cloth = createCloth(world, { width: 2, height: 1, resolution: [3, 2], position: [5, 1, 0], rotation: [-s, 0, 0, s] })
    const c = getClothState(world, cloth)
    // rotated −90° about x: the sheet lies flat, rows going toward +z
    expect(c.pos[0]).toBeCloseTo(4, 12)
    expect(c.pos[1]).toBeCloseTo(1, 12)
    expect(c.pos[3 * 3 + 2]).toBeCloseTo(1, 12)
    expect(c.pos[3 * 3 + 1]).toBeCloseTo(1, 12)
  })
})
