import { describe, expect, it } from 'vitest'
import { ClothSimulation, getClothState, getPins } from '../src/index'

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
