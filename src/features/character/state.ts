import { BLEND, FRAME_PARAMS, LIMITS, L_MAX, L_RADIUS, REF_PARAMS } from '../../kernels/motion'
import { MOTION, SETTINGS, WORK, type ClothCharacter, type ClothSkin } from './types'

/** Character state with zeroed settings and arrays for a capacity of P particles (the caller fills them). */
export function blankCharacter(P: number): ClothCharacter {
  return {
    frame: 0,
    frameSlot: -1,
    inertia: false,
    settings: new Float64Array(SETTINGS),
    motion: new Float64Array(MOTION),
    work: new Float64Array(WORK),
    frameParams: new Float64Array(FRAME_PARAMS),
    rest: new Float64Array(3 * P),
    restNormal: new Float64Array(3 * P),
    ref: new Float32Array(BLEND * P),
    lim: unconstrained(new Float32Array(LIMITS * P)),
    refParams: new Float64Array(REF_PARAMS),
    constrained: false,
    drive: null,
    held: new Uint8Array(P),
    heldList: new Int32Array(P),
    heldCount: 0,
    skin: null,
  }
}

/** A skin of `nb` bones (untracked) with joints and weights for a capacity of P particles. */
export function blankSkin(nb: number, P: number): ClothSkin {
  return {
    bones: new Int32Array(nb),
    slots: new Int32Array(nb).fill(-1),
    bind: new Float64Array(10 * nb),
    pose: new Float64Array(10 * nb),
    matrices: new Float64Array(12 * nb),
    joints: new Int32Array(4 * P),
    weights: new Float64Array(4 * P),
  }
}

/** Max distance Infinity and no backstop (radius 0) for every particle of a limits array. */
export function unconstrained(lim: Float32Array): Float32Array {
  for (let o = 0; o < lim.length; o += LIMITS) {
    lim[o + L_MAX] = Infinity
    lim[o + L_RADIUS] = 0
  }
  return lim
}
