// The README's "Capes and character cloth" snippet, run as written (with the package name mapped to
// the source), on a character that runs, turns and snaps round.
import { addEntity, createWorld } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  createCloth,
  getClothReference,
  getClothState,
  getClothStats,
  installClothPlugin,
  pinRow,
  setClothInertia,
  setClothMotionConstraints,
  setTransform,
  stepCloth,
} from '../../src/index'
import { allFinite } from '../helpers'

describe('README: capes and character cloth', () => {
  it('the snippet runs: the cape stays within its painted max distance and outside its backstop, a 180° snap resets it', () => {
    // --- the snippet ---
    const world = installClothPlugin(createWorld())
    const hero = addEntity(world)
    setTransform(world, hero, [0, 0, 0])

    const cape = createCloth(world, {
      width: 0.55,
      height: 1.05,
      resolution: [14, 24],
      position: [0, 1.47, -0.2],
      rotation: [0, 1, 0, 0], // turned to face away from the body (−z): its backstop lies toward the back
      material: 'wool',
    })
    pinRow(world, cape, 0, hero)
    // feel half the hero's acceleration and turning; a snap of more than 90° in one frame resets it
    setClothInertia(world, cape, {
      frame: hero,
      linear: 0.5,
      angular: 0.5,
      centrifugal: 0.5,
      teleport: { mode: 'reset', angle: Math.PI / 2 },
    })
    // held at the collar, freer lower down, free at the hem; never into the back
    const maxDistance = Array.from({ length: 14 * 24 }, (_, i) => {
      const u = Math.floor(i / 14) / 23 // 0 at the collar, 1 at the hem
      return u === 1 ? Infinity : 0.9 * u * u
    })
    setClothMotionConstraints(world, cape, { maxDistance, backstop: { distance: 0.02, radius: 0.5 } })
    // --- end of the snippet ---

    const c = getClothState(world, cape)
    let worst = -Infinity
    for (let f = 1; f <= 300; f++) {
      const t = f / 60
      const yaw = t < 3 ? 1.5 * t : 1.5 * 3 + Math.PI // a 180° snap at 3 s
      setTransform(world, hero, [4 * Math.min(t, 3), 0, 0], [0, Math.sin(yaw / 2), 0, Math.cos(yaw / 2)])
      stepCloth(world, 1 / 60)
      const ref = getClothReference(world, cape)!
      for (let i = 0; i < c.count; i++) {
        const d = Math.hypot(c.pos[3 * i] - ref[3 * i], c.pos[3 * i + 1] - ref[3 * i + 1], c.pos[3 * i + 2] - ref[3 * i + 2])
        worst = Math.max(worst, d - maxDistance[i])
      }
    }
    expect(worst).toBeLessThan(0.002)
    expect(getClothStats(world).teleports).toBe(1)
    expect(allFinite(world, cape)).toBe(true)
  })
})
