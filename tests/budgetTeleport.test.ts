// teleportCloth on a frozen cloth (found by a seeded soak): the thaw carried it by the teleport a
// second time (10,304 % stretch on a character cape, 39.6 % on a plain one); each test failed before.
import { addEntity, createWorld } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  createCloth,
  getClothLod,
  getClothStretch,
  installClothPlugin,
  pinRow,
  setClothBudget,
  setClothInertia,
  setClothMotionConstraints,
  setClothVisible,
  setTransform,
  stepCloth,
  teleportCloth,
} from '../src/index'

const CAL = { nsPerParticle: 20, nsPerProjection: 12, nsPerColliderTest: 5, nsPerClothSubstep: 500 }

/**
 * A cape on a standing hero; frozen (setClothVisible false under a world budget) or not; the game
 * moves the hero and the cape by (−5.5, 0, 9) with teleportCloth, steps 30 frames, then thaws it
 * (setClothBudget null). Returns the worst edge stretch over the 60 frames after the thaw.
 */
function teleportWhileFrozen(character: boolean, freeze: boolean) {
  const world = installClothPlugin(createWorld())
  const hero = addEntity(world)
  setTransform(world, hero, [0, 0, 0])
  const viewer = addEntity(world)
  setTransform(world, viewer, [0, 2, 5])
  const cape = createCloth(world, {
    width: 0.55,
    height: 1.0,
    resolution: [7, 11],
    position: [0, 1.47, -0.25],
    material: 'wool',
    substeps: 4,
  })
  pinRow(world, cape, 0, hero)
  if (character) {
    setClothInertia(world, cape, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5 })
    const md = Array.from({ length: 77 }, (_, i) => {
      const u = Math.floor(i / 7) / 10
      return u === 1 ? Infinity : 0.9 * u * u
    })
    setClothMotionConstraints(world, cape, { maxDistance: md, backstop: { distance: 0.02, radius: 0.5 } })
  }
  for (let f = 0; f < 60; f++) stepCloth(world, 1 / 60)
  if (freeze) setClothVisible(world, cape, false)
  setClothBudget(world, { viewer, near: 4, far: 40, calibration: CAL, adapt: false })
  for (let f = 0; f < 60; f++) stepCloth(world, 1 / 60)
  expect(getClothLod(world, cape).frozen).toBe(freeze)
  setTransform(world, hero, [-5.5, 0, 9])
  teleportCloth(world, cape, [-5.5, 0, 9])
  for (let f = 0; f < 30; f++) stepCloth(world, 1 / 60)
  setClothBudget(world, null) // thaws it
  let worst = 0
  for (let f = 0; f < 60; f++) {
    stepCloth(world, 1 / 60)
    worst = Math.max(worst, getClothStretch(world, cape).max)
  }
  return worst
}

describe('teleportCloth of a frozen cloth', () => {
  it('control: not frozen, the teleported cape hangs at rest', () => {
    expect(teleportWhileFrozen(true, false)).toBeLessThan(0.02)
    expect(teleportWhileFrozen(false, false)).toBeLessThan(0.02)
  })
  it('a frozen character cape moved with its hero by teleportCloth thaws without stretch', () => {
    // measured: 0.0013 % (10,304 % before: carried by the jump twice, by teleportCloth and again by
    // the thaw; then 152 %: the teleport left pending for its pins moved it back at the thaw)
    expect(teleportWhileFrozen(true, true)).toBeLessThan(0.05)
  })
  it('a frozen plain cape (pins only) moved with its hero by teleportCloth thaws without stretch', () => {
    // measured: 39.6 % before
    expect(teleportWhileFrozen(false, true)).toBeLessThan(0.05)
  })
})
