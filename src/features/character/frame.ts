import { quatToMatrix, relativeRotationAt } from '../../core/math'
import { F_A, F_C, F_ORIGIN, F_Q, meanMotion } from '../../kernels/motion'
import { P_DAMP, P_GX, P_H } from '../../kernels/params'
import type { ClothState, ClothWorldState } from '../../world/state'
import { trackedPose } from './reference'
import {
  FROM_CLOTH,
  M_PRIMED,
  M_POSE,
  M_V,
  M_VC,
  M_W,
  M_WC,
  S_ANGULAR,
  S_CENTRIFUGAL,
  S_LINEAR,
  S_MAX_ANGULAR,
  S_MAX_LINEAR,
  W_FROM,
  W_MEAN,
  W_M,
  W_N,
  W_P,
  W_PV,
  W_PVC,
  W_PW,
  W_PWC,
  W_R,
  W_TO,
  W_V,
  W_VC,
  W_W,
  W_WC,
  type ClothCharacter,
} from './types'

/**
 * Inertia in the character's frame.
 *
 * The cloth is simulated in world space, with the share of the frame's motion it must not feel
 * carried rigidly. Per substep, with u(x) = V + ω × (x − origin) the frame's velocity field, the
 * world-space equation of motion of a particle gets the extra acceleration
 *
 *   (1 − linear)·a_F + (1 − angular)·α × r + (1 − centrifugal)·(ω × (ω × r) + 2 ω × w)
 *
 * (a_F, α the frame's linear and angular acceleration, r = x − origin, w = v − u(x)), which is
 * what makes those terms vanish from the motion relative to the frame; damping acts on w. The
 * discrete form (kernels/motion.ts `predictInFrame`) uses exact rotations over each substep, so
 * with every share 0 a particle is carried exactly as if rigidly attached. Speed limits clamp the
 * velocities whose changes the cloth feels (V to maxLinearSpeed, ω to maxAngularSpeed); motion
 * beyond them is carried rigidly.
 *
 * The frame's motion is known per step: its pose at the end of the cloth's last step and at the
 * end of this one (the tracked `stepTo`, or the last pose for a frame that went away), lerped and
 * slerped across the substeps like pins, so V and ω are constant within a step and change at its
 * first substep.
 */

/**
 * Sync phase: this step's frame poses (into `work`), the frame's velocities and their felt parts,
 * and last step's velocities (the previous substep's, for the first substep's accelerations).
 * Afterwards the motion history holds this step's: its end pose and velocities.
 */
export function beginFrameStep(state: ClothWorldState, c: ClothState, ch: ClothCharacter): void {
  const w = ch.work, m = ch.motion, s = ch.settings
  for (let j = 0; j < 10; j++) w[W_FROM + j] = m[M_POSE + j]
  if (ch.frameSlot >= 0) trackedPose(state, ch.frameSlot, w, W_TO)
  else for (let j = 0; j < 10; j++) w[W_TO + j] = m[M_POSE + j]
  const T = c.h * c.substeps // the cloth's step (longer when it steps every n-th)
  for (let j = 0; j < 3; j++) w[W_V + j] = (w[W_TO + j] - w[W_FROM + j]) / T
  // ω = log(q_to · q_from⁻¹) / T, along the shortest arc
  relativeRotationAt(w, W_TO + 3, w, W_FROM + 3, w, W_R)
  let qx = w[W_R], qy = w[W_R + 1], qz = w[W_R + 2]
  const qw = w[W_R + 3]
  if (qw < 0) {
    qx = -qx
    qy = -qy
    qz = -qz
  }
  const sin = Math.sqrt(qx * qx + qy * qy + qz * qz)
  const f = sin > 1e-12 ? (2 * Math.atan2(sin, Math.abs(qw))) / (sin * T) : 2 / T
  w[W_W] = qx * f
  w[W_W + 1] = qy * f
  w[W_W + 2] = qz * f
  clamp(w, W_V, s, S_MAX_LINEAR, W_VC)
  clamp(w, W_W, s, S_MAX_ANGULAR, W_WC)
  const primed = m[M_PRIMED] === 1
  for (let j = 0; j < 3; j++) {
    w[W_PV + j] = primed ? m[M_V + j] : w[W_V + j]
    w[W_PW + j] = primed ? m[M_W + j] : w[W_W + j]
    w[W_PVC + j] = primed ? m[M_VC + j] : w[W_VC + j]
    w[W_PWC + j] = primed ? m[M_WC + j] : w[W_WC + j]
    m[M_V + j] = w[W_V + j]
    m[M_W + j] = w[W_W + j]
    m[M_VC + j] = w[W_VC + j]
    m[M_WC + j] = w[W_WC + j]
  }
  if (m[M_PRIMED] === FROM_CLOTH && ch.frameSlot >= 0) frameFromCloth(c, w)
  m[M_PRIMED] = 1
  for (let j = 0; j < 10; j++) m[M_POSE + j] = w[W_TO + j]
}

/**
 * The frame's last velocities for a new frame entity (`FROM_CLOTH`), which has no history: a cloth
 * whose mean velocity is nearer rest than the frame's velocity at its centre stood in a frame at
 * rest, and a character that starts moving in its first step in the frame has accelerated (taken
 * as steady, a still or swaying cape with shares 0 swung 19–76 cm RMS out of shape); a cloth moving
 * with the frame keeps the frame's motion in that step as steady (a cape running along with its
 * character in world space; a cloth drifting across a frame standing still is either).
 */
function frameFromCloth(c: ClothState, w: Float64Array): void {
  meanMotion(c.pos, c.vel, c.count, w, W_MEAN)
  // the frame's velocity at the cloth's centre: V + ω × (centre − origin)
  const rx = w[W_MEAN] - w[W_FROM], ry = w[W_MEAN + 1] - w[W_FROM + 1], rz = w[W_MEAN + 2] - w[W_FROM + 2]
  const ux = w[W_V] + w[W_W + 1] * rz - w[W_W + 2] * ry
  const uy = w[W_V + 1] + w[W_W + 2] * rx - w[W_W] * rz
  const uz = w[W_V + 2] + w[W_W] * ry - w[W_W + 1] * rx
  const vx = w[W_MEAN + 3], vy = w[W_MEAN + 4], vz = w[W_MEAN + 5]
  const dx = vx - ux, dy = vy - uy, dz = vz - uz
  const still = vx * vx + vy * vy + vz * vz, along = dx * dx + dy * dy + dz * dz
  if (!(still <= along)) return
  for (let j = 0; j < 3; j++) {
    w[W_PV + j] = 0
    w[W_PW + j] = 0
    w[W_PVC + j] = 0
    w[W_PWC + j] = 0
  }
}

/**
 * The felt parts of the frame's last velocities under the speed limits now set (when they change:
 * kept as clamped under the old ones, the next step took the difference for an acceleration, and
 * a strip on a hero cruising at 20 m/s jumped by 11.8 m/s when `maxLinearSpeed` went from 2 to ∞).
 */
export function clampFeltVelocities(ch: ClothCharacter): void {
  const m = ch.motion
  clamp(m, M_V, ch.settings, S_MAX_LINEAR, M_VC)
  clamp(m, M_W, ch.settings, S_MAX_ANGULAR, M_WC)
}

/**
 * w[oo..oo+2] = w[vo..vo+2] scaled down to length settings[slot] when longer. (Scalars travel in
 * arrays: a double passed to a call V8 does not inline is boxed, an allocation per step.)
 */
function clamp(w: Float64Array, vo: number, settings: Float64Array, slot: number, oo: number): void {
  const max = settings[slot]
  const x = w[vo], y = w[vo + 1], z = w[vo + 2]
  const l = Math.sqrt(x * x + y * y + z * z)
  const s = l > max ? max / l : 1
  w[oo] = x * s
  w[oo + 1] = y * s
  w[oo + 2] = z * s
}

/** Rotation matrix of exp(ω·h), ω at w[wo..], h = params[P_H], into w[W_R + 9·r..]. */
function turn(w: Float64Array, wo: number, params: Float64Array, r: number): void {
  const x = w[wo], y = w[wo + 1], z = w[wo + 2]
  const l = Math.sqrt(x * x + y * y + z * z)
  const half = 0.5 * l * params[P_H]
  const s = l > 1e-300 ? Math.sin(half) / l : 0
  const q = W_R + 36 // quaternion scratch after the four matrices
  w[q] = x * s
  w[q + 1] = y * s
  w[q + 2] = z * s
  w[q + 3] = Math.cos(half)
  quatToMatrix(w, q, w, W_R + 9 * r)
}

/** R₁R₀ and C₁C₀ (row-major 3×3 each), scratch of `frameSubstep`. */
const turns = new Float64Array(18)

/**
 * Predict phase: the frame kernel's parameters for local substep k of n (see `predictInFrame`).
 * With R₁ the frame's rotation this substep and R₀ the previous substep's (both over this h), the
 * carried velocity change at r is (R₁ + R₀ᵀ − 2I)·r/h in total, of which the angular-acceleration
 * part skew(ω₁ − ω₀) is felt in share `angular` and the rest (centrifugal) in share `centrifugal`;
 * the turn of the relative velocity, (R₁R₀ − I)·w, likewise in share `centrifugal` (the Coriolis
 * effect: w is measured against the frame's field of the previous substep, P·r, which is a
 * substep's turn behind; with R₁ alone a cloth moving in the frame felt (1 + share)/2 of it, and
 * one at share 0 drifting across a frame turning at 3 rad/s was 58 cm off its straight line after
 * a second). Felt parts use the clamped velocities. With u₀(x) = U₀ + P·r (P = (I − R₀ᵀ)/h) the
 * frame's velocity field in the previous substep, w = v − U₀ − P·r, and
 *
 *   v' = v + ΔV + M·r + N·w + g·h = (I + N)·v + (M − N·P)·r + (ΔV − N·U₀ + g·h)
 *
 * with N = d·((R₁R₀ − I) − centrifugal·(C₁C₀ − I)) − (1 − d)·I (d the damping factor, C felt).
 */
export function frameSubstep(c: ClothState, ch: ClothCharacter, k: number, n: number): void {
  const w = ch.work, s = ch.settings, F = ch.frameParams
  const p = c.params
  const h = p[P_H], d = p[P_DAMP]
  const sl = s[S_LINEAR], sa = s[S_ANGULAR], sc = s[S_CENTRIFUGAL]
  const f0 = k / n
  for (let j = 0; j < 3; j++) F[F_ORIGIN + j] = w[W_FROM + j] + (w[W_TO + j] - w[W_FROM + j]) * f0
  if (k >= 2) return // the rest is the same as at substep 1 (velocities change only between steps)
  // the previous substep's velocities: last step's at a step's first substep, else this step's
  const pv = k === 0 ? W_PV : W_V, pw = k === 0 ? W_PW : W_W, pvc = k === 0 ? W_PVC : W_VC, pwc = k === 0 ? W_PWC : W_WC
  turn(w, W_W, p, 0) // R₁
  turn(w, pw, p, 1) // R₀
  turn(w, W_WC, p, 2) // felt R₁
  turn(w, pwc, p, 3) // felt R₀
  const R1 = W_R, R0 = W_R + 9, C1 = W_R + 18, C0 = W_R + 27
  // R₁R₀ and its felt part C₁C₀: the turn of the relative velocity (see below)
  for (let i = 0; i < 3; i++) {
    for (let j = 0; j < 3; j++) {
      let r = 0, cc = 0
      for (let m = 0; m < 3; m++) {
        r += w[R1 + 3 * i + m] * w[R0 + 3 * m + j]
        cc += w[C1 + 3 * i + m] * w[C0 + 3 * m + j]
      }
      turns[3 * i + j] = r
      turns[9 + 3 * i + j] = cc
    }
  }
  // skew(ω₁ − ω₀) of the felt velocities: the angular-acceleration part
  const ax = w[W_WC] - w[pwc], ay = w[W_WC + 1] - w[pwc + 1], az = w[W_WC + 2] - w[pwc + 2]
  for (let i = 0; i < 3; i++) {
    for (let j = 0; j < 3; j++) {
      const e = i === j ? 1 : 0
      const ij = 3 * i + j, ji = 3 * j + i
      const total = (w[R1 + ij] + w[R0 + ji] - 2 * e) / h
      const feltTotal = (w[C1 + ij] + w[C0 + ji] - 2 * e) / h
      // skew(a)·r = a × r: row i, column j
      const ang = i === j ? 0 : ij === 1 ? -az : ij === 2 ? ay : ij === 3 ? az : ij === 5 ? -ax : ij === 6 ? -ay : ax
      w[W_M + ij] = total - (sa * ang + sc * (feltTotal - ang)) // M
      w[W_N + ij] = d * (turns[ij] - e - sc * (turns[9 + ij] - e)) - (1 - d) * e // N
      w[W_P + ij] = (e - w[R0 + ji]) / h // P
    }
  }
  for (let i = 0; i < 3; i++) {
    let nu = 0
    for (let j = 0; j < 3; j++) {
      const ij = 3 * i + j
      F[F_A + ij] = (i === j ? 1 : 0) + w[W_N + ij]
      let np = 0
      for (let m = 0; m < 3; m++) np += w[W_N + 3 * i + m] * w[W_P + 3 * m + j]
      F[F_Q + ij] = w[W_M + ij] - np
      nu += w[W_N + ij] * w[pv + j]
    }
    const dv = w[W_V + i] - w[pv + i] - sl * (w[W_VC + i] - w[pvc + i])
    F[F_C + i] = dv - nu + p[P_GX + i] * h
  }
}
