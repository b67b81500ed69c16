// TEMPORARY: texture coordinates for cloth geometries until `getClothMesh` returns `uvs` (issue 18
// item 3) and the three adapter copies them. Delete this file and its one call in main.ts then.
import type * as THREE from 'three'
import { getClothMesh, getClothState } from '../src/index'

/**
 * Writes uvs from the cloth's rest positions (u along its first row, v down from it) when the
 * library gives none, after the adapter has (re)written the geometry's topology.
 */
export function fillMissingUvs(world: object, cloth: number, geometry: THREE.BufferGeometry): void {
  const mesh = getClothMesh(world, cloth) as { uvs?: unknown; vertexCount: number }
  if (mesh.uvs) return
  const uv = geometry.getAttribute('uv') as THREE.BufferAttribute
  const index = geometry.getIndex()!
  if (geometry.userData.uvFor === uv && geometry.userData.uvVersion === index.version && geometry.userData.uvCount === mesh.vertexCount) return
  const r = getClothState(world, cloth).topology.restPositions
  const f = (geometry.userData.uvFrame ??= frame(r, mesh.vertexCount))
  for (let i = 0; i < mesh.vertexCount; i++) {
    const dx = r[3 * i] - f.o[0], dy = r[3 * i + 1] - f.o[1], dz = r[3 * i + 2] - f.o[2]
    uv.setXY(i, (dx * f.u[0] + dy * f.u[1] + dz * f.u[2]) / f.lu, 1 - (dx * f.v[0] + dy * f.v[1] + dz * f.v[2]) / f.lv)
  }
  uv.needsUpdate = true
  geometry.userData.uvFor = uv
  geometry.userData.uvVersion = index.version
  geometry.userData.uvCount = mesh.vertexCount
}

/** A grid cloth's frame: particle 0 is a corner, the first row runs to the first bend. */
function frame(r: ArrayLike<number>, count: number): { o: number[]; u: number[]; v: number[]; lu: number; lv: number } {
  const d = [r[3] - r[0], r[4] - r[1], r[5] - r[2]]
  let cols = 2
  for (; cols < count; cols++) {
    const e = [r[3 * cols] - r[0], r[3 * cols + 1] - r[1], r[3 * cols + 2] - r[2]]
    const cross = Math.hypot(d[1] * e[2] - d[2] * e[1], d[2] * e[0] - d[0] * e[2], d[0] * e[1] - d[1] * e[0])
    if (cross > 1e-6 * Math.hypot(...e) * Math.hypot(...d)) break
  }
  const o = [r[0], r[1], r[2]]
  const u = [r[3 * (cols - 1)] - o[0], r[3 * (cols - 1) + 1] - o[1], r[3 * (cols - 1) + 2] - o[2]]
  const lu = Math.hypot(...u)
  const last = count - cols
  const v = [r[3 * last] - o[0], r[3 * last + 1] - o[1], r[3 * last + 2] - o[2]]
  const lv = Math.hypot(...v)
  return { o, u: u.map((x) => x / lu), v: v.map((x) => x / lv), lu, lv }
}
