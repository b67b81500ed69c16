/**
 * Health check of one cloth after a step (the explosion guard's per-step test), in one pass over
 * positions and velocities. Thresholds come from a per-cloth parameter block (slots below) so the
 * call passes no doubles and allocates nothing.
 *
 * - finite: every position and velocity is a finite number;
 * - bounds: every particle lies within `G_REACH` metres of the box around the pinned particles
 *   (inverse mass 0) and the `G_ANCHOR` box (a character cloth's reference pose: where its motion
 *   constraints hold it); a cloth without either may span at most `G_REACH` along each axis;
 * - speed: the rms particle speed relative to the cloth's mean velocity is at most √`G_SPEED2`.
 *   (Relative: a cape on a fast vehicle moves fast as a whole; an exploding one moves apart.)
 *
 * Particles with `skip[i]` = 1 (vertices no triangle uses: no part of the cloth) are left out of
 * every test.
 */

/** 1 to test finiteness, 0 to skip. */
export const G_FINITE = 0
/** Allowed distance beyond the pinned particles' box (or extent of an unpinned cloth), m; 0 = off. */
export const G_REACH = 1
/** Square of the allowed rms relative speed, m²/s²; 0 = off. */
export const G_SPEED2 = 2
/** Measured by the last check: rms relative speed², m²/s² (diagnostics). */
export const G_OUT_SPEED2 = 3
/** Measured by the last check: how far the cloth reached beyond the allowed region, m (≤ 0: inside). */
export const G_OUT_EXCESS = 4
/**
 * A box the cloth is held to besides its pins (min xyz, max xyz, m): a cloth with motion
 * constraints, its reference pose at the end of the step. Empty (min > max) otherwise.
 */
export const G_ANCHOR = 5
export const GUARD_PARAM_COUNT = 11

/** Empties the `G_ANCHOR` box of a threshold block; returns the block. */
export function clearGuardAnchor(g: Float64Array): Float64Array {
  g[G_ANCHOR] = g[G_ANCHOR + 1] = g[G_ANCHOR + 2] = Infinity
  g[G_ANCHOR + 3] = g[G_ANCHOR + 4] = g[G_ANCHOR + 5] = -Infinity
  return g
}

/** Check results. */
export const HEALTH_OK = 0
export const HEALTH_NONFINITE = 1
export const HEALTH_BOUNDS = 2
export const HEALTH_SPEED = 3

export function checkClothHealth(
  pos: Float64Array,
  vel: Float64Array,
  invMass: Float64Array,
  count: number,
  g: Float64Array,
  skip: Uint8Array | null = null,
): number {
  // every parameter is read on every call (a typed-array read first met in optimized code on a
  // rare path deoptimizes it)
  const finite = g[G_FINITE], reach = g[G_REACH], speed2 = g[G_SPEED2]
  let bad = 0
  let minX = Infinity, minY = Infinity, minZ = Infinity
  let maxX = -Infinity, maxY = -Infinity, maxZ = -Infinity
  let pMinX = g[G_ANCHOR], pMinY = g[G_ANCHOR + 1], pMinZ = g[G_ANCHOR + 2]
  let pMaxX = g[G_ANCHOR + 3], pMaxY = g[G_ANCHOR + 4], pMaxZ = g[G_ANCHOR + 5]
  let sx = 0, sy = 0, sz = 0, s2 = 0
  let n = 0
  for (let i = 0; i < count; i++) {
    if (skip !== null && skip[i] === 1) continue
    n++
    const j = 3 * i
    const x = pos[j], y = pos[j + 1], z = pos[j + 2]
    const vx = vel[j], vy = vel[j + 1], vz = vel[j + 2]
    // NaN or ±Infinity anywhere makes the sum × 0 NaN; finite values add exactly 0
    bad += (x + y + z + vx + vy + vz) * 0
    if (x < minX) minX = x
    if (x > maxX) maxX = x
    if (y < minY) minY = y
    if (y > maxY) maxY = y
    if (z < minZ) minZ = z
    if (z > maxZ) maxZ = z
    if (invMass[i] === 0) {
      if (x < pMinX) pMinX = x
      if (x > pMaxX) pMaxX = x
      if (y < pMinY) pMinY = y
      if (y > pMaxY) pMaxY = y
      if (z < pMinZ) pMinZ = z
      if (z > pMaxZ) pMaxZ = z
    }
    sx += vx
    sy += vy
    sz += vz
    s2 += vx * vx + vy * vy + vz * vz
  }
  if (n === 0) return HEALTH_OK
  const nonFinite = bad !== 0
  const testFinite = finite !== 0
  if (nonFinite && testFinite) return HEALTH_NONFINITE
  // every subtraction runs on every call (no arithmetic behind a rarely taken branch: optimized
  // code that meets an operation it never saw run deoptimizes, and deoptimizing allocates)
  const ex = maxX - minX, ey = maxY - minY, ez = maxZ - minZ
  const lx = pMinX - minX, hx = maxX - pMaxX, ly = pMinY - minY, hy = maxY - pMaxY, lz = pMinZ - minZ, hz = maxZ - pMaxZ
  const pinned = pMinX <= pMaxX
  const ax = pinned ? lx : ex, bx = pinned ? hx : 0
  const ay = pinned ? ly : ey, by = pinned ? hy : 0
  const az = pinned ? lz : ez, bz = pinned ? hz : 0
  // pinned: how far the cloth's box sticks out of the pinned particles' box; unpinned: its extent
  let excess = ax
  if (bx > excess) excess = bx
  if (ay > excess) excess = ay
  if (by > excess) excess = by
  if (az > excess) excess = az
  if (bz > excess) excess = bz
  excess -= reach
  g[G_OUT_EXCESS] = excess
  const inv = 1 / n
  const mx = sx * inv, my = sy * inv, mz = sz * inv
  const rel2 = s2 * inv - (mx * mx + my * my + mz * mz)
  g[G_OUT_SPEED2] = rel2
  if (reach > 0 && excess > 0) return HEALTH_BOUNDS
  if (speed2 > 0 && rel2 > speed2) return HEALTH_SPEED
  return HEALTH_OK
}

/** Doubles per piece in `checkPieceHealth`'s scratch. */
export const PIECE_STRIDE = 11

/**
 * `checkClothHealth` for a cloth in several pieces (torn): the same finite test over the whole
 * cloth; the speed test on each particle's speed relative to its own piece's mean velocity (pieces
 * blown apart by a storm fly at their own speeds; a runaway shows as motion within a piece); and
 * the bounds test per piece: a piece holding pinned particles must stay within
 * `G_REACH` of the box around all the cloth's pinned particles and its `G_ANCHOR` box (as the whole cloth did before it
 * tore, so a piece that has just torn off one pin while stretched toward another is not flagged),
 * and a piece without pins may span at most `G_REACH` along each axis: a piece torn off and falling
 * away is judged by its own shape, not by its distance from the pins it no longer hangs from.
 * `piece` labels particles [0, count) with pieces [0, pieceCount); `box` is scratch of
 * `PIECE_STRIDE` doubles per piece (min xyz, max xyz, pinned flag, velocity sum xyz, particles).
 *
 * One long function on purpose: a single pass over the particles gathers every piece's bounds and
 * momentum, then one pass over the pieces judges them; split into calls, the per-particle loop
 * would pass doubles across call boundaries.
 */
export function checkPieceHealth(
  pos: Float64Array,
  vel: Float64Array,
  invMass: Float64Array,
  count: number,
  piece: Int32Array,
  pieceCount: number,
  box: Float64Array,
  g: Float64Array,
  skip: Uint8Array | null = null,
): number {
  const finite = g[G_FINITE], reach = g[G_REACH], speed2 = g[G_SPEED2]
  for (let p = 0; p < pieceCount; p++) {
    const o = PIECE_STRIDE * p
    box[o] = box[o + 1] = box[o + 2] = Infinity
    box[o + 3] = box[o + 4] = box[o + 5] = -Infinity
    box[o + 6] =
      box[o + 7] =
      box[o + 8] =
      box[o + 9] =
      box[o + 10] =
        0
  }
  let bad = 0
  let pMinX = g[G_ANCHOR], pMinY = g[G_ANCHOR + 1], pMinZ = g[G_ANCHOR + 2]
  let pMaxX = g[G_ANCHOR + 3], pMaxY = g[G_ANCHOR + 4], pMaxZ = g[G_ANCHOR + 5]
  let s2 = 0
  let n = 0
  for (let i = 0; i < count; i++) {
    if (skip !== null && skip[i] === 1) continue
    n++
    const j = 3 * i
    const x = pos[j], y = pos[j + 1], z = pos[j + 2]
    const vx = vel[j], vy = vel[j + 1], vz = vel[j + 2]
    bad += (x + y + z + vx + vy + vz) * 0
    const o = PIECE_STRIDE * piece[i]
    if (x < box[o]) box[o] = x
    if (x > box[o + 3]) box[o + 3] = x
    if (y < box[o + 1]) box[o + 1] = y
    if (y > box[o + 4]) box[o + 4] = y
    if (z < box[o + 2]) box[o + 2] = z
    if (z > box[o + 5]) box[o + 5] = z
    if (invMass[i] === 0) {
      box[o + 6] = 1
      if (x < pMinX) pMinX = x
      if (x > pMaxX) pMaxX = x
      if (y < pMinY) pMinY = y
      if (y > pMaxY) pMaxY = y
      if (z < pMinZ) pMinZ = z
      if (z > pMaxZ) pMaxZ = z
    }
    box[o + 7] += vx
    box[o + 8] += vy
    box[o + 9] += vz
    box[o + 10]++
    s2 += vx * vx + vy * vy + vz * vz
  }
  if (n === 0) return HEALTH_OK
  if (bad !== 0 && finite !== 0) return HEALTH_NONFINITE
  let excess = -Infinity
  // Σ|v − v̄_piece|² = Σ|v|² − Σ_pieces |Σv|²/n
  let mean2 = 0
  for (let p = 0; p < pieceCount; p++) {
    const o = PIECE_STRIDE * p
    if (box[o] > box[o + 3]) continue // no particle (a vertex no triangle uses, skipped)
    const np = box[o + 10]
    mean2 += (box[o + 7] * box[o + 7] + box[o + 8] * box[o + 8] + box[o + 9] * box[o + 9]) / np
    const pinned = box[o + 6] === 1
    // pinned: how far the piece's box sticks out of the pins' box; unpinned: its extent
    const ax = pinned ? pMinX - box[o] : box[o + 3] - box[o], bx = pinned ? box[o + 3] - pMaxX : 0
    const ay = pinned ? pMinY - box[o + 1] : box[o + 4] - box[o + 1], by = pinned ? box[o + 4] - pMaxY : 0
    const az = pinned ? pMinZ - box[o + 2] : box[o + 5] - box[o + 2], bz = pinned ? box[o + 5] - pMaxZ : 0
    if (ax > excess) excess = ax
    if (bx > excess) excess = bx
    if (ay > excess) excess = ay
    if (by > excess) excess = by
    if (az > excess) excess = az
    if (bz > excess) excess = bz
  }
  excess -= reach
  g[G_OUT_EXCESS] = excess
  const rel2 = (s2 - mean2) / n
  g[G_OUT_SPEED2] = rel2
  if (reach > 0 && excess > 0) return HEALTH_BOUNDS
  if (speed2 > 0 && rel2 > speed2) return HEALTH_SPEED
  return HEALTH_OK
}
