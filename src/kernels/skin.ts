/**
 * Skinned reference poses of character cloth: rest positions and normals blended from several
 * bones (linear blend skinning). Matrices are row-major 3×4 (a 3×3 block then the translation
 * column: m0 m1 m2 t0 / m3 m4 m5 t1 / m6 m7 m8 t2, stored as [m0 m1 m2 m3 m4 m5 m6 m7 m8 t0 t1
 * t2]), 12 values each. Normals are transformed by the 3×3 blocks and renormalised (exact for
 * rotations and uniform scale); a degenerate normal becomes +z.
 */

/**
 * Linear blend skinning: Σ_k w_ik·(M_b·rest_i + t_b), b = joints[4i + k], the matrices at
 * mats[12b..], less the anchor at anchor[ao..ao+2] (float32 offsets from a nearby anchor keep
 * their precision), into out[o + stride·i ..]; the normal, the same blend of the 3×3 blocks
 * applied to restNormal_i and renormalised, into out[no + stride·i ..]. Zero weights are skipped.
 */
export function skinReference(
  mats: Float64Array,
  joints: Int32Array,
  weights: Float64Array,
  rest: Float64Array,
  restNormal: Float64Array,
  anchor: Float64Array,
  ao: number,
  out: Float32Array,
  o: number,
  no: number,
  stride: number,
  count: number,
): void {
  const gx = anchor[ao], gy = anchor[ao + 1], gz = anchor[ao + 2]
  for (let i = 0; i < count; i++) {
    const j = 3 * i
    const x = rest[j], y = rest[j + 1], z = rest[j + 2]
    const u = restNormal[j], v = restNormal[j + 1], w = restNormal[j + 2]
    let px = 0, py = 0, pz = 0, nx = 0, ny = 0, nz = 0
    for (let k = 4 * i; k < 4 * i + 4; k++) {
      const wt = weights[k]
      if (wt === 0) continue
      const b = 12 * joints[k]
      const a00 = mats[b],
        a01 = mats[b + 1],
        a02 = mats[b + 2],
        a10 = mats[b + 3],
        a11 = mats[b + 4],
        a12 = mats[b + 5],
        a20 = mats[b + 6],
        a21 = mats[b + 7],
        a22 = mats[b + 8]
      px += wt * (a00 * x + a01 * y + a02 * z + mats[b + 9])
      py += wt * (a10 * x + a11 * y + a12 * z + mats[b + 10])
      pz += wt * (a20 * x + a21 * y + a22 * z + mats[b + 11])
      nx += wt * (a00 * u + a01 * v + a02 * w)
      ny += wt * (a10 * u + a11 * v + a12 * w)
      nz += wt * (a20 * u + a21 * v + a22 * w)
    }
    const p = o + stride * i, q = no + stride * i
    out[p] = px - gx
    out[p + 1] = py - gy
    out[p + 2] = pz - gz
    const l2 = nx * nx + ny * ny + nz * nz
    const s = l2 > 1e-30 ? 1 / Math.sqrt(l2) : 0
    out[q] = nx * s
    out[q + 1] = ny * s
    out[q + 2] = l2 > 1e-30 ? nz * s : 1
  }
}
