import { SHAPE_BOX, SHAPE_CAPSULE, SHAPE_HULL, SHAPE_PLANE, SHAPE_SPHERE } from '../core/shapes'

/**
 * The collider frame block the contact kernels read (Float64Array, slots below: the collider's
 * world pose at the start and end of the substep, thickness, friction, the shape's dimensions),
 * the scratch block they write, and the two shape queries every contact kernel asks: the closest
 * point on a shape to a local point, and whether a local segment passes within the thickness.
 */
/** Collider position at the start of the substep (3). */
export const F_PS = 0
/** Collider rotation at the start (9, row-major). */
export const F_RS = 3
/** Collider position at the end of the substep (3). */
export const F_PE = 12
/** Collider rotation at the end (9). */
export const F_RE = 15
/** Rs·Reᵀ (9): maps a point attached to the collider from its end pose back to its start pose. */
export const F_M = 24
/** Cloth thickness (particle radius), m. */
export const F_RADIUS = 33
/**
 * Squared particle displacement (m²) up to which the closest-point test cannot miss the shape this
 * substep; a particle that moved farther takes the swept test. −1: every particle is swept; Infinity: never.
 */
export const F_LIM2 = 34
/** Static and kinetic friction coefficients of the contact. */
export const F_MU_S = 35
export const F_MU_K = 36
/** Shape dimensions (4): see `ColliderStore.size`. */
export const F_S0 = 37
/** Plane colliders: world normal at the end of the substep (3) and plane constant n·x (1). */
export const F_PN = 41
export const F_PC = 44
/** Local bounding sphere of the shape: centre (3) and radius (1). */
export const F_BC = 45
/**
 * The bounding sphere's world centre at the end of the substep (3), and how near a particle must
 * end to it to be touched this substep (1): its radius + the thickness + the most any point of the
 * shape moved (Infinity: no bound).
 */
export const F_SW = 49
export const F_SWR = 52
export const FRAME_SIZE = 53

/** Length of the scratch block the kernels use. */
export const COLLIDE_SCRATCH = 32
// scratch slots: local point (0-2), closest point (3-5), local normal (6-8), signed distance (9),
// world normal (10-12), push-out depth (13), swept segment start (14-16) and end (17-19),
// candidates of the capsule segment test (20-26)

/**
 * Closest point on the shape's surface to the local point s[0..2]: writes the point (s[3..5]), the
 * outward unit normal (s[6..8]) and the signed distance (s[9], negative inside). For hulls the
 * distance is the largest face-plane distance (exact inside; outside near an edge it underestimates,
 * so a particle is pushed to the sharp, plane-offset hull: never less than the thickness away).
 * One long function on purpose: every shape's query in one place, so the contact kernels, which
 * call it per particle, keep one call site for all shapes.
 */
export function closestPoint(shape: number, f: Float64Array, planes: Float64Array | null, planeCount: number, s: Float64Array): void {
  const lx = s[0], ly = s[1], lz = s[2]
  if (shape === SHAPE_SPHERE || shape === SHAPE_CAPSULE) {
    const R = f[F_S0]
    let t = 0
    if (shape === SHAPE_CAPSULE) {
      const hh = f[F_S0 + 1]
      t = ly < -hh ? -hh : ly > hh ? hh : ly
    }
    const vx = lx, vy = ly - t, vz = lz
    const len = Math.sqrt(vx * vx + vy * vy + vz * vz)
    let nx = 0, ny = 1, nz = 0
    if (len > 1e-12) {
      nx = vx / len
      ny = vy / len
      nz = vz / len
    } else if (shape === SHAPE_CAPSULE) {
      nx = 1
      ny = 0
    }
    s[3] = nx * R
    s[4] = t + ny * R
    s[5] = nz * R
    s[6] = nx
    s[7] = ny
    s[8] = nz
    s[9] = len - R
    return
  }
  if (shape === SHAPE_BOX) {
    const hx = f[F_S0], hy = f[F_S0 + 1], hz = f[F_S0 + 2]
    const qx = lx < -hx ? -hx : lx > hx ? hx : lx
    const qy = ly < -hy ? -hy : ly > hy ? hy : ly
    const qz = lz < -hz ? -hz : lz > hz ? hz : lz
    const ex = lx - qx, ey = ly - qy, ez = lz - qz
    const e2 = ex * ex + ey * ey + ez * ez
    if (e2 > 0) {
      const d = Math.sqrt(e2)
      s[3] = qx
      s[4] = qy
      s[5] = qz
      s[6] = ex / d
      s[7] = ey / d
      s[8] = ez / d
      s[9] = d
      return
    }
    // inside: the nearest face
    const dx = hx - Math.abs(lx), dy = hy - Math.abs(ly), dz = hz - Math.abs(lz)
    s[3] = lx
    s[4] = ly
    s[5] = lz
    s[6] = 0
    s[7] = 0
    s[8] = 0
    if (dx <= dy && dx <= dz) {
      const sg = lx < 0 ? -1 : 1
      s[3] = sg * hx
      s[6] = sg
      s[9] = -dx
    } else if (dy <= dz) {
      const sg = ly < 0 ? -1 : 1
      s[4] = sg * hy
      s[7] = sg
      s[9] = -dy
    } else {
      const sg = lz < 0 ? -1 : 1
      s[5] = sg * hz
      s[8] = sg
      s[9] = -dz
    }
    return
  }
  let nx = 0, ny = 1, nz = 0, d = 0
  if (shape === SHAPE_HULL && planes !== null) {
    d = -Infinity
    for (let k = 0; k < planeCount; k++) {
      const o = 4 * k
      const dk = planes[o] * lx + planes[o + 1] * ly + planes[o + 2] * lz - planes[o + 3]
      if (dk > d) {
        d = dk
        nx = planes[o]
        ny = planes[o + 1]
        nz = planes[o + 2]
      }
    }
  } else if (shape === SHAPE_PLANE) {
    nx = f[F_S0]
    ny = f[F_S0 + 1]
    nz = f[F_S0 + 2]
    d = nx * lx + ny * ly + nz * lz - f[F_S0 + 3]
  }
  s[3] = lx - nx * d
  s[4] = ly - ny * d
  s[5] = lz - nz * d
  s[6] = nx
  s[7] = ny
  s[8] = nz
  s[9] = d
}

/**
 * Whether the local segment s[14..16] → s[17..19] passes within the thickness of the shape
 * (boxes and hulls with their faces moved out by the thickness, so sharp-cornered: conservative).
 * Returns 1 or 0.
 */
export function segmentHits(shape: number, f: Float64Array, planes: Float64Array | null, planeCount: number, s: Float64Array): number {
  const ax = s[14], ay = s[15], az = s[16]
  const mx = s[17] - ax, my = s[18] - ay, mz = s[19] - az
  const r = f[F_RADIUS]
  const m2 = mx * mx + my * my + mz * mz
  if (shape === SHAPE_SPHERE || shape === SHAPE_CAPSULE) {
    const R = f[F_S0] + r
    const hh = shape === SHAPE_CAPSULE ? f[F_S0 + 1] : 0
    // squared distance from a + S·m to the core segment (0, [−hh, hh], 0) is convex and piecewise
    // quadratic in S: its minimum over [0, 1] is at an end, a piece's stationary point or a breakpoint
    const mxz = mx * mx + mz * mz
    s[20] = 0
    s[21] = 1
    s[22] = mxz > 1e-24 ? -(ax * mx + az * mz) / mxz : 0
    s[23] = m2 > 1e-24 ? -(ax * mx + (ay - hh) * my + az * mz) / m2 : 0
    s[24] = m2 > 1e-24 ? -(ax * mx + (ay + hh) * my + az * mz) / m2 : 0
    s[25] = my * my > 1e-24 ? (hh - ay) / my : 0
    s[26] = my * my > 1e-24 ? (-hh - ay) / my : 0
    let best = Infinity
    for (let k = 20; k <= 26; k++) {
      let S = s[k]
      S = S < 0 ? 0 : S > 1 ? 1 : S
      const y = ay + my * S
      const dy = y < -hh ? y + hh : y > hh ? y - hh : 0
      const dx = ax + mx * S, dz = az + mz * S
      const d2 = dx * dx + dy * dy + dz * dz
      if (d2 < best) best = d2
    }
    return best < R * R ? 1 : 0
  }
  let t0 = 0, t1 = 1
  if (shape === SHAPE_BOX) {
    for (let k = 0; k < 3; k++) {
      const H = f[F_S0 + k] + r
      const a = s[14 + k], m = s[17 + k] - a
      if (m * m < 1e-24) {
        if (a < -H || a > H) return 0
        continue
      }
      let e0 = (-H - a) / m, e1 = (H - a) / m
      if (e0 > e1) {
        const tmp = e0
        e0 = e1
        e1 = tmp
      }
      if (e0 > t0) t0 = e0
      if (e1 < t1) t1 = e1
      if (t0 > t1) return 0
    }
    return 1
  }
  if (shape === SHAPE_HULL && planes !== null) {
    for (let k = 0; k < planeCount; k++) {
      const o = 4 * k
      const da = planes[o] * ax + planes[o + 1] * ay + planes[o + 2] * az - planes[o + 3] - r
      const db = planes[o] * s[17] + planes[o + 1] * s[18] + planes[o + 2] * s[19] - planes[o + 3] - r
      if (da > 0 && db > 0) return 0
      if (da > 0) {
        const t = da / (da - db)
        if (t > t0) t0 = t
      } else if (db > 0) {
        const t = da / (da - db)
        if (t < t1) t1 = t
      }
      if (t0 > t1) return 0
    }
    return 1
  }
  return 0
}
