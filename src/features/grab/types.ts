/**
 * Grabs of one cloth (`ClothState.grab`): soft point constraints pulling particles toward targets
 * (a hand, a mouse). Grow on `grabParticle` (API time); a step only reads and writes them.
 */
export interface ClothGrabs {
  /** Live grabs. */
  count: number
  /** Handle of each grab (unique in the world, never reused). */
  id: Int32Array
  /** Grabbed particle of each grab. */
  particle: Int32Array
  /** `GRAB_STRIDE` doubles per grab (see `kernels/grab.ts`): targets, grip settings, multipliers, force. */
  data: Float64Array
}

/** Per-world grab bookkeeping (`ClothWorldState.grab`). */
export interface GrabWorld {
  /** The next grab handle. */
  next: number
}
