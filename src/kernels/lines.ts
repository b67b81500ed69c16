import { P_INV_H2 } from './params'

/**
 * Direct solve of the stretch along lines of edges (`ClothLines`, built by `src/model/lines.ts`):
 * each line's distance constraints C_k = |x_{k+1} − x_k| − r_k at once, one linearised XPBD step
 *
 *   (J W Jᵀ + α̃) Δλ = −C,   Δx = W Jᵀ Δλ,   α̃ = compliance / h²
 *
 * J W Jᵀ of a line is tridiagonal (diagonal w_k + w_{k+1}, off-diagonal −w_{k+1} n_k·n_{k+1} with
 * n_k the unit edge directions), so the solve is the Thomas algorithm: linear in the line's length.
 * A Gauss-Seidel sweep moves a correction one edge per pass; this moves it along the whole line in
 * one, which is what a swinging sheet's rows and columns need (tension travels along them faster
 * than a sweep carries it). Exact for a straight line; for a bent one a Newton step, which converges
 * quadratically (a 10-link zigzag 8 % stretched: 1.4 % after one step, 2e-4 after two).
 *
 * Two-sided like the sweep's distance constraints. A pinned particle (inverse mass 0) decouples the
 * line at it; a row that cannot move at all (both ends pinned, rigid) gets no correction. An edge
 * of zero length has no direction: it gets none either (the sweep's own loop keeps it bounded).
 * Multipliers start at 0 (one step: nothing carries over), so a compliant edge solved here after
 * the sweep has solved it too is held somewhat stiffer than its compliance alone would give.
 *
 * `n`, `cc`, `dd`: scratch of 3, 1 and 1 values per slot (slot k = the edge from ids[k] to ids[k+1]).
 */
export function solveLines(
  pos: Float64Array,
  invMass: Float64Array,
  start: Int32Array,
  ids: Int32Array,
  rest: Float64Array,
  compliance: Float64Array,
  params: Float64Array,
  lineCount: number,
  lambda: Float64Array | null,
  n: Float64Array,
  cc: Float64Array,
  dd: Float64Array,
): void {
  const invH2 = params[P_INV_H2]
  for (let q = 0; q < lineCount; q++) {
    const k0 = start[q], k1 = start[q + 1] - 1 // edges k0 .. k1 - 1
    // edge directions and the right-hand side −C
    for (let k = k0; k < k1; k++) {
      const a = 3 * ids[k], b = 3 * ids[k + 1]
      const dx = pos[b] - pos[a], dy = pos[b + 1] - pos[a + 1], dz = pos[b + 2] - pos[a + 2]
      const l = Math.sqrt(dx * dx + dy * dy + dz * dz)
      const inv = l > 1e-12 ? 1 / l : 0
      n[3 * k] = dx * inv
      n[3 * k + 1] = dy * inv
      n[3 * k + 2] = dz * inv
      // −C − α̃λ (λ accumulated over the substep's iterations, or 0 with one)
      dd[k] = (inv === 0 ? 0 : rest[k] - l) - (lambda === null ? 0 : compliance[k] * invH2 * lambda[k])
    }
    // forward elimination (Thomas): cc[k] = c'_k, dd[k] = d'_k; `off` is the row's raw
    // off-diagonal c_k, which is also the next row's sub-diagonal (the matrix is symmetric)
    let cPrev = 0, dPrev = 0, sub = 0
    for (let k = k0; k < k1; k++) {
      const wb = invMass[ids[k + 1]]
      const m = invMass[ids[k]] + wb + compliance[k] * invH2 - sub * cPrev
      const off = k + 1 < k1 ? -wb * (n[3 * k] * n[3 * k + 3] + n[3 * k + 1] * n[3 * k + 4] + n[3 * k + 2] * n[3 * k + 5]) : 0
      if (m > 1e-300) {
        cPrev = off / m
        dPrev = (dd[k] - sub * dPrev) / m
        sub = off
      } else {
        // both ends immovable and rigid: no correction, and no coupling (its off-diagonals are 0)
        cPrev = 0
        dPrev = 0
        sub = 0
      }
      cc[k] = cPrev
      dd[k] = dPrev
    }
    // back substitution, applying each edge's Δλ as it is found
    let x = 0
    for (let k = k1 - 1; k >= k0; k--) {
      x = dd[k] - cc[k] * x
      if (lambda !== null) lambda[k] += x
      const a = ids[k], b = ids[k + 1]
      const fa = invMass[a] * x, fb = invMass[b] * x
      const nx = n[3 * k], ny = n[3 * k + 1], nz = n[3 * k + 2]
      pos[3 * a] -= fa * nx
      pos[3 * a + 1] -= fa * ny
      pos[3 * a + 2] -= fa * nz
      pos[3 * b] += fb * nx
      pos[3 * b + 1] += fb * ny
      pos[3 * b + 2] += fb * nz
    }
  }
}
