// A hand grabbing the demo's cape while the character runs on: the grip saturates at its force
// limit and the cape, held by its painted max distance, cannot follow. Particles at their limit
// weigh more in the next distance solve (HELD_WEIGHT in kernels/motion.ts), so the hand's pull
// goes into the free cloth it holds instead of dragging each limited row past the one above.
import { createWorld } from 'bitecs'
import { describe, expect, it } from 'vitest'
import { createWindZone, getClothState, getClothStretch, grabParticle, installClothPlugin, moveGrab, stepCloth } from '../../src/index'
import { createCape } from '../../demo/capeShape'
import { Character } from '../../demo/character'
import { allFinite } from '../helpers'

/**
 * The largest edge stretch while a hand holds the cape's lowest particle for 1 s, moving 0.8 m
 * sideways and 0.3 m down, from `start` s into a 4 m/s run; the grip up to `weights` times the
 * cape's weight.
 */
function stretchUnderHand(start: number, weights: number): number {
  const world = installClothPlugin(createWorld(), { sleep: false })
  const hero = new Character(world)
  const { cape } = createCape(world, hero, { rows: 24, cols: 15, material: 'wool', substeps: 8, iterations: 1, tethers: true })
  createWindZone(world, { direction: [1, 0, 0], strength: 0 }) // the demo's still air
  hero.command('run')
  const step = () => {
    hero.update(1 / 60)
    stepCloth(world, 1 / 60)
  }
  for (let f = 0; f < Math.round(start * 60); f++) step()
  const c = getClothState(world, cape)
  let k = 0, mass = 0
  for (let i = 0; i < c.count; i++) {
    if (c.pos[3 * i + 1] < c.pos[3 * k + 1]) k = i
    if (c.invMass[i] > 0) mass += 1 / c.invMass[i]
  }
  const at = [c.pos[3 * k], c.pos[3 * k + 1], c.pos[3 * k + 2]]
  const grip = grabParticle(world, cape, k, at, { maxForce: weights * mass * 9.81 })
  let worst = 0
  for (let s = 1; s <= 10; s++) {
    moveGrab(world, grip, [at[0] - 0.08 * s, at[1] - 0.03 * s, at[2]])
    for (let f = 0; f < 6; f++) step()
    worst = Math.max(worst, getClothStretch(world, cape).max)
  }
  expect(allFinite(world, cape)).toBe(true)
  return worst
}

describe('a hand on the demo cape of a running character', () => {
  // A running cape is chaotic: which edge a hand overstretches depends on the moment it grabs, and
  // a rounding anywhere moves each moment's result by tens of percent (one moment went from 38 to
  // 62 % when a bind stopped rounding the rest shape by 1e-8 m). So the claim is over 12 moments.
  it("grabbed at 12 moments of the run: with the demo's grip (the cape's weight) the worst edge stretches a median under 43 %, at most 70 %; with the default grip (twice that) under 70 %, at most 85 %", () => {
    const starts = Array.from({ length: 12 }, (_, i) => 1.5 + 0.25 * i)
    const demo = starts.map((t) => stretchUnderHand(t, 1))
    const strong = starts.map((t) => stretchUnderHand(t, 2))
    console.log(
      `largest edge stretch under a hand: grip 1× weight ${demo.map((x) => (100 * x).toFixed(0)).join(', ')} %; 2× ${
        strong.map((x) => (100 * x).toFixed(0)).join(', ')
      } %`,
    )
    const median = (a: number[]) => [...a].sort((x, y) => x - y)[a.length >> 1]
    // before particles at their limit weighed more in the solve: 58–73 % and 84–121 % (4 moments).
    // Measured: medians 37 and 61 %, at most 41 and 75 % (README). The medians are bound near their
    // figures; a single moment moves by tens of percent with any rounding, so the maxima keep room
    expect(median(demo)).toBeLessThan(0.43)
    expect(Math.max(...demo)).toBeLessThan(0.7)
    expect(median(strong)).toBeLessThan(0.7)
    expect(Math.max(...strong)).toBeLessThan(0.85)
    // the grip did pull
    for (const x of demo) expect(x).toBeGreaterThan(0.05)
  })
})
