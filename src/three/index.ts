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
 * A render proxy (`createRenderProxy`: a finer mesh driven by the cloth) is drawn the same way:
 *
 * ```ts
 * const proxy = createRenderProxy(world, cloth, buildGridMesh({ width, height, resolution: 61 }))
 * const mesh = createProxyMesh(world, proxy)
 * scene.add(mesh)
 * // each frame, after stepCloth:
 * updateProxyGeometry(world, proxy, mesh.geometry)
 * ```
 *
 * three is an optional peer dependency: only this entry imports it.
 * @module bitecs-cloth/three
 */
import { BufferAttribute, BufferGeometry, Box3, DoubleSide, DynamicDrawUsage, Mesh, MeshStandardMaterial, Sphere } from 'three'
import type { Material, NormalBufferAttributes, Object3D } from 'three'
import {
  ClothError,
  getClothDrawTransform,
  getClothMesh,
  getClothState,
  getClothStats,
  updateRenderProxy,
  type ClothMesh,
  type ClothRenderProxy,
} from '../index'

/**
 * The attributes of a cloth geometry (and its index, `geometry.index`); a geometry takes others of
 * your own too (vertex colours, tangents), which you keep the length of `position` yourself (a
 * tear can grow the cloth's arrays: compare `position.count` after an update).
 */
export type ClothGeometryAttributes = NormalBufferAttributes & {
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
  /**
   * The mesh views last copied (getClothMesh hands out new ones when the topology changes). This
   * and the cloth's state are let go when the geometry is disposed (`release`): a pooled mesh of a
   * removed cloth kept the dead cloth's arrays alive, 235 kB for a 14×24 cape.
   */
  mesh: ClothMesh | null
  /** The cloth last copied (its world, entity and state: an id a removed cloth left may name another). */
  world: object | null
  cloth: number
  clothState: object | null
  /** The cloth's `version` at the last copy (a sleeping or frozen cloth is not uploaded again). */
  version: number
  position: BufferAttribute
  normal: BufferAttribute
  uv: BufferAttribute
  index: BufferAttribute
}

const states = /* @__PURE__ */ new WeakMap<object, GeometryState>()

/**
 * A geometry made by createClothGeometry was disposed: it lets go of its cloth, so a pooled mesh
 * keeps nothing of a removed cloth alive and may take any cloth next (a recycled id included: the
 * safeguard against a forgotten mesh drawing a new cloth holds for meshes still in use).
 */
function release(event: { target: unknown }): void {
  const state = states.get(event.target as object)
  if (state === undefined) return
  state.mesh = null
  state.world = null
  state.cloth = -1
  state.clothState = null
  state.version = -1
}

/** The vertex and index room of a new array: the count now, and half as much again when it grows. */
function roomFor(needed: number, current: number): number {
  return current === 0 ? needed : Math.max(needed, Math.ceil(current * 1.5))
}

/** The world, checked first in every export (a ClothError('world') unless it has the cloth plugin). */
function checkWorld(world: unknown): object {
  if (typeof world !== 'object' || world === null) {
    throw new ClothError('world', world, 'must be a bitECS world with the cloth plugin installed')
  }
  getClothStats(world) // (throws the same error for a world without the plugin)
  return world
}

function checkMaterial(material: unknown): void {
  if (material !== undefined && (material as { isMaterial?: unknown } | null)?.isMaterial !== true) {
    throw new ClothError('material', material, 'must be a three.js Material')
  }
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
  return { mesh: null, world: null, cloth: -1, clothState: null, version: -1, position, normal, uv, index }
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
    // (what it showed, kept across the dispose, which `release` answers by forgetting it)
    const { world, cloth, clothState, version } = state
    geometry.dispose() // the renderer frees the old buffers and uploads the new ones at the next draw
    state = attributes(
      geometry,
      vertices > vertexRoom ? roomFor(vertices, vertexRoom) : vertexRoom,
      indices > indexRoom ? roomFor(indices, indexRoom) : indexRoom,
    )
    state.world = world
    state.cloth = cloth
    state.clothState = clothState
    state.version = version
    states.set(geometry, state)
  }
  const index = state.index.array as Uint32Array
  index.set(mesh.indices)
  state.index.needsUpdate = true
  ;(state.uv.array as Float32Array).set(mesh.uvs)
  state.uv.needsUpdate = true
  geometry.setDrawRange(0, indices)
  state.mesh = mesh
  return state
}

/** Scratch of fitBounds: min xyz, max xyz, squared radius. */
const bounds = /* @__PURE__ */ new Float64Array(7)

/** Positions (floats, not vertices) per call of boxRun and sphereRun. */
const BOUNDS_RUN = 192

/**
 * Box and sphere around the live vertices (three's own compute* would also count the spare room),
 * but those no triangle uses (`unused`: a stray vertex of an imported mesh stays where it was
 * made, and a cape run 100 m from it had a 50 m sphere). The loops go in runs of BOUNDS_RUN floats,
 * one call each: a single loop over every vertex, entered once per frame, is one V8 may only ever
 * optimize on the stack (OSR), starting it unoptimized every frame, where its doubles are boxed; a
 * short loop called many times is optimized as a whole.
 */
function fitBounds(geometry: ClothGeometry, positions: Float32Array, vertices: number, unused: Uint8Array | null): void {
  const box = (geometry.boundingBox ??= new Box3())
  const sphere = (geometry.boundingSphere ??= new Sphere())
  if (vertices === 0) {
    box.makeEmpty()
    sphere.makeEmpty()
    return
  }
  const b = bounds
  b[0] = b[1] = b[2] = Infinity
  b[3] = b[4] = b[5] = -Infinity
  b[6] = 0
  const n = 3 * vertices
  for (let s = 0; s < n; s += BOUNDS_RUN) boxRun(positions, s, s + BOUNDS_RUN < n ? s + BOUNDS_RUN : n, b, unused)
  if (!(b[0] <= b[3])) {
    box.makeEmpty()
    sphere.makeEmpty()
    return
  }
  for (let s = 0; s < n; s += BOUNDS_RUN) sphereRun(positions, s, s + BOUNDS_RUN < n ? s + BOUNDS_RUN : n, b, unused)
  box.min.set(b[0], b[1], b[2])
  box.max.set(b[3], b[4], b[5])
  sphere.center.set(0.5 * (b[0] + b[3]), 0.5 * (b[1] + b[4]), 0.5 * (b[2] + b[5]))
  sphere.radius = Math.sqrt(b[6])
}

/** Grows the box in b[0..5] by positions [from, to), but the vertices marked in `unused`. */
function boxRun(positions: Float32Array, from: number, to: number, b: Float64Array, unused: Uint8Array | null): void {
  let minX = b[0], minY = b[1], minZ = b[2], maxX = b[3], maxY = b[4], maxZ = b[5]
  for (let i = from; i < to; i += 3) {
    if (unused !== null && unused[i / 3] === 1) continue
    const x = positions[i], y = positions[i + 1], z = positions[i + 2]
    if (x < minX) minX = x
    if (x > maxX) maxX = x
    if (y < minY) minY = y
    if (y > maxY) maxY = y
    if (z < minZ) minZ = z
    if (z > maxZ) maxZ = z
  }
  b[0] = minX
  b[1] = minY
  b[2] = minZ
  b[3] = maxX
  b[4] = maxY
  b[5] = maxZ
}

/** Grows b[6], the largest squared distance from the box's centre, by positions [from, to), but the vertices marked in `unused`. */
function sphereRun(positions: Float32Array, from: number, to: number, b: Float64Array, unused: Uint8Array | null): void {
  const cx = 0.5 * (b[0] + b[3]), cy = 0.5 * (b[1] + b[4]), cz = 0.5 * (b[2] + b[5])
  let r2 = b[6]
  for (let i = from; i < to; i += 3) {
    if (unused !== null && unused[i / 3] === 1) continue
    const dx = positions[i] - cx, dy = positions[i + 1] - cy, dz = positions[i + 2] - cz
    const d2 = dx * dx + dy * dy + dz * dz
    if (d2 > r2) r2 = d2
  }
  b[6] = r2
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
  geometry.addEventListener('dispose', release)
  return updateClothGeometry(world, cloth, geometry)
}

/**
 * Brings a geometry made by createClothGeometry up to date with the cloth: positions, normals and
 * bounds when the cloth changed since the last update (a sleeping or frozen cloth, or a frame that
 * ran no step, uploads nothing); after a tear also the new vertices, the rewritten index and the
 * draw range. It
 * allocates nothing unless a tear outgrew the geometry's arrays. The geometry may be moved to
 * another cloth, of this world or another: the next update copies that cloth's topology. A
 * ClothError when the cloth it showed was removed and its id now names another cloth of the same
 * world: the old mesh, left in a scene, would
 * silently draw the new one twice (make a mesh for the new cloth, as a render proxy must be made
 * again). A disposed geometry (`geometry.dispose()`, as a pool does) has let go of its cloth and
 * takes any cloth, a recycled id too.
 *
 * @param world A bitECS world with the cloth plugin installed.
 * @param cloth A cloth entity of that world.
 * @param geometry A geometry made by createClothGeometry (or the `geometry` of createClothMesh).
 * @returns The same geometry.
 */
export function updateClothGeometry(world: object, cloth: number, geometry: BufferGeometry): ClothGeometry {
  checkWorld(world)
  let state = states.get(geometry)
  if (state === undefined) throw new ClothError('geometry', geometry, 'must be a geometry made by createClothGeometry')
  const mesh = getClothMesh(world, cloth)
  const clothState = getClothState(world, cloth)
  // (the same id in another world is another cloth, as another id is: a level reloaded into a new
  // world keeps its meshes)
  if (state.world === world && state.cloth === cloth && state.clothState !== clothState) {
    throw new ClothError(
      'cloth',
      cloth,
      'is not the cloth this geometry showed: that one was removed and its id names a new cloth (make a mesh for the new one)',
    )
  }
  const clothGeometry = geometry as ClothGeometry // it is: createClothGeometry made it
  // unchanged since the last copy (asleep, frozen, between steps): nothing to upload again
  if (state.clothState === clothState && mesh === state.mesh && state.version === clothState.version) return clothGeometry
  state.world = world
  state.cloth = cloth
  state.clothState = clothState
  if (mesh !== state.mesh) state = copyTopology(clothGeometry, state, mesh)
  state.version = clothState.version
  ;(state.position.array as Float32Array).set(mesh.positions)
  ;(state.normal.array as Float32Array).set(mesh.normals)
  state.position.needsUpdate = true
  state.normal.needsUpdate = true
  fitBounds(clothGeometry, mesh.positions, mesh.vertexCount, clothState.topology.unused)
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
  checkWorld(world)
  checkMaterial(material)
  const geometry = createClothGeometry(world, cloth)
  const mesh = new Mesh(geometry, material ?? (new MeshStandardMaterial({ side: DoubleSide }) as unknown as M))
  mesh.name = 'cloth'
  return mesh
}

/** What an update needs to remember about a geometry made by createProxyGeometry. */
interface ProxyGeometryState {
  proxy: ClothRenderProxy
  /** The proxy mesh's `indexVersion` last uploaded. */
  indexVersion: number
  /** The cloth's `version` at the last upload (a sleeping or frozen cloth is not uploaded again). */
  version: number
  position: BufferAttribute
  normal: BufferAttribute
  index: BufferAttribute
}

const proxyStates = /* @__PURE__ */ new WeakMap<object, ProxyGeometryState>()

/**
 * A three.js geometry of a render proxy as it is now: `position`, `normal`, `uv` and the index are
 * the proxy's own arrays (`updateRenderProxy` rewrites them in place, so nothing is copied), with
 * bounds set. Call updateProxyGeometry after each step.
 *
 * @param world A bitECS world with the cloth plugin installed.
 * @param proxy A render proxy of a cloth of that world (createRenderProxy).
 */
export function createProxyGeometry(world: object, proxy: ClothRenderProxy): ClothGeometry {
  const mesh = updateRenderProxy(checkWorld(world), proxy)
  const geometry = new BufferGeometry<ClothGeometryAttributes>()
  geometry.name = 'cloth proxy'
  const position = new BufferAttribute(mesh.positions, 3).setUsage(DynamicDrawUsage)
  const normal = new BufferAttribute(mesh.normals, 3).setUsage(DynamicDrawUsage)
  const index = new BufferAttribute(mesh.indices, 1)
  geometry.setAttribute('position', position)
  geometry.setAttribute('normal', normal)
  geometry.setAttribute('uv', new BufferAttribute(mesh.uvs, 2))
  geometry.setIndex(index)
  const version = getClothState(world, proxy.cloth).version
  proxyStates.set(geometry, { proxy, indexVersion: mesh.indexVersion, version, position, normal, index })
  fitBounds(geometry, mesh.positions, mesh.vertexCount, null)
  return geometry
}

/**
 * Brings a geometry made by createProxyGeometry up to date: moves the proxy with its cloth
 * (`updateRenderProxy`), flags positions and normals for upload, the index too when a tear hid
 * render triangles, and refits the bounds. Allocates nothing.
 *
 * @param world A bitECS world with the cloth plugin installed.
 * @param proxy The render proxy the geometry was made for.
 * @param geometry A geometry made by createProxyGeometry (or the `geometry` of createProxyMesh).
 * @returns The same geometry.
 */
export function updateProxyGeometry(world: object, proxy: ClothRenderProxy, geometry: BufferGeometry): ClothGeometry {
  checkWorld(world)
  const state = proxyStates.get(geometry)
  if (state === undefined) throw new ClothError('geometry', geometry, 'must be a geometry made by createProxyGeometry')
  if (state.proxy !== proxy) throw new ClothError('geometry', geometry, 'was made for another render proxy')
  const mesh = updateRenderProxy(world, proxy)
  const clothGeometry = geometry as ClothGeometry // it is: createProxyGeometry made it
  const version = getClothState(world, proxy.cloth).version
  if (version === state.version) return clothGeometry
  state.version = version
  state.position.needsUpdate = true
  state.normal.needsUpdate = true
  if (mesh.indexVersion !== state.indexVersion) {
    state.indexVersion = mesh.indexVersion
    state.index.needsUpdate = true
  }
  fitBounds(clothGeometry, mesh.positions, mesh.vertexCount, null)
  return clothGeometry
}

/**
 * A three.js mesh of a render proxy: createProxyGeometry with `material`, by default a
 * double-sided MeshStandardMaterial. Update it with `updateProxyGeometry(world, proxy, mesh.geometry)`
 * after each step.
 *
 * @param world A bitECS world with the cloth plugin installed.
 * @param proxy A render proxy of a cloth of that world.
 * @param material Any three.js material.
 */
export function createProxyMesh<M extends Material = MeshStandardMaterial>(
  world: object,
  proxy: ClothRenderProxy,
  material?: M,
): Mesh<ClothGeometry, M> {
  checkWorld(world)
  checkMaterial(material)
  const mesh = new Mesh(createProxyGeometry(world, proxy), material ?? (new MeshStandardMaterial({ side: DoubleSide }) as unknown as M))
  mesh.name = 'cloth proxy'
  return mesh
}

/**
 * Puts a cloth's mesh (or its proxy's) where the cloth's character is now: sets `object.matrix` to
 * `getClothDrawTransform` (the anchor's rigid motion since the step the mesh shows) and turns its
 * `matrixAutoUpdate` off. Call it each frame after the geometry update, on an object whose parent
 * has no transform of its own (cloth positions are world positions). On displays faster than the
 * 60 Hz step, with uneven frame times or a pipelined frame, the pinned edge then stays on its
 * character every frame. Pieces torn off that nothing carries are written into the geometry of
 * createClothGeometry moved back by the matrix, so they stay where they lie.
 *
 * @param world A bitECS world with the cloth plugin installed.
 * @param cloth A cloth entity of that world.
 * @param object The three.js object drawing it (the mesh of createClothMesh or createProxyMesh).
 */
export function updateClothDrawMatrix(world: object, cloth: number, object: Object3D): Object3D {
  checkWorld(world)
  if (typeof object !== 'object' || object === null || !(object as { isObject3D?: boolean }).isObject3D) {
    throw new ClothError('object', object, 'must be a three.js Object3D')
  }
  object.matrixAutoUpdate = false
  getClothDrawTransform(world, cloth, object.matrix.elements)
  object.matrixWorldNeedsUpdate = true
  holdLoosePieces(world, cloth, object)
  return object
}

/**
 * The draw matrix carries the cloth with its anchor; pieces torn off that nothing carries (the
 * cloth's `detached` particles, which teleports and thaws leave where they are too) are written
 * into a geometry of createClothGeometry moved back by it, so they are drawn where they lie (a rag
 * on the ground was drawn following the character, 61 mm at 144 Hz and 6 m for a hidden cape). A
 * piece a hand holds is left to the matrix, as before: the hand is most often the character's own
 * (written back, a rag carried in the character's hand was drawn 31 mm behind it on average).
 * Nothing to do for a cloth in one piece.
 */
function holdLoosePieces(world: object, cloth: number, object: Object3D): void {
  const geometry = (object as Partial<Mesh>).geometry
  const state = geometry === undefined ? undefined : states.get(geometry)
  if (state === undefined) return
  const c = getClothState(world, cloth)
  const list = c.detached
  if (state.clothState !== c || list[0] === 0) return
  const m = object.matrix.elements // rigid: x = R·l + t, so l = Rᵀ·(x − t), and normals Rᵀ·n
  const mesh = getClothMesh(world, cloth)
  const to = state.position.array as Float32Array, normals = state.normal.array as Float32Array
  const held = heldPieces(c)
  for (let q = 1; q <= list[0]; q++) {
    const j = 3 * list[q]
    if (held !== null && held[c.piece![list[q]]] === 1) {
      for (let a = 0; a < 3; a++) {
        to[j + a] = mesh.positions[j + a]
        normals[j + a] = mesh.normals[j + a]
      }
      continue
    }
    const x = mesh.positions[j] - m[12], y = mesh.positions[j + 1] - m[13], z = mesh.positions[j + 2] - m[14]
    to[j] = m[0] * x + m[1] * y + m[2] * z
    to[j + 1] = m[4] * x + m[5] * y + m[6] * z
    to[j + 2] = m[8] * x + m[9] * y + m[10] * z
    const nx = mesh.normals[j], ny = mesh.normals[j + 1], nz = mesh.normals[j + 2]
    normals[j] = m[0] * nx + m[1] * ny + m[2] * nz
    normals[j + 1] = m[4] * nx + m[5] * ny + m[6] * nz
    normals[j + 2] = m[8] * nx + m[9] * ny + m[10] * nz
  }
  state.position.needsUpdate = true
  state.normal.needsUpdate = true
  fitBounds(geometry as ClothGeometry, to, mesh.vertexCount, c.topology.unused)
}

/** Scratch of `heldPieces`: a mark per piece. */
let heldMarks = new Uint8Array(0)

/** The cloth's pieces a grab holds, marked 1 in a scratch by piece label, or null when none is. */
function heldPieces(c: ReturnType<typeof getClothState>): Uint8Array | null {
  const G = c.grab
  if (G.count === 0 || c.piece === null) return null
  if (heldMarks.length < c.pieceCount) heldMarks = new Uint8Array(Math.max(c.pieceCount, 2 * heldMarks.length))
  heldMarks.fill(0, 0, c.pieceCount)
  for (let g = 0; g < G.count; g++) heldMarks[c.piece[G.particle[g]]] = 1
  return heldMarks
}
