import { writeRenderMesh } from './kernels/mesh'
import { checkStepFinished, getCloth, getClothWorld } from './world/access'
import type { ClothMesh, ClothRender, ClothState } from './world/state'

/**
 * The cloth's render mesh: float32 positions, unit normals and texture coordinates per live
 * particle and the triangle indices, as views sized to the live counts. The same arrays come back every call (refreshed when
 * the cloth moved), so uploading them each frame allocates nothing.
 */
export function getClothMesh(world: object, cloth: number): ClothMesh {
  const state = getClothWorld(world)
  const c = getCloth(state, cloth)
  const triCount = c.topology.triangleCount
  const r = c.render
  let mesh = r.mesh
  if (!mesh || mesh.vertexCount !== c.count || mesh.triangleCount !== triCount || mesh.positions.buffer !== r.positions.buffer) {
    mesh = r.mesh = {
      positions: r.positions.subarray(0, 3 * c.count),
      normals: r.normals.subarray(0, 3 * c.count),
      uvs: r.uvs.subarray(0, 2 * c.count),
      indices: r.indices.subarray(0, 3 * triCount),
      vertexCount: c.count,
      triangleCount: triCount,
    }
    r.version = -1
  }
  // between beginClothStep and endClothStep the workers may be writing the positions: only a mesh
  // read since the last finished step can be handed out
  if (r.version !== c.version) checkStepFinished(state, world, cloth)
  refreshClothRender(c)
  return mesh
}

/** The cloth's render buffers, rewritten from its particles if they moved since the last time. */
export function refreshClothRender(c: ClothState): ClothRender {
  const r = c.render
  if (r.version !== c.version) {
    writeRenderMesh(c.pos, c.count, r.indices, c.topology.triangleCount, r.positions, r.normals)
    r.version = c.version
  }
  return r
}
