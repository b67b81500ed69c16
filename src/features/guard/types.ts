/** Guard settings, per world (defaults for new cloths) or per cloth. */
export interface ClothGuardOptions {
  /** Master switch. Default true. */
  enabled?: boolean
  /** Reset a cloth whose positions or velocities are NaN or infinite. Default true. */
  finite?: boolean
  /**
   * Reset a cloth with a particle farther than `bounds` × its size from the box around its pinned
   * particles (a cloth without pins: wider than `bounds` × its size). The size is the longest
   * shortest path along the cloth's edges at rest. Default 2 (every edge at twice its length);
   * false turns the test off.
   */
  bounds?: number | false
  /**
   * Reset a cloth whose rms particle speed relative to its mean velocity exceeds this, m/s (a torn
   * cloth: each particle relative to its own piece's mean velocity).
   * Default: half the world's `maxSpeed` (125 m/s). false turns the test off.
   */
  speed?: number | false
  /** Steps between copies of the last good pose (1 = every step, the default). */
  snapshotInterval?: number
}

/** Why the guard reset a cloth. */
export type ClothResetReason = 'nonfinite' | 'bounds' | 'speed'

/** One guard reset. */
export interface ClothResetEvent {
  /** The cloth entity. */
  cloth: number
  reason: ClothResetReason
  /** The world's step counter (`getClothStats(world).steps`) when it happened. */
  step: number
  /** The first non-finite particle, the one farthest out of bounds, or the fastest one. */
  particle: number
  /** 'snapshot': the last good pose was restored; 'rest': the rest shape (the snapshot failed too). */
  restoredTo: 'snapshot' | 'rest'
}

/** Resolved guard settings. */
export interface GuardSettings {
  enabled: boolean
  finite: boolean
  bounds: number | false
  speed: number | false
  snapshotInterval: number
}

/** Guard state of one cloth (allocated with the cloth). */
export interface ClothGuardState {
  settings: GuardSettings
  /** Thresholds for the check kernel (see `kernels/guard.ts`). */
  params: Float64Array
  /** Longest shortest path along the cloth's edges at rest, m. */
  size: number
  /** Positions at the last good step, and how many particles they cover. */
  safe: Float64Array
  safeCount: number
  /** Positions at creation (the rest shape as placed in the world; torn-off particles added as they appear). */
  rest: Float64Array
  /** Per-piece scratch for the check of a cloth in several pieces (`PIECE_STRIDE` per piece, see `kernels/guard.ts`). */
  pieceBox: Float64Array
  /** Good steps since the last copy into `safe`. */
  sinceSafe: number
  /** Consecutive failed checks (0 after a good step). */
  failStreak: number
}

/** Per-world guard state. */
export interface GuardWorld {
  defaults: GuardSettings
  listeners: ((event: ClothResetEvent) => void)[]
  /** The last `EVENT_CAPACITY` resets, a ring buffer of plain fields. */
  evCloth: Int32Array
  evReason: Uint8Array
  evStep: Float64Array
  evParticle: Int32Array
  evRest: Uint8Array
  /** Ring start and fill. */
  evHead: number
  evCount: number
  /** Resets raised during the current guard phase (delivered to listeners at its end). */
  raised: number
  /** The object handed to listeners (reused: copy what you keep). */
  event: ClothResetEvent
}

export const EVENT_CAPACITY = 64
export const REASONS: readonly ClothResetReason[] = ['nonfinite', 'nonfinite', 'bounds', 'speed']
