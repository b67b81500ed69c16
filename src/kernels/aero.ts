/**
 * Per-triangle aerodynamics (flat-plate model, two-sided). For a triangle of area A with unit normal
 * n̂ and air velocity relative to it w = ū − v̄ (mean air velocity at its corners minus its mean
 * velocity):
 *
 *   drag     = ½ρ·C_d·A·|w|·(w·n̂)·n̂                     along the normal, ∝ |w|² cos θ
 *   lift     = ½ρ·C_l·A·|w|·(w·n̂)·(1 − (n̂·ŵ)²)·n̂        along the normal, ∝ |w|² cos θ sin² θ
 *   friction = ρ·C_f·A·|w|·w_t                           along the surface (both faces, C_f = 0.01)
 *
 * (θ the angle between the wind and the normal.) Air pushes on a flat plate through pressure,
 * normal to it, and drags along it by skin friction: cloth has sharp edges, where the flow
 * separates, so there is no leading-edge suction to pull it upwind along its plane. The lift term
 * is the extra normal force of flow that stays attached at grazing incidence: near θ = 90° (a flag
 * streaming) the normal force rises as (C_d + C_l)·cos θ, head on it is C_d's alone. (It was the
 * part of ½ρ·C_l·A·|w|·(w·n̂)·(n̂ − (n̂·ŵ)ŵ) across the wind: added to the normal drag, its part in
 * the plane pulled a free sheet upwind along it, 0.15 of its downwind speed at θ = 60°.)
 * Drag and lift are even in n̂ (the cloth has no front or back for the air) and vanish when the
 * wind runs along the surface, where only the small skin friction acts. With N = 2A·n̂ and
 * k = ρ|w|(w·N)/(4|N|), they sum to k·[C_d + C_l·(1 − (w·N)²/(|w|²|N|²))]·N.
 *
 * The orientation n̂ is not the triangle's own but a smoothed one: its corners' area-weighted
 * vertex normals after one more averaging pass over the mesh edges (`aeroNormals`). Air pressure
 * on a wavy sheet responds to its shape over a patch, not per triangle; a purely local flat-plate
 * model pumps energy into the shortest waves the mesh can carry (a 1.5 m nylon flag at 10 m/s
 * buzzed at 21 Hz with waves 5 cells long, 12 → 28 Hz as the mesh went from 12 to 48 columns).
 * With the smoothed normal the waves are about twice as long and half as fast, like a flag's.
 * The area stays the triangle's own.
 *
 * Each corner takes a third of the triangle's force, the force on its third of the area, and turns
 * it into acceleration with its own mass: a_i += (F/3)·w_i. Masses are lumped the same way (a
 * third of each triangle's mass to each corner), so uniform air on a uniform sheet accelerates
 * every particle alike, however many triangles meet at it; a uniform force at the three corners
 * has no moment about the triangle's centroid. (Giving all three corners the same acceleration
 * F/(m_a + m_b + m_c) instead pushed a particle touching 4 triangles 0.6× and one touching 8 1.2×
 * as hard as the air does: a checkerboard of pushes on a flag.)
 */

/**
 * Skin-friction coefficient per face (turbulent flat plate, Re ≈ 10⁵–10⁶). Small, but it is what
 * streams a flag out along the wind when it lies flat in it, where drag and lift vanish.
 */
export const SKIN_FRICTION = 0.01

/** Parameter slots of the aerodynamics kernels (a per-cloth block). */
/** Substep length h, s. */
export const A_H = 0
/** Drag coefficient C_d. */
export const A_DRAG = 1
/** Lift coefficient C_l. */
export const A_LIFT = 2
/** Stride of the air array: 4 (per particle) or 0 (one uniform air state in air[0..3]). */
export const A_STRIDE = 3
/** The world's particle speed limit, m/s: air faster than this drags particles only up to it. */
export const A_MAX_SPEED = 4
export const AERO_PARAM_COUNT = 5

/**
 * Smoothed normals for the aerodynamics into `out` (xyz per particle, unnormalised): the
 * area-weighted vertex normals of particles [0, count), then one pass adding each vertex's
 * neighbours (over the mesh edges) to it. `tmp` is scratch of the same size.
 */
export function aeroNormals(
  pos: Float64Array,
  count: number,
  tris: Uint32Array,
  triCount: number,
  edges: Int32Array,
  edgeCount: number,
  out: Float64Array,
  tmp: Float64Array,
): void {
  tmp.fill(0, 0, 3 * count)
  for (let t = 0; t < triCount; t++) {
    const a = 3 * tris[3 * t], b = 3 * tris[3 * t + 1], c = 3 * tris[3 * t + 2]
    const ax = pos[a], ay = pos[a + 1], az = pos[a + 2]
    const ux = pos[b] - ax, uy = pos[b + 1] - ay, uz = pos[b + 2] - az
    const vx = pos[c] - ax, vy = pos[c + 1] - ay, vz = pos[c + 2] - az
    const nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx
    tmp[a] += nx
    tmp[a + 1] += ny
    tmp[a + 2] += nz
    tmp[b] += nx
    tmp[b + 1] += ny
    tmp[b + 2] += nz
    tmp[c] += nx
    tmp[c + 1] += ny
    tmp[c + 2] += nz
  }
  for (let j = 0; j < 3 * count; j++) out[j] = tmp[j]
  for (let e = 0; e < edgeCount; e++) {
    const a = 3 * edges[2 * e], b = 3 * edges[2 * e + 1]
    out[a] += tmp[b]
    out[a + 1] += tmp[b + 1]
    out[a + 2] += tmp[b + 2]
    out[b] += tmp[a]
    out[b + 1] += tmp[a + 1]
    out[b + 2] += tmp[a + 2]
  }
}

/**
 * Adds the aerodynamic acceleration of triangles [0, triCount) to `accel` (xyz per particle; the
 * caller zeroes it). `air` holds ux uy uz ρ per particle (stride 4) or once (stride 0); `normals`
 * are the smoothed normals from `aeroNormals`; `invMass` the particles' inverse masses without
 * pins (a pinned particle's acceleration is never integrated).
 */
export function accumulateAerodynamics(
  pos: Float64Array,
  vel: Float64Array,
  tris: Uint32Array,
  triCount: number,
  invMass: Float64Array,
  air: Float64Array,
  normals: Float64Array,
  accel: Float64Array,
  params: Float64Array,
): void {
  const cd = params[A_DRAG], cl = params[A_LIFT]
  const cdl = cd + cl
  const stride = params[A_STRIDE] | 0
  for (let t = 0; t < triCount; t++) {
    const ia = tris[3 * t], ib = tris[3 * t + 1], ic = tris[3 * t + 2]
    const a = 3 * ia, b = 3 * ib, c = 3 * ic
    const ax = pos[a], ay = pos[a + 1], az = pos[a + 2]
    const ux = pos[b] - ax, uy = pos[b + 1] - ay, uz = pos[b + 2] - az
    const vx = pos[c] - ax, vy = pos[c + 1] - ay, vz = pos[c + 2] - az
    const ox = uy * vz - uz * vy, oy = uz * vx - ux * vz, oz = ux * vy - uy * vx
    const n2 = ox * ox + oy * oy + oz * oz
    // the smoothed orientation, scaled to this triangle's |N| = 2A
    const sx = normals[a] + normals[b] + normals[c]
    const sy = normals[a + 1] + normals[b + 1] + normals[c + 1]
    const sz = normals[a + 2] + normals[b + 2] + normals[c + 2]
    const s2 = sx * sx + sy * sy + sz * sz
    if (n2 < 1e-30 || !(s2 > 1e-24 * n2)) continue // degenerate, or folded layers shielding each other
    const nl = Math.sqrt(n2)
    const f = nl / Math.sqrt(s2)
    const nx = sx * f, ny = sy * f, nz = sz * f
    const ka = stride * ia, kb = stride * ib, kc = stride * ic
    const third = 1 / 3
    const wx = (air[ka] + air[kb] + air[kc] - vel[a] - vel[b] - vel[c]) * third
    const wy = (air[ka + 1] + air[kb + 1] + air[kc + 1] - vel[a + 1] - vel[b + 1] - vel[c + 1]) * third
    const wz = (air[ka + 2] + air[kb + 2] + air[kc + 2] - vel[a + 2] - vel[b + 2] - vel[c + 2]) * third
    const rho = (air[ka + 3] + air[kb + 3] + air[kc + 3]) * third
    const wn = wx * nx + wy * ny + wz * nz
    const w2 = wx * wx + wy * wy + wz * wz
    if (w2 < 1e-18) continue
    const wl = Math.sqrt(w2)
    // a third of the force per corner
    const k = (rho * wl * wn) / (12 * nl)
    // skin friction on both faces: ρ·C_f·A·|w|·w_t with w_t = w − (w·N)N/|N|², A = |N|/2
    const kf = (SKIN_FRICTION * rho * wl * nl) / 6
    const fn = k * (cdl - (cl * wn * wn) / (w2 * n2)) - (kf * wn) / n2
    const fw = kf
    const gx = fn * nx + fw * wx, gy = fn * ny + fw * wy, gz = fn * nz + fw * wz
    const ma = invMass[ia], mb = invMass[ib], mc = invMass[ic]
    accel[a] += gx * ma
    accel[a + 1] += gy * ma
    accel[a + 2] += gz * ma
    accel[b] += gx * mb
    accel[b + 1] += gy * mb
    accel[b + 2] += gz * mb
    accel[c] += gx * mc
    accel[c + 1] += gy * mc
    accel[c + 2] += gz * mc
  }
}

/**
 * The stability clamp, per free particle, after the triangle pass. An explicit quadratic drag
 * overshoots once h·|a| exceeds the relative air speed it acts on (it would push the cloth past the
 * air's velocity, then back harder: the instability that makes strong wind blow cloth up). So the
 * substep's velocity change along the force, h·|a|, is limited to the air's velocity relative to the
 * particle along that direction, r·â (r = u − v): when h·|a|² > r·a, a is scaled by r·a / (h·|a|²),
 * which brings the relative velocity along the force to zero in one substep and no further: the
 * limit an implicit (backward Euler) drag approaches for very stiff drag. Below the limit the force
 * is untouched. A force that points against the relative air motion (r·a ≤ 0, possible only from
 * neighbouring triangles' lift) is dropped. Air faster than the world's particle speed limit
 * counts as moving at that limit, so wind never pushes a particle past it. No square root below
 * the speed limit.
 */
export function limitAerodynamics(
  vel: Float64Array,
  invMass: Float64Array,
  air: Float64Array,
  accel: Float64Array,
  params: Float64Array,
  count: number,
): void {
  const h = params[A_H]
  const stride = params[A_STRIDE] | 0
  const vmax = params[A_MAX_SPEED]
  const vmax2 = vmax * vmax
  for (let i = 0; i < count; i++) {
    if (invMass[i] === 0) continue
    const j = 3 * i
    const ax = accel[j], ay = accel[j + 1], az = accel[j + 2]
    const aa = ax * ax + ay * ay + az * az
    if (aa === 0) continue
    const k = stride * i
    let ux = air[k], uy = air[k + 1], uz = air[k + 2]
    const u2 = ux * ux + uy * uy + uz * uz
    if (u2 > vmax2) {
      const f = vmax / Math.sqrt(u2)
      ux *= f
      uy *= f
      uz *= f
    }
    const ra = (ux - vel[j]) * ax + (uy - vel[j + 1]) * ay + (uz - vel[j + 2]) * az
    const haa = h * aa
    if (haa <= ra) continue
    const s = ra > 0 ? ra / haa : 0
    accel[j] = ax * s
    accel[j + 1] = ay * s
    accel[j + 2] = az * s
  }
}
