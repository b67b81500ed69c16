import { newArray } from '../core/shared'
/**
 * Scalar inputs of the kernels for one cloth's current substep, kept in a Float64Array rather
 * than passed as number arguments: V8 boxes a double passed to a function it does not inline
 * (a heap allocation per call, about 185 bytes per step before this), while a read from a typed
 * array allocates nothing. Slots:
 */
/** Substep length h, s. */
export const P_H = 0
/** 1/h. */
export const P_INV_H = 1
/** 1/h² (XPBD: α̃ = compliance/h²). */
export const P_INV_H2 = 2
/** Velocity factor for this substep, exp(−damping·h). */
export const P_DAMP = 3
/** Gravity, m/s². */
export const P_GX = 4
export const P_GY = 5
export const P_GZ = 6
/** Particle speed limit, m/s. */
export const P_MAX_SPEED = 7
/** Fraction of relative stretch velocity removed by the damping pass, 1 − exp(−rate·Δt). */
export const P_STRETCH_DAMP = 8
/** Fraction of the fixed step reached at the end of the current substep, (k + 1)/n (pins). */
export const P_STEP_FRACTION = 9
/** Output of `updateVelocities`: the largest squared particle speed of the substep, m²/s² (sleep test). */
export const P_MAX_V2 = 10
/** Fraction of the fixed step reached at the start of the current substep, k/n (character cloth). */
export const P_STEP_START = 11
export const PARAM_COUNT = 12

/** A zeroed parameter block. */
export function createKernelParams(): Float64Array {
  return newArray(Float64Array, PARAM_COUNT)
}

/** Fills the per-substep slots of a parameter block. */
export function setSubstepParams(
  p: Float64Array,
  h: number,
  damping: number,
  gravity: ArrayLike<number>,
  maxSpeed: number,
): void {
  p[P_H] = h
  p[P_INV_H] = 1 / h
  p[P_INV_H2] = 1 / (h * h)
  p[P_DAMP] = Math.exp(-damping * h)
  p[P_GX] = gravity[0]
  p[P_GY] = gravity[1]
  p[P_GZ] = gravity[2]
  p[P_MAX_SPEED] = maxSpeed
}
