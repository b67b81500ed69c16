import { describe, expect, it } from 'vitest'
import {
  ClothMaterial,
  clothSolve,
  createCloth,
  defineMaterial,
  getClothState,
  getClothStretch,
  pinParticle,
  pinRow,
  stepCloth,
} from '../src/index'
import { allFinite, lowestY, makeWorld, momentum, rng } from './helpers'

/**
 * A sheet hanging from its top row (or two corners), in a world without the explosion guard: these
 * tests measure the solver alone, and the guard would put back into shape what they check (a 1 × 1
 * sheet of 32 rows without tethers hangs stably at up to 4× its length, past the guard's bounds).
 */
function hangingSheet(opts: { substeps: number; iterations: number; tethers?: boolean; solver?: 'xpbd' | 'pbd'; material?: any; resolution?: number; corners?: boolean }) {
  const world = makeWorld({ guard: false })
  const n = opts.resolution ?? 24
  const cloth = createCloth(world, {
    width: 1, height: 1, resolution: n, substeps: opts.substeps, iterations: opts.iterations,
    tethers: opts.tethers ?? false, solver: opts.solver, material: opts.material ?? 'cotton',
  })
  if (opts.corners) {
    pinParticle(world, cloth, 0)
    pinParticle(world, cloth, n - 1)
  } else pinRow(world, cloth, 0)
  return { world, cloth }
}

describe('integrator', () => {
  it('free fall matches the discrete closed form n(n+1)/2·g·h² after n substeps', () => {
    const world = makeWorld({ gravity: [0, -9.81, 0] })
    const substeps = 8
    const cloth = createCloth(world, { width: 1, height: 1, resolution: 4, substeps, damping: 0, tethers: false })
    const c = getClothState(world, cloth)
    const y0 = Float64Array.from({ length: c.count }, (_, i) => c.pos[3 * i + 1])
    stepCloth(world, 1 / 60)
    const h = 1 / 60 / substeps
    const expected = ((substeps * (substeps + 1)) / 2) * 9.81 * h * h
    for (let i = 0; i < c.count; i++) expect(y0[i] - c.pos[3 * i + 1]).toBeCloseTo(expected, 12)
    // and over 3 more frames (a rigid free fall: constraints stay satisfied and do nothing)
    stepCloth(world, 3 / 60)
    const n = 4 * substeps
    for (let i = 0; i < c.count; i++) expect(y0[i] - c.pos[3 * i + 1]).toBeCloseTo(((n * (n + 1)) / 2) * 9.81 * h * h, 9)
    for (let i = 0; i < c.count; i++) expect(c.vel[3 * i + 1]).toBeCloseTo(-9.81 * h * n, 9)
  })

  it('the constraint solve does not change an unpinned cloth’s total momentum', () => {
    const world = makeWorld({ gravity: [0, 0, 0] })
    const cloth = createCloth(world, { width: 1, height: 1, resolution: 12, damping: 0, bending: 'both', shear: 'distance' })
    const c = getClothState(world, cloth)
    const r = rng(7)
    // crumple it and give it random velocities, so every constraint kind is violated
    for (let i = 0; i < 3 * c.count; i++) {
      c.pos[i] += (r() - 0.5) * 0.05
      c.vel[i] = (r() - 0.5) * 2
    }
    const p0 = momentum(world, cloth)
    for (let f = 0; f < 30; f++) stepCloth(world, 1 / 60)
    const p1 = momentum(world, cloth)
    for (let k = 0; k < 3; k++) expect(p1[k]).toBeCloseTo(p0[k], 9)
    // and one solve in isolation: positions move, the mass-weighted centre does not
    const cm = () => {
      let x = 0, y = 0, z = 0, m = 0
      for (let i = 0; i < c.count; i++) {
        const mi = 1 / c.invMass[i]
        x += mi * c.pos[3 * i]; y += mi * c.pos[3 * i + 1]; z += mi * c.pos[3 * i + 2]; m += mi
      }
      return [x / m, y / m, z / m]
    }
    for (let i = 0; i < 3 * c.count; i++) c.pos[i] += (r() - 0.5) * 0.05
    const before = cm()
    const posBefore = Float64Array.from(c.pos)
    c.subIndex = 0
    clothSolve(world)
    expect(c.pos.some((v, i) => v !== posBefore[i])).toBe(true)
    const after = cm()
    for (let k = 0; k < 3; k++) expect(after[k]).toBeCloseTo(before[k], 12)
  })
})

describe('accuracy levers', () => {
  const stretchAfter = (substeps: number, iterations: number) => {
    const { world, cloth } = hangingSheet({ substeps, iterations, resolution: 32 })
    for (let f = 0; f < 120; f++) stepCloth(world, 1 / 60)
    expect(allFinite(world, cloth)).toBe(true)
    return getClothStretch(world, cloth).mean
  }

  it('stretch falls as iterations rise', () => {
    const s = [1, 8, 64].map((it) => stretchAfter(1, it))
    expect(s[1]).toBeLessThan(s[0] * 0.7)
    expect(s[2]).toBeLessThan(s[1] * 0.7)
  })

  it('stretch falls as substeps rise, faster than with iterations at the same cost', () => {
    const s = [1, 4, 16].map((sub) => stretchAfter(sub, 1))
    expect(s[1]).toBeLessThan(s[0] * 0.5)
    expect(s[2]).toBeLessThan(s[1] * 0.5)
    expect(s[2]).toBeLessThan(stretchAfter(1, 16))
  })

  it('XPBD: static sag of a compliant material changes < 5 % between 10 and 40 iterations; PBD’s does not hold', () => {
    const soft = defineMaterial({ name: 'soft rubber', stretchCompliance: 0.05, shearCompliance: 0.05 }, ClothMaterial.RUBBER)
    const sag = (iterations: number, solver: 'xpbd' | 'pbd') => {
      const { world, cloth } = hangingSheet({ substeps: 2, iterations, material: soft, resolution: 10, solver })
      const c = getClothState(world, cloth)
      for (let f = 0; f < 400; f++) stepCloth(world, 1 / 60)
      let low = 0
      for (let i = 0; i < c.count; i++) low = Math.min(low, c.pos[3 * i + 1])
      return -low - 1 // extension of the 1 m sheet, m
    }
    const x10 = sag(10, 'xpbd'), x40 = sag(40, 'xpbd')
    expect(x10).toBeGreaterThan(0.01) // the material really stretches (a test that can fail)
    expect(Math.abs(x40 / x10 - 1)).toBeLessThan(0.05)
    const p10 = sag(10, 'pbd'), p40 = sag(40, 'pbd')
    expect(Math.abs(p40 / p10 - 1)).toBeGreaterThan(0.2)
  })
})

describe('without tethers', () => {
  it('a dense sheet on two corner pins at one substep and one iteration stretches but stays finite', () => {
    // the case plain PBD is known to blow up on; it must degrade (stretch), never diverge
    const { world, cloth } = hangingSheet({ substeps: 1, iterations: 1, tethers: false, corners: true, resolution: 32 })
    for (let f = 0; f < 300; f++) stepCloth(world, 1 / 60)
    expect(allFinite(world, cloth)).toBe(true)
    const low300 = lowestY(world, cloth)
    expect(low300).toBeGreaterThan(-6) // hanging (measured: 4.1–4.3 m below the pins), not falling away
    for (let f = 0; f < 300; f++) stepCloth(world, 1 / 60)
    expect(allFinite(world, cloth)).toBe(true)
    expect(Math.abs(lowestY(world, cloth) - low300)).toBeLessThan(0.5) // and settled, not creeping
  })
})

describe('tethers', () => {
  it('cut the max stretch of a sheet hanging from two corners', () => {
    const run = (tethers: boolean) => {
      const { world, cloth } = hangingSheet({ substeps: 4, iterations: 1, tethers, corners: true, resolution: 32 })
      for (let f = 0; f < 180; f++) stepCloth(world, 1 / 60)
      expect(allFinite(world, cloth)).toBe(true)
      return getClothStretch(world, cloth)
    }
    const without = run(false), withT = run(true)
    expect(without.max).toBeGreaterThan(0.1)
    expect(withT.max).toBeLessThan(without.max / 4)
    expect(withT.max).toBeLessThan(0.05)
  })

  it('are rebuilt when pins change and never tie particles to a released pin', () => {
    const { world, cloth } = hangingSheet({ substeps: 2, iterations: 1, tethers: true, corners: true, resolution: 8 })
    stepCloth(world, 1 / 60)
    const c = getClothState(world, cloth)
    const before = c.tethers.set.count
    expect(before).toBeGreaterThan(0)
    for (let t = 0; t < c.tethers.set.count; t++) expect(c.invMass[c.tethers.set.anchor[t]]).toBe(0)
    pinParticle(world, cloth, 63)
    stepCloth(world, 1 / 60)
    for (let t = 0; t < c.tethers.set.count; t++) expect(c.invMass[c.tethers.set.anchor[t]]).toBe(0)
    expect(Array.from(c.tethers.set.anchor.subarray(0, c.tethers.set.count))).toContain(63)
  })
})
