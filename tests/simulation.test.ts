import { describe, expect, it } from 'vitest'
import { ClothError, ClothSimulation, createWindZone, getClothState, getPins, getWindZones, removeWindZone } from '../src/index'

describe('ClothSimulation facade', () => {
  it('wraps a private world: pin a row, step, read the mesh', () => {
    const sim = new ClothSimulation({ width: 1, height: 1, resolution: 10, material: 'silk', iterations: 2 })
    const pins = sim.pinRow(0)
    expect(pins).toHaveLength(10)
    const y0 = sim.positions[3 * 95 + 1]
    for (let f = 0; f < 30; f++) sim.step(1 / 60)
    expect(sim.positions[1]).toBe(0) // top row held
    expect(sim.positions[3 * 95 + 1]).not.toBe(y0) // the rest moves
    const mesh = sim.getMesh()
    expect(mesh.vertexCount).toBe(100)
    expect(mesh.triangleCount).toBe(162)
    expect(sim.getStretch().max).toBeLessThan(0.05)
    // the facade is the ECS API underneath: its positions are a view of the world's cloth state
    const state = getClothState(sim.world, sim.cloth)
    expect(sim.positions.buffer).toBe(state.pos.buffer)
    expect(sim.particleCount).toBe(state.count)
    expect(sim.pinRow(1).every((pin) => getPins(sim.world, sim.cloth).includes(pin))).toBe(true)
  })

  it('pins a particle at a world position and releases it', () => {
    const sim = new ClothSimulation({ width: 1, height: 1, resolution: 4 })
    const pin = sim.pinParticle(0, [0, 3, 0])
    for (let f = 0; f < 60; f++) sim.step(1 / 60)
    expect(sim.positions[1]).toBeCloseTo(3, 9)
    sim.unpin(pin)
    for (let f = 0; f < 30; f++) sim.step(1 / 60)
    expect(sim.positions[1]).toBeLessThan(2.9)
  })
})

function argumentOf(fn: () => unknown): string {
  try {
    fn()
    return '(no error)'
  } catch (e) {
    return e instanceof ClothError ? e.argument : `${(e as Error).name}`
  }
}
const base = { width: 1, height: 1, resolution: 4 }

describe('ClothSimulation: errors name the facade argument', () => {
  it('constructor: bad world settings name options.world…', () => {
    expect(argumentOf(() => new ClothSimulation({ ...base, world: 5 as never }))).toBe('options.world') // (was 'options')
    expect(argumentOf(() => new ClothSimulation({ ...base, world: { gravity: [NaN, 0, 0] } }))).toBe('options.world.gravity') // (was 'options.gravity')
    expect(argumentOf(() => new ClothSimulation({ ...base, world: { fixedTimeStep: 0 } }))).toBe('options.world.fixedTimeStep') // (was 'options.fixedTimeStep')
  })
  it('pinParticle(index, position): a bad position names position', () => {
    const sim = new ClothSimulation(base)
    expect(argumentOf(() => sim.pinParticle(0, [NaN, 0, 0]))).toBe('position') // (was 'offset')
  })
  it('setWind(wind) and gust(strength, duration) name wind.* and strength / duration', () => {
    const sim = new ClothSimulation(base)
    expect(argumentOf(() => sim.setWind({ direction: [0, 0, 0], strength: 1 }))).toBe('wind.direction') // (was 'options.direction')
    expect(argumentOf(() => sim.setWind({ direction: [1, 0, 0], strength: -1 }))).toBe('wind.strength') // (was 'options.strength')
    sim.setWind({ direction: [1, 0, 0], strength: 1 })
    expect(argumentOf(() => sim.gust(NaN))).toBe('strength') // (was 'options.strength')
    expect(argumentOf(() => sim.gust(1, 0))).toBe('duration') // (was 'options.duration')
  })
  it('setWind with strength 0 still checks direction and turbulence', () => {
    const sim = new ClothSimulation(base)
    // (both were accepted silently: with no zone nothing was checked, a zone was removed unchecked)
    expect(argumentOf(() => sim.setWind({ direction: [NaN, 0, 0], strength: 0 }))).toBe('wind.direction')
    sim.setWind({ direction: [1, 0, 0], strength: 2 })
    expect(argumentOf(() => sim.setWind({ direction: 'east' as never, strength: 0, turbulence: -3 }))).not.toBe('(no error)')
  })
})

describe('ClothSimulation: its wind zone handle after the zone went away through sim.world', () => {
  it('setWind({ strength: 0 }) does not remove a zone the game made since on the recycled id', () => {
    const sim = new ClothSimulation(base)
    sim.setWind({ direction: [1, 0, 0], strength: 3 })
    const [own] = getWindZones(sim.world)
    removeWindZone(sim.world, own) // (sim.world is public for what the facade does not cover)
    const gameZone = createWindZone(sim.world, { direction: [0, 0, 1], strength: 1 })
    expect(gameZone).toBe(own) // the id came back
    sim.setWind({ direction: [1, 0, 0], strength: 0 })
    // (the facade had removed the game's zone as its own)
    expect(getWindZones(sim.world)).toEqual([gameZone])
  })
})
