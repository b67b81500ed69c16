import type { ClothMaterialSpec } from './materials'
import { assemble } from './assembly'
import { PairList, analyseMesh, isQuadDiagonal } from './meshInfo'
import { BEND, SHEAR, STRETCH, type ClothTopology, type TopologyOptions } from './topology'
import { orientTriangles, simulatedFaces } from './orient'

/**
 * The mesh of a rectangular sheet of `columns` × `rows` vertices: row-major from the top-left
 * corner (row 0 at the top), in the sheet's local x-y plane with the middle of the top edge at the
 * origin, front facing +z; triangles counter-clockwise from the front, the split diagonal
 * alternating so the sheet has no preferred shear direction. `createCloth`'s rest shape, and the
 * usual render mesh of a proxy (a finer grid of the same sheet).
 */
export function gridMesh(width: number, height: number, columns: number, rows: number): { positions: Float64Array; indices: Uint32Array } {
  const n = columns * rows
  const rest = new Float64Array(3 * n)
  const dx = width / (columns - 1)
  const dy = height / (rows - 1)
  for (let r = 0; r < rows; r++) {
    for (let c = 0; c < columns; c++) {
      const i = r * columns + c
      rest[3 * i] = c * dx - width / 2
      rest[3 * i + 1] = 0 - r * dy // (0 − 0 is +0, not −0)
      rest[3 * i + 2] = 0
    }
  }
  const tris = new Uint32Array(6 * (columns - 1) * (rows - 1))
  let t = 0
  for (let r = 0; r + 1 < rows; r++) {
    for (let c = 0; c + 1 < columns; c++) {
      const i = r * columns + c
      const right = i + 1
      const down = i + columns
      const diag = down + 1
      if ((r + c) % 2 === 0) {
        tris.set([i, down, right, right, down, diag], t)
      } else {
        tris.set([i, down, diag, i, diag, right], t)
      }
      t += 6
    }
  }
  return { positions: rest, indices: tris }
}

/** Builds a rectangular grid: particles row-major from the top-left corner, row 0 at the top (see `gridMesh`). */
export function buildGridTopology(
  width: number,
  height: number,
  columns: number,
  rows: number,
  material: ClothMaterialSpec,
  topology: 'quad' | 'triangle',
  options: TopologyOptions = {},
): ClothTopology {
  const n = columns * rows
  const { positions: rest, indices: tris } = gridMesh(width, height, columns, rows)
  if (topology === 'triangle') {
    return buildMeshTopology(rest, tris, material, { ...options, grid: [columns, rows] })
  }

  // Quad topology: structural rows/columns, both diagonals as shear, bending along rows/columns.
  const pairs = new PairList()
  const shearModel = options.shear ?? 'distance'
  const bending = options.bending ?? 'line'
  const comp = new PairList()
  const lines: number[] = []
  for (let r = 0; r < rows; r++) {
    for (let c = 0; c < columns; c++) {
      const i = r * columns + c
      if (c + 1 < columns) pairs.push(i, i + 1, STRETCH)
      if (r + 1 < rows) pairs.push(i, i + columns, STRETCH)
      if (r + 1 < rows && c + 1 < columns) {
        const target = shearModel === 'compression' ? comp : shearModel === 'distance' ? pairs : null
        target?.push(i, i + columns + 1, SHEAR)
        target?.push(i + 1, i + columns, SHEAR)
      }
      if (bending === 'distance' || bending === 'both') {
        if (c + 2 < columns) pairs.push(i, i + 2, BEND)
        if (r + 2 < rows) pairs.push(i, i + 2 * columns, BEND)
      }
      if (bending === 'line') {
        if (c + 2 < columns) lines.push(i, i + 1, i + 2)
        if (r + 2 < rows) lines.push(i, i + columns, i + 2 * columns)
      }
    }
  }
  const mesh = analyseMesh(rest, tris, n)
  const hinges = bending === 'dihedral' || bending === 'both' ? mesh.hinges : new Int32Array(0)
  return assemble(rest, tris, mesh, pairs, comp, lines, hinges, material, options, columns, rows)
}

/**
 * Builds rest data from any indexed triangle mesh. Edges come from the triangles; where two
 * triangles form a quad (their shared edge is the longest edge of both), the shared edge and the
 * opposite diagonal become shear constraints; the opposite vertices across every other interior
 * edge become a bending pair; every interior edge can also carry a dihedral hinge.
 */
export function buildMeshTopology(
  positions: ArrayLike<number>,
  indices: ArrayLike<number>,
  material: ClothMaterialSpec,
  options: TopologyOptions & { grid?: [number, number] } = {},
): ClothTopology {
  const n = (positions.length / 3) | 0
  const rest = Float64Array.from(positions)
  let tris: Uint32Array = Uint32Array.from(indices)
  if (options.grid === undefined) {
    // a user's mesh: its windings made to agree, its repeated faces and slivers not cloth (grids are clean)
    orientTriangles(tris, n)
    tris = simulatedFaces(tris, rest, n)
  }
  const mesh = analyseMesh(rest, tris, n)
  const shearModel = options.shear ?? 'distance'
  const bending = options.bending ?? 'line'
  const pairs = new PairList()
  const comp = new PairList()
  const shearTarget = shearModel === 'compression' ? comp : shearModel === 'distance' ? pairs : null
  for (let e = 0; e < mesh.edgeCount; e++) {
    const a = mesh.edges[2 * e]
    const b = mesh.edges[2 * e + 1]
    const w0 = mesh.edgeWing[2 * e]
    const w1 = mesh.edgeWing[2 * e + 1]
    if (w1 >= 0 && isQuadDiagonal(rest, a, b, w0, w1)) {
      // a quad's diagonal and its cross diagonal resist shear, not stretch
      shearTarget?.push(a, b, SHEAR)
      shearTarget?.push(w0, w1, SHEAR)
    } else {
      pairs.push(a, b, STRETCH)
      if (w1 >= 0 && (bending === 'distance' || bending === 'both')) pairs.push(w0, w1, BEND)
    }
  }
  const hinges = bending === 'dihedral' || bending === 'both' ? mesh.hinges : new Int32Array(0)
  const lines = bending === 'line' ? lineTriples(rest, n, pairs) : []
  const [columns, rows] = options.grid ?? [0, 0]
  return assemble(rest, tris, mesh, pairs, comp, lines, hinges, material, options, columns, rows)
}

/**
 * Line-bending triples of a mesh: at every vertex, pairs of its stretch edges that point in nearly
 * opposite directions (within 30°), best pairs first, each edge used once per vertex. On a
 * triangulated grid these are exactly the rows and columns.
 */
function lineTriples(rest: Float64Array, n: number, pairs: PairList): number[] {
  const neighbours: number[][] = Array.from({ length: n }, () => [])
  for (let k = 0; k < pairs.length; k++) {
    if (pairs.kind[k] !== STRETCH) continue
    neighbours[pairs.a[k]].push(pairs.b[k])
    neighbours[pairs.b[k]].push(pairs.a[k])
  }
  const out: number[] = []
  const cosLimit = -Math.cos(Math.PI / 6)
  for (let v = 0; v < n; v++) {
    const nb = neighbours[v]
    const candidates: [number, number, number][] = []
    for (let i = 0; i < nb.length; i++) {
      for (let j = i + 1; j < nb.length; j++) {
        const a = nb[i], b = nb[j]
        const ax = rest[3 * a] - rest[3 * v], ay = rest[3 * a + 1] - rest[3 * v + 1], az = rest[3 * a + 2] - rest[3 * v + 2]
        const bx = rest[3 * b] - rest[3 * v], by = rest[3 * b + 1] - rest[3 * v + 1], bz = rest[3 * b + 2] - rest[3 * v + 2]
        const la = Math.hypot(ax, ay, az), lb = Math.hypot(bx, by, bz)
        if (la === 0 || lb === 0) continue
        const cos = (ax * bx + ay * by + az * bz) / (la * lb)
        if (cos < cosLimit) candidates.push([cos, a, b])
      }
    }
    candidates.sort((p, q) => p[0] - q[0] || p[1] - q[1] || p[2] - q[2])
    const used = new Set<number>()
    for (const [, a, b] of candidates) {
      if (used.has(a) || used.has(b)) continue
      used.add(a)
      used.add(b)
      out.push(a, v, b)
    }
  }
  return out
}
