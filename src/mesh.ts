import { ClothError } from './core/errors'
import { writeRenderMesh } from './kernels/mesh'
import { getCloth, getClothWorld } from './world/access'
import type { ClothMesh, ClothRender, ClothState, ClothWorldState } from './world/state'

/**
 * The cloth's render mesh: float32 positions, unit normals and texture coordinates per live
 * particle and the triangle indices, as views sized to the live counts. The same arrays come back every call (refreshed when
 * the cloth moved), so uploading them each frame allocates nothing.
 *
 * Between `beginClothStep` and `endClothStep` it gives the mesh of the last finished step (the
 * frame's start brought it up to date, see `refreshFrameMeshes`), in every mode; a cloth whose mesh
 * was never read before the frame began has none to give then (a ClothError).
 */
export function getClothMesh(world: object, cloth: number): ClothMesh {
  const state = getClothWorld(world)
  const c = getCloth(state, cloth)
  const r = c.render
  if (state.frame.open && !state.frame.delivering) {
    // the workers may be writing the particles: hand out what the step's start left
    if (r.version !== c.version) throw notReadBeforeFrame(world, cloth, 'mesh')
    return meshViews(c, false)
  }
  const mesh = meshViews(c, true)
  refreshClothRender(c)
  return mesh
}

/**
 * The cloth's mesh views, made anew when the live counts or the buffers changed (`stale`: the
 * buffers are then rewritten at the next refresh; left out while a frame runs, where the counts
 * cannot change and the buffers are those of the last finished step).
 */
function meshViews(c: ClothState, stale: boolean): ClothMesh {
  const triCount = c.topology.triangleCount
  const r = ownIndices(c)
  const mesh = r.mesh
  if (
    mesh && mesh.vertexCount === c.count && mesh.triangleCount === triCount && mesh.positions.buffer === r.positions.buffer
    && mesh.indices.buffer === r.indices.buffer
  ) return mesh
  if (stale) r.version = -1
  return r.mesh = {
    positions: r.positions.subarray(0, 3 * c.count),
    normals: r.normals.subarray(0, 3 * c.count),
    uvs: r.uvs.subarray(0, 2 * c.count),
    indices: r.indices.subarray(0, 3 * triCount),
    vertexCount: c.count,
    triangleCount: triCount,
  }
}

/**
 * The cloth's render buffers, rewritten from its particles if they moved since the last time. A
 * tearable cloth's triangles (which a worker's tear rewrites in place) are copied into buffers of
 * the render's own, so a mesh handed out during a frame never changes under the reader.
 */
export function refreshClothRender(c: ClothState): ClothRender {
  const r = ownIndices(c)
  if (r.version !== c.version) {
    const t = c.topology
    if (c.tear !== null) r.indices.set(t.triangles)
    writeRenderMesh(c.pos, c.count, r.indices, t.triangleCount, r.positions, r.normals)
    r.version = c.version
  }
  return r
}

/** A tearable cloth's render index buffer of its own (`makeTearable` shares the topology's), its contents written at the next refresh. */
function ownIndices(c: ClothState): ClothRender {
  const r = c.render
  const tris = c.topology.triangles
  if (c.tear !== null && (r.indices === tris || r.indices.length !== tris.length)) {
    r.indices = new Uint32Array(tris.length)
    r.version = -1
  }
  return r
}

/**
 * At the start of a fixed step whose finish the caller does not wait for (`beginClothStep`, and
 * `endClothStepAsync` between its steps), after the sync phase and before any worker writes a
 * particle: brings the render mesh of every cloth read before (`getClothMesh`) up to date, so that
 * reads until the step's finish give the last finished step. Only cloths whose mesh is stale cost
 * anything (read after the last step, as when drawing after `endClothStep`, they are not); no
 * allocation but a tearable cloth's first index copy.
 */
export function refreshFrameMeshes(state: ClothWorldState): void {
  const cloths = state.cloths
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    if (c.render.mesh !== null && c.render.version !== c.version) {
      meshViews(c, true)
      refreshClothRender(c)
    }
  }
}

/** The ClothError of a mesh or proxy first read between `beginClothStep` and `endClothStep`. */
export function notReadBeforeFrame(world: object, cloth: number, what: string): ClothError {
  return new ClothError(
    'world',
    world,
    `is between beginClothStep and endClothStep, and cloth ${cloth}'s ${what} was never read before this frame began, so it has no finished step to show: read it once outside a frame (as creating its three.js mesh does); from then on it can be read between the two calls`,
  )
}
