import { describe, expect, it } from 'vitest'
import {
  getClothLod,
  getClothState,
  getClothStretch,
  setClothBudget,
  setClothVisible,
  setTransform,
  stepCloth,
  teleportCloth,
} from '../src/index'
import { CAL, budgetCape } from './fixtures/budgetCape'

/**
 * A cape on a standing hero; frozen (setClothVisible false under a world budget) or not; the game
 * moves the hero and the cape by (−5.5, 0, 9) with teleportCloth, steps 30 frames, then thaws it
 * (setClothBudget null). Returns the worst edge stretch over the 60 frames after the thaw.
 */
function teleportWhileFrozen(character: boolean, freeze: boolean) {
  const { world, hero, viewer, cape } = budgetCape(character, [0, 2, 5])
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

/**
 * A cape on a hero running at 4 m/s along z, hidden (setClothVisible false under a world budget)
 * just before a frame in which the hero jumps (`jump`: a long frame, 0.5 s, whose time beyond the
 * steps a frame may run is dropped and carried; or a 10 m teleport, detected or with the cape moved
 * along by `teleportCloth`), shown again 30 frames later.
 * Returns the pinned particles' largest distance from their targets over the 10 frames after.
 */
function frozenInAJump(character: boolean, jump: 'hitch' | 'teleport' | 'teleportCloth'): number {
  const { world, hero, viewer, cape } = budgetCape(character, [0, 2, 3])
  setClothBudget(world, { viewer, near: 4, far: 40, calibration: CAL, adapt: false, interval: 1 })
  let z = 0
  const frame = (dt: number, leap = 0) => {
    z += 4 * dt + leap
    setTransform(world, hero, [0, 0, z])
    setTransform(world, viewer, [0, 2, z + 3])
    stepCloth(world, dt)
  }
  for (let f = 0; f < 60; f++) frame(1 / 60)
  setClothVisible(world, cape, false)
  if (jump === 'teleportCloth') teleportCloth(world, cape, [0, 0, 10]) // the game moves the cape with its hero
  if (jump === 'hitch') frame(0.5)
  else frame(1 / 60, 10)
  expect(getClothLod(world, cape).frozen).toBe(true)
  for (let f = 0; f < 30; f++) frame(1 / 60)
  setClothVisible(world, cape, true)
  const c = getClothState(world, cape)
  let worst = 0
  for (let f = 0; f < 10; f++) {
    frame(1 / 60)
    // the collar row (particles 0..6) hangs from the hero at its rest offsets: x and y as created, z − 0.25 behind
    for (let i = 0; i < 7; i++) worst = Math.max(worst, Math.abs(c.pos[3 * i + 2] - (z - 0.25)))
  }
  return worst
}

describe('a cloth frozen in the frame its pin target jumps', () => {
  // Found by a hunt: the freeze took the target's pose after the jump, which the cloth, frozen
  // before it followed, never made: it thawed that far behind its pins (1.71 m after the 0.5 s
  // frame at 4 m/s; 9.9 m after the teleport) and glid back at up to 18 m/s. (A review found the
  // first fix undid the jump for a cape teleportCloth had moved already: 9.9 m again.)
  it.each([false, true])(
    'thaws on its pins (character settings: %s), after a dropped-time hitch and after a 10 m teleport, detected or by teleportCloth',
    (character) => {
      expect(frozenInAJump(character, 'hitch')).toBeLessThan(0.01)
      expect(frozenInAJump(character, 'teleport')).toBeLessThan(0.01)
      expect(frozenInAJump(character, 'teleportCloth')).toBeLessThan(0.01)
    },
  )
})
