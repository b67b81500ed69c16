import { createWorld } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  createCloth,
  getClothState,
  getClothTearCount,
  grabParticle,
  installClothPlugin,
  makeTearable,
  pinRow,
  restoreClothState,
  saveClothState,
  stepCloth,
  type ClothSnapshot,
} from '../../src/index'
import { hashBytes, rejects } from '../helpers'

/** A 12×12 sheet hanging from its top row, its bottom corners pulled apart until it tears. */
function tearingSheet() {
  const world = installClothPlugin(createWorld())
  const cloth = createCloth(world, { width: 1, height: 1, resolution: 12, position: [0, 2, 0], tethers: false })
  pinRow(world, cloth, 0)
  makeTearable(world, cloth, { strain: 0.08, hysteresis: 1, maxTearsPerStep: 1, minPiece: 1 })
  grabParticle(world, cloth, 143, [0.8, 0.2, 0], { maxForce: 50 })
  grabParticle(world, cloth, 132, [-0.8, 0.2, 0], { maxForce: 50 })
  const c = getClothState(world, cloth)
  const hash = () => `${hashBytes(c.pos.subarray(0, 3 * c.count))}:${getClothTearCount(world, cloth)}`
  return { world, cloth, hash }
}

describe('tearing snapshots', () => {
  it('a tearable cloth restored from any frame without a tear since replays that step byte for byte, tears included', () => {
    const { world, cloth, hash } = tearingSheet()
    const bad: string[] = []
    let restored = 0, tearsOnReplay = 0
    for (let f = 0; f < 100; f++) {
      const snap = saveClothState(world, cloth)
      const before = getClothTearCount(world, cloth)
      stepCloth(world, 1 / 60)
      const first = hash()
      if (getClothTearCount(world, cloth) !== before) continue // tore: a torn mesh is not restored, by design
      restoreClothState(world, cloth, snap)
      stepCloth(world, 1 / 60)
      restored++
      if (hash() !== first) bad.push(`frame ${f}: ${first} then ${hash()}`)
      tearsOnReplay = getClothTearCount(world, cloth)
    }
    expect(bad).toEqual([])
    expect(restored).toBeGreaterThan(40) // 47 of the 100 steps tear nothing
    expect(tearsOnReplay).toBeGreaterThan(40) // 53 tears along the way
  })

  it('rejects a malformed tear clock with ClothError naming the snapshot, and restores an older snapshot without one', () => {
    const { world, cloth } = tearingSheet()
    for (let f = 0; f < 5; f++) stepCloth(world, 1 / 60)
    const snap = saveClothState(world, cloth)
    const broken = (change: (s: ClothSnapshot & Record<string, unknown>) => void) => {
      const s = structuredClone(snap) as ClothSnapshot & Record<string, unknown>
      change(s)
      return s
    }
    rejects(() => restoreClothState(world, cloth, broken((s) => (s.tearClock = new Float64Array(1)))), 'snapshot')
    rejects(() => restoreClothState(world, cloth, broken((s) => (s.tearClock = [1, 2] as never))), 'snapshot')
    rejects(() => restoreClothState(world, cloth, broken((s) => (s.tearClock = Float64Array.of(3, 7)))), 'snapshot.tearClock') // grew after now
    rejects(() => restoreClothState(world, cloth, broken((s) => (s.tearClock = Float64Array.of(NaN, -2)))), 'snapshot.tearClock')
    rejects(() => restoreClothState(world, cloth, broken((s) => (s.tearClock = Float64Array.of(0.5, -2)))), 'snapshot.tearClock')
    rejects(() => restoreClothState(world, cloth, broken((s) => (s.tearTip = new Uint8Array(3)))), 'snapshot')
    rejects(
      () => restoreClothState(world, cloth, broken((s) => (s.tearTip = new Uint8Array(snap.tearTip!.length).fill(2)))),
      'snapshot.tearTip[0]',
    )
    rejects(() => restoreClothState(world, cloth, broken((s) => (s.tearSplitAt = undefined))), 'snapshot')
    rejects(
      () => restoreClothState(world, cloth, broken((s) => (s.tearSplitAt = new Int32Array(snap.tearSplitAt!.length).fill(1e6)))),
      'snapshot.tearSplitAt[0]',
    )
    // a snapshot from before the tear clock was saved still restores
    const old = broken((s) => {
      delete s.tearClock
      delete s.tearTip
      delete s.tearSplitAt
    })
    expect(() => restoreClothState(world, cloth, old)).not.toThrow()
  })
})
