/**
 * Collider shape codes and the convex-hull geometry type: shared by the collider store, the
 * collision kernels and the hull builder.
 */

/** Collider shapes (`Collider.shape`). */
export const SHAPE_SPHERE = 0
export const SHAPE_CAPSULE = 1
export const SHAPE_BOX = 2
export const SHAPE_HULL = 3
export const SHAPE_PLANE = 4

/** Planes and geometry of a convex-hull collider, in the collider's local frame. */
export interface ConvexHull {
  /** n·x ≤ d inside: nx ny nz d per plane (stride 4), unit normals pointing out. */
  planes: Float64Array
  planeCount: number
  /** Hull vertices, xyz (stride 3). */
  vertices: Float64Array
  /** Outward-facing triangles over `vertices` (for drawing). */
  indices: Uint32Array
}
