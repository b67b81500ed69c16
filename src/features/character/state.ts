import { newArray } from '../../core/shared'
import { BLEND, FRAME_PARAMS, LIMITS, L_MAX, L_RADIUS, REF_PARAMS, RIGID } from '../../kernels/motion'
import { MOTION, SETTINGS, WORK, type ClothCharacter, type ClothSkin } from './types'

/**
 * Character state with zeroed settings and arrays for a capacity of P particles (the caller fills
 * them). Its arrays are `newArray`s: in shared memory while a threaded world exists, and a new
 * layout for the workers (see `src/core/shared.ts`).
 */
export function blankCharacter(P: number): ClothCharacter {
  return {
    frame: 0,
    frameSlot: -1,
    inertia: false,
    settings: newArray(Float64Array, SETTINGS),
    motion: newArray(Float64Array, MOTION),
    work: newArray(Float64Array, WORK),
    frameParams: newArray(Float64Array, FRAME_PARAMS),
    rest: newArray(Float64Array, 3 * P),
    restNormal: newArray(Float64Array, 3 * P),
    ref: newArray(Float32Array, BLEND * P),
    bind: newArray(Float32Array, RIGID * P),
    limitHeld: newArray(Int32Array, P + 1),
    start: newArray(Float64Array, 3 * P),
    lim: unconstrained(newArray(Float32Array, LIMITS * P)),
    refParams: newArray(Float64Array, REF_PARAMS),
    constrained: false,
    drive: null,
    held: newArray(Uint8Array, P),
    heldList: newArray(Int32Array, P),
    heldCount: 0,
    skin: null,
  }
}

/** A skin of `nb` bones (untracked) with joints and weights for a capacity of P particles. */
export function blankSkin(nb: number, P: number): ClothSkin {
  return {
    bones: newArray(Int32Array, nb),
    slots: newArray(Int32Array, nb).fill(-1),
    bind: newArray(Float64Array, 10 * nb),
    pose: newArray(Float64Array, 10 * nb),
    matrices: newArray(Float64Array, 12 * nb),
    matricesFrom: newArray(Float64Array, 12 * nb),
    joints: newArray(Int32Array, 4 * P),
    weights: newArray(Float64Array, 4 * P),
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
