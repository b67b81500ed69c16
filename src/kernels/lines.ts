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
 * Two-sided like the sweep's distance constraints. A pinned particle (inverse mass 0) splits the
 * line into segments. A segment held at both ends is projected edge by edge instead, swept both
 * ways several times (`projectSegment`): along a straight line between two held particles its
 * edges are one constraint more than its particles can meet (the pins fix its length), so the
 * system is singular, and nearly so when it sags a little; solved directly, a row 1 % too long
 * between two pins moved a particle 20 m, and such rows buzzed at metres per second for good. A
 * row that cannot move at all gets no correction; an edge of zero length has no direction and gets
 * none either. Multipliers start at the substep's accumulated `lambda` (null: at 0, one
 * iteration). `pass`: 0 takes the whole Newton step; the pipeline's passes take STEP_SHARE of it,
 * 1 in each iteration and 2 at the substep's end, after the tethers (see `solveOfCloth`), which
 * also leaves a segment held at both ends as it is when its ends are pulled farther apart than its
 * length (the tethers spread that stretch evenly).
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
  pass: number,
): void {
  for (let q = 0; q < lineCount; q++) {
    const k1 = start[q + 1] - 1 // the line's edges: start[q] .. k1 − 1
    for (let s0 = start[q]; s0 < k1;) {
      // a segment: edges s0 .. s1 − 1, the particles between them movable (the elimination finds
      // where it ends; it moves nothing, so a segment held at both ends is projected instead)
      const s1 = eliminateSegment(pos, invMass, ids, rest, compliance, params, lambda, n, cc, dd, s0, k1)
      if (invMass[ids[s0]] === 0 && invMass[ids[s1]] === 0) {
        if (pass !== 2 || !pulledTaut(pos, ids, rest, s0, s1))
          projectSegment(pos, invMass, ids, rest, compliance, params, lambda, dd, s0, s1)
      } else substituteSegment(pos, invMass, ids, lambda, n, cc, dd, s0, s1, pass)
      s0 = s1
    }
  }
}

/**
 * Whether a segment held at both ends is held farther apart than its rest lengths add up to (by
 * more than 0.1 %): no pose meets them all, and projected edge by edge it zigzags (see `solveLines`).
 */
function pulledTaut(pos: Float64Array, ids: Int32Array, rest: Float64Array, k0: number, k1: number): boolean {
  let length = 0
  for (let k = k0; k < k1; k++) length += rest[k]
  const a = 3 * ids[k0], b = 3 * ids[k1]
  const dx = pos[b] - pos[a], dy = pos[b + 1] - pos[a + 1], dz = pos[b + 2] - pos[a + 2]
  const reach = 1.001 * length
  return dx * dx + dy * dy + dz * dz > reach * reach
}

/** The smallest pivot of the elimination, as a share of its row's diagonal (see `eliminateSegment`). */
const FLOOR = 0.05

/**
 * The share of its Newton step each of the pipeline's line passes takes. In full, a sheet pulled
 * by a grab held out of its reach (the grab at its largest force) buzzed at 0.52 m/s at 4 substeps
 * for good, the lines' and the other constraints' corrections taking each other back every second
 * substep; at 0.95 it rests (0.015 m/s), and a compliant sheet still sags within 0.3 % of its
 * compliance (at 0.9: 1.1 %).
 */
const STEP_SHARE = 0.95

/**
 * The forward half of a segment's tridiagonal solve (see `solveLines`): from edge k0, each edge's
 * direction (into `n`) and right-hand side −C − α̃λ, and the elimination of the row before it,
 * whose off-diagonal −w·n_{k−1}·n_k needs this edge's direction (w: the particle they share); up to
 * the first held particle after ids[k0] or the line's end (edge `end` − 1). Returns the segment's
 * end k1 (its edges: k0 .. k1 − 1); cc[k] = c'_k and dd[k] = d'_k of the elimination (Thomas).
 * Each edge loads one new particle; the one it shares with the edge before is carried in registers.
 */
function eliminateSegment(
  pos: Float64Array,
  invMass: Float64Array,
  ids: Int32Array,
  rest: Float64Array,
  compliance: Float64Array,
  params: Float64Array,
  lambda: Float64Array | null,
  n: Float64Array,
  cc: Float64Array,
  dd: Float64Array,
  k0: number,
  end: number,
): number {
  const invH2 = params[P_INV_H2]
  // `sub`: the last row's raw off-diagonal, which is this row's sub-diagonal (the matrix is symmetric)
  let cPrev = 0, dPrev = 0, sub = 0
  let i = ids[k0]
  let wa = invMass[i]
  let ax = pos[3 * i], ay = pos[3 * i + 1], az = pos[3 * i + 2]
  let pnx = 0, pny = 0, pnz = 0, rhsPrev = 0, diagPrev = 0
  let k = k0
  for (;;) {
    i = ids[k + 1]
    const wb = invMass[i]
    const bx = pos[3 * i], by = pos[3 * i + 1], bz = pos[3 * i + 2]
    const dx = bx - ax, dy = by - ay, dz = bz - az
    const l = Math.sqrt(dx * dx + dy * dy + dz * dz)
    const inv = l > 1e-12 ? 1 / l : 0
    const nx = dx * inv, ny = dy * inv, nz = dz * inv
    n[3 * k] = nx
    n[3 * k + 1] = ny
    n[3 * k + 2] = nz
    const alpha = compliance[k] * invH2
    const rhs = (inv === 0 ? 0 : rest[k] - l) - (lambda === null ? 0 : alpha * lambda[k])
    const diag = wa + wb + alpha
    if (k > k0) {
      // row k − 1 (the pivot kept at FLOOR of its diagonal at least: a line folded back on
      // itself is close to singular, and its solve would throw particles far)
      let m = diagPrev - sub * cPrev
      if (m < FLOOR * diagPrev) m = FLOOR * diagPrev
      const off = -wa * (pnx * nx + pny * ny + pnz * nz)
      if (m > 1e-300) {
        cPrev = off / m
        dPrev = (rhsPrev - sub * dPrev) / m
        sub = off
      } else {
        cPrev = 0 // nothing to move: no correction, and no coupling
        dPrev = 0
        sub = 0
      }
      cc[k - 1] = cPrev
      dd[k - 1] = dPrev
    }
    pnx = nx
    pny = ny
    pnz = nz
    rhsPrev = rhs
    diagPrev = diag
    wa = wb
    ax = bx
    ay = by
    az = bz
    k++
    if (k === end || wb === 0) break
  }
  // the last row, with no off-diagonal
  let m = diagPrev - sub * cPrev
  if (m < FLOOR * diagPrev) m = FLOOR * diagPrev
  cc[k - 1] = 0
  dd[k - 1] = m > 1e-300 ? (rhsPrev - sub * dPrev) / m : 0
  return k
}

/**
 * The backward half: each edge's Δλ from the elimination of `eliminateSegment`, applied as it is
 * found (all of it with `pass` 0, else STEP_SHARE of it, see `solveLines`). Particle b of edge k
 * (ids[k + 1], at offset jb) is carried in registers from edge k + 1, which moved it first, and
 * stored once both have.
 */
function substituteSegment(
  pos: Float64Array,
  invMass: Float64Array,
  ids: Int32Array,
  lambda: Float64Array | null,
  n: Float64Array,
  cc: Float64Array,
  dd: Float64Array,
  k0: number,
  k1: number,
  pass: number,
): void {
  const share = pass === 0 ? 1 : STEP_SHARE
  let jb = 3 * ids[k1]
  let wb = invMass[ids[k1]]
  let bx = pos[jb], by = pos[jb + 1], bz = pos[jb + 2]
  let x = 0
  for (let k = k1 - 1; k >= k0; k--) {
    x = dd[k] - cc[k] * x
    const dl = share * x
    if (lambda !== null) lambda[k] += dl
    const a = ids[k]
    const ja = 3 * a
    const wa = invMass[a]
    const fa = wa * dl, fb = wb * dl
    const nx = n[3 * k], ny = n[3 * k + 1], nz = n[3 * k + 2]
    pos[jb] = bx + fb * nx
    pos[jb + 1] = by + fb * ny
    pos[jb + 2] = bz + fb * nz
    bx = pos[ja] - fa * nx
    by = pos[ja + 1] - fa * ny
    bz = pos[ja + 2] - fa * nz
    jb = ja
    wb = wa
  }
  pos[jb] = bx
  pos[jb + 1] = by
  pos[jb + 2] = bz
}

/**
 * How many times a segment held at both ends is swept, forward then back (see `projectSegment`).
 * Swept once forward, as the distance sweep does, the top row of a sheet released level between
 * its two corner pins stretched 9.4 % beside its right-hand pin (the error a one-way sweep carries
 * to its end) while every other edge stayed under 5 %; four times both ways, 4.8 %.
 */
const HELD_SWEEPS = 4

/**
 * A segment held at both ends: its edges k0 .. k1 − 1 projected one after another (XPBD), forward
 * and back HELD_SWEEPS times. Each edge's multiplier is accumulated over the sweeps (in the
 * substep's `lambda`, or from 0 in `scratch` without), so a compliant edge keeps its compliance
 * however often it is swept.
 */
function projectSegment(
  pos: Float64Array,
  invMass: Float64Array,
  ids: Int32Array,
  rest: Float64Array,
  compliance: Float64Array,
  params: Float64Array,
  lambda: Float64Array | null,
  scratch: Float64Array,
  k0: number,
  k1: number,
): void {
  const invH2 = params[P_INV_H2]
  let acc = lambda
  if (acc === null) {
    acc = scratch
    acc.fill(0, k0, k1)
  }
  const E = k1 - k0
  for (let t = 0; t < 2 * E * HELD_SWEEPS; t++) {
    const u = t % (2 * E)
    const k = u < E ? k0 + u : k1 - 1 - (u - E)
    const a = 3 * ids[k], b = 3 * ids[k + 1]
    const wa = invMass[ids[k]], wb = invMass[ids[k + 1]]
    const dx = pos[b] - pos[a], dy = pos[b + 1] - pos[a + 1], dz = pos[b + 2] - pos[a + 2]
    const l = Math.sqrt(dx * dx + dy * dy + dz * dz)
    const alpha = compliance[k] * invH2
    if (!(l > 1e-12) || !(wa + wb + alpha > 1e-300)) continue
    const dl = (rest[k] - l - alpha * acc[k]) / (wa + wb + alpha)
    acc[k] += dl
    const f = dl / l
    pos[a] -= wa * f * dx
    pos[a + 1] -= wa * f * dy
    pos[a + 2] -= wa * f * dz
    pos[b] += wb * f * dx
    pos[b + 1] += wb * f * dy
    pos[b + 2] += wb * f * dz
  }
}
