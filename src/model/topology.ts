/** Kinds of two-particle distance constraints (stored per constraint in `distKind`). */
export const STRETCH = 0
export const SHEAR = 1
export const BEND = 2

/**
 * How bending is modelled. 'line' (default): three-particle constraints along rows and columns
 * (any two nearly opposite edges at a vertex on a mesh), first-order in a kink, so grid-scale
 * wrinkles are resisted. 'distance': skip-one springs (grids) or cross-edge springs (meshes), the
 * cheapest, blind to small zigzags. 'dihedral': hinge angles, the most accurate and the most
 * expensive, needed for one-sided bending and curved rest shapes. 'both': distance + dihedral.
 */
export type BendingModel = 'line' | 'distance' | 'dihedral' | 'both' | 'none'
/** How shear diagonals act: two-sided distance, compression-only (unilateral), or not at all. */
export type ShearModel = 'distance' | 'compression' | 'none'
/**
 * Which folds a dihedral hinge resists. 'both' is the usual two-sided spring; 'front' resists only
 * folds that close the front faces (the side triangle normals point to) onto each other and lets
 * the cloth fold the other way freely; 'back' is the mirror.
 */
export type BendSide = 'both' | 'front' | 'back'

/**
 * Rest data of a cloth: mesh, masses and constraints, built once and read-only afterwards, so
 * several cloth instances can share it. Constraint arrays are in solver order (see `orderPairs`).
 *
 * Hinge layout (`hingeIds`, 4 per hinge):
 * ```
 *        w0            triangle A = (e0, e1, w0)
 *       /  \           triangle B = (e1, e0, w1)
 *     e0 ---- e1       the angle is 0 when flat, signed by the fold direction
 *       \  /
 *        w1
 * ```
 */
export interface ClothTopology {
  /** Number of particles. (Counts here are kept small integers, `| 0` where they come from a division.) */
  readonly particleCount: number
  /** Rest positions, xyz interleaved, m. */
  readonly restPositions: Float64Array
  /**
   * Particle masses, kg (area-weighted from the material density, clamped against tiny triangles);
   * 0 for vertices no triangle uses.
   */
  readonly masses: Float64Array
  /**
   * 1 for each vertex no triangle uses (common in exported meshes), null when every vertex is used.
   * Such a vertex is no part of the cloth: it keeps its place (inverse mass 0, never integrated),
   * has no constraints, collides with nothing, and is left out of every bounds, the guard's, the
   * sleep test's and the budget's. Rigid moves of the whole cloth (teleports) carry it along.
   */
  readonly unused: Uint8Array | null
  /**
   * Connected piece of each vertex (numbered from 0 in vertex order; unused vertices count as piece
   * 0), or null when the triangles form one piece. A mesh of several pieces (a cape and a separate
   * tassel) has its guard bounds measured per piece, like a torn cloth.
   */
  readonly pieces: Int32Array | null
  readonly pieceCount: number
  /** Triangle vertex indices, 3 per triangle, counter-clockwise seen from the front. */
  readonly triangles: Uint32Array
  readonly triangleCount: number
  /** Unique mesh edges, 2 indices per edge (what is rendered, measured for stretch and torn). */
  readonly edges: Int32Array
  /** Rest length of each mesh edge, m. */
  readonly edgeRest: Float64Array
  readonly edgeCount: number

  /** The structural (STRETCH) pairs again, for measuring stretch: 2 indices each. */
  readonly stretchIds: Int32Array
  readonly stretchRest: Float64Array
  readonly stretchCount: number

  /**
   * Two-sided distance constraints, in solver order: 2 position offsets each, the particle index
   * × 3 (where its x sits in `pos`), so the solver's hot loop indexes positions without a
   * multiply. Divide by 3 for the particle index.
   */
  readonly distOffsets: Int32Array
  /** Rest length, m. */
  readonly distRest: Float64Array
  /** Compliance, m/N (0 = rigid). */
  readonly distCompliance: Float64Array
  /** STRETCH, SHEAR or BEND. */
  readonly distKind: Uint8Array
  readonly distCount: number

  /** Compression-only distance constraints (act only when shorter than rest). */
  readonly compIds: Int32Array
  readonly compRest: Float64Array
  readonly compCompliance: Float64Array
  readonly compCount: number

  /** Line-bending triples: x0, x1 (middle), x2 per triple, in solver order. */
  readonly lineIds: Int32Array
  /** Rest distance of the middle particle from its neighbours' midpoint, m (0 on flat cloth). */
  readonly lineRest: Float64Array
  /** Compliance, m/N. */
  readonly lineCompliance: Float64Array
  readonly lineCount: number

  /** Dihedral hinges: e0, e1, w0, w1 per hinge (diagram above). */
  readonly hingeIds: Int32Array
  /** Rest dihedral angle, rad. */
  readonly hingeRest: Float64Array
  /** Compliance, rad/(N·m) per hinge. */
  readonly hingeCompliance: Float64Array
  readonly hingeCount: number
  /** +1: resist only positive fold error (folds toward the back), −1: only negative (toward the front), 0: both. */
  readonly hingeSide: number

  /** Grid shape when built by the grid builder (row-major, row 0 at the top), else 0. */
  readonly columns: number
  readonly rows: number
}

/** Options shared by the grid and mesh builders. */
export interface TopologyOptions {
  bending?: BendingModel
  shear?: ShearModel
  bendSide?: BendSide
  /**
   * Particles the solve order starts from (usually where the cloth will be pinned). Constraints
   * are swept outward from them, which is what makes Gauss-Seidel converge fast for hanging cloth.
   * Default: from the top (highest rest y) down.
   */
  orderFrom?: ArrayLike<number>
}

/** Signed dihedral angle of a hinge, rad, 0 when flat. Same convention as the dihedral kernel. */
export function dihedralAngle(p: ArrayLike<number>, e0: number, e1: number, w0: number, w1: number): number {
  const ex = p[3 * e1] - p[3 * e0], ey = p[3 * e1 + 1] - p[3 * e0 + 1], ez = p[3 * e1 + 2] - p[3 * e0 + 2]
  const ax = p[3 * w0] - p[3 * e0], ay = p[3 * w0 + 1] - p[3 * e0 + 1], az = p[3 * w0 + 2] - p[3 * e0 + 2]
  const bx = p[3 * w1] - p[3 * e0], by = p[3 * w1 + 1] - p[3 * e0 + 1], bz = p[3 * w1 + 2] - p[3 * e0 + 2]
  // nA = e × a, nB = b × e
  const nAx = ey * az - ez * ay, nAy = ez * ax - ex * az, nAz = ex * ay - ey * ax
  const nBx = by * ez - bz * ey, nBy = bz * ex - bx * ez, nBz = bx * ey - by * ex
  const el = Math.sqrt(ex * ex + ey * ey + ez * ez)
  if (el < 1e-12) return 0
  const cx = nAy * nBz - nAz * nBy, cy = nAz * nBx - nAx * nBz, cz = nAx * nBy - nAy * nBx
  return Math.atan2((cx * ex + cy * ey + cz * ez) / el, nAx * nBx + nAy * nBy + nAz * nBz)
}
