import { GRAB_STRIDE, G_AT, G_FORCE, G_FRAME, G_IMPULSE, G_LAMBDA, G_SAMPLE, G_STEP_FROM, G_STEP_TO, G_TO } from '../../kernels/grab'
import { P_INV_H2 } from '../../kernels/params'
import { K_STEP_FRACTION, type ClothState, type ClothWorldState } from '../../world/state'

/**
 * Per-step and per-substep work of the grabs (see `api.ts`). The sync phase moves each grab's
 * target on to this step's slice of the frame's motion; the solve phase sets the substep's target
 * before the sweeps, runs the `solveGrabs` kernel in each sweep and books the substep's force after.
 */

/**
 * At a frame sample: the frame's motion of every grab target starts where the target was asked to
 * be at the last frame sample (carried by teleports since), as a pin target's starts at its last
 * sample. (Started where the last step left it, a step short of that sample by the time still in
 * the accumulator, a hand moving steadily was followed short by a share of each frame: at
 * 59.94 Hz a dragged sheet fell 1 m behind a hand at 2 m/s, then snapped to it.)
 */
export function beginGrabFrame(c: ClothState): void {
  const G = c.grab
  for (let g = 0; g < G.count; g++) {
    const o = GRAB_STRIDE * g
    for (let j = 0; j < 3; j++) G.data[o + G_FRAME + j] = G.data[o + G_SAMPLE + j]
  }
}

/**
 * At a frame sample, after the jumps carried the targets so far: the targets asked for now are the
 * next frame's start. A frozen cloth keeps its sample, which its thaw carries with it (sampled
 * while frozen, then carried by the walk it sat out, a hand's glide started 1.2 m ahead of it).
 */
export function sampleGrabTargets(c: ClothState): void {
  if (c.budget.frozen) return
  const G = c.grab
  for (let g = 0; g < G.count; g++) {
    const o = GRAB_STRIDE * g
    for (let j = 0; j < 3; j++) G.data[o + G_SAMPLE + j] = G.data[o + G_TO + j]
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

/**
 * At the step's first collide phase (after `advanceGrabs`): how far the grabbed particles are from where their
 * hands have them at the step's end, the farthest into out[o], for the collider broadphase (see
 * `pinTravel`: a hand yanking a sheet 0.3 m toward a ball its bounds did not reach dragged it
 * 37 mm inside).
 */
export function grabTravel(c: ClothState, out: Float64Array, o: number): void {
  const G = c.grab, pos = c.pos
  let far2 = 0
  for (let g = 0; g < G.count; g++) {
    const d = GRAB_STRIDE * g + G_STEP_TO, i = 3 * G.particle[g]
    const dx = G.data[d] - pos[i], dy = G.data[d + 1] - pos[i + 1], dz = G.data[d + 2] - pos[i + 2]
    const d2 = dx * dx + dy * dy + dz * dz
    if (d2 > far2) far2 = d2
  }
  if (Math.sqrt(far2) > out[o]) out[o] = Math.sqrt(far2)
}
