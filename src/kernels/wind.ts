/**
 * Air velocity of wind zones at particle positions. Each zone is compiled once per fixed step into
 * a block of `ZONE_STRIDE` doubles (layout below) so the kernels read plain typed arrays.
 *
 * Turbulence is value noise on a 4-D lattice (space in units of the eddy size, time in units of
 * the renewal period): every lattice point gets three pseudo-random components in [−1, 1] from an
 * integer hash of its coordinates and the seed, and the field in between is interpolated with the
 * quintic fade 6t⁵ − 15t⁴ + 10t³, so it is C² smooth in space and time and, being a convex blend
 * of lattice values, bounded by ±1 per component. The pattern is carried downwind by the mean wind
 * (frozen turbulence, Taylor's hypothesis) while it renews itself in time. No `Math.random`: the
 * same seed gives the same wind, bit for bit.
 */

/** Shape: 0 global, 1 box, 2 sphere. */
export const Z_SHAPE = 0
/** Mean wind velocity including the gust, m/s. */
export const Z_VX = 1
export const Z_VY = 2
export const Z_VZ = 3
/** Turbulence amplitude (speed × turbulence), m/s. */
export const Z_TURB = 4
/** 1 / eddy size, 1/m. */
export const Z_INV_SCALE = 5
/** Drift of the noise pattern, m. */
export const Z_DRIFT_X = 6
export const Z_DRIFT_Y = 7
export const Z_DRIFT_Z = 8
/** Noise time coordinate, time / period. */
export const Z_TIME = 9
/** Seed (an integer stored as a double). */
export const Z_SEED = 10
/** Centre, m. */
export const Z_CX = 11
export const Z_CY = 12
export const Z_CZ = 13
/** World → zone rotation, 3×3 row-major (the transpose of the Transform's rotation). */
export const Z_R = 14
/** Box half extents (a sphere's radius in Z_HX), m. */
export const Z_HX = 23
export const Z_HY = 24
export const Z_HZ = 25
/** Falloff distance, m. */
export const Z_FALLOFF = 26
/** Air density in the zone, kg/m³, or −1 for the world's. */
export const Z_DENSITY = 27
/** World-space bounds including the falloff, for culling: min xyz, max xyz. */
export const Z_MIN = 28
export const Z_MAX = 31
export const ZONE_STRIDE = 34

/** Scratch a sampling call needs: 8 lattice corners × 3 components. */
export const NOISE_SCRATCH = 24

/**
 * Adds zone `z` (its block starts at `zones[z]`) to the air of particles [0, count): velocity into
 * air[4i..4i+2] and, when a box or sphere zone sets its own density, the density there blended
 * toward it by the zone's weight, ρ += weight·(ρ_zone − ρ), in the zones' order (air[4i+3] starts
 * at the ambient density: the world's or the last global zone's). Zone velocities add; densities
 * replace, so two zones of the same density give that density. `scratch` holds NOISE_SCRATCH doubles.
 *
 * One long function on purpose: it is the per-particle loop of turbulent wind, and the zone shape
 * test, falloff and lattice-noise lookup are written inline so that no double crosses a call
 * boundary (a call V8 does not inline boxes its double arguments, which would allocate per particle).
 */
export function addZoneAir(
  pos: Float64Array,
  count: number,
  air: Float64Array,
  zones: Float64Array,
  z: number,
  scratch: Float64Array,
): void {
  const shape = zones[z + Z_SHAPE]
  const vx = zones[z + Z_VX], vy = zones[z + Z_VY], vz = zones[z + Z_VZ]
  const amp = zones[z + Z_TURB]
  const cx = zones[z + Z_CX], cy = zones[z + Z_CY], cz = zones[z + Z_CZ]
  const r = z + Z_R
  const r00 = zones[r], r01 = zones[r + 1], r02 = zones[r + 2]
  const r10 = zones[r + 3], r11 = zones[r + 4], r12 = zones[r + 5]
  const r20 = zones[r + 6], r21 = zones[r + 7], r22 = zones[r + 8]
  const hx = zones[z + Z_HX], hy = zones[z + Z_HY], hz = zones[z + Z_HZ]
  const fall = zones[z + Z_FALLOFF]
  const fall2 = fall * fall
  const invFall = fall > 0 ? 1 / fall : 0
  const zoneDensity = zones[z + Z_DENSITY]
  // a box or sphere zone's density replaces what is there, blended by its weight (a global zone's
  // is the ambient density the caller starts from)
  const setsDensity = zoneDensity >= 0 && shape !== 0
  // noise set-up, once per call
  const inv = zones[z + Z_INV_SCALE]
  const ox = zones[z + Z_DRIFT_X], oy = zones[z + Z_DRIFT_Y], oz = zones[z + Z_DRIFT_Z]
  const tau = zones[z + Z_TIME]
  const seed = zones[z + Z_SEED] | 0
  const it = Math.floor(tau) | 0
  const ft = tau - Math.floor(tau)
  const st = ft * ft * ft * (ft * (ft * 6 - 15) + 10)
  let ccx = 0, ccy = 0, ccz = 0
  let cached = false

  for (let i = 0; i < count; i++) {
    const j = 3 * i
    const x = pos[j], y = pos[j + 1], zz = pos[j + 2]
    let w = 1
    if (shape !== 0) {
      // the same arithmetic inside the zone (distance 0, weight exactly 1) as in its falloff band,
      // in doubles throughout: max(e, 0) as (e + |e|)/2 (exact), since a literal 0 or Math.max fed
      // only zeros gets typed as a small integer, and the first particle to drift into the band
      // would then deoptimize the kernel, which boxes numbers (allocates) in a step
      const dx = x - cx, dy = y - cy, dz = zz - cz
      let d2: number
      if (shape === 1) {
        const lx = r00 * dx + r01 * dy + r02 * dz
        const ly = r10 * dx + r11 * dy + r12 * dz
        const lz = r20 * dx + r21 * dy + r22 * dz
        const ex = (lx < 0 ? -lx : lx) - hx, ey = (ly < 0 ? -ly : ly) - hy, ez = (lz < 0 ? -lz : lz) - hz
        const px = 0.5 * (ex + Math.abs(ex)), py = 0.5 * (ey + Math.abs(ey)), pz = 0.5 * (ez + Math.abs(ez))
        d2 = px * px + py * py + pz * pz
      } else {
        const r = Math.sqrt(dx * dx + dy * dy + dz * dz) - hx
        const e = 0.5 * (r + Math.abs(r))
        d2 = e * e
      }
      if (d2 > 0 && d2 >= fall2) continue
      const u = 1 - Math.sqrt(d2) * invFall
      w = u * u * (3 - 2 * u)
    }
    const k = 4 * i
    let ux = vx, uy = vy, uz = vz
    if (amp > 0) {
      const qx = (x - ox) * inv, qy = (y - oy) * inv, qz = (zz - oz) * inv
      const fx0 = Math.floor(qx), fy0 = Math.floor(qy), fz0 = Math.floor(qz)
      const ix = fx0 | 0, iy = fy0 | 0, iz = fz0 | 0
      if (!cached || ix !== ccx || iy !== ccy || iz !== ccz) {
        // the 8 corners of this cell, each blended between time slices it and it + 1
        for (let corner = 0; corner < 8; corner++) {
          const X = (ix + (corner & 1)) | 0, Y = (iy + ((corner >> 1) & 1)) | 0, Z = (iz + ((corner >> 2) & 1)) | 0
          let h0 = Math.imul(seed ^ X, 0x9e3779b1)
          h0 ^= h0 >>> 16
          h0 = Math.imul(h0 ^ Y, 0x85ebca77)
          h0 ^= h0 >>> 13
          h0 = Math.imul(h0 ^ Z, 0xc2b2ae3d)
          h0 ^= h0 >>> 16
          let h1 = Math.imul(h0 ^ (it + 1), 0x27d4eb2f)
          h0 = Math.imul(h0 ^ it, 0x27d4eb2f)
          h0 ^= h0 >>> 15
          h0 = Math.imul(h0, 0x2c1b3c6d)
          h0 ^= h0 >>> 12
          h1 ^= h1 >>> 15
          h1 = Math.imul(h1, 0x2c1b3c6d)
          h1 ^= h1 >>> 12
          const a0 = (h0 & 1023) * (2 / 1023) - 1, a1 = (h1 & 1023) * (2 / 1023) - 1
          const b0 = ((h0 >>> 10) & 1023) * (2 / 1023) - 1, b1 = ((h1 >>> 10) & 1023) * (2 / 1023) - 1
          const c0 = ((h0 >>> 20) & 1023) * (2 / 1023) - 1, c1 = ((h1 >>> 20) & 1023) * (2 / 1023) - 1
          const s = 3 * corner
          scratch[s] = a0 + (a1 - a0) * st
          scratch[s + 1] = b0 + (b1 - b0) * st
          scratch[s + 2] = c0 + (c1 - c0) * st
        }
        ccx = ix
        ccy = iy
        ccz = iz
        cached = true
      }
      const tx = qx - fx0, ty = qy - fy0, tz = qz - fz0
      const sx = tx * tx * tx * (tx * (tx * 6 - 15) + 10)
      const sy = ty * ty * ty * (ty * (ty * 6 - 15) + 10)
      const sz = tz * tz * tz * (tz * (tz * 6 - 15) + 10)
      for (let ch = 0; ch < 3; ch++) {
        const v000 = scratch[ch], v100 = scratch[3 + ch], v010 = scratch[6 + ch], v110 = scratch[9 + ch]
        const v001 = scratch[12 + ch], v101 = scratch[15 + ch], v011 = scratch[18 + ch], v111 = scratch[21 + ch]
        const x00 = v000 + (v100 - v000) * sx, x10 = v010 + (v110 - v010) * sx
        const x01 = v001 + (v101 - v001) * sx, x11 = v011 + (v111 - v011) * sx
        const y0 = x00 + (x10 - x00) * sy, y1 = x01 + (x11 - x01) * sy
        const n = (y0 + (y1 - y0) * sz) * amp
        if (ch === 0) ux += n
        else if (ch === 1) uy += n
        else uz += n
      }
    }
    air[k] += w * ux
    air[k + 1] += w * uy
    air[k + 2] += w * uz
    if (setsDensity) air[k + 3] += w * (zoneDensity - air[k + 3])
  }
}
