// Torture suite, part 2: hard meshes (mass ratios, degenerate triangles, folds at the dihedral
// singularities). See harness.ts for what every case must show.
import { describe, expect, it } from 'vitest'
import { createClothFromMesh, defineMaterial, getClothState, pinParticle, type CreateClothFromMeshOptions } from '../../src/index'
import { expectStable, gridMesh, runTorture } from './harness'
import { maxDistance } from './scenes'

describe('mass ratios', () => {
  const mesh = gridMesh(7, 1 / 6)
  const withMasses = (masses: number[]) => (world: object) => {
    const cloth = createClothFromMesh(world, { ...mesh, masses, bending: 'both' })
    for (let c = 0; c < 7; c++) pinParticle(world, cloth, c)
    return { cloths: [cloth] }
  }
  it('1 : 1e6 between neighbours (a checkerboard of 1 mg and 1 kg particles)', () => {
    const masses = mesh.positions.filter((_, k) => k % 3 === 0).map((_, i) => ((i % 7) + Math.floor(i / 7)) % 2 ? 1 : 1e-6)
    expectStable(runTorture({ build: withMasses(masses), recover: 'rest', frames: 0 }))
  })
  it('1 : 1e6 between rows (a hem of 1 kg particles on a sheet of 1 mg ones), then shaken', () => {
    const masses = Array.from({ length: 49 }, (_, i) => (i >= 42 ? 1 : 1e-6))
    expectStable(runTorture({
      build: withMasses(masses),
      abuse: (s, f) => {
        if (f === 0) getClothState(s.world, s.cloths[0]).vel.fill(3) // a 3 m/s gust through everything
      },
      frames: 60,
      recover: 'rest',
    }))
  })
})

describe('degenerate meshes', () => {
  const variants: [string, (m: { positions: number[] }) => void][] = [
    ['zero-length edges (a column moved onto its neighbour)', (m) => {
      for (let r = 0; r < 7; r++) m.positions[3 * (r * 7 + 3)] = m.positions[3 * (r * 7 + 4)]
    }],
    ['coincident particles (a whole row on one point)', (m) => {
      for (let c = 0; c < 7; c++) {
        m.positions[3 * (3 * 7 + c)] = 0
        m.positions[3 * (3 * 7 + c) + 1] = -0.5
      }
    }],
    ['zero-area triangles (a row squashed onto the one above)', (m) => {
      for (let c = 0; c < 7; c++) m.positions[3 * (4 * 7 + c) + 1] = m.positions[3 * (3 * 7 + c) + 1]
    }],
    ['collinear triangles everywhere (the whole mesh on a line)', (m) => {
      for (let i = 0; i < 49; i++) m.positions[3 * i + 1] = 0
    }],
    ['every particle on one point', (m) => m.positions.fill(0)],
  ]
  for (const [name, deform] of variants) {
    for (const bending of ['distance', 'dihedral', 'both'] as const) {
      it(`${name}, ${bending} bending`, () => {
        expectStable(runTorture({
          build: (world) => {
            const m = gridMesh(7, 1 / 6)
            deform(m)
            const cloth = createClothFromMesh(world, { ...m, bending })
            pinParticle(world, cloth, 0)
            pinParticle(world, cloth, 6)
            return { cloths: [cloth] }
          },
          frames: 0,
          recover: 'rest',
        }))
      })
    }
  }
})

describe('folds: the dihedral singularities', () => {
  /** Two 5×5 panels sharing a crease along x; the second panel is turned by `deg` about it. */
  function folded(deg: number): Pick<CreateClothFromMeshOptions, 'positions' | 'indices'> {
    const n = 5, s = 0.1, a = (deg * Math.PI) / 180
    const positions: number[] = []
    for (let r = 0; r < 2 * n - 1; r++) {
      for (let c = 0; c < n; c++) {
        const x = c * s
        if (r < n) positions.push(x, 0, (n - 1 - r) * s) // panel A in the x-z plane, crease at z = 0
        else {
          const d = (r - n + 1) * s // distance from the crease on panel B
          positions.push(x, d * Math.sin(a), -d * Math.cos(a))
        }
      }
    }
    const indices: number[] = []
    for (let r = 0; r + 1 < 2 * n - 1; r++) {
      for (let c = 0; c + 1 < n; c++) {
        const i = r * n + c
        indices.push(i, i + n, i + 1, i + 1, i + n, i + n + 1)
      }
    }
    return { positions, indices }
  }
  // 0: flat; 180: folded flat onto itself; ±90, 45, 135: bent either way. Zero gravity, one panel
  // held: the rest shape is the only equilibrium. Four pushes, 150 frames apart; after each, the
  // free panel must be back at its rest pose.
  const pushes = [[0, 0.03, 0], [0, -0.03, 0], [0.03, 0, 0], [0, 0, 0.03]]
  for (const deg of [0, 180, 90, -90, 45, 135]) {
    for (const bending of ['dihedral', 'both'] as const) {
      it(`rest angle ${deg}°, ${bending} bending, pushed four ways and let go`, () => {
        const card = defineMaterial({ name: 'card', bendCompliance: 20, damping: 4 })
        const errors: number[] = []
        let rest: Float64Array | null = null
        expectStable(runTorture({
          world: { gravity: [0, 0, 0] },
          build: (world) => {
            const cloth = createClothFromMesh(world, { ...folded(deg), material: card, bending, iterations: 4, substeps: 4 })
            for (let i = 0; i < 25; i++) pinParticle(world, cloth, i) // panel A held
            return { cloths: [cloth] }
          },
          abuse: (s, f) => {
            const c = getClothState(s.world, s.cloths[0])
            rest ??= Float64Array.from(c.pos)
            if (f % 150 === 149) errors.push(maxDistance(c.pos, rest, c.count))
            if (f % 150 !== 0) return
            const push = pushes[f / 150]
            for (let i = 25; i < c.count; i++) for (let k = 0; k < 3; k++) c.pos[3 * i + k] += (push[k] * ((i % 5) + 1)) / 3
          },
          frames: 600,
          settle: 60,
          drapeTolerance: 0.01,
        }))
        expect(errors.length).toBe(4)
        for (const e of errors) expect(e).toBeLessThan(0.005) // m, on a 0.4 m panel
      })
    }
  }
})
