/** Pins of one cloth (`ClothState.pins`). The pin data itself lives in the `Pin` store. */
export interface ClothPins {
  /** Pin entities holding the cloth, in creation order. */
  list: number[]
  /** Do not follow a pin target's jump at the next frame sample (set by `teleportCloth`). */
  skipTeleport: boolean
}
