// The line solve (`lineSolve`) on workers: the same bytes as without them, from creation and when
// turned on between steps (the cloth's new line arrays reach the worker).
import { describe, expect, it } from 'vitest'
import { createCloth, disposeClothWorld, getClothState, pinParticle, setClothQuality, stepCloth } from '../../src/index'
import { hashBytes } from '../helpers'
import { threadedWorld } from './scene'

describe('lineSolve on workers', () => {
  it('two swinging sheets, one solving lines from the start, one from frame 20, some iterations: same bytes with 0 and 1 worker', () => {
    const build = (threads: number) => {
      const world = threadedWorld(threads, { sleep: false })
      const level: number[] = [-Math.SQRT1_2, 0, 0, Math.SQRT1_2]
      const sheets = [0, 1].map((k) => {
        const s = createCloth(world, {
          width: 1,
          height: 1,
          resolution: 16,
          position: [2 * k, 2, 0],
          rotation: level,
          substeps: 3,
          iterations: 1 + k,
          lineSolve: k === 0,
        })
        pinParticle(world, s, 0)
        pinParticle(world, s, 15)
        return s
      })
      const hash = () => sheets.map((s) => hashBytes(getClothState(world, s).pos) + hashBytes(getClothState(world, s).vel)).join('')
      return { world, sheets, hash }
    }
    const runs = [build(0), build(1)]
    try {
      for (let f = 0; f < 60; f++) {
        for (const r of runs) {
          if (f === 20) setClothQuality(r.world, r.sheets[1], { lineSolve: true })
          stepCloth(r.world, 1 / 60)
        }
        expect(runs[1].hash(), `frame ${f}`).toBe(runs[0].hash())
      }
      expect(getClothState(runs[0].world, runs[0].sheets[1]).lines).not.toBeNull()
    } finally {
      for (const r of runs) disposeClothWorld(r.world)
    }
  })
})
