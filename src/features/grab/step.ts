import { GRAB_STRIDE, G_AT, G_FORCE, G_FRAME, G_IMPULSE, G_LAMBDA, G_STEP_FROM, G_STEP_TO, G_TO } from '../../kernels/grab'
import { P_INV_H2 } from '../../kernels/params'
import { K_STEP_FRACTION, type ClothState, type ClothWorldState } from '../../world/state'

/**
 * Per-step and per-substep work of the grabs (see `api.ts`). The sync phase moves each grab's
 * target on to this step's slice of the frame's motion; the solve phase sets the substep's target
 * before the sweeps, runs the `solveGrabs` kernel in each sweep and books the substep's force after.
 */

/** At a frame sample: the frame's motion of every grab target starts where the last step ended. */
export function beginGrabFrame(c: ClothState): void {
  const G = c.grab
  for (let g = 0; g < G.count; g++) {
    const o = GRAB_STRIDE * g
    for (let j = 0; j < 3; j++) G.data[o + G_FRAME + j] = G.data[o + G_STEP_TO + j]
  }
}

/**
 * Start of a fixed step the cloth runs: each target moves on to where the frame's motion has it at
 * the step's end (the step's fraction of the frame, as for pin targets).
 */
export function advanceGrabs(state: ClothWorldState, c: ClothState): void {
  const G = c.grab
  const f = state.kinematics.time[K_STEP_FRACTION]
  for (let g = 0; g < G.count; g++) {
    const o = GRAB_STRIDE * g
    for (let j = 0; j < 3; j++) {
      const a = G.data[o + G_FRAME + j], b = G.data[o + G_TO + j]
      G.data[o + G_STEP_FROM + j] = G.data[o + G_STEP_TO + j]
      G.data[o + G_STEP_TO + j] = f >= 1 ? b : a + (b - a) * f
    }
  }
}

/** Before the sweeps of local substep k of n: the substep's target, multipliers from zero. */
export function beginGrabSubstep(c: ClothState): void {
  const G = c.grab
  const u = (c.subIndex + 1) / c.substeps
  for (let g = 0; g < G.count; g++) {
    const o = GRAB_STRIDE * g
    for (let j = 0; j < 3; j++) {
      const a = G.data[o + G_STEP_FROM + j]
      G.data[o + G_AT + j] = a + (G.data[o + G_STEP_TO + j] - a) * u
      G.data[o + G_LAMBDA + j] = 0
    }
  }
}

/** After the sweeps: adds the substep's impulse; after the last substep, the step's mean force. */
export function endGrabSubstep(c: ClothState): void {
  const G = c.grab
  const last = c.subIndex === c.substeps - 1
  // mean force over the step: Σλ / (n·h²)
  const toForce = c.params[P_INV_H2] / c.substeps
  for (let g = 0; g < G.count; g++) {
    const o = GRAB_STRIDE * g
    for (let j = 0; j < 3; j++) {
      G.data[o + G_IMPULSE + j] += G.data[o + G_LAMBDA + j]
      if (!last) continue
      G.data[o + G_FORCE + j] = G.data[o + G_IMPULSE + j] * toForce
      G.data[o + G_IMPULSE + j] = 0
    }
  }
}
