/**
 * `bitecs-cloth/three`: draws a cloth with three.js.
 *
 * ```ts
 * import { createClothMesh, updateClothGeometry } from 'bitecs-cloth/three'
 *
 * const mesh = createClothMesh(world, cloth)
 * scene.add(mesh)
 * // each frame, after stepCloth:
 * updateClothGeometry(world, cloth, mesh.geometry)
 * ```
 *
 * The geometry owns its arrays (position, normal, uv, index), sized with room to spare; the draw
 * range covers the live triangles. A tear adds vertices and rewrites the index: the next update
 * copies both, and grows the arrays (1.5 times, with `geometry.dispose()` so the renderer frees the
 * old GPU buffers) only when the torn cloth no longer fits. Between tears an update copies the
 * positions and normals and refits the bounds, and allocates nothing.
 *
 * three is an optional peer dependency: only this entry imports it.
 * @module bitecs-cloth/three
 */
import { BufferAttribute, BufferGeometry, Box3, DoubleSide, DynamicDrawUsage, Mesh, MeshStandardMaterial, Sphere } from 'three'
import type { Material } from 'three'
import { ClothError, getClothMesh, type ClothMesh } from '../index'

/** The attributes of a cloth geometry (and its index, `geometry.index`). */
export type ClothGeometryAttributes = {
  /** xyz per vertex, m (Float32Array). */
  position: BufferAttribute
  /** Unit normal per vertex, area-weighted (Float32Array). */
  normal: BufferAttribute
  /** Texture coordinates per vertex (Float32Array). */
  uv: BufferAttribute
}

/**
 * A three.js geometry made by createClothGeometry. Its arrays may be longer than the cloth: the
 * live vertices come first, and the draw range covers the live triangles.
 */
export type ClothGeometry = BufferGeometry<ClothGeometryAttributes>

/** What an update needs to remember about a geometry made by createClothGeometry. */
interface GeometryState {
  /** The mesh views last copied (getClothMesh hands out new ones when the topology changes). */
  mesh: ClothMesh | null
  position: BufferAttribute
  normal: BufferAttribute
  uv: BufferAttribute
  index: BufferAttribute
}

const states = /* @__PURE__ */ new WeakMap<object, GeometryState>()

/** The vertex and index room of a new array: the count now, and half as much again when it grows. */
function roomFor(needed: number, current: number): number {
  return current === 0 ? needed : Math.max(needed, Math.ceil(current * 1.5))
}

function checkWorld(world: unknown): object {
  if (typeof world !== 'object' || world === null) {
    throw new ClothError('world', world, 'must be a bitECS world with the cloth plugin installed')
  }
  return world
}

function attributes(geometry: ClothGeometry, vertices: number, indices: number): GeometryState {
  const position = new BufferAttribute(new Float32Array(3 * vertices), 3).setUsage(DynamicDrawUsage)
  const normal = new BufferAttribute(new Float32Array(3 * vertices), 3).setUsage(DynamicDrawUsage)
  const uv = new BufferAttribute(new Float32Array(2 * vertices), 2)
  const index = new BufferAttribute(new Uint32Array(indices), 1)
  geometry.setAttribute('position', position)
  geometry.setAttribute('normal', normal)
  geometry.setAttribute('uv', uv)
  geometry.setIndex(index)
  return { mesh: null, position, normal, uv, index }
}

/**
 * Copies what changes only with the topology (a tear, makeTearable, another cloth): the index, the
 * texture coordinates and the draw range, growing the arrays when they are too small.
 */
function copyTopology(geometry: ClothGeometry, state: GeometryState, mesh: ClothMesh): GeometryState {
  const vertices = mesh.vertexCount
  const indices = 3 * mesh.triangleCount
  const vertexRoom = state.position.count
  const indexRoom = state.index.count
  if (vertices > vertexRoom || indices > indexRoom) {
    geometry.dispose() // the renderer frees the old buffers and uploads the new ones at the next draw
    state = attributes(
      geometry,
      vertices > vertexRoom ? roomFor(vertices, vertexRoom) : vertexRoom,
      indices > indexRoom ? roomFor(indices, indexRoom) : indexRoom,
    )
    states.set(geometry, state)
  }
  const index = state.index.array as Uint32Array
  index.set(mesh.indices)
  state.index.needsUpdate = true
  // TODO(ClothMesh.uvs): read mesh.uvs unconditionally once ClothMesh has it.
  const uvs = (mesh as ClothMesh & { uvs?: Float32Array }).uvs
  const uv = state.uv.array as Float32Array
  if (uvs) uv.set(uvs.subarray(0, 2 * vertices))
  else uv.fill(0, 0, 2 * vertices)
  state.uv.needsUpdate = true
  geometry.setDrawRange(0, indices)
  state.mesh = mesh
  return state
}

/** Box and sphere around the live vertices (three's own compute* would also count the spare room). */
function fitBounds(geometry: ClothGeometry, positions: Float32Array, vertices: number): void {
  const box = (geometry.boundingBox ??= new Box3())
  const sphere = (geometry.boundingSphere ??= new Sphere())
  if (vertices === 0) {
    box.makeEmpty()
    sphere.makeEmpty()
    return
  }
  let minX = Infinity, minY = Infinity, minZ = Infinity
  let maxX = -Infinity, maxY = -Infinity, maxZ = -Infinity
  for (let i = 0; i < 3 * vertices; i += 3) {
    const x = positions[i], y = positions[i + 1], z = positions[i + 2]
    if (x < minX) minX = x
    if (x > maxX) maxX = x
    if (y < minY) minY = y
    if (y > maxY) maxY = y
    if (z < minZ) minZ = z
    if (z > maxZ) maxZ = z
  }
  box.min.set(minX, minY, minZ)
  box.max.set(maxX, maxY, maxZ)
  const cx = 0.5 * (minX + maxX), cy = 0.5 * (minY + maxY), cz = 0.5 * (minZ + maxZ)
  let r2 = 0
  for (let i = 0; i < 3 * vertices; i += 3) {
    const dx = positions[i] - cx, dy = positions[i + 1] - cy, dz = positions[i + 2] - cz
    const d2 = dx * dx + dy * dy + dz * dz
    if (d2 > r2) r2 = d2
  }
  sphere.center.set(cx, cy, cz)
  sphere.radius = Math.sqrt(r2)
}

/**
 * A three.js geometry of a cloth as it is now: `position`, `normal` (unit, area-weighted), `uv`
 * and an index, with its draw range and bounds set. Call updateClothGeometry after each step.
 *
 * @param world A bitECS world with the cloth plugin installed.
 * @param cloth A cloth entity of that world.
 */
export function createClothGeometry(world: object, cloth: number): ClothGeometry {
  const mesh = getClothMesh(checkWorld(world), cloth)
  const geometry = new BufferGeometry<ClothGeometryAttributes>()
  geometry.name = 'cloth'
  states.set(geometry, attributes(geometry, mesh.vertexCount, 3 * mesh.triangleCount))
  return updateClothGeometry(world, cloth, geometry)
}

/**
 * Brings a geometry made by createClothGeometry up to date with the cloth: positions, normals and
 * bounds always; after a tear also the new vertices, the rewritten index and the draw range. It
 * allocates nothing unless a tear outgrew the geometry's arrays. The geometry may be moved to
 * another cloth: the next update copies that cloth's topology.
 *
 * @param world A bitECS world with the cloth plugin installed.
 * @param cloth A cloth entity of that world.
 * @param geometry A geometry made by createClothGeometry (or the `geometry` of createClothMesh).
 * @returns The same geometry.
 */
export function updateClothGeometry(world: object, cloth: number, geometry: BufferGeometry): ClothGeometry {
  let state = states.get(geometry)
  if (state === undefined) throw new ClothError('geometry', geometry, 'must be a geometry made by createClothGeometry')
  const mesh = getClothMesh(checkWorld(world), cloth)
  const clothGeometry = geometry as ClothGeometry // it is: createClothGeometry made it
  if (mesh !== state.mesh) state = copyTopology(clothGeometry, state, mesh)
  ;(state.position.array as Float32Array).set(mesh.positions)
  ;(state.normal.array as Float32Array).set(mesh.normals)
  state.position.needsUpdate = true
  state.normal.needsUpdate = true
  fitBounds(clothGeometry, mesh.positions, mesh.vertexCount)
  return clothGeometry
}

/**
 * A three.js mesh of a cloth: createClothGeometry with `material`, by default a double-sided
 * MeshStandardMaterial (a cloth is seen from both sides). Update it with
 * `updateClothGeometry(world, cloth, mesh.geometry)` after each step.
 *
 * @param world A bitECS world with the cloth plugin installed.
 * @param cloth A cloth entity of that world.
 * @param material Any three.js material; give it `side: DoubleSide` to see both faces.
 */
export function createClothMesh<M extends Material = MeshStandardMaterial>(
  world: object,
  cloth: number,
  material?: M,
): Mesh<ClothGeometry, M> {
  if (material !== undefined && (material as { isMaterial?: unknown } | null)?.isMaterial !== true) {
    throw new ClothError('material', material, 'must be a three.js Material')
  }
  const geometry = createClothGeometry(world, cloth)
  const mesh = new Mesh(geometry, material ?? (new MeshStandardMaterial({ side: DoubleSide }) as unknown as M))
  mesh.name = 'cloth'
  return mesh
}
