/** Values of `ClothPins.hand`. */
export const HAND = 11

/** Pins of one cloth (`ClothState.pins`). The pin data itself lives in the `Pin` store. */
export interface ClothPins {
  /** Pin entities holding the cloth, in creation order. */
  list: number[]
  /** Do not follow a pin target's jump at the next frame sample (set by `teleportCloth`). */
  skipTeleport: boolean
  /**
   * With `skipTeleport`: the rigid motion `teleportCloth` moved the cloth by, as a record of 10
   * (centre, unit quaternion, translation: see `moveClothBy` in world/rigid.ts), then 1 (0: not
   * known, from an older snapshot).
   */
  hand: Float64Array
  /** True until the cloth's first step (or a restore): its particles lie where the game placed them. */
  fresh: boolean
  /**
   * A fresh cloth moved back by its first pin's target's motion since the last step
   * (`backdateNewCloth`): the record of 10 (see `hand`), then that target's slot + 1 (0: none), then
   * the cloth's `version` after the move.
   */
  backdate: Float64Array
}
