import { SHAPE_BOX, SHAPE_CAPSULE, SHAPE_HULL, SHAPE_SPHERE } from '../core/shapes'
import {
  F_BC,
  F_LIM2,
  F_M,
  F_MU_K,
  F_MU_S,
  F_PC,
  F_PE,
  F_PN,
  F_PS,
  F_RADIUS,
  F_RE,
  F_RS,
  F_S0,
  F_SW,
  F_SWR,
  closestPoint,
  segmentHits,
} from './colliderFrame'

/**
 * Particle–collider contact kernels. One call handles one cloth against one collider for one
 * substep: every free particle is pushed out to the collider's surface plus the cloth's thickness,
 * then Coulomb friction acts on its motion relative to the surface.
 *
 * Everything a kernel needs about the collider and the contact sits in a `frame` block
 * (Float64Array, slots in `colliderFrame.ts`), filled once per cloth–collider pair per substep: the collider's
 * world pose at the start and at the end of the substep (so its motion is known exactly), the
 * thickness, the combined friction and the shape's dimensions. Rotations are row-major 3×3
 * matrices: world = R·local, local = Rᵀ·(world − p).
 *
 * Why both poses:
 * - friction acts on the particle's motion relative to the surface point it touches, so a cape on
 *   a running character is carried along instead of sliding off;
 * - the push-out must not turn into velocity beyond what the contact needs. The writeback phase
 *   computes v = (x − prev)/h; pushing a particle out of a penetration it already had at the start
 *   of the substep would launch it. The part of the push-out that separates the particle from the
 *   surface faster than the surface moves is therefore applied to `prev` too (a perfectly inelastic
 *   contact: no bounce, no pop);
 * - fast relative motion (a collider at 20 m/s, a falling particle) is handled in the collider's
 *   frame: a particle that was outside the shape at the start of the substep is kept on the near
 *   side of the separating plane through its closest point at the start, so it cannot pass through
 *   the shape whatever the speed. Slow particles (the common case) take the cheaper closest-point test.
 */

/**
 * Contact response for particle j (offset 3·i) pushed along the world normal s[10..12] by s[13]:
 * moves it out, removes the separating velocity the push would add beyond the contact's needs,
 * then applies Coulomb friction to its tangential motion relative to the surface (static: the
 * relative slip is undone when it is within μs × the normal correction; kinetic: reduced by μk ×
 * the normal correction). Position-based friction after Macklin et al., "Unified particle physics
 * for real-time applications" (2014), §6.1, measured against the moving surface.
 */
export function respond(
  pos: Float64Array,
  prev: Float64Array,
  j: number,
  f: Float64Array,
  s: Float64Array,
  touched: Uint8Array | null,
): void {
  if (touched !== null) touched[(j / 3) | 0] = 1
  const nx = s[10], ny = s[11], nz = s[12], push = s[13]
  const x = pos[j] + nx * push, y = pos[j + 1] + ny * push, z = pos[j + 2] + nz * push
  // where the surface point now at x was at the start of the substep
  const rx = x - f[F_PE], ry = y - f[F_PE + 1], rz = z - f[F_PE + 2]
  const sx = f[F_PS] + f[F_M] * rx + f[F_M + 1] * ry + f[F_M + 2] * rz
  const sy = f[F_PS + 1] + f[F_M + 3] * rx + f[F_M + 4] * ry + f[F_M + 5] * rz
  const sz = f[F_PS + 2] + f[F_M + 6] * rx + f[F_M + 7] * ry + f[F_M + 8] * rz
  // the particle's motion relative to the surface this substep
  let dx = sx - prev[j], dy = sy - prev[j + 1], dz = sz - prev[j + 2]
  const dn = dx * nx + dy * ny + dz * nz
  // separating faster than the surface: that part came from an old penetration, not from this
  // substep's approach; move prev along so it does not become velocity
  const shift = dn > 0 ? (dn < push ? dn : push) : 0
  prev[j] += nx * shift
  prev[j + 1] += ny * shift
  prev[j + 2] += nz * shift
  dx -= dn * nx
  dy -= dn * ny
  dz -= dn * nz
  const t2 = dx * dx + dy * dy + dz * dz
  const load = push - shift
  const ms = f[F_MU_S] * load
  let k = 1
  if (t2 > ms * ms) {
    k = (f[F_MU_K] * load) / Math.sqrt(t2)
    if (k > 1) k = 1
  }
  pos[j] = x - dx * k
  pos[j + 1] = y - dy * k
  pos[j + 2] = z - dz * k
}

/** Contact from the local result in s[6..9] (normal, distance) if closer than the thickness; returns 1 or 0. */
function contactFromLocal(
  pos: Float64Array,
  prev: Float64Array,
  j: number,
  f: Float64Array,
  s: Float64Array,
  touched: Uint8Array | null,
): number {
  const d = s[9], r = f[F_RADIUS]
  if (d >= r) return 0
  const nx = s[6], ny = s[7], nz = s[8]
  s[10] = f[F_RE] * nx + f[F_RE + 1] * ny + f[F_RE + 2] * nz
  s[11] = f[F_RE + 3] * nx + f[F_RE + 4] * ny + f[F_RE + 5] * nz
  s[12] = f[F_RE + 6] * nx + f[F_RE + 7] * ny + f[F_RE + 8] * nz
  s[13] = r - d
  respond(pos, prev, j, f, s, touched)
  return 1
}

/** Writes particle j's current position in the collider's end frame into s[0..2]. */
function toLocalEnd(pos: Float64Array, j: number, f: Float64Array, s: Float64Array): void {
  const bx = pos[j] - f[F_PE], by = pos[j + 1] - f[F_PE + 1], bz = pos[j + 2] - f[F_PE + 2]
  s[0] = f[F_RE] * bx + f[F_RE + 3] * by + f[F_RE + 6] * bz
  s[1] = f[F_RE + 1] * bx + f[F_RE + 4] * by + f[F_RE + 7] * bz
  s[2] = f[F_RE + 2] * bx + f[F_RE + 5] * by + f[F_RE + 8] * bz
}

/*
 * FAST_CLEAR (written out in each collider loop: a helper taking doubles was boxed, 4.5 KB per
 * step, whenever the compiler stopped inlining it): a fast particle stays clear of a collider this
 * substep when it ends farther from the shape's bounding-sphere centre than the sphere's reach
 * (`F_SWR`, which covers the shape's own motion) plus its own path (m2: squared length), judged in
 * the world. The distance to a point changes by at most the distance moved, so nothing is missed;
 * most fast particles near a fast collider stop here instead of in the swept test.
 */

/**
 * Swept test for a particle that moved far relative to the collider this substep. In the
 * collider's frame the particle went from a (its start position in the start pose) to b (now, in
 * the end pose). If a was outside the shape, the plane through a's closest surface point separates
 * a from the whole (convex) shape; when b ends near the shape, or the segment a→b passed through
 * it, b is put back at least the thickness in front of that plane, so the particle stays on the
 * side it came from however far it moved. If a was already inside, the closest-point test at b is
 * all there is. Returns 1 for a contact.
 */
export function sweptContact(
  shape: number,
  pos: Float64Array,
  prev: Float64Array,
  j: number,
  f: Float64Array,
  planes: Float64Array | null,
  planeCount: number,
  s: Float64Array,
  touched: Uint8Array | null,
): number {
  const r = f[F_RADIUS]
  const px = prev[j] - f[F_PS], py = prev[j + 1] - f[F_PS + 1], pz = prev[j + 2] - f[F_PS + 2]
  const ax = f[F_RS] * px + f[F_RS + 3] * py + f[F_RS + 6] * pz
  const ay = f[F_RS + 1] * px + f[F_RS + 4] * py + f[F_RS + 7] * pz
  const az = f[F_RS + 2] * px + f[F_RS + 5] * py + f[F_RS + 8] * pz
  toLocalEnd(pos, j, f, s)
  const bx = s[0], by = s[1], bz = s[2]
  // nowhere near the shape along the whole path: done
  const mx = bx - ax, my = by - ay, mz = bz - az
  const cx = bx - f[F_BC], cy = by - f[F_BC + 1], cz = bz - f[F_BC + 2]
  const reach = f[F_BC + 3] + r + Math.sqrt(mx * mx + my * my + mz * mz)
  if (cx * cx + cy * cy + cz * cz > reach * reach) return 0
  closestPoint(shape, f, planes, planeCount, s)
  const db = s[9]
  // a start on the surface (to rounding) is outside: with thickness 0 a contact leaves the particle
  // exactly there, and taken as inside, the next substep's sweep let it through a thin box or hull
  // (a sheet thrown at 2 m/s passed a 1 mm box whole)
  const onSurface = -1e-9 * (1 + f[F_BC + 3])
  if (db < r) {
    s[0] = ax
    s[1] = ay
    s[2] = az
    const nx = s[6], ny = s[7], nz = s[8]
    closestPoint(shape, f, planes, planeCount, s)
    if (s[9] <= onSurface) {
      // started inside: push out where it is now
      s[6] = nx
      s[7] = ny
      s[8] = nz
      s[9] = db
      return contactFromLocal(pos, prev, j, f, s, touched)
    }
  } else {
    // the distance to a shape changes by at most the distance moved, so a particle that ends
    // farther than the thickness plus its path length never came within the thickness on the way
    // (most particles near a fast collider: skips the start point's test and the segment test)
    if (db >= r && (db - r) * (db - r) >= mx * mx + my * my + mz * mz) return 0
    s[0] = ax
    s[1] = ay
    s[2] = az
    closestPoint(shape, f, planes, planeCount, s)
    if (s[9] <= onSurface) return 0
    s[14] = ax
    s[15] = ay
    s[16] = az
    s[17] = bx
    s[18] = by
    s[19] = bz
    if (segmentHits(shape, f, planes, planeCount, s) === 0) return 0
  }
  // s[3..8]: a's closest point and normal, the separating plane
  s[9] = (bx - s[3]) * s[6] + (by - s[4]) * s[7] + (bz - s[5]) * s[8]
  return contactFromLocal(pos, prev, j, f, s, touched)
}

/** Sphere of radius f[F_S0] centred at the collider's position. Returns the number of contacts. */
export function collideSphere(
  pos: Float64Array,
  prev: Float64Array,
  invMass: Float64Array,
  count: number,
  f: Float64Array,
  s: Float64Array,
  touched: Uint8Array | null = null,
): number {
  const cx = f[F_PE], cy = f[F_PE + 1], cz = f[F_PE + 2]
  const R = f[F_S0] + f[F_RADIUS], R2 = R * R, lim2 = f[F_LIM2]
  const swx = f[F_SW], swy = f[F_SW + 1], swz = f[F_SW + 2], swr = f[F_SWR]
  let contacts = 0
  for (let i = 0; i < count; i++) {
    if (invMass[i] === 0) continue
    const j = 3 * i
    const x = pos[j], y = pos[j + 1], z = pos[j + 2]
    const mx = x - prev[j], my = y - prev[j + 1], mz = z - prev[j + 2]
    const m2 = mx * mx + my * my + mz * mz
    if (m2 > lim2) {
      const wx = x - swx, wy = y - swy, wz = z - swz
      const gap = Math.sqrt(wx * wx + wy * wy + wz * wz) - swr // (see FAST_CLEAR)
      if (!(gap > 0 && gap * gap > m2)) contacts += sweptContact(SHAPE_SPHERE, pos, prev, j, f, null, 0, s, touched)
      continue
    }
    const dx = x - cx, dy = y - cy, dz = z - cz
    const d2 = dx * dx + dy * dy + dz * dz
    if (d2 >= R2) continue
    const d = Math.sqrt(d2)
    if (d > 1e-12) {
      s[10] = dx / d
      s[11] = dy / d
      s[12] = dz / d
    } else {
      s[10] = f[F_RE + 1]
      s[11] = f[F_RE + 4]
      s[12] = f[F_RE + 7]
    }
    s[13] = R - d
    respond(pos, prev, j, f, s, touched)
    contacts++
  }
  return contacts
}

/** Capsule of radius f[F_S0] around the segment ±f[F_S0 + 1] along the collider's local y. */
export function collideCapsule(
  pos: Float64Array,
  prev: Float64Array,
  invMass: Float64Array,
  count: number,
  f: Float64Array,
  s: Float64Array,
  touched: Uint8Array | null = null,
): number {
  const cx = f[F_PE], cy = f[F_PE + 1], cz = f[F_PE + 2]
  const ax = f[F_RE + 1], ay = f[F_RE + 4], az = f[F_RE + 7]
  const hh = f[F_S0 + 1]
  const R = f[F_S0] + f[F_RADIUS], R2 = R * R, lim2 = f[F_LIM2]
  const swx = f[F_SW], swy = f[F_SW + 1], swz = f[F_SW + 2], swr = f[F_SWR]
  let contacts = 0
  for (let i = 0; i < count; i++) {
    if (invMass[i] === 0) continue
    const j = 3 * i
    const x = pos[j], y = pos[j + 1], z = pos[j + 2]
    const mx = x - prev[j], my = y - prev[j + 1], mz = z - prev[j + 2]
    const m2 = mx * mx + my * my + mz * mz
    if (m2 > lim2) {
      const wx = x - swx, wy = y - swy, wz = z - swz
      const gap = Math.sqrt(wx * wx + wy * wy + wz * wz) - swr // (see FAST_CLEAR)
      if (!(gap > 0 && gap * gap > m2)) contacts += sweptContact(SHAPE_CAPSULE, pos, prev, j, f, null, 0, s, touched)
      continue
    }
    const dx = x - cx, dy = y - cy, dz = z - cz
    let t = dx * ax + dy * ay + dz * az
    t = t < -hh ? -hh : t > hh ? hh : t
    const vx = dx - ax * t, vy = dy - ay * t, vz = dz - az * t
    const d2 = vx * vx + vy * vy + vz * vz
    if (d2 >= R2) continue
    const d = Math.sqrt(d2)
    if (d > 1e-12) {
      s[10] = vx / d
      s[11] = vy / d
      s[12] = vz / d
    } else {
      s[10] = f[F_RE]
      s[11] = f[F_RE + 3]
      s[12] = f[F_RE + 6]
    }
    s[13] = R - d
    respond(pos, prev, j, f, s, touched)
    contacts++
  }
  return contacts
}

/** Box with half-extents f[F_S0..F_S0+2] in the collider's local frame. */
export function collideBox(
  pos: Float64Array,
  prev: Float64Array,
  invMass: Float64Array,
  count: number,
  f: Float64Array,
  s: Float64Array,
  touched: Uint8Array | null = null,
): number {
  const px = f[F_PE], py = f[F_PE + 1], pz = f[F_PE + 2]
  const r00 = f[F_RE], r01 = f[F_RE + 1], r02 = f[F_RE + 2]
  const r10 = f[F_RE + 3], r11 = f[F_RE + 4], r12 = f[F_RE + 5]
  const r20 = f[F_RE + 6], r21 = f[F_RE + 7], r22 = f[F_RE + 8]
  const hx = f[F_S0], hy = f[F_S0 + 1], hz = f[F_S0 + 2]
  const r = f[F_RADIUS], r2 = r * r, lim2 = f[F_LIM2]
  const swx = f[F_SW], swy = f[F_SW + 1], swz = f[F_SW + 2], swr = f[F_SWR]
  let contacts = 0
  for (let i = 0; i < count; i++) {
    if (invMass[i] === 0) continue
    const j = 3 * i
    const x = pos[j], y = pos[j + 1], z = pos[j + 2]
    const mx = x - prev[j], my = y - prev[j + 1], mz = z - prev[j + 2]
    const m2 = mx * mx + my * my + mz * mz
    if (m2 > lim2) {
      const wx = x - swx, wy = y - swy, wz = z - swz
      const gap = Math.sqrt(wx * wx + wy * wy + wz * wz) - swr // (see FAST_CLEAR)
      if (!(gap > 0 && gap * gap > m2)) contacts += sweptContact(SHAPE_BOX, pos, prev, j, f, null, 0, s, touched)
      continue
    }
    const bx = x - px, by = y - py, bz = z - pz
    const lx = r00 * bx + r10 * by + r20 * bz
    const ly = r01 * bx + r11 * by + r21 * bz
    const lz = r02 * bx + r12 * by + r22 * bz
    const ex = lx < -hx ? lx + hx : lx > hx ? lx - hx : 0
    const ey = ly < -hy ? ly + hy : ly > hy ? ly - hy : 0
    const ez = lz < -hz ? lz + hz : lz > hz ? lz - hz : 0
    if (ex * ex + ey * ey + ez * ez > r2) continue
    s[0] = lx
    s[1] = ly
    s[2] = lz
    closestPoint(SHAPE_BOX, f, null, 0, s)
    contacts += contactFromLocal(pos, prev, j, f, s, touched)
  }
  return contacts
}

/** Convex hull given by `planeCount` local planes (n·x ≤ d inside, stride 4). */
export function collideHull(
  pos: Float64Array,
  prev: Float64Array,
  invMass: Float64Array,
  count: number,
  f: Float64Array,
  planes: Float64Array,
  planeCount: number,
  s: Float64Array,
  touched: Uint8Array | null = null,
): number {
  const px = f[F_PE], py = f[F_PE + 1], pz = f[F_PE + 2]
  const r00 = f[F_RE], r01 = f[F_RE + 1], r02 = f[F_RE + 2]
  const r10 = f[F_RE + 3], r11 = f[F_RE + 4], r12 = f[F_RE + 5]
  const r20 = f[F_RE + 6], r21 = f[F_RE + 7], r22 = f[F_RE + 8]
  const r = f[F_RADIUS], lim2 = f[F_LIM2]
  const swx = f[F_SW], swy = f[F_SW + 1], swz = f[F_SW + 2], swr = f[F_SWR]
  let contacts = 0, hint = 0
  for (let i = 0; i < count; i++) {
    if (invMass[i] === 0) continue
    const j = 3 * i
    const x = pos[j], y = pos[j + 1], z = pos[j + 2]
    const mx = x - prev[j], my = y - prev[j + 1], mz = z - prev[j + 2]
    const m2 = mx * mx + my * my + mz * mz
    if (m2 > lim2) {
      const wx = x - swx, wy = y - swy, wz = z - swz
      const gap = Math.sqrt(wx * wx + wy * wy + wz * wz) - swr // (see FAST_CLEAR)
      if (!(gap > 0 && gap * gap > m2))
        contacts += sweptContact(SHAPE_HULL, pos, prev, j, f, planes, planeCount, s, touched)
      continue
    }
    const bx = x - px, by = y - py, bz = z - pz
    const lx = r00 * bx + r10 * by + r20 * bz
    const ly = r01 * bx + r11 * by + r21 * bz
    const lz = r02 * bx + r12 * by + r22 * bz
    // separated by any face plane (beyond the thickness): no contact. The plane that separated
    // the previous particle is tried first (neighbours usually share it), so most misses cost one
    // dot product; otherwise the loop ends with the deepest plane, the contact's normal
    if (planes[hint] * lx + planes[hint + 1] * ly + planes[hint + 2] * lz - planes[hint + 3] >= r) continue
    let best = -Infinity, kb = 0, k = 0
    for (; k < planeCount; k++) {
      const o = 4 * k
      const dk = planes[o] * lx + planes[o + 1] * ly + planes[o + 2] * lz - planes[o + 3]
      if (dk >= r) break
      if (dk > best) {
        best = dk
        kb = o
      }
    }
    if (k < planeCount) {
      hint = 4 * k
      continue
    }
    const nx = planes[kb], ny = planes[kb + 1], nz = planes[kb + 2]
    s[10] = r00 * nx + r01 * ny + r02 * nz
    s[11] = r10 * nx + r11 * ny + r12 * nz
    s[12] = r20 * nx + r21 * ny + r22 * nz
    s[13] = r - best
    respond(pos, prev, j, f, s, touched)
    contacts++
  }
  return contacts
}

/**
 * Half-space below a plane (world normal f[F_PN..], n·x ≥ f[F_PC] outside). A half-space has no
 * far side to tunnel to, so no swept test is needed.
 */
export function collidePlane(
  pos: Float64Array,
  prev: Float64Array,
  invMass: Float64Array,
  count: number,
  f: Float64Array,
  s: Float64Array,
  touched: Uint8Array | null = null,
): number {
  const nx = f[F_PN], ny = f[F_PN + 1], nz = f[F_PN + 2]
  const c = f[F_PC] + f[F_RADIUS]
  let contacts = 0
  for (let i = 0; i < count; i++) {
    if (invMass[i] === 0) continue
    const j = 3 * i
    const d = pos[j] * nx + pos[j + 1] * ny + pos[j + 2] * nz - c
    if (d >= 0) continue
    s[10] = nx
    s[11] = ny
    s[12] = nz
    s[13] = -d
    respond(pos, prev, j, f, s, touched)
    contacts++
  }
  return contacts
}

/**
 * One pass over a cloth's particles for the per-step broadphase: out[0..5] their bounds (min xyz,
 * max xyz), out[6] the largest squared speed, out[7..9] the mean velocity of the free particles and,
 * when `deviation` is 1, out[10] the largest |v − mean| of a free particle (m/s; else 0).
 * Particles with `skip[i]` = 1 (vertices no triangle uses) are left out.
 */
export function measureCloth(
  pos: Float64Array,
  vel: Float64Array,
  invMass: Float64Array,
  count: number,
  deviation: number,
  out: Float64Array,
  skip: Uint8Array | null = null,
): void {
  let x0 = Infinity, y0 = Infinity, z0 = Infinity, x1 = -Infinity, y1 = -Infinity, z1 = -Infinity
  let v2max = 0, mx = 0, my = 0, mz = 0, n = 0
  for (let i = 0; i < count; i++) {
    if (skip !== null && skip[i] === 1) continue // a vertex no triangle uses: no part of the cloth
    const j = 3 * i
    const x = pos[j], y = pos[j + 1], z = pos[j + 2]
    if (x < x0) x0 = x
    if (x > x1) x1 = x
    if (y < y0) y0 = y
    if (y > y1) y1 = y
    if (z < z0) z0 = z
    if (z > z1) z1 = z
    const vx = vel[j], vy = vel[j + 1], vz = vel[j + 2]
    const v2 = vx * vx + vy * vy + vz * vz
    if (v2 > v2max) v2max = v2
    if (invMass[i] === 0) continue
    mx += vx
    my += vy
    mz += vz
    n++
  }
  if (n > 0) {
    mx /= n
    my /= n
    mz /= n
  }
  out[0] = x0
  out[1] = y0
  out[2] = z0
  out[3] = x1
  out[4] = y1
  out[5] = z1
  out[6] = v2max
  out[7] = mx
  out[8] = my
  out[9] = mz
  let dev2 = 0
  if (deviation === 1) {
    for (let i = 0; i < count; i++) {
      if (invMass[i] === 0) continue
      const j = 3 * i
      const dx = vel[j] - mx, dy = vel[j + 1] - my, dz = vel[j + 2] - mz
      const d2 = dx * dx + dy * dy + dz * dz
      if (d2 > dev2) dev2 = d2
    }
  }
  out[10] = Math.sqrt(dev2)
}
