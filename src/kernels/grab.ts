import { P_INV_H2 } from './params'

/**
 * Grab constraints: soft point constraints that pull a particle toward a target point, one block of
 * `GRAB_STRIDE` doubles per grab. The layout is shared with `src/features/grab/`, which fills the
 * targets and reads the forces back.
 */
/** Requested target xyz (set by `moveGrab`). */
export const G_TO = 0
/** Where the target stood at the last frame sample, carried by teleports since (the frame's motion starts there). */
export const G_FRAME = 3
/** Target at the start and at the end of the current fixed step. */
export const G_STEP_FROM = 6
export const G_STEP_TO = 9
/** Target of the current substep. */
export const G_AT = 12
/** Compliance, m/N (the inverse of the grip's stiffness). */
export const G_COMPLIANCE = 15
/** Largest force the grab applies, N. */
export const G_MAX_FORCE = 16
/** Multiplier of the current substep, xyz (position level, kg·m): the substep's force is λ/h². */
export const G_LAMBDA = 17
/** Sum of the step's substep multipliers, xyz. */
export const G_IMPULSE = 20
/** Mean force of the last finished step, xyz, N. */
export const G_FORCE = 23
/** The requested target at the last frame sample (the next frame's motion starts there). */
export const G_SAMPLE = 26
export const GRAB_STRIDE = 29

/**
 * One Gauss-Seidel pass over `count` grabs. Each is the vector constraint C = x − target on its
 * particle with compliance α (XPBD: Δλ = (−C − α̃λ)/(w + α̃), α̃ = α/h², Δx = w·Δλ), its accumulated
 * multiplier clamped to |λ| ≤ maxForce·h², so the force λ/h² never exceeds `maxForce`. A pinned
 * particle (w = 0) is left alone.
 */
export function solveGrabs(
  pos: Float64Array,
  invMass: Float64Array,
  particle: Int32Array,
  data: Float64Array,
  count: number,
  p: Float64Array,
): void {
  const invH2 = p[P_INV_H2]
  for (let g = 0; g < count; g++) {
    const i = particle[g]
    const w = invMass[i]
    if (w === 0) continue
    const o = GRAB_STRIDE * g
    const at = data[o + G_COMPLIANCE] * invH2
    const pi = 3 * i
    const lx = data[o + G_LAMBDA], ly = data[o + G_LAMBDA + 1], lz = data[o + G_LAMBDA + 2]
    const inv = 1 / (w + at)
    let nx = lx + (data[o + G_AT] - pos[pi] - at * lx) * inv
    let ny = ly + (data[o + G_AT + 1] - pos[pi + 1] - at * ly) * inv
    let nz = lz + (data[o + G_AT + 2] - pos[pi + 2] - at * lz) * inv
    const lim = data[o + G_MAX_FORCE] / invH2
    const n2 = nx * nx + ny * ny + nz * nz
    if (n2 > lim * lim) {
      const s = lim / Math.sqrt(n2)
      nx *= s
      ny *= s
      nz *= s
    }
    pos[pi] += w * (nx - lx)
    pos[pi + 1] += w * (ny - ly)
    pos[pi + 2] += w * (nz - lz)
    data[o + G_LAMBDA] = nx
    data[o + G_LAMBDA + 1] = ny
    data[o + G_LAMBDA + 2] = nz
  }
}
