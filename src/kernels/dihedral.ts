import { P_INV_H2 } from './params'

/**
 * XPBD dihedral bending over hinges [start, end). Layout per hinge (see `ClothTopology`): e0, e1 on
 * the shared edge, w0 the wing of triangle A = (e0, e1, w0), w1 the wing of triangle B = (e1, e0, w1).
 *
 * With e = x1 − x0, nA = e × (x_w0 − x0), nB = (x_w1 − x0) × e, the signed angle is
 * θ = atan2((nA × nB)·ê, nA·nB) (0 when flat; atan2 instead of acos, so no NaN from a cosine that
 * rounds past ±1 and a sign at every angle). Its gradients (Bridson et al. 2003) are, with
 * uA = nA/|nA|², uB = nB/|nB|²:
 *
 *   ∇w0 = −|e|·uA        ∇w1 = −|e|·uB
 *   ∇e0 = ((x1 − x_w0)·ê)·uA + ((x1 − x_w1)·ê)·uB
 *   ∇e1 = ((x_w0 − x0)·ê)·uA + ((x_w1 − x0)·ê)·uB
 *
 * θ is negative when the wings fold toward the front (the side the triangle normals face).
 * C = θ − θ_rest wrapped into [−π, π]. Guards (after Jolt): a hinge whose edge or either triangle
 * has collapsed (height below 1e-6 of the edge) is skipped, as is a vanishing denominator.
 *
 * @param side 0 resists both fold directions; +1 only C > 0; −1 only C < 0 (asymmetric bending)
 * @param lambda accumulated multipliers (zero them at the substep start), or null to solve each
 *   iteration from zero (one iteration per substep, or classic PBD)
 */
export function solveDihedrals(
  pos: Float64Array,
  invMass: Float64Array,
  ids: Int32Array,
  restAngle: Float64Array,
  compliance: Float64Array,
  lambda: Float64Array | null,
  side: number,
  params: Float64Array,
  start: number,
  end: number,
): void {
  const invH2 = params[P_INV_H2]
  for (let h = start; h < end; h++) {
    const i0 = ids[4 * h], i1 = ids[4 * h + 1], i2 = ids[4 * h + 2], i3 = ids[4 * h + 3]
    const w0 = invMass[i0], w1 = invMass[i1], w2 = invMass[i2], w3 = invMass[i3]
    if (w0 + w1 + w2 + w3 === 0) continue
    const lam = lambda === null ? 0 : lambda[h]
    const p0 = 3 * i0, p1 = 3 * i1, p2 = 3 * i2, p3 = 3 * i3
    const x0 = pos[p0], y0 = pos[p0 + 1], z0 = pos[p0 + 2]
    const ex = pos[p1] - x0, ey = pos[p1 + 1] - y0, ez = pos[p1 + 2] - z0
    const ax = pos[p2] - x0, ay = pos[p2 + 1] - y0, az = pos[p2 + 2] - z0
    const bx = pos[p3] - x0, by = pos[p3 + 1] - y0, bz = pos[p3 + 2] - z0
    const e2 = ex * ex + ey * ey + ez * ez
    const nAx = ey * az - ez * ay, nAy = ez * ax - ex * az, nAz = ex * ay - ey * ax
    const nBx = by * ez - bz * ey, nBy = bz * ex - bx * ez, nBz = bx * ey - by * ex
    const nA2 = nAx * nAx + nAy * nAy + nAz * nAz
    const nB2 = nBx * nBx + nBy * nBy + nBz * nBz
    const tiny = 1e-12 * e2 * e2
    if (e2 < 1e-18 || nA2 <= tiny || nB2 <= tiny) continue
    const el = Math.sqrt(e2)
    const inv = 1 / el
    const cx = nAy * nBz - nAz * nBy, cy = nAz * nBx - nAx * nBz, cz = nAx * nBy - nAy * nBx
    const theta = Math.atan2((cx * ex + cy * ey + cz * ez) * inv, nAx * nBx + nAy * nBy + nAz * nBz)
    let C = theta - restAngle[h]
    if (C > Math.PI) C -= 2 * Math.PI
    else if (C < -Math.PI) C += 2 * Math.PI
    if (side !== 0 && C * side <= 0) continue
    const iA = 1 / nA2, iB = 1 / nB2
    // projections of the wings onto the edge direction
    const sA = (ax * ex + ay * ey + az * ez) * inv // (x_w0 − x0)·ê
    const sB = (bx * ex + by * ey + bz * ez) * inv // (x_w1 − x0)·ê
    const cA0 = (el - sA) * iA, cB0 = (el - sB) * iB // (x1 − x_w0)·ê / |nA|², ...
    const cA1 = sA * iA, cB1 = sB * iB
    const g0x = cA0 * nAx + cB0 * nBx, g0y = cA0 * nAy + cB0 * nBy, g0z = cA0 * nAz + cB0 * nBz
    const g1x = cA1 * nAx + cB1 * nBx, g1y = cA1 * nAy + cB1 * nBy, g1z = cA1 * nAz + cB1 * nBz
    const kA = -el * iA, kB = -el * iB
    const g2x = kA * nAx, g2y = kA * nAy, g2z = kA * nAz
    const g3x = kB * nBx, g3y = kB * nBy, g3z = kB * nBz
    const at = compliance[h] * invH2
    const den = w0 * (g0x * g0x + g0y * g0y + g0z * g0z) +
      w1 * (g1x * g1x + g1y * g1y + g1z * g1z) +
      w2 * (g2x * g2x + g2y * g2y + g2z * g2z) +
      w3 * (g3x * g3x + g3y * g3y + g3z * g3z) +
      at
    if (den < 1e-12) continue
    const dl = (-C - at * lam) / den
    if (lambda !== null) lambda[h] = lam + dl
    let f = w0 * dl
    pos[p0] += f * g0x
    pos[p0 + 1] += f * g0y
    pos[p0 + 2] += f * g0z
    f = w1 * dl
    pos[p1] += f * g1x
    pos[p1 + 1] += f * g1y
    pos[p1 + 2] += f * g1z
    f = w2 * dl
    pos[p2] += f * g2x
    pos[p2 + 1] += f * g2y
    pos[p2 + 2] += f * g2z
    f = w3 * dl
    pos[p3] += f * g3x
    pos[p3 + 1] += f * g3y
    pos[p3 + 2] += f * g3z
  }
}
