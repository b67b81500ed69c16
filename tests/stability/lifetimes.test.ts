// Entity lifetimes: what a cloth follows must be alive and the same entity. bitECS 0.4 recycles
// ids (last removed, first reused) and never clears data, so an id that comes back names another
// entity; a frozen cloth, a snapshot or a queued event must not mistake one for the other.
import { addEntity, createWorld, entityExists, removeComponent, removeEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  ClothError,
  addSphereCollider,
  createCloth,
  getClothComponents,
  restoreClothState,
  saveClothState,
  drainClothResets,
  drainClothTears,
  getClothTearCount,
  getClothLod,
  getClothState,
  getClothStats,
  getPins,
  installClothPlugin,
  makeTearable,
  onClothReset,
  onClothTear,
  pinParticle,
  pinRow,
  removeCloth,
  setClothBudget,
  setClothVisible,
  setTransform,
  stepCloth,
  unpin,
} from '../../src/index'
import { CHEAP_CALIBRATION } from '../helpers'

const frame = 1 / 60

/** A cape on a character (Transform entity) in a world with a budget that freezes invisible cloths. */
function frozenCapeScene() {
  const world = installClothPlugin(createWorld(), { sleep: false })
  const hero = addEntity(world)
  setTransform(world, hero, [0, 1.6, 0])
  const cape = createCloth(world, { width: 0.6, height: 0.9, resolution: 8, position: [0, 1.6, -0.15] })
  pinRow(world, cape, 0, hero)
  setClothBudget(world, { calibration: CHEAP_CALIBRATION, adapt: false, interval: 1 })
  for (let f = 0; f < 60; f++) stepCloth(world, frame)
  setClothVisible(world, cape, false)
  stepCloth(world, frame)
  expect(getClothLod(world, cape).frozen).toBe(true)
  const c = getClothState(world, cape)
  return { world, hero, cape, c, frozenAt: Float64Array.from(c.pos) }
}

/** Largest distance of the cloth's particles from a pose, m. */
function farthest(pos: Float64Array, from: Float64Array, n: number): number {
  let d = 0
  for (let i = 0; i < n; i++)
    d = Math.max(d, Math.hypot(pos[3 * i] - from[3 * i], pos[3 * i + 1] - from[3 * i + 1], pos[3 * i + 2] - from[3 * i + 2]))
  return d
}

/** Creates entities until one gets id `id` back (bitECS recycles ids); returns it, the others stay. */
function recycle(world: object, id: number): number {
  for (let k = 0; k < 1000; k++) {
    const e = addEntity(world)
    if (e === id) return e
  }
  throw new Error(`id ${id} never came back`)
}

describe('a frozen cloth thaws carried only by the pins it still hangs from', () => {
  for (const torso of [false, true]) {
    it(`unpinned while frozen, then its character${torso ? ' (with a torso collider)' : ''} walks 100 m away: it thaws where it was let go, not 100 m on`, () => {
      const s = frozenCapeScene()
      // a collider on the character keeps it tracked after the pins are gone
      if (torso) addSphereCollider(s.world, addEntity(s.world), { body: s.hero, offset: [0, -0.5, 0.3], radius: 0.1 })
      for (const pin of getPins(s.world, s.cape)) unpin(s.world, pin)
      for (let f = 1; f <= 60; f++) {
        setTransform(s.world, s.hero, [f * 100 / 60, 1.6, 0])
        stepCloth(s.world, frame)
      }
      setClothVisible(s.world, s.cape, true)
      stepCloth(s.world, frame)
      expect(getClothLod(s.world, s.cape).frozen).toBe(false)
      // one step of free fall from where it froze, nothing more
      expect(farthest(s.c.pos, s.frozenAt, s.c.count)).toBeLessThan(0.05)
    })
  }

  it('carried 5 m by its character while frozen, then let go: thawed 5 m on, where it was dropped', () => {
    const s = frozenCapeScene()
    for (let f = 1; f <= 30; f++) {
      setTransform(s.world, s.hero, [f * 5 / 30, 1.6, 0])
      stepCloth(s.world, frame)
    }
    for (const pin of getPins(s.world, s.cape)) unpin(s.world, pin)
    for (let f = 1; f <= 30; f++) {
      setTransform(s.world, s.hero, [5 + f * 95 / 30, 1.6, 0])
      stepCloth(s.world, frame)
    }
    setClothVisible(s.world, s.cape, true)
    stepCloth(s.world, frame)
    const moved = Float64Array.from(s.frozenAt)
    for (let i = 0; i < s.c.count; i++) moved[3 * i] += 5
    expect(farthest(s.c.pos, moved, s.c.count)).toBeLessThan(0.05)
  })

  it('its character removed while frozen and the id recycled by an entity 500 m away (a collider body): the cape is not carried there', () => {
    const s = frozenCapeScene()
    const id = s.hero
    removeEntity(s.world, s.hero)
    expect(getPins(s.world, s.cape)).toEqual([])
    const other = recycle(s.world, id)
    setTransform(s.world, other, [500, 1.6, 0])
    addSphereCollider(s.world, other, { radius: 0.3 }) // tracked again: it may take the freed slot
    for (let f = 0; f < 10; f++) stepCloth(s.world, frame)
    setTransform(s.world, other, [600, 1.6, 0])
    setClothVisible(s.world, s.cape, true)
    stepCloth(s.world, frame)
    expect(farthest(s.c.pos, s.frozenAt, s.c.count)).toBeLessThan(0.05)
  })

  it('its character removed and the id recycled by a new character the cape is pinned to again while frozen: no carry by the old one’s motion', () => {
    const s = frozenCapeScene()
    const id = s.hero
    removeEntity(s.world, s.hero)
    const other = recycle(s.world, id)
    setTransform(s.world, other, [300, 1.6, 0])
    pinParticle(s.world, s.cape, 0, other) // (held where the particle is, in the new character's frame)
    setTransform(s.world, other, [310, 1.6, 0])
    for (let f = 0; f < 10; f++) stepCloth(s.world, frame)
    setClothVisible(s.world, s.cape, true)
    stepCloth(s.world, frame)
    // carried by the new pin's target from where it was pinned (10 m), not by 300 m of id reuse
    const moved = Float64Array.from(s.frozenAt)
    for (let i = 0; i < s.c.count; i++) moved[3 * i] += 10
    expect(farthest(s.c.pos, moved, s.c.count)).toBeLessThan(0.05)
    expect(getClothStats(s.world).guardResets).toBe(0)
  })

  it('one of its pins released while frozen, the others still on the character: it thaws carried along with the character', () => {
    const s = frozenCapeScene()
    const pins = getPins(s.world, s.cape)
    unpin(s.world, pins[0])
    for (let f = 1; f <= 60; f++) {
      setTransform(s.world, s.hero, [f * 0.1, 1.6, 0])
      stepCloth(s.world, frame)
    }
    setClothVisible(s.world, s.cape, true)
    stepCloth(s.world, frame)
    const moved = Float64Array.from(s.frozenAt)
    for (let i = 0; i < s.c.count; i++) moved[3 * i] += 6
    expect(farthest(s.c.pos, moved, s.c.count)).toBeLessThan(0.05)
    expect(entityExists(s.world, s.hero)).toBe(true)
  })

  it('its pins moved from one character to another while frozen: carried by the first up to the switch, then by the second', () => {
    const s = frozenCapeScene()
    for (let f = 1; f <= 20; f++) {
      setTransform(s.world, s.hero, [f * 0.1, 1.6, 0]) // 2 m with the first character
      stepCloth(s.world, frame)
    }
    const rider = addEntity(s.world)
    setTransform(s.world, rider, [2, 1.6, 0])
    const old = getPins(s.world, s.cape)
    for (let col = 0; col < 8; col++) pinParticle(s.world, s.cape, col, rider)
    for (const pin of old) unpin(s.world, pin)
    for (let f = 1; f <= 20; f++) {
      setTransform(s.world, rider, [2, 1.6 + f * 0.15, 0]) // 3 m up with the second
      setTransform(s.world, s.hero, [-f, 1.6, 0]) // the first walks off
      stepCloth(s.world, frame)
    }
    setClothVisible(s.world, s.cape, true)
    stepCloth(s.world, frame)
    const moved = Float64Array.from(s.frozenAt)
    for (let i = 0; i < s.c.count; i++) {
      moved[3 * i] += 2
      moved[3 * i + 1] += 3
    }
    expect(farthest(s.c.pos, moved, s.c.count)).toBeLessThan(0.05)
  })
})

describe('events of a cloth removed before they are delivered are dropped: its id may already name another cloth', () => {
  /** Two tearable sheets hanging by their top rows with a threshold gravity exceeds: both tear in the same step. */
  function twoTearing() {
    const world = installClothPlugin(createWorld())
    const sheets = [0, 3].map((x) => {
      const cl = createCloth(world, { width: 1, height: 1, resolution: 6, position: [x, 2, 0] })
      pinRow(world, cl, 0)
      makeTearable(world, cl, { strain: 1e-6, maxTearsPerStep: 3, hysteresis: 1 })
      return cl
    })
    stepCloth(world, frame) // one tear each; from the next step on, three each
    return { world, sheets }
  }

  it('tear events: the undrained events of a removed cloth give their room in the drain queue back', () => {
    // (they were only marked dead: a game that drains rarely then lost the events of live cloths)
    const world = installClothPlugin(createWorld())
    const big = createCloth(world, { width: 1, height: 1, resolution: 24, position: [0, 2, 0] })
    pinRow(world, big, 0)
    makeTearable(world, big, { strain: 1e-6, maxTearsPerStep: 64, hysteresis: 1 })
    for (let f = 0; f < 600 && getClothTearCount(world, big) < 300; f++) stepCloth(world, frame)
    expect(getClothTearCount(world, big)).toBeGreaterThanOrEqual(300) // more than the queue's 256
    removeCloth(world, big)
    const small = createCloth(world, { width: 1, height: 1, resolution: 6, position: [3, 2, 0] })
    pinRow(world, small, 0)
    makeTearable(world, small, { strain: 1e-6, maxTearsPerStep: 3, hysteresis: 1 })
    for (let f = 0; f < 3; f++) stepCloth(world, frame)
    const drained: number[] = []
    drainClothTears(world, (e) => drained.push(e.cloth))
    expect(drained.length).toBeGreaterThan(0)
    expect(drained.every((c) => c === small)).toBe(true)
  })

  it('tear events: a drain callback removes a cloth: the rest of its queued events are not handed over', () => {
    // (they were: the drain had emptied the queue before the callback removed the cloth)
    const { world, sheets } = twoTearing()
    for (let f = 0; f < 3; f++) stepCloth(world, frame)
    const queued: number[] = []
    const drained: number[] = []
    let removed = false
    // every queued event, in order, to find one of sheets[1] with more of its own after it
    drainClothTears(world, (e) => queued.push(e.cloth))
    expect(queued.filter((c) => c === sheets[1]).length).toBeGreaterThan(1)
    for (let f = 0; f < 3; f++) stepCloth(world, frame)
    const delivered = drainClothTears(world, (e) => {
      drained.push(e.cloth)
      if (!removed && e.cloth === sheets[1]) {
        removeCloth(world, sheets[1])
        removed = true
      }
    })
    expect(removed).toBe(true)
    expect(delivered).toBe(drained.length)
    expect(drained.filter((c) => c === sheets[1])).toEqual([sheets[1]]) // the one that led to its removal, no later
    expect(drained.filter((c) => c === sheets[0]).length).toBeGreaterThan(0)
  })

  it('tear events: a listener removes the other torn cloth and creates one that reuses its id; no later event names the new cloth', () => {
    const { world, sheets } = twoTearing()
    const seen: number[] = []
    let replacement = -1
    onClothTear(world, (e) => {
      seen.push(e.cloth)
      if (replacement < 0 && e.cloth === sheets[0]) {
        removeCloth(world, sheets[1])
        replacement = createCloth(world, { width: 1, height: 1, resolution: 4, position: [6, 2, 0] })
      }
    })
    for (let f = 0; f < 5 && replacement < 0; f++) stepCloth(world, frame)
    expect(replacement).toBe(sheets[1]) // the id came back
    const drained: number[] = []
    drainClothTears(world, (e) => drained.push(e.cloth))
    expect(seen.length).toBeGreaterThan(1)
    // the replacement never tore: its id may not appear after it was created
    expect(seen.slice(seen.indexOf(sheets[0]) + 1).filter((c) => c === replacement)).toEqual([])
    expect(drained.filter((c) => c === replacement)).toEqual([])
    expect(drained.filter((c) => c === sheets[0]).length).toBeGreaterThan(0)
  })

  it('tear events: a listener removes the cloth it is told about and creates another (same id): the rest of that cloth’s events are dropped', () => {
    const { world, sheets } = twoTearing()
    const after: number[] = []
    let replacement = -1
    onClothTear(world, (e) => {
      if (replacement >= 0) after.push(e.cloth)
      else if (e.cloth === sheets[1]) {
        removeCloth(world, sheets[1])
        replacement = createCloth(world, { width: 1, height: 1, resolution: 4, position: [6, 2, 0] })
      }
    })
    for (let f = 0; f < 5 && replacement < 0; f++) stepCloth(world, frame)
    expect(replacement).toBe(sheets[1])
    expect(after.filter((c) => c === replacement)).toEqual([])
  })

  it('guard reset events: the same for a listener that replaces another reset cloth', () => {
    const world = installClothPlugin(createWorld())
    const cloths = [0, 3].map((x) => {
      const cl = createCloth(world, { width: 1, height: 1, resolution: 4, position: [x, 2, 0] })
      pinRow(world, cl, 0)
      return cl
    })
    stepCloth(world, frame)
    for (const cl of cloths) getClothState(world, cl).pos[20] = NaN // a host bug in both
    const seen: number[] = []
    let replacement = -1
    onClothReset(world, (e) => {
      seen.push(e.cloth)
      if (replacement < 0 && e.cloth === cloths[0]) {
        removeCloth(world, cloths[1])
        replacement = createCloth(world, { width: 1, height: 1, resolution: 4, position: [6, 2, 0] })
      }
    })
    stepCloth(world, frame)
    expect(replacement).toBe(cloths[1])
    expect(seen).toEqual([cloths[0]])
    expect(drainClothResets(world).map((e) => e.cloth)).toEqual([cloths[0]])
  })
})

describe('a snapshot names its pin targets by id: an id reused since is refused', () => {
  function saved() {
    const world = installClothPlugin(createWorld())
    const hero = addEntity(world)
    setTransform(world, hero, [0, 1.6, 0])
    const cape = createCloth(world, { width: 0.6, height: 0.9, resolution: 6, position: [0, 1.6, -0.15] })
    pinRow(world, cape, 0, hero)
    for (let f = 0; f < 10; f++) stepCloth(world, frame)
    return { world, hero, cape, snapshot: saveClothState(world, cape) }
  }

  it('the target removed and its id taken by another entity with a Transform: restoring throws a ClothError instead of pinning the cape to the stranger', () => {
    const s = saved()
    removeEntity(s.world, s.hero)
    const stranger = recycle(s.world, s.hero)
    setTransform(s.world, stranger, [50, 0, 0])
    expect(() => restoreClothState(s.world, s.cape, s.snapshot)).toThrow(ClothError)
    expect(() => restoreClothState(s.world, s.cape, s.snapshot)).toThrow(/lost its Transform/)
    expect(getPins(s.world, s.cape)).toEqual([]) // nothing was changed by the refused restore
  })

  it('the target’s Transform taken away and given back: refused too (its pins were released)', () => {
    const s = saved()
    removeComponent(s.world, s.hero, getClothComponents(s.world).Transform)
    setTransform(s.world, s.hero, [0, 1.6, 0])
    expect(() => restoreClothState(s.world, s.cape, s.snapshot)).toThrow(/lost its Transform/)
  })

  it('other entities coming and going, ids reused: the restore goes through and replays', () => {
    const s = saved()
    for (let k = 0; k < 5; k++) {
      const e = addEntity(s.world)
      setTransform(s.world, e, [k, 0, 0])
      removeEntity(s.world, e)
    }
    for (let f = 0; f < 10; f++) stepCloth(s.world, frame)
    const after = getClothState(s.world, s.cape).pos.slice()
    restoreClothState(s.world, s.cape, s.snapshot)
    for (let f = 0; f < 10; f++) stepCloth(s.world, frame)
    expect(getClothState(s.world, s.cape).pos).toEqual(after)
  })
})
