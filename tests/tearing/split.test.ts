import { describe, expect, it } from 'vitest'
import {
  createCloth,
  drainClothTears,
  getClothMesh,
  getClothState,
  getClothStats,
  getClothTearCount,
  makeTearable,
  onClothTear,
  pinRow,
  setClothTethers,
  setTransform,
  stepCloth,
} from '../../src/index'
import { allFinite, makeWorld } from '../helpers'
import { meshPieces, pieceCount } from './util'
import { pinSidesToBars } from '../fixtures/bars'

/** A 1 m sheet pinned along its left and right edges to two bars that move apart. */
function pulledSheet(tearable: boolean, n = 16) {
  const world = makeWorld()
  const cloth = createCloth(world, { width: 1, height: 1, resolution: n, position: [0, 2, 0], material: 'cotton' })
  const [left, right] = pinSidesToBars(world, cloth, n)
  if (tearable) makeTearable(world, cloth)
  const events: { particle: number; newParticle: number; x: number; strain: number; cloth: number }[] = []
  onClothTear(world, (e) => events.push({ particle: e.particle, newParticle: e.newParticle, x: e.x, strain: e.strain, cloth: e.cloth }))
  const run = (frames: number, each?: () => void) => {
    for (let f = 0; f < frames; f++) {
      const d = Math.min(0.5, (f + 1) * 0.004)
      setTransform(world, left, [-d, 0, 0])
      setTransform(world, right, [d, 0, 0])
      stepCloth(world, 1 / 60)
      each?.()
    }
  }
  return { world, cloth, c: getClothState(world, cloth), events, run, n }
}

describe('tearing', () => {
  it('a sheet whose side pins are pulled apart splits into two pieces, with a real gap in the rendered mesh', () => {
    const { world, cloth, c, events, run, n } = pulledSheet(true)
    run(200)
    expect(allFinite(world, cloth)).toBe(true)
    const mesh = getClothMesh(world, cloth)
    expect(mesh.vertexCount).toBe(c.count)
    expect(mesh.vertexCount).toBeGreaterThan(n * n)
    for (let i = 0; i < mesh.positions.length; i++) expect(Number.isFinite(mesh.positions[i])).toBe(true)
    for (let i = 0; i < mesh.normals.length; i++) expect(Number.isFinite(mesh.normals[i])).toBe(true)
    const label = meshPieces(mesh.indices, mesh.vertexCount)
    expect(pieceCount(label)).toBe(2)
    // each piece hangs from its own pins: the pinned columns are in different pieces, at their bars
    const leftPiece = label[0], rightPiece = label[n - 1]
    expect(leftPiece).not.toBe(rightPiece)
    for (let r = 0; r < n; r++) {
      expect(label[r * n]).toBe(leftPiece)
      expect(label[r * n + n - 1]).toBe(rightPiece)
      expect(c.pos[3 * r * n]).toBeCloseTo(-0.5 - 0.5, 6)
      expect(c.pos[3 * (r * n + n - 1)]).toBeCloseTo(0.5 + 0.5, 6)
    }
    // the gap: no vertex of one piece within 20 cm of a vertex of the other
    let gap = Infinity
    for (let i = 0; i < mesh.vertexCount; i++) {
      if (label[i] !== leftPiece) continue
      for (let j = 0; j < mesh.vertexCount; j++) {
        if (label[j] !== rightPiece) continue
        const d = Math.hypot(
          mesh.positions[3 * i] - mesh.positions[3 * j],
          mesh.positions[3 * i + 1] - mesh.positions[3 * j + 1],
          mesh.positions[3 * i + 2] - mesh.positions[3 * j + 2],
        )
        gap = Math.min(gap, d)
      }
    }
    expect(gap).toBeGreaterThan(0.2)
    // no constraint or tether ties the two pieces together
    const t = c.topology
    for (let k = 0; k < t.distCount; k++) expect(label[t.distOffsets[2 * k] / 3]).toBe(label[t.distOffsets[2 * k + 1] / 3])
    for (let k = 0; k < t.stretchCount; k++) expect(label[t.stretchIds[2 * k]]).toBe(label[t.stretchIds[2 * k + 1]])
    for (let k = 0; k < c.tethers.set.count; k++) expect(label[c.tethers.set.particle[k]]).toBe(label[c.tethers.set.anchor[k]])
    // the pieces have relaxed: nothing is still stretched across the tear
    expect(getClothStats(world).tears).toBe(c.count - n * n)
    expect(events.length).toBe(c.count - n * n)
  })

  it('a tearable cloth given more tethers per particle than it reserved builds them all', () => {
    const world = makeWorld()
    const cloth = createCloth(world, { width: 1, height: 1, resolution: 8, tethers: { perParticle: 1 } })
    pinRow(world, cloth, 0)
    makeTearable(world, cloth)
    stepCloth(world, 1 / 60)
    const free = 8 * 8 - 8
    expect(getClothState(world, cloth).tethers.set.count).toBe(free)
    setClothTethers(world, cloth, { perParticle: 4 })
    stepCloth(world, 1 / 60)
    expect(getClothState(world, cloth).tethers.set.count).toBe(4 * free)
  })

  it('the same load on a cloth without Tearable never tears and pays nothing for strain checks', () => {
    const { world, cloth, c, events, run, n } = pulledSheet(false)
    run(200)
    expect(c.count).toBe(n * n)
    expect(events).toEqual([])
    const stats = getClothStats(world)
    expect(stats.tears).toBe(0)
    expect(stats.strainChecks).toBe(0)
    expect(getClothTearCount(world, cloth)).toBe(0)
    expect(pieceCount(meshPieces(getClothMesh(world, cloth).indices, c.count))).toBe(1)
    expect(allFinite(world, cloth)).toBe(true)
  })

  it('fires one tear event per break, and never more than maxTearsPerStep per step', () => {
    const { world, cloth, c, events, run, n } = pulledSheet(false)
    makeTearable(world, cloth, { maxTearsPerStep: 2 })
    const perStep: number[] = []
    let before = 0
    run(200, () => {
      perStep.push(events.length - before)
      before = events.length
    })
    expect(Math.max(...perStep)).toBe(2)
    expect(events.length).toBeGreaterThan(0)
    expect(events.length).toBe(getClothStats(world).tears)
    expect(events.length).toBe(getClothTearCount(world, cloth))
    expect(events.length).toBe(c.count - n * n)
    // each break made exactly one new particle, each reported once
    const fresh = new Set(events.map((e) => e.newParticle))
    expect(fresh.size).toBe(events.length)
    for (const e of events) {
      expect(e.cloth).toBe(cloth)
      expect(e.newParticle).toBeGreaterThanOrEqual(n * n)
      expect(e.strain).toBeGreaterThan(0.3)
      expect(Number.isFinite(e.x)).toBe(true)
    }
    // the polling queue saw the same tears
    let drained = 0
    drainClothTears(world, () => drained++)
    expect(drained).toBe(events.length)
    expect(drainClothTears(world, () => {})).toBe(0)
  })
})
