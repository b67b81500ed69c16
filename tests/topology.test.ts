import { describe, expect, it } from 'vitest'
import { buildGridTopology, buildMeshTopology } from '../src/model/builders'
import { BEND, SHEAR, STRETCH } from '../src/model/topology'
import {
  ClothMaterial,
  createCloth,
  createClothFromMesh,
  createWindZone,
  getClothMesh,
  getClothState,
  getClothStats,
  makeTearable,
  pinParticle,
  stepCloth,
} from '../src/index'
import { allFinite, hashBytes, makeWorld } from './helpers'

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

describe('meshes as exports leave them: faces held twice, slivers', () => {
  /** An n × n vertex sheet of 1 m in the x-y plane, two triangles per quad, wound the same way. */
  function sheet(n: number): { positions: number[]; indices: number[] } {
    const positions: number[] = [], indices: number[] = []
    for (let r = 0; r < n; r++) for (let c = 0; c < n; c++) positions.push(c / (n - 1), -r / (n - 1), 0)
    for (let r = 0; r < n - 1; r++) {
      for (let c = 0; c < n - 1; c++) {
        const a = r * n + c
        indices.push(a, a + n, a + 1, a + 1, a + n, a + n + 1)
      }
    }
    return { positions, indices }
  }

  /** Pins the top row, blows a wind across, steps 90 frames with a tear threshold; returns the positions' bytes and the cloth. */
  function run(mesh: { positions: number[]; indices: number[] }, bending: 'line' | 'dihedral') {
    const world = makeWorld()
    const cloth = createClothFromMesh(world, { ...mesh, bending })
    for (let c = 0; c < 12; c++) pinParticle(world, cloth, c)
    makeTearable(world, cloth, { strain: 0.05, maxTearsPerStep: 64, hysteresis: 1, minPiece: 1 })
    createWindZone(world, { direction: [0.3, 0, 1], strength: 15, turbulence: 0.5, seed: 1 })
    for (let f = 0; f < 90; f++) stepCloth(world, 1 / 60)
    const c = getClothState(world, cloth)
    const stats = getClothStats(world)
    return { bytes: hashBytes(c.pos.subarray(0, 3 * c.count)), c, resets: stats.guardResets, tears: stats.tears, world, cloth }
  }

  // Each copy had been cloth: the sheet weighed twice its density × area (0.300 kg for 0.150), its
  // edges with four triangles each lost every dihedral hinge (0 for 341) and took shear as stretch,
  // and torn in a wind the guard reset it 9 times in 120 frames (found by a hunt).
  it.each(['line', 'dihedral'] as const)(
    'a double-sided sheet (every face twice, once per side) is its one-sided sheet, byte for byte (%s bending)',
    (bending) => {
      const one = sheet(12)
      const both = one.indices.slice()
      for (let t = 0; t < one.indices.length; t += 3) both.push(one.indices[t], one.indices[t + 2], one.indices[t + 1])
      const a = run(one, bending), b = run({ positions: one.positions, indices: both }, bending)
      expect(b.c.topology.triangleCount).toBe(a.c.topology.triangleCount)
      expect(b.c.topology.hingeCount).toBe(a.c.topology.hingeCount)
      expect(b.bytes).toBe(a.bytes)
      expect(a.tears).toBeGreaterThan(0) // (it tore)
      expect(b.resets).toBe(0)
    },
  )

  // A zero-area triangle along a row put a third triangle on two of its edges, which a tear could
  // not part: drawn metres long across the opening, it joined the falling piece to the pinned one
  // (5-8 guard resets, a drawn edge 34× its rest length; found by a hunt).
  it('a zero-area triangle along a row (whose vertices other triangles hold) is no part of the cloth', () => {
    const clean = sheet(12)
    const sliver = { positions: clean.positions, indices: [...clean.indices, 38, 39, 40] }
    const a = run(clean, 'line'), b = run(sliver, 'line')
    expect(b.bytes).toBe(a.bytes)
    expect(b.resets).toBe(0)
  })

  // Known limit (README): an edge with three or more triangles keeps one stretch constraint, which a
  // tear gives to one side, so a fin's triangle may be drawn across the crack.
  it('fins on three interior edges: torn, no guard reset, drawn triangles stay within 3× their rest edges', () => {
    const drawn = (mesh: { positions: number[]; indices: number[] }) => {
      const r = run(mesh, 'line')
      const world = r.world, rest = r.c.topology.restPositions
      const m = getClothMesh(world, r.cloth)
      let worst = 0
      for (let t = 0; t < m.indices.length; t++) {
        const a = m.indices[t], b = m.indices[t % 3 === 2 ? t - 2 : t + 1]
        const l0 = Math.hypot(rest[3 * a] - rest[3 * b], rest[3 * a + 1] - rest[3 * b + 1], rest[3 * a + 2] - rest[3 * b + 2])
        const l = Math.hypot(
          m.positions[3 * a] - m.positions[3 * b],
          m.positions[3 * a + 1] - m.positions[3 * b + 1],
          m.positions[3 * a + 2] - m.positions[3 * b + 2],
        )
        if (l0 > 0) worst = Math.max(worst, l / l0)
      }
      return { worst, resets: r.resets, tears: r.tears }
    }
    const finned = sheet(12)
    for (const a of [5 * 12 + 5, 7 * 12 + 3, 2 * 12 + 8]) {
      const k = finned.positions.length / 3
      finned.positions.push(finned.positions[3 * a] + 0.05, finned.positions[3 * a + 1], 0.1)
      finned.positions.push(finned.positions[3 * a] + 0.05, finned.positions[3 * a + 1], -0.1)
      finned.indices.push(a, a + 1, k, a + 1, a, k + 1)
    }
    const plain = drawn(sheet(12)), fins = drawn(finned)
    console.log(`worst drawn edge after tearing: plain ${plain.worst.toFixed(2)}×, fins ${fins.worst.toFixed(2)}×`)
    expect(fins.tears).toBeGreaterThan(0)
    expect(fins.resets).toBe(0)
    expect(fins.worst).toBeLessThan(3)
  })

  it('a mesh of zero-area triangles only is still cloth (a sheet collapsed onto a line)', () => {
    const world = makeWorld()
    const cloth = createClothFromMesh(world, { positions: [0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, 0], indices: [0, 1, 2, 1, 2, 3] })
    expect(getClothState(world, cloth).topology.triangleCount).toBe(2)
    for (let f = 0; f < 30; f++) stepCloth(world, 1 / 60)
    expect(allFinite(world, cloth)).toBe(true)
  })
})

describe('T-junctions stitched with zero-area triangles (as decimators and exporters leave them)', () => {
  /**
   * A 1 m sheet whose left half has rows every 0.2 m and right half every 0.1 m: the right half's
   * seam vertices at odd rows lie on the left half's seam edges, each closed by a zero-area
   * triangle (b, v, d) along its edge b–d.
   */
  function stitched() {
    const positions: number[] = [], indices: number[] = []
    const add = (x: number, y: number) => (positions.push(x, y, 0), positions.length / 3 - 1)
    const L = Array.from({ length: 6 }, (_, r) => Array.from({ length: 5 }, (_, c) => add(c * 0.1, -r * 0.2)))
    const seam = Array.from({ length: 11 }, (_, r) => add(0.5, -r * 0.1))
    const R = Array.from({ length: 11 }, (_, r) => Array.from({ length: 5 }, (_, c) => add(0.6 + c * 0.1, -r * 0.1)))
    const quad = (a: number, b: number, c: number, d: number) => indices.push(a, c, b, b, c, d)
    for (let r = 0; r < 5; r++) {
      for (let c = 0; c < 4; c++) quad(L[r][c], L[r][c + 1], L[r + 1][c], L[r + 1][c + 1])
      quad(L[r][4], seam[2 * r], L[r + 1][4], seam[2 * r + 2])
      indices.push(seam[2 * r], seam[2 * r + 1], seam[2 * r + 2]) // zero area
    }
    for (let r = 0; r < 10; r++) {
      quad(seam[r], R[r][0], seam[r + 1], R[r + 1][0])
      for (let c = 0; c < 4; c++) quad(R[r][c], R[r][c + 1], R[r + 1][c], R[r + 1][c + 1])
    }
    return { positions, indices, top: [...L[0], seam[0], ...R[0]] }
  }

  it('keeps the stitches (each edge of one on one face with area at most): drawn watertight, finite and never reset in a gusty wind', () => {
    // dropped as slivers are, the seams opened as 3.4 cm holes in the drawn mesh (found by a hunt)
    const m = stitched()
    const world = makeWorld()
    const cloth = createClothFromMesh(world, { positions: m.positions, indices: m.indices })
    for (const p of m.top) pinParticle(world, cloth, p)
    createWindZone(world, { direction: [0.3, 0, 1], strength: 12, turbulence: 0.6, seed: 3 })
    expect(getClothMesh(world, cloth).indices.length).toBe(m.indices.length)
    for (let f = 0; f < 240; f++) stepCloth(world, 1 / 60)
    expect(allFinite(world, cloth)).toBe(true)
    expect(getClothStats(world).guardResets).toBe(0)
  })
})
