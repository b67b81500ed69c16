// A self-colliding cloth under the world budget, far from its viewer: the budget lowers it no
// further than 6 substeps (or its own count when fewer). At the floor of other cloths, 1 substep ×
// 1 iteration, a heap of folds dropped on the ground was squashed to 60 % of its height and
// jittered at 0.3–0.5 m/s for good, never still enough to sleep.
import { addEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import { enableSelfCollision, getClothLod, setClothBudget, setClothQuality, setTransform, stepCloth } from '../../src/index'
import { CALIBRATION, makeWorld } from '../helpers'
import { accordionSheet, closestNonNeighbours, ground, maxSpeed } from './scenes'

const COLS = 16, ROWS = 24, LAYERS = 4, WIDTH = 0.6
const SPACING = WIDTH / (COLS - 1)

function drop(far: boolean, substeps?: number) {
  const world = makeWorld()
  ground(world)
  const cloth = accordionSheet(world, { cols: COLS, rows: ROWS, layers: LAYERS, d: SPACING, y0: 0.15, x0: -WIDTH / 2 })
  enableSelfCollision(world, cloth)
  if (substeps !== undefined) setClothQuality(world, cloth, { substeps })
  if (far) {
    const viewer = addEntity(world)
    setTransform(world, viewer, [0, 0, 500])
    setClothBudget(world, { viewer, near: 1, far: 2, farStepEvery: 4, calibration: CALIBRATION, adapt: false })
  }
  for (let f = 0; f < 180; f++) stepCloth(world, 1 / 60)
  return { gap: closestNonNeighbours(world, cloth, SPACING), v: maxSpeed(world, cloth), lod: getClothLod(world, cloth) }
}

describe('a self-colliding cloth far from the viewer', () => {
  it('runs at 6 substeps, every step, and its folds settle with the layers kept apart as at its own 8', () => {
    const far = drop(true)
    expect(far.lod.substeps).toBe(6)
    expect(far.lod.stepEvery).toBe(1)
    // what tests/collision/selfCollision.test.ts asks of the same scene at 8 substeps
    expect(far.gap).toBeGreaterThanOrEqual(0.9)
    expect(far.v).toBeLessThan(0.05)
  })
  it('keeps its own count when it asks for fewer than 6', () => {
    expect(drop(true, 3).lod.substeps).toBe(3)
  })
})
