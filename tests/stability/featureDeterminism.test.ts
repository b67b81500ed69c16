// Determinism and snapshots with colliders, wind and tearing: the same inputs give the same bytes
// whatever entities came and went, and a snapshot restores a run byte for byte, colliders, wind
// zones and a torn cloth included (see README, Snapshots, for what a torn cloth's snapshot covers).
import { addComponent, addEntity, createWorld, removeEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  ClothError,
  addBoxCollider,
  addSphereCollider,
  createCloth,
  createWindZone,
  enableSelfCollision,
  getClothComponents,
  getClothState,
  getClothStats,
  getClothTearCount,
  gustWind,
  installClothPlugin,
  makeTearable,
  pinParticle,
  removeCollider,
  restoreClothState,
  saveClothState,
  setTransform,
  stepCloth,
  type ClothSnapshot,
} from '../../src/index'
import { hashBytes, rng } from '../helpers'
import { hangingSheet } from './harness'
import { heroWithBody, poseLegs } from './scenes'
import { accordionSheet, ground } from '../collision/scenes'

/**
 * A character with body colliders and a self-colliding cape; a tearable sheet pulled apart by two
 * hands in a turbulent wind and a moving box zone; a sphere swinging through the sheet; ground.
 */
function buildScene(world: object) {
  const body = heroWithBody(world, { resolution: [6, 8] })
  enableSelfCollision(world, body.cloths[0])
  const hands = [addEntity(world), addEntity(world)]
  setTransform(world, hands[0], [2.5, 2, 0])
  setTransform(world, hands[1], [3.5, 2, 0])
  const sheet = createCloth(world, { width: 1, height: 1, resolution: 8, position: [3, 2, 0], bending: 'both' })
  pinParticle(world, sheet, 0, hands[0])
  pinParticle(world, sheet, 7, hands[1])
  makeTearable(world, sheet, { strain: 0.15, maxTearsPerStep: 3 })
  const ball = addEntity(world)
  setTransform(world, ball, [3, 1.3, -1])
  addSphereCollider(world, ball, { radius: 0.2 })
  const breeze = createWindZone(world, { direction: [0.2, 0, 1], strength: 6, turbulence: 0.4, seed: 3 })
  const fan = createWindZone(world, { shape: 'box', position: [3, 1.5, -1], size: [1, 1, 1], direction: [0, 0.3, 1], strength: 10 })
  return { ...body, sheet, hands, ball, breeze, fan, cloths: [body.cloths[0], sheet] }
}
type SceneParts = ReturnType<typeof buildScene>

/** The inputs of each frame from a seeded generator: poses, gusts, frame times. */
function makeInputs(seed: number) {
  const r = rng(seed)
  const p = [0, 1.6, 0]
  let yaw = 0, t = 0, f = 0
  return (world: object, s: SceneParts) => {
    p[0] += (r() - 0.5) * 0.1
    p[2] += r() * 0.05
    yaw += (r() - 0.5) * 0.2
    if (r() < 0.01) p[0] += 5
    setTransform(world, s.hero, p, [0, Math.sin(yaw / 2), 0, Math.cos(yaw / 2)])
    poseLegs({ ...s, world }, p, yaw, t)
    const spread = f < 60 ? 0.02 * f : Math.max(0, 1.2 - 0.03 * (f - 60)) // pulled apart, then let go
    setTransform(world, s.hands[0], [2.5 - spread, 2, 0])
    setTransform(world, s.hands[1], [3.5 + spread, 2, 0.2 * r()])
    setTransform(world, s.ball, [3 + Math.sin(t * 3), 1.3, -0.5 + 0.6 * Math.cos(t * 2)])
    setTransform(world, s.fan, [3, 1.5 + 0.2 * Math.sin(t), -1])
    if (f % 90 === 45) gustWind(world, s.breeze, { strength: 10 * r(), duration: 1 })
    const dt = (0.5 + r()) / 60
    t += dt
    f++
    return dt
  }
}

function stateHash(world: object, cloths: number[]): string {
  return cloths
    .map((cl) => {
      const c = getClothState(world, cl)
      const n = 3 * c.count
      return hashBytes(c.pos.subarray(0, n)) + hashBytes(c.prev.subarray(0, n)) + hashBytes(c.vel.subarray(0, n)) + ':' + c.count
    })
    .join('.')
}

describe('determinism with colliders, wind and tearing', () => {
  it('two worlds fed the same inputs are byte-identical after every frame (tears, contacts, gusts and all)', () => {
    const a = installClothPlugin(createWorld()), b = installClothPlugin(createWorld())
    const sa = buildScene(a), sb = buildScene(b)
    const ia = makeInputs(11), ib = makeInputs(11)
    for (let f = 0; f < 300; f++) {
      stepCloth(a, ia(a, sa))
      stepCloth(b, ib(b, sb))
      expect(stateHash(b, sb.cloths), `frame ${f}`).toBe(stateHash(a, sa.cloths))
    }
    const stats = getClothStats(a)
    expect(getClothTearCount(a, sa.sheet)).toBeGreaterThan(0)
    expect(stats.colliderTests).toBeGreaterThan(0)
    expect(stats.selfCollisionTests).toBeGreaterThan(0)
    expect(stats.windTriangles).toBeGreaterThan(0)
  })

  it('entity churn (entities, colliders, wind zones, tearable and self-colliding cloths coming and going) never changes the bytes', () => {
    const a = installClothPlugin(createWorld()), b = installClothPlugin(createWorld())
    // world b: a history before the scene, so every entity id differs
    const junk = Array.from({ length: 23 }, () => addEntity(b))
    for (let k = 0; k < junk.length; k += 2) removeEntity(b, junk[k])
    const early = createCloth(b, { width: 1, height: 1, resolution: 4, position: [-50, 1, 0] })
    const sa = buildScene(a), sb = buildScene(b)
    expect(sb.cloths).not.toEqual(sa.cloths)
    const ia = makeInputs(5), ib = makeInputs(5)
    const r = rng(99)
    const { Transform } = getClothComponents(b)
    const extras: number[] = []
    const colliders: number[] = []
    for (let f = 0; f < 240; f++) {
      // world b only: unrelated entities, colliders (far away, or on a layer nothing here collides
      // with), a far wind zone and far cloths come and go
      if (f % 7 === 0) {
        const e = addEntity(b)
        addComponent(b, e, Transform)
        setTransform(b, e, [r(), r(), r()])
        extras.push(e)
      }
      if (f % 11 === 0 && extras.length > 0) removeEntity(b, extras.splice(Math.floor(r() * extras.length), 1)[0])
      if (f % 13 === 0) {
        const e = addEntity(b)
        setTransform(b, e, f % 2 ? [-60 + r(), 1, 0] : [0, 1.2, 0])
        addBoxCollider(b, e, { halfExtents: [0.3, 0.3, 0.3], layer: f % 2 ? 1 : 64, mask: f % 2 ? 0xffffffff : 64 })
        colliders.push(e)
      }
      if (f % 17 === 0 && colliders.length > 0) {
        const e = colliders.splice(Math.floor(r() * colliders.length), 1)[0]
        if (f % 2) removeCollider(b, e)
        else removeEntity(b, e)
      }
      if (f === 40) removeEntity(b, early)
      if (f === 60) extras.push(createWindZone(b, { shape: 'sphere', position: [-80, 0, 0], size: 2, direction: [1, 0, 0], strength: 50 }))
      if (f === 70) {
        const extra = createCloth(b, { width: 0.5, height: 0.5, resolution: 5, position: [-70, 1, 0] })
        pinParticle(b, extra, 0)
        makeTearable(b, extra, { strain: 0.01 })
        enableSelfCollision(b, extra)
        extras.push(extra)
      }
      stepCloth(a, ia(a, sa))
      stepCloth(b, ib(b, sb))
      expect(stateHash(b, sb.cloths), `frame ${f}`).toBe(stateHash(a, sa.cloths))
    }
    expect(getClothTearCount(a, sa.sheet)).toBeGreaterThan(0)
  })
})

describe('snapshots with colliders, wind and tearing', () => {
  function record(world: object, s: SceneParts, inputs: ReturnType<typeof makeInputs>, frames: number) {
    const out: string[] = []
    for (let f = 0; f < frames; f++) {
      stepCloth(world, inputs(world, s))
      out.push(stateHash(world, s.cloths))
    }
    return out
  }
  /** Inputs replayable from frame `from`: a fresh generator advanced past the earlier frames in a scratch world. */
  function inputsFrom(seed: number, from: number) {
    const gen = makeInputs(seed)
    const sink = installClothPlugin(createWorld())
    const s = buildScene(sink)
    for (let f = 0; f < from; f++) gen(sink, s)
    return gen
  }
  const saveAll = (world: object, cloths: number[]) => cloths.map((cl) => saveClothState(world, cl))
  const restoreAll = (world: object, cloths: number[], snaps: ClothSnapshot[]) =>
    cloths.forEach((cl, k) => restoreClothState(world, cl, snaps[k]))

  it('save, run, restore, run again: byte for byte (moving colliders, body colliders, turbulent wind and gusts, a torn cloth, self-collision)', () => {
    const world = installClothPlugin(createWorld())
    const s = buildScene(world)
    const inputs = makeInputs(21)
    record(world, s, inputs, 100)
    const tornAtSave = getClothTearCount(world, s.sheet)
    expect(tornAtSave).toBeGreaterThan(0) // saved torn
    // no further tears from here (a snapshot cannot roll a cloth back across a tear: see below)
    makeTearable(world, s.sheet, { strain: 100 })
    const snaps = saveAll(world, s.cloths)
    const first = record(world, s, inputsFrom(21, 100), 100)
    expect(getClothTearCount(world, s.sheet)).toBe(tornAtSave)
    restoreAll(world, s.cloths, snaps)
    expect(record(world, s, inputsFrom(21, 100), 100)).toEqual(first)
  })

  it('restoring undoes what happened since (colliders moved, gusts, pins changed, the cape pressed onto the ground): the run continues as in a twin world that never saw it', () => {
    const a = installClothPlugin(createWorld()), b = installClothPlugin(createWorld())
    const sa = buildScene(a), sb = buildScene(b)
    const ia = makeInputs(8), ib = makeInputs(8)
    record(a, sa, ia, 100)
    record(b, sb, ib, 100)
    for (const [w, s] of [[a, sa], [b, sb]] as const) makeTearable(w, s.sheet, { strain: 100 }) // no tears from here
    expect(stateHash(b, sb.cloths)).toBe(stateHash(a, sa.cloths))
    const snaps = saveAll(a, sa.cloths)
    // the mess, in world a only
    const r = rng(77)
    for (let f = 0; f < 60; f++) {
      setTransform(a, sa.hero, [r(), 0.3 + r() * 0.1, r()], [0.7, 0, 0, 0.7]) // thrown face down onto the ground
      poseLegs({ ...sa, world: a }, [r(), 0.3, r()], 0, f)
      setTransform(a, sa.ball, [3 + r() - 0.5, 1.5, 0.1 * r()]) // pressed into the sheet
      setTransform(a, sa.hands[0], [2 - r(), 2, r()])
      if (f === 10) gustWind(a, sa.breeze, { strength: 30, duration: 3 })
      if (f === 20) pinParticle(a, sa.sheet, 60, sa.hands[0]) // (kept: restoring removes it, and its tethers)
      stepCloth(a, (0.5 + r()) / 60)
    }
    restoreAll(a, sa.cloths, snaps)
    const ja = inputsFrom(8, 100), jb = inputsFrom(8, 100)
    for (let f = 0; f < 120; f++) {
      stepCloth(a, ja(a, sa))
      stepCloth(b, jb(b, sb))
      expect(stateHash(a, sa.cloths), `frame ${f}`).toBe(stateHash(b, sb.cloths))
    }
  })

  it('keeps a tearable cloth’s tear counters: edges part way through their hysteresis stay so', () => {
    const world = installClothPlugin(createWorld())
    const s = buildScene(world)
    const inputs = makeInputs(3)
    record(world, s, inputs, 40)
    const c = getClothState(world, s.sheet)
    const snap = saveClothState(world, s.sheet)
    const over = Uint8Array.from(c.tear!.over.subarray(0, c.tear!.edges.count))
    const tears = getClothTearCount(world, s.sheet)
    c.tear!.over.fill(7)
    restoreClothState(world, s.sheet, snap)
    expect(Uint8Array.from(c.tear!.over.subarray(0, c.tear!.edges.count))).toEqual(over)
    expect(getClothTearCount(world, s.sheet)).toBe(tears)
  })

  it('rejects a torn cloth’s snapshot once the cloth has torn further, or into a twin torn differently, with a ClothError naming the snapshot', () => {
    const world = installClothPlugin(createWorld())
    const s = buildScene(world)
    const inputs = makeInputs(21)
    record(world, s, inputs, 30)
    const snap = saveClothState(world, s.sheet)
    const before = getClothTearCount(world, s.sheet)
    record(world, s, inputs, 60)
    expect(getClothTearCount(world, s.sheet)).toBeGreaterThan(before)
    const error = (fn: () => void) => {
      try {
        fn()
      } catch (e) {
        return e as ClothError
      }
      throw new Error('no error')
    }
    const e1 = error(() => restoreClothState(world, s.sheet, snap))
    expect(e1).toBeInstanceOf(ClothError)
    expect(e1.argument).toBe('snapshot')
    expect(e1.message).toMatch(/tore \(\d+ tears? since\).*does not restore a torn mesh/)
    // a twin built the same way but torn elsewhere, as often: its mesh is not this one
    const twin = installClothPlugin(createWorld())
    const st = buildScene(twin)
    const ti = makeInputs(22)
    record(twin, st, ti, 30)
    const e2 = error(() => restoreClothState(twin, st.sheet, saveClothState(world, s.sheet)))
    expect(e2.argument).toBe('snapshot')
    const tornTwin = getClothState(twin, st.sheet).count === getClothState(world, s.sheet).count ? /torn differently/ : /mesh|tore/
    expect(e2.message).toMatch(tornTwin)
    // and tearable vs not
    const plain = installClothPlugin(createWorld())
    const sp = buildScene(plain)
    const fresh = saveClothState(plain, sp.sheet)
    const other = createCloth(plain, { width: 1, height: 1, resolution: 8, position: [3, 2, 0], bending: 'both' })
    expect(error(() => restoreClothState(plain, other, fresh)).message).toMatch(/tearable/)
  })

  /** Two worlds built by `build` and run alike for `frames`; a messes with its world after a save, restores, and both go on alike. */
  function undoes(
    build: (w: object) => { cloths: number[] },
    input: (w: object, s: any, f: number) => void,
    mess: (w: object, s: any, f: number) => void,
  ) {
    const a = installClothPlugin(createWorld()), b = installClothPlugin(createWorld())
    const sa = build(a), sb = build(b)
    for (let f = 0; f < 60; f++) {
      input(a, sa, f)
      input(b, sb, f)
      stepCloth(a, 1 / 60)
      stepCloth(b, 1 / 60)
    }
    const snaps = saveAll(a, sa.cloths)
    for (let f = 0; f < 30; f++) {
      mess(a, sa, f)
      stepCloth(a, 1 / 60)
    }
    restoreAll(a, sa.cloths, snaps)
    for (let f = 60; f < 120; f++) {
      input(a, sa, f)
      input(b, sb, f)
      stepCloth(a, 1 / 60)
      stepCloth(b, 1 / 60)
      expect(stateHash(a, sa.cloths), `frame ${f}`).toBe(stateHash(b, sb.cloths))
    }
  }

  it('rewinds the motion of a collider pressing into the cloth', () => {
    undoes(
      (w) => {
        const cloth = hangingSheet(w)
        const ball = addEntity(w)
        setTransform(w, ball, [0, 1.5, 0.1])
        addSphereCollider(w, ball, { radius: 0.2 })
        return { cloths: [cloth], ball }
      },
      (w, s, f) => setTransform(w, s.ball, [0.3 * Math.sin(f / 10), 1.5, 0.1]),
      (w, s) => setTransform(w, s.ball, [0, 1.5, -0.8]),
    )
  })

  it('rewinds which particles rest on a collider (they count heavier against the layers above)', () => {
    undoes(
      (w) => {
        const g = ground(w)
        // a sheet folded like an accordion into 3 layers a particle spacing apart, on the ground
        const cloth = accordionSheet(w, { cols: 8, rows: 12, layers: 3, d: 0.05, y0: 0.012 })
        enableSelfCollision(w, cloth)
        return { cloths: [cloth], ground: g }
      },
      (w, s) => setTransform(w, s.ground, [0, 0, 0]),
      (w, s) => setTransform(w, s.ground, [0, -5, 0]), // the ground away: nothing rests on it
    )
  })

  it('restores a tearable cloth’s tethers (rebuilt in place when its pins change)', () => {
    const world = installClothPlugin(createWorld())
    const s = buildScene(world)
    record(world, s, makeInputs(4), 100) // past the pull (frames 0–60): the step after the save tears nothing
    const c = getClothState(world, s.sheet)
    const copy = () => ({
      n: c.tethers.set.count,
      p: Array.from(c.tethers.set.particle.subarray(0, c.tethers.set.count)),
      a: Array.from(c.tethers.set.anchor.subarray(0, c.tethers.set.count)),
      r: Array.from(c.tethers.set.rest.subarray(0, c.tethers.set.count)),
    })
    const saved = copy()
    expect(saved.n).toBeGreaterThan(0)
    const snap = saveClothState(world, s.sheet)
    pinParticle(world, s.sheet, 60, s.hands[0])
    stepCloth(world, 1 / 60) // rebuilds the tethers in place, around three anchors
    expect(copy()).not.toEqual(saved)
    restoreClothState(world, s.sheet, snap)
    expect(copy()).toEqual(saved)
  })

  it('tells a twin torn elsewhere (same particle count, another mesh) from this cloth', () => {
    /** A tearable sheet whose corner `pull` is yanked until exactly one edge breaks (capacity 1). */
    const torn = (pull: 0 | 7) => {
      const w = installClothPlugin(createWorld())
      const cloth = hangingSheet(w)
      makeTearable(w, cloth, { strain: 0.1, maxTearsPerStep: 1, capacity: 1, hysteresis: 1 })
      const hand = addEntity(w)
      setTransform(w, hand, [pull === 0 ? -0.5 : 0.5, 1, 0])
      pinParticle(w, cloth, 56 + pull, hand)
      for (let f = 0; f < 30; f++) {
        setTransform(w, hand, [pull === 0 ? -0.5 - f * 0.05 : 0.5 + f * 0.05, 1, 0])
        stepCloth(w, 1 / 60)
      }
      expect(getClothTearCount(w, cloth)).toBe(1)
      return { w, cloth }
    }
    const left = torn(0), right = torn(7)
    expect(getClothState(left.w, left.cloth).count).toBe(getClothState(right.w, right.cloth).count)
    let err: unknown
    try {
      restoreClothState(right.w, right.cloth, saveClothState(left.w, left.cloth))
    } catch (e) {
      err = e
    }
    expect(err).toBeInstanceOf(ClothError)
    expect((err as ClothError).message).toMatch(/torn differently/)
  })
})
