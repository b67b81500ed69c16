// A world in other length units (README, Units and scale): every default that carries a metre or a
// metre per second is scaled with the unit, and a centimetre world then moves as the metre world
// does, ×100. Found by a hunt: with the metre defaults, a cm world capped its swing at 2.5 m/s,
// never slept, and took a character running at 5 m/s for one teleporting every frame.
import { addEntity, createWorld } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  createCloth,
  defineMaterial,
  getClothState,
  getClothStats,
  getClothStretch,
  installClothPlugin,
  isClothSleeping,
  pinParticle,
  pinRow,
  setTransform,
  stepCloth,
  type ClothMaterialSpec,
  type ClothPluginOptions,
} from '../src/index'

/** The README's settings for a world whose unit is `u` metres (0.01: centimetres), kilograms and seconds. */
function inUnits(u: number): { plugin: ClothPluginOptions; material: (name: string) => ClothMaterialSpec } {
  const k = 1 / u // units per metre
  const base = (name: string) => defineMaterial({}, name)
  return {
    plugin: { gravity: [0, -9.81 * k, 0], maxSpeed: 250 * k, teleportDistance: 2 * k, sleep: { speed: 0.01 * k } },
    material: (name) =>
      defineMaterial({
        density: base(name).density / (k * k),
        bendCompliance: base(name).bendCompliance / (k * k),
        thickness: base(name).thickness * k,
      }, name),
  }
}

/** A sheet `k` units wide pinned at its two top corners, released from level: the hem's track / k, its top speed / k, the frame it slept. */
function swing(k: number, plugin: ClothPluginOptions, material: ClothMaterialSpec) {
  const world = installClothPlugin(createWorld(), plugin)
  const s = Math.SQRT1_2
  const cloth = createCloth(world, { width: k, height: k, resolution: 12, position: [0, 3 * k, 0], rotation: [-s, 0, 0, s], material })
  pinParticle(world, cloth, 0)
  pinParticle(world, cloth, 11)
  const c = getClothState(world, cloth)
  const hem = 3 * (11 * 12 + 6)
  const track: number[] = []
  let top = 0, slept = -1
  for (let f = 0; f < 900; f++) {
    stepCloth(world, 1 / 60)
    for (let a = 0; a < 3; a++) track.push(c.pos[hem + a] / k)
    for (let i = 0; i < c.count; i++) top = Math.max(top, Math.hypot(c.vel[3 * i], c.vel[3 * i + 1], c.vel[3 * i + 2]) / k)
    if (slept < 0 && isClothSleeping(world, cloth)) slept = f
  }
  return { track, top, slept, resets: getClothStats(world).guardResets }
}

/** A cape on a character zig-zagging at 5 m/s (in units), its heading snapping by 90° every half second. */
function zigzag(k: number, plugin: ClothPluginOptions, material: ClothMaterialSpec) {
  const world = installClothPlugin(createWorld(), plugin)
  const hero = addEntity(world)
  setTransform(world, hero, [0, 0, 0])
  const cape = createCloth(world, { width: 0.55 * k, height: 1.05 * k, resolution: [8, 14], position: [0, 1.47 * k, -0.2 * k], material })
  pinRow(world, cape, 0, hero)
  let x = 0, z = 0, stretch = 0
  for (let f = 0; f < 240; f++) {
    const along = Math.floor(f / 30) % 2 === 0
    x += along ? (5 * k) / 60 : 0
    z += along ? 0 : (5 * k) / 60
    setTransform(world, hero, [x, 0, z])
    stepCloth(world, 1 / 60)
    stretch = Math.max(stretch, getClothStretch(world, cape).max)
  }
  const stats = getClothStats(world)
  return { teleports: stats.teleports, resets: stats.guardResets, stretch }
}

describe('units', () => {
  it('a centimetre world with the README settings swings, tops out and sleeps as the metre world (its hem within 1e-6 of the size); with the metre defaults it does not', () => {
    const metre = swing(1, {}, defineMaterial({}, 'cotton'))
    const cm = inUnits(0.01)
    const scaled = swing(100, cm.plugin, cm.material('cotton'))
    const defaults = swing(100, { gravity: [0, -981, 0] }, cm.material('cotton'))
    let far = 0
    for (let q = 0; q < metre.track.length; q++) far = Math.max(far, Math.abs(metre.track[q] - scaled.track[q]))
    expect(far).toBeLessThan(1e-6)
    expect(scaled.slept).toBe(metre.slept)
    expect(scaled.top).toBeCloseTo(metre.top, 6)
    expect(metre.slept).toBeGreaterThan(0)
    expect(scaled.resets).toBe(0)
    // with the metre defaults: the speed cap (250 cm/s) holds the hem back, and it never sleeps
    expect(defaults.top).toBeLessThan(0.8 * metre.top)
    expect(defaults.slept).toBe(-1)
  })

  it('a character running at 5 m/s in centimetres is no teleport with the README settings (with the metre defaults, one every frame)', () => {
    const metre = zigzag(1, {}, defineMaterial({}, 'wool'))
    const cm = inUnits(0.01)
    const scaled = zigzag(100, cm.plugin, cm.material('wool'))
    const defaults = zigzag(100, { gravity: [0, -981, 0] }, cm.material('wool'))
    expect(metre.teleports).toBe(0)
    expect(scaled.teleports).toBe(0)
    expect(scaled.resets).toBe(0)
    expect(defaults.teleports).toBe(240) // (every frame: the cape carried rigidly)
    // the snaps are chaotic, so ×100's roundings part the runs; a unit of 1/128 m scales every number
    // exactly, and gives the metre world's stretch to the last bit
    const binary = inUnits(1 / 128)
    expect(zigzag(128, binary.plugin, binary.material('wool')).stretch).toBe(metre.stretch)
    expect(scaled.stretch).toBeGreaterThan(0.5 * metre.stretch)
    expect(scaled.stretch).toBeLessThan(2 * metre.stretch)
  })
})
