// UV seams: createClothFromMesh joins vertices by index only, so a mesh whose seams duplicate
// vertices (as textured exports do) simulates as separate pieces; the README's way is to simulate
// the welded mesh and draw the seamed one as a render proxy.
import { createWorld } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  createClothFromMesh,
  createRenderProxy,
  getClothState,
  installClothPlugin,
  pinParticle,
  stepCloth,
  updateRenderProxy,
} from '../../src/index'

type Mesh = { positions: number[]; indices: number[] }

/** A w × h sheet in the x-y plane, top edge at y = 0, columns × rows vertices; split: how quads are cut. */
function gridSheet(w: number, h: number, cols: number, rows: number, split: 'alt' | 'slash' | 'backslash' = 'alt'): Mesh {
  const positions: number[] = []
  for (let r = 0; r < rows; r++) for (let c = 0; c < cols; c++) positions.push((c / (cols - 1) - 0.5) * w, -(r / (rows - 1)) * h, 0)
  const indices: number[] = []
  for (let r = 0; r + 1 < rows; r++) {
    for (let c = 0; c + 1 < cols; c++) {
      const i = r * cols + c, right = i + 1, down = i + cols, diag = down + 1
      const s = split === 'alt' ? ((r + c) % 2 === 0 ? 'slash' : 'backslash') : split
      if (s === 'slash') indices.push(i, down, right, right, down, diag)
      else indices.push(i, down, diag, i, diag, right)
    }
  }
  return { positions, indices }
}
function withVerticalSeam(m: Mesh, cols: number, rows: number, col: number): { mesh: Mesh; pairs: [number, number][] } {
  const positions = m.positions.slice()
  const n = positions.length / 3
  const dup = new Map<number, number>()
  const pairs: [number, number][] = []
  for (let r = 0; r < rows; r++) {
    const i = r * cols + col
    dup.set(i, n + r)
    positions.push(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2])
    pairs.push([i, n + r])
  }
  const indices = m.indices.slice()
  for (let t = 0; t < indices.length; t += 3) {
    // a triangle right of the seam: its centroid x is beyond the seam column's x
    let cx = 0
    for (let k = 0; k < 3; k++) cx += positions[3 * indices[t + k]]
    cx /= 3
    const seamX = m.positions[3 * col]
    if (cx > seamX) { for (let k = 0; k < 3; k++) if (dup.has(indices[t + k])) indices[t + k] = dup.get(indices[t + k])! }
  }
  return { mesh: { positions, indices }, pairs }
}
function maxPairGap(w: object, cloth: number, pairs: [number, number][]): number {
  const p = getClothState(w, cloth).pos
  let g = 0
  for (const [a, b] of pairs) g = Math.max(g, Math.hypot(p[3 * a] - p[3 * b], p[3 * a + 1] - p[3 * b + 1], p[3 * a + 2] - p[3 * b + 2]))
  return g
}
const world = () => installClothPlugin(createWorld())
const steps = (w: object, n: number) => {
  for (let i = 0; i < n; i++) stepCloth(w, 1 / 60)
}
const finite = (w: object, cloth: number) => getClothState(w, cloth).pos.every(Number.isFinite)

describe('UV seams', () => {
  it('the way to draw a seam: simulate the welded mesh, draw the seamed one as a render proxy (no gap, the seam uvs kept)', () => {
    const cols = 11, rows = 11
    const welded = gridSheet(1, 1, cols, rows)
    const { mesh } = withVerticalSeam(welded, cols, rows, 5)
    const uvs: number[] = []
    for (let i = 0; i < mesh.positions.length / 3; i++) uvs.push(i >= cols * rows ? 0.9 : 0.1, 0.5) // a seam: different uvs
    const w = world()
    const cloth = createClothFromMesh(w, welded)
    pinParticle(w, cloth, 0)
    pinParticle(w, cloth, cols - 1)
    const proxy = createRenderProxy(w, cloth, { positions: mesh.positions, indices: mesh.indices, uvs })
    steps(w, 120)
    const pm = updateRenderProxy(w, proxy)
    let gap = 0
    for (let r = 0; r < rows; r++) {
      const a = r * cols + 5, b = cols * rows + r
      gap = Math.max(
        gap,
        Math.hypot(
          pm.positions[3 * a] - pm.positions[3 * b],
          pm.positions[3 * a + 1] - pm.positions[3 * b + 1],
          pm.positions[3 * a + 2] - pm.positions[3 * b + 2],
        ),
      )
    }
    expect(gap).toBeLessThan(1e-4)
    expect(pm.uvs[2 * cols * rows]).toBeCloseTo(0.9, 5)
  })

  it('vertices are joined by index only: a mesh with a UV seam (duplicated vertices) simulates as two pieces that part (documented)', () => {
    const cols = 11, rows = 11
    const { mesh, pairs } = withVerticalSeam(gridSheet(1, 1, cols, rows), cols, rows, 5)
    const w = world()
    const cloth = createClothFromMesh(w, mesh)
    pinParticle(w, cloth, 0)
    pinParticle(w, cloth, cols - 1)
    steps(w, 120)
    const gap = maxPairGap(w, cloth, pairs)
    expect(finite(w, cloth)).toBe(true)
    // measured: 0.71 m apart after 2 s, two pieces
    expect(gap).toBeGreaterThan(0.1)
    expect(getClothState(w, cloth).pieceCount).toBe(2)
  })
})
