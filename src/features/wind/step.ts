import {
  A_DRAG,
  A_H,
  A_LIFT,
  A_MAX_SPEED,
  A_STRIDE,
  AERO_PARAM_COUNT,
  accumulateAerodynamics,
  aeroNormals,
  limitAerodynamics,
} from '../../kernels/aero'
import { particleBounds } from '../../kernels/mesh'
import {
  Z_CX,
  Z_CY,
  Z_CZ,
  Z_DENSITY,
  Z_DRIFT_X,
  Z_DRIFT_Y,
  Z_DRIFT_Z,
  Z_FALLOFF,
  Z_HX,
  Z_HY,
  Z_HZ,
  Z_INV_SCALE,
  Z_MAX,
  Z_MIN,
  Z_R,
  Z_SEED,
  Z_SHAPE,
  Z_TIME,
  Z_TURB,
  Z_VX,
  Z_VY,
  Z_VZ,
  ZONE_STRIDE,
  addZoneAir,
} from '../../kernels/wind'
import { quatToMatrix } from '../../core/math'
import type { ClothState, ClothWorldState } from '../../world/state'
import type { ClothWind } from './types'
import { newArray } from '../../core/shared'

/**
 * Once per fixed step (sync phase): advances the wind time, the gusts and the drift of each zone's
 * turbulence, then compiles the zones (pose from their Transform, sampled like pin targets) into
 * the parameter blocks the kernels read. Nothing to do without zones.
 */
export function advanceWind(state: ClothWorldState): void {
  const wind = state.wind
  const zones = wind.zones
  if (zones.length === 0) return
  const dt = state.fixedTimeStep
  wind.time[0] += dt
  const Z = state.components.WindZone
  for (let k = 0; k < zones.length; k++) {
    const z = zones[k]
    const dur = Z.gustDuration[z]
    if (dur > 0) {
      const t = Z.gustTime[z] + dt
      Z.gustTime[z] = t
      const u = t / dur
      let g = 0
      if (u >= 1) Z.gustDuration[z] = 0
      else if (u < 0.3) {
        const s = u / 0.3
        g = Z.gustFrom[z] + (Z.gustPeak[z] - Z.gustFrom[z]) * s * s * (3 - 2 * s)
      } else if (u <= 0.7) g = Z.gustPeak[z]
      else {
        const s = (1 - u) / 0.3
        g = Z.gustPeak[z] * s * s * (3 - 2 * s)
      }
      Z.gust[z] = g
    }
    const speed = Math.max(0, Z.strength[z] + Z.gust[z])
    Z.drift[3 * z] += Z.dirX[z] * speed * dt
    Z.drift[3 * z + 1] += Z.dirY[z] * speed * dt
    Z.drift[3 * z + 2] += Z.dirZ[z] * speed * dt
  }
  compileZones(state)
}

/** Swaps a[i] and a[j]. */
function swap(a: Float64Array, i: number, j: number): void {
  const t = a[i]
  a[i] = a[j]
  a[j] = t
}

/** Writes each zone's parameter block for the current step. */
export function compileZones(state: ClothWorldState): void {
  const wind = state.wind
  const zones = wind.zones
  const Z = state.components.WindZone
  const P = wind.params
  const poses = state.kinematics.stepTo
  for (let k = 0; k < zones.length; k++) {
    const z = zones[k]
    const o = k * ZONE_STRIDE
    const speed = Math.max(0, Z.strength[z] + Z.gust[z])
    const shape = Z.shape[z]
    P[o + Z_SHAPE] = shape
    P[o + Z_VX] = Z.dirX[z] * speed
    P[o + Z_VY] = Z.dirY[z] * speed
    P[o + Z_VZ] = Z.dirZ[z] * speed
    P[o + Z_TURB] = speed * Z.turbulence[z]
    P[o + Z_INV_SCALE] = 1 / Z.turbulenceScale[z]
    P[o + Z_DRIFT_X] = Z.drift[3 * z]
    P[o + Z_DRIFT_Y] = Z.drift[3 * z + 1]
    P[o + Z_DRIFT_Z] = Z.drift[3 * z + 2]
    P[o + Z_TIME] = wind.time[0] / Z.turbulencePeriod[z]
    P[o + Z_SEED] = Z.seed[z] | 0
    const s = 7 * Z.slot[z]
    const px = poses[s], py = poses[s + 1], pz = poses[s + 2]
    P[o + Z_CX] = px
    P[o + Z_CY] = py
    P[o + Z_CZ] = pz
    // the block stores Mᵀ (world → zone): M, then transposed in place
    const r = o + Z_R
    quatToMatrix(poses, s + 3, P, r)
    swap(P, r + 1, r + 3)
    swap(P, r + 2, r + 6)
    swap(P, r + 5, r + 7)
    const hx = Z.halfX[z], hy = Z.halfY[z], hz = Z.halfZ[z]
    P[o + Z_HX] = hx
    P[o + Z_HY] = hy
    P[o + Z_HZ] = hz
    const f = Z.falloff[z]
    P[o + Z_FALLOFF] = f
    P[o + Z_DENSITY] = Z.airDensity[z]
    // world bounds: a box's extent along each world axis is Σ|m_ij|·h_j
    let ex = hx, ey = hx, ez = hx
    if (shape === 1) {
      // Mᵀ: m_ij sits at r + 3j + i
      ex = Math.abs(P[r]) * hx + Math.abs(P[r + 3]) * hy + Math.abs(P[r + 6]) * hz
      ey = Math.abs(P[r + 1]) * hx + Math.abs(P[r + 4]) * hy + Math.abs(P[r + 7]) * hz
      ez = Math.abs(P[r + 2]) * hx + Math.abs(P[r + 5]) * hy + Math.abs(P[r + 8]) * hz
    }
    P[o + Z_MIN] = px - ex - f
    P[o + Z_MIN + 1] = py - ey - f
    P[o + Z_MIN + 2] = pz - ez - f
    P[o + Z_MAX] = px + ex + f
    P[o + Z_MAX + 1] = py + ey + f
    P[o + Z_MAX + 2] = pz + ez + f
  }
  wind.compiled = true
}

/**
 * Forces phase, per cloth and substep. On the cloth's first substep of the step it finds the zones
 * that reach the cloth (global zones always; box and sphere zones whose bounds overlap the cloth's)
 * and samples the air at its particles, once per step: the field is smooth on the scale of a step.
 * When the air is uniform (only steady global zones) nothing is sampled per particle. Then, every
 * substep, the triangle pass and the stability clamp fill `accel`; `ClothState.accel` is null when
 * no zone reaches the cloth, and the predict kernel skips it.
 */
export function applyWind(state: ClothWorldState, c: ClothState): void {
  const wind = state.wind
  const cw = c.wind
  if (cw === null || wind.zones.length === 0) {
    c.accel = null
    return
  }
  if (c.subIndex === 0) prepareClothWind(state, c, cw)
  if (cw.active === 0) {
    c.accel = null
    return
  }
  const t = c.topology
  const accel = cw.accel
  accel.fill(0, 0, 3 * c.count)
  const p = cw.params
  p[A_H] = c.h
  p[A_DRAG] = c.material.drag
  p[A_LIFT] = c.material.lift
  p[A_MAX_SPEED] = state.maxSpeed
  aeroNormals(c.pos, c.count, t.triangles, t.triangleCount, t.edges, t.edgeCount, cw.normals, cw.scratch)
  accumulateAerodynamics(c.pos, c.vel, t.triangles, t.triangleCount, c.baseInvMass, cw.air, cw.normals, accel, p)
  if (wind.clamp) limitAerodynamics(c.vel, c.invMass, cw.air, accel, p, c.count)
  c.accel = accel
  state.stats.windTriangles += t.triangleCount
}

/**
 * Whether some blowing wind zone reaches the box `b` (min xyz, max xyz): a global zone always; a
 * box or sphere zone when its bounds overlap the box (the forces phase's rule). A calm zone (no
 * speed, no turbulence, no gust this step) does not count: this is the sleep test.
 */
export function windReaches(state: ClothWorldState, b: Float64Array): boolean {
  const wind = state.wind
  const nz = wind.zones.length
  if (nz === 0) return false
  if (!wind.compiled) compileZones(state)
  const P = wind.params
  // every array slot is read on every call, before any test: a read first reached (through a
  // branch or a short-circuit) long after start-up would run unoptimized code, which boxes numbers
  const bx0 = b[0], by0 = b[1], bz0 = b[2], bx1 = b[3], by1 = b[4], bz1 = b[5]
  for (let k = 0; k < nz; k++) {
    const o = k * ZONE_STRIDE
    const shape = P[o + Z_SHAPE]
    const vx = P[o + Z_VX], vy = P[o + Z_VY], vz = P[o + Z_VZ], turb = P[o + Z_TURB]
    const x0 = P[o + Z_MIN], y0 = P[o + Z_MIN + 1], z0 = P[o + Z_MIN + 2]
    const x1 = P[o + Z_MAX], y1 = P[o + Z_MAX + 1], z1 = P[o + Z_MAX + 2]
    const cx = P[o + Z_CX], cy = P[o + Z_CY], cz = P[o + Z_CZ]
    const r = P[o + Z_HX] + P[o + Z_FALLOFF]
    const dx = Math.max(bx0 - cx, cx - bx1, 0)
    const dy = Math.max(by0 - cy, cy - by1, 0)
    const dz = Math.max(bz0 - cz, cz - bz1, 0)
    const blowing = vx * vx + vy * vy + vz * vz + turb * turb > 0
    const boxes = bx1 >= x0 && bx0 <= x1 && by1 >= y0 && by0 <= y1 && bz1 >= z0 && bz0 <= z1
    const inSphere = dx * dx + dy * dy + dz * dz <= r * r
    const inBox = !boxZoneMisses(P, o, b)
    if (blowing && (shape === 0 || (boxes && (shape === 2 ? inSphere : inBox)))) return true
  }
  return false
}

/**
 * Whether the box `b` (min xyz, max xyz) lies wholly outside the box zone at P[o..] and its falloff
 * band along one of the zone's own axes (the zone's world bounds are the other three axes a
 * separating-axis test needs; the nine edge-edge axes are left out: a miss it cannot see counts
 * as reaching). A zone turned 45° reached, by its world bounds, a sheet 1.4 m off its axis: the
 * sheet never slept and ran the aerodynamics for no air.
 */
function boxZoneMisses(P: Float64Array, o: number, b: Float64Array): boolean {
  const ex = 0.5 * (b[3] - b[0]), ey = 0.5 * (b[4] - b[1]), ez = 0.5 * (b[5] - b[2])
  const dx = 0.5 * (b[0] + b[3]) - P[o + Z_CX], dy = 0.5 * (b[1] + b[4]) - P[o + Z_CY], dz = 0.5 * (b[2] + b[5]) - P[o + Z_CZ]
  const f = P[o + Z_FALLOFF]
  const r = o + Z_R // Mᵀ, row-major: row i is the zone's axis i in world coordinates
  for (let i = 0; i < 3; i++) {
    const a0 = P[r + 3 * i], a1 = P[r + 3 * i + 1], a2 = P[r + 3 * i + 2]
    const along = a0 * dx + a1 * dy + a2 * dz
    const reach = P[o + Z_HX + i] + f + Math.abs(a0) * ex + Math.abs(a1) * ey + Math.abs(a2) * ez
    if (Math.abs(along) > reach) return true
  }
  return false
}

function prepareClothWind(state: ClothWorldState, c: ClothState, cw: ClothWind): void {
  const wind = state.wind
  if (!wind.compiled) compileZones(state)
  const P = wind.params
  const nz = wind.zones.length
  let active = 0
  let uniform = true
  let haveBounds = false
  const b = wind.bounds
  for (let k = 0; k < nz; k++) {
    const o = k * ZONE_STRIDE
    if (P[o + Z_SHAPE] !== 0) {
      if (!haveBounds) {
        particleBounds(c.pos, c.count, b, 0, c.topology.unused)
        haveBounds = true
      }
      if (
        b[3] < P[o + Z_MIN] || b[0] > P[o + Z_MAX] || b[4] < P[o + Z_MIN + 1] || b[1] > P[o + Z_MAX + 1] ||
        b[5] < P[o + Z_MIN + 2] || b[2] > P[o + Z_MAX + 2]
      ) continue
      if (P[o + Z_SHAPE] === 1 && boxZoneMisses(P, o, b)) continue
      if (P[o + Z_SHAPE] === 2) {
        // sphere: the exact distance from its centre to the cloth's box
        const cx = P[o + Z_CX], cy = P[o + Z_CY], cz = P[o + Z_CZ]
        const dx = cx < b[0] ? b[0] - cx : cx > b[3] ? cx - b[3] : 0
        const dy = cy < b[1] ? b[1] - cy : cy > b[4] ? cy - b[4] : 0
        const dz = cz < b[2] ? b[2] - cz : cz > b[5] ? cz - b[5] : 0
        const r = P[o + Z_HX] + P[o + Z_FALLOFF]
        if (dx * dx + dy * dy + dz * dz > r * r) continue
      }
      uniform = false
    }
    if (P[o + Z_TURB] > 0) uniform = false
    wind.active[active++] = o
  }
  cw.active = active > 0 ? 1 : 0
  if (active === 0) return
  const air = cw.air
  // the ambient air's density: the world's, or the last global zone's that sets one; a box or
  // sphere zone's replaces it inside (see addZoneAir). (Each zone's change from the world's was
  // added: two zones of 2.4 kg/m³ made 3.6.)
  let rho = wind.airDensity[0]
  for (let k = 0; k < active; k++) {
    const o = wind.active[k]
    if (P[o + Z_SHAPE] === 0 && P[o + Z_DENSITY] >= 0) rho = P[o + Z_DENSITY]
  }
  if (uniform) {
    let ux = 0, uy = 0, uz = 0
    for (let k = 0; k < active; k++) {
      const o = wind.active[k]
      ux += P[o + Z_VX]
      uy += P[o + Z_VY]
      uz += P[o + Z_VZ]
    }
    air[0] = ux
    air[1] = uy
    air[2] = uz
    air[3] = rho // (densities are never negative: the world's and each zone's are checked)
    cw.params[A_STRIDE] = 0
    return
  }
  for (let i = 0; i < c.count; i++) {
    const k = 4 * i
    air[k] = 0
    air[k + 1] = 0
    air[k + 2] = 0
    air[k + 3] = rho
  }
  for (let k = 0; k < active; k++) addZoneAir(c.pos, c.count, air, P, wind.active[k], wind.scratch)
  cw.params[A_STRIDE] = 4
}

/**
 * Allocates (or regrows to the cloth's capacity) a cloth's aerodynamics buffers. Called when a zone
 * is created, when a cloth is created while zones exist, and when a cloth's capacity grows
 * (tearing): never in a step.
 */
export function ensureClothWind(c: ClothState): void {
  const particles = (c.pos.length / 3) | 0
  if (c.wind === null || c.wind.accel.length < 3 * particles) {
    c.wind = {
      air: newArray(Float64Array, 4 * particles),
      accel: newArray(Float64Array, 3 * particles),
      normals: newArray(Float64Array, 3 * particles),
      scratch: newArray(Float64Array, 3 * particles),
      params: newArray(Float64Array, AERO_PARAM_COUNT),
      active: 0,
    }
    c.accel = null
  }
}
