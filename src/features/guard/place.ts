import type { ClothState, ClothWorldState } from '../../world/state'
import { placePins } from '../pins/step'

// scratch for the rigid fit: S (9), N (16), q (4), centroids (6), matrix product (16)
const fit = new Float64Array(56)
const F_S = 0, F_N = 9, F_Q = 25, F_CS = 29, F_CT = 32, F_M = 35

/**
 * pos ← R·(src − c_src) + c_now for every particle, with R, c_src, c_now fitted to the pinned
 * particles (their current positions are the targets); prev ← pos, vel ← 0.
 */
export function placeRigidly(state: ClothWorldState, c: ClothState, src: Float64Array, srcCount: number): void {
  const P = state.components.Pin
  const pos = c.pos
  // where the pins hold their particles at the end of this step (a NaN may have reached pinned
  // particles too: 0 × NaN is NaN in the constraint updates): as on the last substep, blends as
  // they stand
  placePins(state, c, c.substeps - 1, c.substeps, false)
  const f = fit
  const n = fitToPins(P.particle, c.pins.list, src, srcCount, pos, f)
  // (nothing pins the cloth: identity and c_src = c_now = 0, the pose goes back where it was)
  const qx = f[F_Q], qy = f[F_Q + 1], qz = f[F_Q + 2], qw = f[F_Q + 3]
  const csx = f[F_CS], csy = f[F_CS + 1], csz = f[F_CS + 2]
  const ctx = n > 0 ? f[F_CT] : csx, cty = n > 0 ? f[F_CT + 1] : csy, ctz = n > 0 ? f[F_CT + 2] : csz
  const prev = c.prev, vel = c.vel
  let mx = 0, my = 0, mz = 0
  for (let i = 0; i < c.count; i++) {
    const j = 3 * i
    vel[j] = 0
    vel[j + 1] = 0
    vel[j + 2] = 0
    if (i >= srcCount) continue
    if (c.pinCount[i] === 0) {
      const vx = src[j] - csx, vy = src[j + 1] - csy, vz = src[j + 2] - csz
      const tx = 2 * (qy * vz - qz * vy), ty = 2 * (qz * vx - qx * vz), tz = 2 * (qx * vy - qy * vx)
      pos[j] = ctx + vx + qw * tx + (qy * tz - qz * ty)
      pos[j + 1] = cty + vy + qw * ty + (qz * tx - qx * tz)
      pos[j + 2] = ctz + vz + qw * tz + (qx * ty - qy * tx)
    }
    mx += pos[j]
    my += pos[j + 1]
    mz += pos[j + 2]
  }
  // particles the copy does not cover (added by tearing since): kept if finite, else put on the
  // centroid of the restored ones
  const m = Math.min(srcCount, c.count)
  if (m > 0) {
    mx /= m
    my /= m
    mz /= m
  }
  for (let i = srcCount; i < c.count; i++) {
    const j = 3 * i
    if (c.pinCount[i] === 0 && !Number.isFinite(pos[j] + pos[j + 1] + pos[j + 2])) {
      pos[j] = mx
      pos[j + 1] = my
      pos[j + 2] = mz
    }
  }
  for (let j = 0; j < 3 * c.count; j++) prev[j] = pos[j]
}

/**
 * The rigid motion that best maps the pinned particles' source positions (`src`) onto their
 * current ones (`pos`): centroids into f[F_CS..], f[F_CT..] and the rotation into f[F_Q..]
 * (identity when fewer than two pins determine it). Returns the number of pins used.
 */
function fitToPins(
  particle: ArrayLike<number>,
  pins: number[],
  src: Float64Array,
  srcCount: number,
  pos: Float64Array,
  f: Float64Array,
): number {
  for (let k = 0; k < f.length; k++) f[k] = 0
  let n = 0
  for (let q = 0; q < pins.length; q++) {
    const i = particle[pins[q]]
    if (i >= srcCount) continue
    const j = 3 * i
    f[F_CS] += src[j]
    f[F_CS + 1] += src[j + 1]
    f[F_CS + 2] += src[j + 2]
    f[F_CT] += pos[j]
    f[F_CT + 1] += pos[j + 1]
    f[F_CT + 2] += pos[j + 2]
    n++
  }
  f[F_Q + 3] = 1
  if (n > 0) {
    for (let k = 0; k < 3; k++) {
      f[F_CS + k] /= n
      f[F_CT + k] /= n
    }
    // cross-covariance S_ab = Σ (s − c_s)_a (t − c_t)_b
    for (let q = 0; q < pins.length; q++) {
      const i = particle[pins[q]]
      if (i >= srcCount) continue
      const j = 3 * i
      for (let a = 0; a < 3; a++) {
        const s = src[j + a] - f[F_CS + a]
        for (let b = 0; b < 3; b++) f[F_S + 3 * a + b] += s * (pos[j + b] - f[F_CT + b])
      }
    }
    hornRotation(f)
  }
  return n
}

/**
 * The rotation q (x, y, z, w into f[F_Q..]) that best maps the centred source points onto the
 * centred targets, from the cross-covariance S in f[F_S..]: the eigenvector of Horn's symmetric
 * 4×4 matrix with the largest eigenvalue, by shifted power iteration from the identity (so an
 * undetermined rotation, e.g. one pin, stays the identity).
 */
function hornRotation(f: Float64Array): void {
  const sxx = f[F_S], sxy = f[F_S + 1], sxz = f[F_S + 2]
  const syx = f[F_S + 3], syy = f[F_S + 4], syz = f[F_S + 5]
  const szx = f[F_S + 6], szy = f[F_S + 7], szz = f[F_S + 8]
  // order (w, x, y, z)
  const N = F_N
  f[N] = sxx + syy + szz
  f[N + 1] = syz - szy
  f[N + 2] = szx - sxz
  f[N + 3] = sxy - syx
  f[N + 5] = sxx - syy - szz
  f[N + 6] = sxy + syx
  f[N + 7] = szx + sxz
  f[N + 10] = -sxx + syy - szz
  f[N + 11] = syz + szy
  f[N + 15] = -sxx - syy + szz
  f[N + 4] = f[N + 1]
  f[N + 8] = f[N + 2]
  f[N + 12] = f[N + 3]
  f[N + 9] = f[N + 6]
  f[N + 13] = f[N + 7]
  f[N + 14] = f[N + 11]
  let shift = 0
  for (let k = 0; k < 9; k++) shift += Math.abs(f[F_S + k])
  if (!(shift > 0) || !Number.isFinite(shift)) return
  for (let k = 0; k < 4; k++) f[N + 5 * k] += shift // all eigenvalues ≥ 0 now
  // (N + shift)^(2^48), rescaled each time, is a multiple of the projector onto the top eigenspace
  const M = F_M
  for (let it = 0; it < 48; it++) {
    let big = 0
    for (let r = 0; r < 4; r++) {
      for (let col = 0; col < 4; col++) {
        let v = 0
        for (let k = 0; k < 4; k++) v += f[N + 4 * r + k] * f[N + 4 * k + col]
        f[M + 4 * r + col] = v
        if (Math.abs(v) > big) big = Math.abs(v)
      }
    }
    if (!(big > 0) || !Number.isFinite(big)) return
    for (let k = 0; k < 16; k++) f[N + k] = f[M + k] / big
  }
  // project the identity (column 0); if the best rotation is a half turn away from it, the
  // identity has no component there: take the strongest column instead
  let best = 0, bestL = 0, l0 = 0
  for (let col = 0; col < 4; col++) {
    const l = f[N + col] ** 2 + f[N + 4 + col] ** 2 + f[N + 8 + col] ** 2 + f[N + 12 + col] ** 2
    if (col === 0) l0 = l
    if (l > bestL) {
      best = col
      bestL = l
    }
  }
  if (l0 > 1e-12 * bestL) {
    best = 0
    bestL = l0
  }
  if (!(bestL > 0)) return
  const inv = 1 / Math.sqrt(bestL)
  const w = f[N + best] * inv, x = f[N + 4 + best] * inv, y = f[N + 8 + best] * inv, z = f[N + 12 + best] * inv
  f[F_Q] = x
  f[F_Q + 1] = y
  f[F_Q + 2] = z
  f[F_Q + 3] = w
}
