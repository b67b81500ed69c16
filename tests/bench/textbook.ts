/**
 * The reference line of the benchmarks: textbook position-based dynamics written as a plain loop,
 * the way a C programmer would (and the solver notes measured it): a 1 m sheet of n×n particles,
 * structure-of-arrays Float32Array positions, distance constraints for the structural edges, both
 * quad diagonals and skip-one bending, generated row by row (so swept from the top row down), each
 * projected rigidly (stiffness 1) with a square root, Gauss-Seidel, `iterations` sweeps per
 * substep; velocities from the motion of the substep. No compliance, damping, tethers, pins other
 * than inverse mass 0, or allocation. Nothing here is used by the library.
 */
export interface Textbook {
  readonly n: number
  readonly count: number
  /** Distance constraints (pairs). */
  readonly constraints: number
  step(substeps: number, iterations: number): void
  /** Mean and max of max(0, |d|/rest − 1) over the structural edges. */
  stretch(out: { mean: number; max: number }): { mean: number; max: number }
}

/**
 * A sheet in the x-y plane hanging down from its top row (row 0 at y = 2), or lying level (its rows
 * running away along +z, released to swing down), pinned at its two top corners or its whole top row.
 */
export function createTextbook(n: number, pins: 'corners' | 'row', pose: 'hanging' | 'level' = 'hanging'): Textbook {
  const count = n * n
  const x = new Float32Array(count), y = new Float32Array(count), z = new Float32Array(count)
  const px = new Float32Array(count), py = new Float32Array(count), pz = new Float32Array(count)
  const vx = new Float32Array(count), vy = new Float32Array(count), vz = new Float32Array(count)
  const w = new Float32Array(count)
  const s = 1 / (n - 1)
  for (let r = 0; r < n; r++) {
    for (let c = 0; c < n; c++) {
      const i = r * n + c
      x[i] = c * s - 0.5
      y[i] = pose === 'hanging' ? 2 - r * s : 2
      z[i] = pose === 'hanging' ? 0 : r * s
      w[i] = 1 // equal masses: inverse masses only matter as ratios here
    }
  }
  if (pins === 'row') { for (let c = 0; c < n; c++) w[c] = 0 }
  else w[0] = w[n - 1] = 0
  const a: number[] = [], b: number[] = [], kind: number[] = []
  const add = (i: number, j: number, k: number) => {
    a.push(i)
    b.push(j)
    kind.push(k)
  }
  for (let r = 0; r < n; r++) {
    for (let c = 0; c < n; c++) {
      const i = r * n + c
      if (c + 1 < n) add(i, i + 1, 0)
      if (r + 1 < n) add(i, i + n, 0)
      if (r + 1 < n && c + 1 < n) {
        add(i, i + n + 1, 1)
        add(i + 1, i + n, 1)
      }
      if (c + 2 < n) add(i, i + 2, 2)
      if (r + 2 < n) add(i, i + 2 * n, 2)
    }
  }
  const m = a.length
  const ca = Int32Array.from(a), cb = Int32Array.from(b)
  const rest = new Float32Array(m)
  for (let k = 0; k < m; k++) rest[k] = Math.hypot(x[cb[k]] - x[ca[k]], y[cb[k]] - y[ca[k]], z[cb[k]] - z[ca[k]])
  const structural: number[] = []
  for (let k = 0; k < m; k++) if (kind[k] === 0) structural.push(k)
  const sk = Int32Array.from(structural)

  const substep = (h: number, iterations: number) => {
    const gh = -9.81 * h
    for (let i = 0; i < count; i++) {
      px[i] = x[i]
      py[i] = y[i]
      pz[i] = z[i]
      if (w[i] === 0) continue
      vy[i] += gh
      x[i] += vx[i] * h
      y[i] += vy[i] * h
      z[i] += vz[i] * h
    }
    for (let it = 0; it < iterations; it++) {
      for (let k = 0; k < m; k++) {
        const i = ca[k], j = cb[k]
        const wi = w[i], wj = w[j]
        const ws = wi + wj
        if (ws === 0) continue
        const dx = x[j] - x[i], dy = y[j] - y[i], dz = z[j] - z[i]
        const l = Math.sqrt(dx * dx + dy * dy + dz * dz)
        if (l < 1e-9) continue
        const f = (l - rest[k]) / (l * ws)
        x[i] += wi * f * dx
        y[i] += wi * f * dy
        z[i] += wi * f * dz
        x[j] -= wj * f * dx
        y[j] -= wj * f * dy
        z[j] -= wj * f * dz
      }
    }
    const inv = 1 / h
    for (let i = 0; i < count; i++) {
      vx[i] = (x[i] - px[i]) * inv
      vy[i] = (y[i] - py[i]) * inv
      vz[i] = (z[i] - pz[i]) * inv
    }
  }

  return {
    n,
    count,
    constraints: m,
    step(substeps: number, iterations: number) {
      const h = 1 / 60 / substeps
      for (let k = 0; k < substeps; k++) substep(h, iterations)
    },
    stretch(out) {
      let sum = 0, max = 0
      for (let q = 0; q < sk.length; q++) {
        const k = sk[q]
        const i = ca[k], j = cb[k]
        const e = Math.hypot(x[j] - x[i], y[j] - y[i], z[j] - z[i]) / rest[k] - 1
        if (e > 0) {
          sum += e
          if (e > max) max = e
        }
      }
      out.mean = sum / sk.length
      out.max = max
      return out
    },
  }
}
