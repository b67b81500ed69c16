import { createWorld } from 'bitecs'
import { expect } from 'vitest'
import {
  ClothError,
  getClothState,
  getClothStats,
  installClothPlugin,
  stepCloth,
  type ClothCostCalibration,
  type ClothPluginOptions,
} from '../src/index'

/** Expects `fn` to throw a ClothError naming `argument` (and, when given, mentioning `value`). */
export function rejects(fn: () => unknown, argument: string, value?: string): void {
  let error: unknown
  try {
    fn()
  } catch (e) {
    error = e
  }
  expect(error, `expected a ClothError for ${argument}`).toBeInstanceOf(ClothError)
  expect((error as ClothError).argument).toBe(argument)
  expect((error as Error).message).toContain(argument)
  if (value !== undefined) expect((error as Error).message).toContain(value)
}

/**
 * Fixed cost-model numbers for budget tests: the levels they expect do not depend on the machine
 * (`CALIBRATION`), or a cheaper model under which more cloths get high levels (`CHEAP_CALIBRATION`).
 */
export const CALIBRATION: ClothCostCalibration = { nsPerParticle: 20, nsPerProjection: 12, nsPerColliderTest: 5, nsPerClothSubstep: 500 }
export const CHEAP_CALIBRATION: ClothCostCalibration = {
  nsPerParticle: 10,
  nsPerProjection: 2,
  nsPerColliderTest: 3,
  nsPerClothSubstep: 100,
}

/** A fresh world with the plugin installed. */
export function makeWorld(options?: ClothPluginOptions) {
  return installClothPlugin(createWorld(), options)
}

/**
 * True when every position of the cloth is finite and the world's explosion guard has reset no
 * cloth (since install or the last `resetClothStats`): the guard (on by default) puts a cloth that
 * went non-finite or flew off back into a safe pose, so finiteness alone would only show that the
 * guard works, not that the solver stayed stable.
 */
export function allFinite(world: object, cloth: number): boolean {
  const c = getClothState(world, cloth)
  for (let i = 0; i < 3 * c.count; i++) if (!Number.isFinite(c.pos[i])) return false
  return getClothStats(world).guardResets === 0
}

/** Total linear momentum Σ m·v of a cloth's free particles. */
export function momentum(world: object, cloth: number): [number, number, number] {
  const c = getClothState(world, cloth)
  const p: [number, number, number] = [0, 0, 0]
  for (let i = 0; i < c.count; i++) {
    if (c.invMass[i] === 0) continue
    const m = 1 / c.invMass[i]
    p[0] += m * c.vel[3 * i]
    p[1] += m * c.vel[3 * i + 1]
    p[2] += m * c.vel[3 * i + 2]
  }
  return p
}

/** Lowest y of a cloth's particles. */
export function lowestY(world: object, cloth: number): number {
  const c = getClothState(world, cloth)
  let y = Infinity
  for (let i = 0; i < c.count; i++) y = Math.min(y, c.pos[3 * i + 1])
  return y
}

/** Deterministic pseudo-random numbers in [0, 1) (mulberry32). */
export function rng(seed: number): () => number {
  let a = seed >>> 0
  return () => {
    a = (a + 0x6d2b79f5) >>> 0
    let t = a
    t = Math.imul(t ^ (t >>> 15), t | 1)
    t ^= t + Math.imul(t ^ (t >>> 7), t | 61)
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296
  }
}

/** FNV-1a hash of a typed array's bytes, as 8 hex digits. */
export function hashBytes(arr: ArrayBufferView): string {
  const bytes = new Uint8Array(arr.buffer, arr.byteOffset, arr.byteLength)
  let h = 0x811c9dc5
  for (let i = 0; i < bytes.length; i++) {
    h ^= bytes[i]
    h = Math.imul(h, 0x01000193) >>> 0
  }
  return h.toString(16).padStart(8, '0')
}

/**
 * Mechanical energy (kinetic + gravitational at 9.81 m/s² along −y) of a cloth's free particles,
 * per step over `steps` steps of 1/60 s: how many steps gained energy, the largest gain and the
 * total change, both as shares of M·g·L (M the cloth's mass, L = 1 m).
 */
export function energyGains(world: object, cloth: number, steps: number): { count: number; largest: number; total: number } {
  const c = getClothState(world, cloth)
  let M = 0
  for (let i = 0; i < c.count; i++) M += 1 / c.baseInvMass[i]
  const energy = () => {
    let e = 0
    for (let i = 0; i < c.count; i++) {
      if (c.invMass[i] === 0) continue
      const v2 = c.vel[3 * i] ** 2 + c.vel[3 * i + 1] ** 2 + c.vel[3 * i + 2] ** 2
      e += (0.5 * v2 + 9.81 * c.pos[3 * i + 1]) / c.baseInvMass[i]
    }
    return e
  }
  const e0 = energy()
  let prev = e0, count = 0, largest = 0
  for (let f = 0; f < steps; f++) {
    stepCloth(world, 1 / 60)
    const e = energy()
    if (e > prev) {
      count++
      largest = Math.max(largest, (e - prev) / (M * 9.81))
    }
    prev = e
  }
  return { count, largest, total: (prev - e0) / (M * 9.81) }
}
