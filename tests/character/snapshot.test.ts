// Determinism and snapshots of character cloth: the same inputs give the same bytes; a snapshot
// rewinds the frame's motion history, the reference pose, constraints, held particles and skin.
import { addEntity, createWorld, removeEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  ClothError,
  createCloth,
  getClothReference,
  getClothState,
  getClothStats,
  getPins,
  installClothPlugin,
  pinRow,
  restoreClothState,
  saveClothState,
  setClothInertia,
  setClothMotionConstraints,
  setClothSkinning,
  setTransform,
  stepCloth,
  unpin,
  type ClothSnapshot,
} from '../../src/index'
import { hashBytes, rng } from '../helpers'
import { capeBehind, yawQuat } from './scenes'

/** A caped character (inertia 0.5, teleport reset at 90°, painted constraints) and a skinned sleeve on two bones. */
function buildScene(world: object, configure = true) {
  const hero = addEntity(world)
  setTransform(world, hero, [0, 1.6, 0])
  const torso = addEntity(world) // the sleeve's frame: no pin's target, no bone
  setTransform(world, torso, [0, 1.3, 0])
  const arm = [addEntity(world), addEntity(world)]
  setTransform(world, arm[0], [0.2, 1.4, 0])
  setTransform(world, arm[1], [0.5, 1.4, 0])
  const cape = capeBehind(world, [6, 9], 3)
  pinRow(world, cape, 0, hero)
  const sleeve = createCloth(world, { width: 0.6, height: 0.1, resolution: [7, 2], position: [0.5, 1.4, 0] })
  if (configure) configureScene(world, { hero, torso, arm, cape, sleeve })
  return { hero, torso, arm, cape, sleeve, cloths: [cape, sleeve] }
}

function configureScene(world: object, s: { hero: number; torso: number; arm: number[]; cape: number; sleeve: number }) {
  setClothInertia(world, s.cape, {
    frame: s.hero,
    linear: 0.5,
    angular: 0.5,
    centrifugal: 0.3,
    maxLinearSpeed: 6,
    teleport: { mode: 'reset', angle: Math.PI / 2 },
  })
  setClothMotionConstraints(world, s.cape, {
    maxDistance: Array.from({ length: 54 }, (_, i) => (i < 6 ? 0 : 0.04 * Math.floor(i / 6))),
    backstop: { distance: 0.02, radius: 0.6 },
    drive: 0.02,
  })
  const n = 14
  const joints: number[] = [], weights: number[] = []
  for (let i = 0; i < n; i++) {
    const u = (i % 7) / 6
    joints.push(0, 1, 0, 0)
    weights.push(1 - u, u, 0, 0)
  }
  setClothSkinning(world, s.sleeve, { bones: s.arm, joints, weights })
  setClothMotionConstraints(world, s.sleeve, { maxDistance: Array.from({ length: n }, (_, i) => (i % 7 === 0 ? 0 : 0.05)), every: 3 })
  setClothInertia(world, s.sleeve, { frame: s.torso, linear: 0.2, angular: 0.2, centrifugal: 0.2 })
}

/** Frame inputs from a seed: the character wanders and turns, snaps round now and then, teleports rarely; the elbow bends. */
function makeInputs(seed: number) {
  const r = rng(seed)
  const p = [0, 1.6, 0]
  let yaw = 0, f = 0
  return (world: object, s: ReturnType<typeof buildScene>) => {
    f++
    p[0] += (r() - 0.3) * 0.12
    p[2] += (r() - 0.5) * 0.05
    yaw += (r() - 0.5) * 0.2
    if (r() < 0.02) yaw += Math.PI // a snap: a teleport by angle
    if (r() < 0.01) p[0] += 4 // a jump: a teleport by distance
    setTransform(world, s.hero, p, yawQuat(yaw))
    setTransform(world, s.torso, [p[0], 1.3, p[2]], yawQuat(yaw))
    setTransform(world, s.arm[0], [p[0] + 0.2, 1.4, p[2]], yawQuat(yaw))
    const bend = Math.sin(f * 0.1)
    setTransform(world, s.arm[1], [p[0] + 0.5, 1.4, p[2]], [0, 0, Math.sin(bend / 2), Math.cos(bend / 2)])
    return (0.5 + r()) / 60
  }
}

function stateHash(world: object, cloths: number[]): string {
  return cloths.map((cl) => {
    const c = getClothState(world, cl)
    return hashBytes(c.pos) + hashBytes(c.prev) + hashBytes(c.vel)
  }).join('.')
}

function record(
  world: object,
  scene: ReturnType<typeof buildScene>,
  inputs: ReturnType<typeof makeInputs>,
  frames: number,
  hook?: (f: number) => void,
) {
  const out: string[] = []
  for (let f = 0; f < frames; f++) {
    hook?.(f)
    stepCloth(world, inputs(world, scene))
    out.push(stateHash(world, scene.cloths))
  }
  return out
}

/** Inputs replayable from frame `from`. */
function inputsFrom(seed: number, from: number) {
  const gen = makeInputs(seed)
  const sink = installClothPlugin(createWorld())
  const scene = buildScene(sink, false)
  for (let f = 0; f < from; f++) gen(sink, scene)
  return gen
}

const saveAll = (world: object, cloths: number[]) => cloths.map((cl) => saveClothState(world, cl))
const restoreAll = (world: object, cloths: number[], snaps: ClothSnapshot[]) =>
  cloths.forEach((cl, k) => restoreClothState(world, cl, snaps[k]))

describe('character cloth determinism', () => {
  it('two worlds fed the same inputs are byte-identical after every frame (snaps, jumps, resets, skinning)', () => {
    const a = installClothPlugin(createWorld()), b = installClothPlugin(createWorld())
    // world b: other entities first, so every id differs
    for (let k = 0; k < 17; k++) addEntity(b)
    const sa = buildScene(a), sb = buildScene(b)
    const ia = makeInputs(3), ib = makeInputs(3)
    for (let f = 0; f < 400; f++) {
      stepCloth(a, ia(a, sa))
      stepCloth(b, ib(b, sb))
      expect(stateHash(b, sb.cloths), `frame ${f}`).toBe(stateHash(a, sa.cloths))
    }
    expect(getClothStats(a).teleports).toBeGreaterThan(5) // snaps and jumps did happen (resets of the cape)
  })
})

describe('character cloth snapshots', () => {
  it('save, run, restore, run again: byte for byte, every frame', () => {
    const world = installClothPlugin(createWorld())
    const scene = buildScene(world)
    const inputs = makeInputs(5)
    record(world, scene, inputs, 37)
    const snaps = saveAll(world, scene.cloths)
    const first = record(world, scene, inputs, 300)
    restoreAll(world, scene.cloths, snaps)
    expect(record(world, scene, inputsFrom(5, 37), 300)).toEqual(first)
  })

  it('restoring undoes settings changed since the save (shares, constraints, skinning): the run continues as in a twin world that never saw them', () => {
    const world = installClothPlugin(createWorld())
    const scene = buildScene(world)
    const inputs = makeInputs(9)
    record(world, scene, inputs, 30)
    const snaps = saveAll(world, scene.cloths)
    const mess = (f: number) => {
      if (f === 5) setClothInertia(world, scene.cape, { frame: scene.arm[0], linear: 1 })
      if (f === 10) setClothMotionConstraints(world, scene.cape, null)
      if (f === 15) setClothSkinning(world, scene.sleeve, null)
      if (f === 20) setClothInertia(world, scene.sleeve, null)
    }
    const messy = record(world, scene, inputs, 60, mess)
    restoreAll(world, scene.cloths, snaps)
    const clean = record(world, scene, inputsFrom(9, 30), 60)
    expect(clean).not.toEqual(messy)
    const twin = installClothPlugin(createWorld())
    const twinScene = buildScene(twin)
    const twinInputs = makeInputs(9)
    record(twin, twinScene, twinInputs, 30)
    expect(record(twin, twinScene, twinInputs, 60)).toEqual(clean)
  })

  it('a snapshot from before any character settings takes them away again', () => {
    const world = installClothPlugin(createWorld())
    const scene = buildScene(world, false)
    const inputs = makeInputs(2)
    record(world, scene, inputs, 10)
    const snaps = saveAll(world, scene.cloths)
    configureScene(world, scene)
    record(world, scene, inputs, 20)
    restoreAll(world, scene.cloths, snaps)
    for (const cl of scene.cloths) expect(getClothState(world, cl).character).toBeNull()
    const twin = installClothPlugin(createWorld())
    const twinScene = buildScene(twin, false)
    const twinInputs = makeInputs(2)
    record(twin, twinScene, twinInputs, 10)
    expect(record(world, scene, inputsFrom(2, 10), 40)).toEqual(record(twin, twinScene, twinInputs, 40))
  })

  it('restores into a twin world built by the same calls; rejects a snapshot whose frame or bone entity is gone, naming the snapshot', () => {
    const a = installClothPlugin(createWorld()), b = installClothPlugin(createWorld())
    const sa = buildScene(a), sb = buildScene(b)
    const inputs = makeInputs(4)
    record(a, sa, inputs, 45)
    const snaps = saveAll(a, sa.cloths)
    const expected = record(a, sa, inputs, 120)
    restoreAll(b, sb.cloths, snaps)
    expect(record(b, sb, inputsFrom(4, 45), 120)).toEqual(expected)
    removeEntity(b, sb.arm[1])
    let error: unknown
    try {
      restoreClothState(b, sb.sleeve, snaps[1])
    } catch (e) {
      error = e
    }
    expect(error).toBeInstanceOf(ClothError)
    expect((error as ClothError).argument).toBe('snapshot')
    const broken = { ...snaps[0], character: snaps[0].character.slice(0, 3) }
    expect(() => restoreClothState(a, sa.cape, broken)).toThrow(ClothError)
  })

  it('rejects a snapshot whose frame or bone was removed and its id recycled for another entity with a Transform', () => {
    for (const role of ['frame', 'bone'] as const) {
      const world = installClothPlugin(createWorld())
      const follow = addEntity(world)
      setTransform(world, follow, [0, 1.6, 0])
      const cloth = createCloth(world, { width: 0.5, height: 0.5, resolution: [5, 5], position: [0, 1.5, 0] })
      pinRow(world, cloth, 0) // pinned to the world: what it follows is no pin target
      if (role === 'frame') setClothInertia(world, cloth, { frame: follow })
      else {
        setClothSkinning(world, cloth, {
          bones: [follow],
          joints: new Array(4 * 25).fill(0),
          weights: Array.from({ length: 4 * 25 }, (_, q) => (q % 4 === 0 ? 1 : 0)),
        })
      }
      setClothMotionConstraints(world, cloth, { maxDistance: 0.05 })
      stepCloth(world, 1 / 60)
      const snap = saveClothState(world, cloth)
      removeEntity(world, follow)
      const other = addEntity(world)
      expect(other).toBe(follow) // (bitECS hands the id out again)
      setTransform(world, other, [50, 0, 0])
      let error: unknown
      try {
        restoreClothState(world, cloth, snap)
      } catch (e) {
        error = e
      }
      expect(error, role).toBeInstanceOf(ClothError)
      expect((error as ClothError).message).toMatch(/lost its Transform/)
    }
  })

  it('a snapshot keeps where its pins were attached: settings given after a restore bind the cape as the saved world does', () => {
    // a pin records its target's pose when made, which character settings given later bind the cloth
    // to; a restore that makes the pins again (here into a world whose pins were removed, its hero
    // elsewhere) must not take the target's pose at the restore for it (the reference was 3.3 m off)
    const a = installClothPlugin(createWorld()), b = installClothPlugin(createWorld())
    const sa = buildScene(a, false), sb = buildScene(b, false)
    const walk = (w: object, hero: number, f: number) => setTransform(w, hero, [0.05 * f, 1.6, 0], yawQuat(0.02 * f))
    for (let f = 1; f <= 60; f++) {
      walk(a, sa.hero, f)
      stepCloth(a, 1 / 60)
    }
    const snap = saveClothState(a, sa.cape)
    for (const pin of getPins(b, sb.cape)) unpin(b, pin)
    walk(b, sb.hero, 60)
    stepCloth(b, 1 / 60)
    restoreClothState(b, sb.cape, snap)
    const paint = { maxDistance: Array.from({ length: 54 }, (_, i) => (i < 6 ? 0 : 0.04 * Math.floor(i / 6))) }
    setClothMotionConstraints(a, sa.cape, paint)
    setClothMotionConstraints(b, sb.cape, paint)
    const ra = getClothReference(a, sa.cape)!, rb = getClothReference(b, sb.cape)!
    let diff = 0, offPins = 0
    const pos = getClothState(a, sa.cape).pos
    for (let j = 0; j < ra.length; j++) diff = Math.max(diff, Math.abs(ra[j] - rb[j]))
    for (let j = 0; j < 18; j++) offPins = Math.max(offPins, Math.abs(ra[j] - pos[j]))
    expect(offPins).toBeLessThan(1e-5)
    expect(diff).toBeLessThan(1e-9)
    // a pose no Transform gives is refused, naming the snapshot
    for (const [at, value] of [[0, 1e12], [3, 2], [7, 0], [8, Number.NaN]] as const) {
      const pinPoses = snap.pinPoses!.slice()
      pinPoses[at] = value
      expect(() => restoreClothState(b, sb.cape, { ...snap, pinPoses }), `${at}`).toThrow(ClothError)
    }
  })

  it('saving into an earlier snapshot reuses its arrays', () => {
    const world = installClothPlugin(createWorld())
    const scene = buildScene(world)
    const snap = saveClothState(world, scene.sleeve)
    stepCloth(world, 1 / 60)
    const again = saveClothState(world, scene.sleeve, snap)
    expect(again.character).toBe(snap.character)
    expect(again.characterParticles).toBe(snap.characterParticles)
    expect(again.characterBoneData).toBe(snap.characterBoneData)
  })
})
