import { K_SCALED, type ClothWorldState } from './state'
import { jumpTest } from './kinematics'

/**
 * Sync phase, right after a frame sample (`sampleFrame`): an entity whose scale leapt, on some axis
 * more than doubling or falling under half of what its last step's change of scale predicts over
 * the frame's span, is marked K_SCALED (unless it jumped otherwise: then its scale history is made
 * the new scale here): the frame's steps take the
 * new scale at once instead of sweeping through the ones between (`beginKinematicStep`), as a
 * teleport of its position does not sweep. Swept, a ball on an offset whose body's scale snapped
 * from 1 to 6 in a frame ran through the curtain in front of it: 2596 % stretch, at 99 m/s; a box
 * on a body scaled 1 → 1000 swept 999 m up, through everything, and reset a cloth. Its jump record
 * is the identity (the cloths it carries stay where they are); sleepers near where it was wake as
 * for a teleport (`colliderReachedBeforeJump`: the sample before keeps the old scale).
 */
export function markScaleLeaps(state: ClothWorldState): void {
  const k = state.kinematics
  const span = jumpTest[0] // (the frame's span in steps, as `sampleFrame` left it)
  const live = k.live
  for (let q = 0; q < live.length; q++) {
    const slot = live[q]
    const so = 3 * slot
    let leapt = false
    for (let c = 0; c < 3 && !leapt; c++) {
      const predicted = k.scaleSampleFrom[so + c] + (k.scaleStepTo[so + c] - k.scaleStepFrom[so + c]) * span
      const now = k.scaleSampleTo[so + c]
      leapt = 2 * Math.abs(now - predicted) > Math.max(predicted, now)
    }
    if (!leapt) continue
    if (k.jumped[slot] !== 0) {
      // it jumped as well (a teleport, a hitch's carry): its scale history is the new one, so the
      // frame's steps do not sweep it (a respawn as a giant swept its ball through a curtain at
      // 99 m/s); sleepers near where it was are tested at the new scale
      for (let c = 0; c < 3; c++) k.scaleSampleFrom[so + c] = k.scaleStepTo[so + c] = k.scaleSampleTo[so + c]
      continue
    }
    k.jumped[slot] = K_SCALED
    const j = 10 * slot, o = 7 * slot
    k.jump[j] = k.sampleTo[o]
    k.jump[j + 1] = k.sampleTo[o + 1]
    k.jump[j + 2] = k.sampleTo[o + 2]
    k.jump[j + 3] = 0
    k.jump[j + 4] = 0
    k.jump[j + 5] = 0
    k.jump[j + 6] = 1
    k.jump[j + 7] = 0
    k.jump[j + 8] = 0
    k.jump[j + 9] = 0
  }
}
