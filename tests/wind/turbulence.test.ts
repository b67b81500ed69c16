import { describe, expect, it } from 'vitest'
import { createCloth, createWindZone, getClothState, pinRow, sampleWind, stepCloth } from '../../src/index'
import { hashBytes, makeWorld } from '../helpers'

/** Wind sampled on a small grid of points over `steps` steps. */
function record(seed: number, steps = 120) {
  const world = makeWorld()
  const cloth = createCloth(world, { width: 1, height: 1, resolution: 8, position: [0, 2, 0], material: 'silk' })
  pinRow(world, cloth, 0)
  createWindZone(world, { direction: [1, 0, 0], strength: 10, turbulence: 0.4, turbulenceScale: 1.5, seed })
  const samples: number[] = []
  for (let s = 0; s < steps; s++) {
    stepCloth(world, 1 / 60)
    for (let x = -2; x <= 2; x += 0.5) for (let y = 0; y <= 2; y += 0.5) samples.push(...(sampleWind(world, [x, y, 0.3]) as number[]))
  }
  return { samples, hash: hashBytes(getClothState(world, cloth).pos) }
}

describe('turbulence', () => {
  it('is deterministic for a seed, bit for bit, and differs with the seed', () => {
    const a = record(7), b = record(7), c = record(8)
    expect(b.samples).toEqual(a.samples)
    expect(b.hash).toBe(a.hash)
    expect(c.samples).not.toEqual(a.samples)
    expect(c.hash).not.toBe(a.hash)
  })

  it('is bounded by turbulence × strength per component and really varies', () => {
    const { samples } = record(3, 240)
    const bound = 0.4 * 10
    let maxDev = 0, sum2 = 0
    for (let i = 0; i < samples.length; i += 3) {
      const d = [samples[i] - 10, samples[i + 1], samples[i + 2]]
      for (const v of d) {
        maxDev = Math.max(maxDev, Math.abs(v))
        sum2 += v * v
      }
    }
    expect(maxDev).toBeLessThanOrEqual(bound + 1e-9)
    const rms = Math.sqrt(sum2 / samples.length)
    expect(rms).toBeGreaterThan(0.15 * bound)
  })

  it('is smooth in time and space', () => {
    const world = makeWorld()
    createCloth(world, { width: 1, height: 1, resolution: 3 })
    createWindZone(world, { direction: [0, 0, 1], strength: 10, turbulence: 0.5, turbulenceScale: 2, turbulencePeriod: 0.8, seed: 11 })
    const amp = 5
    let prev = Array.from(sampleWind(world, [0.3, 1.1, -0.2]))
    let maxStep = 0, maxSpace = 0
    for (let f = 0; f < 240; f++) {
      stepCloth(world, 1 / 60)
      const u = Array.from(sampleWind(world, [0.3, 1.1, -0.2]))
      const v = sampleWind(world, [0.35, 1.1, -0.2])
      for (let k = 0; k < 3; k++) {
        maxStep = Math.max(maxStep, Math.abs(u[k] - prev[k]))
        maxSpace = Math.max(maxSpace, Math.abs(u[k] - v[k]))
      }
      prev = u
    }
    // one 1/60 s step moves the pattern 0.17 m downwind and 2 % of a period: small changes only
    expect(maxStep).toBeLessThan(0.25 * amp)
    expect(maxStep).toBeGreaterThan(0)
    // 5 cm apart on a 2 m eddy scale
    expect(maxSpace).toBeLessThan(0.1 * amp)
  })
})
