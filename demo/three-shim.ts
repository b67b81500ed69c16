// TEMPORARY stand-in for `bitecs-cloth/three` (src/three/index.ts) until it lands on main; same
// API. Deleted when the demo switches to the real adapter.
import * as THREE from 'three'
import { getClothMesh, getClothState } from '../src/index'

function fill(world: object, cloth: number, g: THREE.BufferGeometry): void {
  const m = getClothMesh(world, cloth)
  const c = getClothState(world, cloth)
  let pos = g.getAttribute('position') as THREE.BufferAttribute | undefined
  if (!pos || pos.count < m.vertexCount) {
    const cap = Math.max(m.vertexCount, Math.ceil(m.vertexCount * 1.5))
    pos = new THREE.BufferAttribute(new Float32Array(3 * cap), 3)
    g.setAttribute('position', pos)
    g.setAttribute('normal', new THREE.BufferAttribute(new Float32Array(3 * cap), 3))
    g.setAttribute('uv', new THREE.BufferAttribute(new Float32Array(2 * cap), 2))
    g.userData.uvCount = 0
  }
  const nor = g.getAttribute('normal') as THREE.BufferAttribute
  ;(pos.array as Float32Array).set(m.positions)
  ;(nor.array as Float32Array).set(m.normals)
  pos.needsUpdate = nor.needsUpdate = true
  if (g.userData.uvCount !== m.vertexCount) {
    // uvs from rest positions: u along the first row, v down the first column
    const r = c.topology.restPositions
    const uv = g.getAttribute('uv') as THREE.BufferAttribute
    const a = g.userData.frame ?? (g.userData.frame = frame(r, m.vertexCount))
    for (let i = 0; i < m.vertexCount; i++) {
      const dx = r[3 * i] - a.o[0], dy = r[3 * i + 1] - a.o[1], dz = r[3 * i + 2] - a.o[2]
      uv.setXY(i, (dx * a.u[0] + dy * a.u[1] + dz * a.u[2]) / a.lu, 1 - (dx * a.v[0] + dy * a.v[1] + dz * a.v[2]) / a.lv)
    }
    uv.needsUpdate = true
    g.userData.uvCount = m.vertexCount
  }
  let idx = g.getIndex()
  if (!idx || idx.count < m.indices.length) {
    idx = new THREE.BufferAttribute(new Uint32Array(Math.ceil(m.indices.length * 1.5) + 3), 1)
    g.setIndex(idx)
  }
  ;(idx.array as Uint32Array).set(m.indices)
  idx.needsUpdate = true
  g.setDrawRange(0, m.indices.length)
  g.computeBoundingSphere()
  g.computeBoundingBox()
}

function frame(r: ArrayLike<number>, count: number): { o: number[]; u: number[]; v: number[]; lu: number; lv: number } {
  // a grid cloth: particle 0 is a corner, the first row runs to `cols − 1`
  let cols = 0
  {
    // find the end of the first row: the last particle collinear with 0 → 1
    const d = [r[3] - r[0], r[4] - r[1], r[5] - r[2]]
    cols = 2
    for (;;) {
      const e = [r[3 * cols] - r[0], r[3 * cols + 1] - r[1], r[3 * cols + 2] - r[2]]
      const cross = Math.hypot(d[1] * e[2] - d[2] * e[1], d[2] * e[0] - d[0] * e[2], d[0] * e[1] - d[1] * e[0])
      if (cols >= count || cross > 1e-6 * Math.hypot(...e) * Math.hypot(...d)) break
      cols++
    }
  }
  const last = count - 1
  const o = [r[0], r[1], r[2]]
  const u = [r[3 * (cols - 1)] - o[0], r[3 * (cols - 1) + 1] - o[1], r[3 * (cols - 1) + 2] - o[2]]
  const lu = Math.hypot(...u)
  const rowsStart = last - (cols - 1)
  const v = [r[3 * rowsStart] - o[0], r[3 * rowsStart + 1] - o[1], r[3 * rowsStart + 2] - o[2]]
  const lv = Math.hypot(...v)
  return { o, u: u.map((x) => x / lu), v: v.map((x) => x / lv), lu, lv }
}

export function createClothGeometry(world: object, cloth: number): THREE.BufferGeometry {
  const g = new THREE.BufferGeometry()
  fill(world, cloth, g)
  return g
}

export function updateClothGeometry(world: object, cloth: number, geometry: THREE.BufferGeometry): void {
  fill(world, cloth, geometry)
}

export function createClothMesh(world: object, cloth: number, material?: THREE.Material): THREE.Mesh {
  return new THREE.Mesh(createClothGeometry(world, cloth), material)
}
