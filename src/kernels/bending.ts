import { P_INV_H2 } from './params'

/**
 * Three-particle "line" bending, XPBD, over triples [start, end): the middle particle x1 of a
 * triple (x0, x1, x2) is kept at its rest distance r from the midpoint of its neighbours,
 *
 *   C = |d| − r,   d = x1 − (x0 + x2)/2,   ∇x1 = n,  ∇x0 = ∇x2 = −n/2   (n = d/|d|)
 *
 * On flat cloth r = 0 and C is the out-of-plane (or in-plane) kink of the line. Unlike a skip-one
 * spring, whose length changes only to second order when the middle particle moves sideways, C is
 * first order in that motion, so grid-scale zigzags are resisted: on a swaying 32×32 sheet the
 * grid-scale roughness drops from 0.55 mm to 0.05 mm (a dihedral hinge gets 0.02 mm at several
 * times the cost). Its compliance follows from the bending rigidity B: a kink d over segments of
 * length L is a curvature 2d/L², so α = L²/(4B) per triple on a square grid.
 *
 * A triple with r = 0 (every triple of a flat sheet) is solved as the vector constraint C = d,
 * whose energy ½|d|²/α is the same: Δλ = −(d + α̃λ)/(w + α̃) per component, with no square root,
 * no direction to normalise and no special case for a straight line; with λ starting at zero this
 * is exactly the correction of the scalar form. A triple with r > 0 (a curved rest shape) uses the
 * scalar form. Multipliers take three slots per triple (`lambda[3k..3k+2]`; the scalar form uses
 * the first).
 *
 * @param lambda accumulated multipliers, 3 per triple (zero them at the substep start), or null to
 *   solve each iteration from zero (one iteration per substep, or classic PBD)
 */
export function solveLineBending(
  pos: Float64Array,
  invMass: Float64Array,
  ids: Int32Array,
  rest: Float64Array,
  compliance: Float64Array,
  lambda: Float64Array | null,
  params: Float64Array,
  start: number,
  end: number,
): void {
  const invH2 = params[P_INV_H2]
  for (let k = start; k < end; k++) {
    const k3 = (3 * k) | 0
    const i0 = ids[k3], i1 = ids[(k3 + 1) | 0], i2 = ids[(k3 + 2) | 0]
    const w0 = invMass[i0], w1 = invMass[i1], w2 = invMass[i2]
    const ws = w1 + 0.25 * (w0 + w2)
    if (ws === 0) continue
    const a = (3 * i0) | 0, b = (3 * i1) | 0, c = (3 * i2) | 0
    const a1 = (a + 1) | 0, a2 = (a + 2) | 0, b1 = (b + 1) | 0, b2 = (b + 2) | 0, c1 = (c + 1) | 0, c2 = (c + 2) | 0
    const ax = pos[a], ay = pos[a1], az = pos[a2]
    const bx = pos[b], by = pos[b1], bz = pos[b2]
    const cx = pos[c], cy = pos[c1], cz = pos[c2]
    const dx = bx - 0.5 * (ax + cx)
    const dy = by - 0.5 * (ay + cy)
    const dz = bz - 0.5 * (az + cz)
    const at = compliance[k] * invH2
    const r = rest[k]
    let gx: number, gy: number, gz: number
    if (r === 0) {
      const f = -1 / (ws + at)
      if (lambda === null) {
        gx = dx * f
        gy = dy * f
        gz = dz * f
      } else {
        const lx = lambda[k3], ly = lambda[(k3 + 1) | 0], lz = lambda[(k3 + 2) | 0]
        gx = (dx + at * lx) * f
        gy = (dy + at * ly) * f
        gz = (dz + at * lz) * f
        lambda[k3] = lx + gx
        lambda[(k3 + 1) | 0] = ly + gy
        lambda[(k3 + 2) | 0] = lz + gz
      }
    } else {
      const d2 = dx * dx + dy * dy + dz * dz
      if (d2 < 1e-24) continue // straight: no direction to correct along
      const d = Math.sqrt(d2)
      const lam = lambda === null ? 0 : lambda[k3]
      const dl = (r - d - at * lam) / (ws + at)
      if (lambda !== null) lambda[k3] = lam + dl
      const s = dl / d // correction per unit of d
      gx = s * dx
      gy = s * dy
      gz = s * dz
    }
    // all loads before any store (a store could alias a later load, which forces a reload)
    const s0 = -0.5 * w0, s2 = -0.5 * w2
    pos[b] = bx + w1 * gx
    pos[b1] = by + w1 * gy
    pos[b2] = bz + w1 * gz
    pos[a] = ax + s0 * gx
    pos[a1] = ay + s0 * gy
    pos[a2] = az + s0 * gz
    pos[c] = cx + s2 * gx
    pos[c1] = cy + s2 * gy
    pos[c2] = cz + s2 * gz
  }
}
