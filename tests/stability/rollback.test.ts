// Rollback and determinism in scenes the other snapshot tests do not cover: character cloth frozen,
// teleported, skinned and scaled around a restore, grabs, sleep, tearing, budgets, entity churn,
// Transforms written mid-frame, setup orders. Four of these failed before their fixes: a frozen
// cloth carried by its frame restored before its frame was (snapshot.ts restores the character
// section before the budget's), and a character frame's or bone's scale read live from the store
// (it is sampled with the frame now, and saved with the character section).
import { addEntity, createWorld, removeEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  ClothError,
  addCapsuleCollider,
  addSphereCollider,
  createWindZone,
  disposeClothWorld,
  enableSelfCollision,
  gustWind,
  makeTearable,
  onClothTear,
  setClothQualityTarget,
  beginClothStep,
  createCloth,
  endClothStep,
  getClothLod,
  getClothComponents,
  getClothState,
  getPins,
  pinParticle,
  unpin,
  grabParticle,
  isGrabActive,
  moveGrab,
  releaseGrab,
  installClothPlugin,
  isClothSleeping,
  pinRow,
  restoreClothState,
  saveClothState,
  setClothBudget,
  setClothInertia,
  setClothMotionConstraints,
  setClothSkinning,
  setClothSleep,
  setTransform,
  teleportCloth,
  stepCloth,
  type ClothSnapshot,
} from '../../src/index'
import { capeBehind, yawQuat } from '../character/scenes'
import { threadedWorld } from '../threads/scene'
import { CHEAP_CALIBRATION } from '../helpers'

/** Copies of positions, previous positions and velocities of the cloths. */
function bytes(world: object, cloths: number[]): Float64Array[] {
  const out: Float64Array[] = []
  for (const cl of cloths) {
    const c = getClothState(world, cl)
    out.push(c.pos.slice(0, 3 * c.count), c.prev.slice(0, 3 * c.count), c.vel.slice(0, 3 * c.count))
  }
  return out
}

/** Largest absolute difference between two byte sets (0 when identical; NaN-aware). */
function maxDiff(a: Float64Array[], b: Float64Array[]): number {
  let d = 0
  if (a.length !== b.length) return Infinity
  for (let k = 0; k < a.length; k++) {
    if (a[k].length !== b[k].length) return Infinity
    for (let j = 0; j < a[k].length; j++) {
      if (Object.is(a[k][j], b[k][j])) continue
      const e = Math.abs(a[k][j] - b[k][j])
      d = Number.isNaN(e) ? Infinity : Math.max(d, e)
    }
  }
  return d
}

/** Largest position difference (m) between the cloths of two worlds. */
function posDiff(a: object, b: object, cloths: number[], clothsB = cloths): number {
  let d = 0
  cloths.forEach((cl, k) => {
    const pa = getClothState(a, cl).pos, pb = getClothState(b, clothsB[k]).pos
    for (let j = 0; j < 3 * getClothState(a, cl).count; j++) d = Math.max(d, Math.abs(pa[j] - pb[j]))
  })
  return d
}

interface Scene {
  world: object
  cloths: number[]
  /** Sets the host's inputs of frame f (absolute), returns the frame time. */
  inputs: (f: number, variant?: number) => number
}

/**
 * Runs twin a and b in lockstep for `at` frames; a saves, runs `mess` frames (variant inputs and
 * the `messHook`), restores, and both run on `after` frames; compares bytes every frame.
 */
function rollback(
  build: () => Scene,
  at: number,
  mess: number,
  after: number,
  hooks: {
    messHook?: (s: Scene, f: number) => void
    afterRestore?: (s: Scene) => void
    both?: (s: Scene, f: number) => void
    report?: boolean
  } = {},
): { first: number; worst: number } {
  const a = build(), b = build()
  for (let f = 0; f < at; f++) {
    hooks.both?.(a, f)
    hooks.both?.(b, f)
    stepCloth(a.world, a.inputs(f))
    stepCloth(b.world, b.inputs(f))
  }
  const snaps: ClothSnapshot[] = a.cloths.map((cl) => saveClothState(a.world, cl))
  for (let f = at; f < at + mess; f++) {
    hooks.messHook?.(a, f)
    stepCloth(a.world, a.inputs(f, 1))
  }
  a.cloths.forEach((cl, k) => restoreClothState(a.world, cl, snaps[k]))
  if (at > 0) a.inputs(at - 1) // the host restores its Transforms
  hooks.afterRestore?.(a)
  let first = -1, worst = 0
  for (let f = at; f < at + after; f++) {
    hooks.both?.(a, f)
    hooks.both?.(b, f)
    stepCloth(a.world, a.inputs(f))
    stepCloth(b.world, b.inputs(f))
    const d = maxDiff(bytes(a.world, a.cloths), bytes(b.world, b.cloths))
    if (d !== 0 && first < 0) {
      first = f
      if (hooks.report) console.log(`first differing frame ${f}: positions differ by ${posDiff(a.world, b.world, a.cloths, b.cloths)} m`)
    }
    worst = Math.max(worst, d)
  }
  return { first, worst }
}

// ---------------------------------------------------------------------------------------------

/**
 * A character cloth without pins (held by max distance 0 on its top row), its frame the hero, who
 * also carries a sphere collider (so the hero stays tracked whatever the cloth's frame); a
 * budget culls the cloth while the viewer is far, the hero walks on meanwhile, then the viewer
 * comes back and the cloth thaws, carried by its frame's motion since the freeze.
 */
function frozenAnchorScene(): Scene & { hero: number; other: number; viewer: number } {
  const world = installClothPlugin(createWorld(), { sleep: false })
  const hero = addEntity(world)
  setTransform(world, hero, [0, 1.6, 0])
  const other = addEntity(world)
  setTransform(world, other, [30, 1.6, 0])
  const body = addEntity(world)
  addSphereCollider(world, body, { body: hero, offset: [0, -0.4, 0], radius: 0.15 })
  const viewer = addEntity(world)
  setTransform(world, viewer, [0, 2, 3])
  const cloth = capeBehind(world, [6, 9], 2)
  setClothInertia(world, cloth, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5 })
  setClothMotionConstraints(world, cloth, {
    maxDistance: Array.from({ length: 54 }, (_, i) => (i < 6 ? 0 : 0.05 * Math.floor(i / 6))),
  })
  setClothBudget(world, { viewer, near: 5, far: 20, cull: 40, calibration: CHEAP_CALIBRATION, adapt: false, interval: 3 })
  const inputs = (f: number, variant = 0) => {
    const t = f / 60
    // the hero walks along +x; the viewer goes away (frames 10..40), stays away, comes back at 80
    setTransform(world, hero, [0.05 * f + 3 * variant, 1.6, 0.3 * Math.sin(t)], yawQuat(0.2 * Math.sin(t)))
    setTransform(world, other, [30 + 0.1 * f, 1.6, -5 * variant], yawQuat(0.5 * variant))
    const away = f < 10 ? 0 : f < 80 ? 100 : 0
    setTransform(world, viewer, [0.05 * f, 2, 3 + away])
    return 1 / 60
  }
  return { world, cloths: [cloth], inputs, hero, other, viewer }
}

describe('snapshots of a frozen character cloth carried by its frame (no pins)', () => {
  it('sanity: the scene freezes and thaws', () => {
    const s = frozenAnchorScene()
    let froze = false, thawed = false
    for (let f = 0; f < 100; f++) {
      stepCloth(s.world, s.inputs(f))
      const lod = getClothLod(s.world, s.cloths[0])
      if (lod.frozen) froze = true
      if (froze && !lod.frozen) thawed = true
    }
    expect(froze).toBe(true)
    expect(thawed).toBe(true)
  })

  it('saved frozen, the frame switched to another entity since, restored: thaws like the twin', () => {
    const r = rollback(frozenAnchorScene, 50, 10, 50, {
      messHook: (s, f) => {
        if (f === 50) {
          const sc = s as ReturnType<typeof frozenAnchorScene>
          setClothInertia(sc.world, sc.cloths[0], { frame: sc.other, linear: 0.5, angular: 0.5, centrifugal: 0.5 })
        }
      },
      report: true,
    })
    expect(r, 'first differing frame, worst difference (m)').toEqual({ first: -1, worst: 0 })
  })

  it('saved frozen, character settings dropped since (world space again), restored: thaws like the twin', () => {
    const r = rollback(frozenAnchorScene, 50, 10, 50, {
      messHook: (s, f) => {
        if (f === 50) {
          setClothMotionConstraints(s.world, s.cloths[0], null)
          setClothInertia(s.world, s.cloths[0], null)
        }
      },
      report: true,
    })
    expect(r, 'first differing frame, worst difference (m)').toEqual({ first: -1, worst: 0 })
  })

  it('saved frozen, plain rollback: thaws like the twin', () => {
    const r = rollback(frozenAnchorScene, 50, 10, 50)
    expect(r).toEqual({ first: -1, worst: 0 })
  })
})

// ---------------------------------------------------------------------------------------------
// A caped character with painted limits, a backstop and teleport handling, and a skinned sleeve.

/** The hero, its two arm bones, and the 6×9 cape of these scenes (neither pinned nor held yet). */
function heroWithCape(world: object, iterations = 2): { hero: number; arm: number[]; cape: number } {
  const hero = addEntity(world)
  setTransform(world, hero, [0, 1.6, 0])
  const arm = [addEntity(world), addEntity(world)]
  setTransform(world, arm[0], [0.2, 1.4, 0])
  setTransform(world, arm[1], [0.5, 1.4, 0])
  const cape = capeBehind(world, [6, 9], iterations)
  return { hero, arm, cape }
}

/** A sleeve skinned on the two arm bones, held at max distance 0 at its shoulder end. */
function skinnedSleeve(world: object, arm: number[]): number {
  const sleeve = createCloth(world, { width: 0.6, height: 0.1, resolution: [7, 2], position: [0.5, 1.4, 0] })
  const joints: number[] = [], weights: number[] = []
  for (let i = 0; i < 14; i++) {
    const u = (i % 7) / 6
    joints.push(0, 1, 0, 0)
    weights.push(1 - u, u, 0, 0)
  }
  setClothSkinning(world, sleeve, { bones: arm, joints, weights })
  setClothMotionConstraints(world, sleeve, { maxDistance: Array.from({ length: 14 }, (_, i) => (i % 7 === 0 ? 0 : 0.05)) })
  return sleeve
}

function capeScene(
  opts: { mode?: 'keep' | 'reset'; every?: number; drive?: number; sleep?: boolean; skin?: boolean; threads?: number } = {},
) {
  return (): Scene & { hero: number; arm: number[]; cape: number; sleeve: number } => {
    const world = opts.threads !== undefined
      ? threadedWorld(opts.threads, { sleep: opts.sleep ?? false })
      : installClothPlugin(createWorld(), { sleep: opts.sleep ?? false })
    const { hero, arm, cape } = heroWithCape(world)
    pinRow(world, cape, 0, hero)
    setClothInertia(world, cape, {
      frame: hero,
      linear: 0.5,
      angular: 0.5,
      centrifugal: 0.5,
      teleport: { mode: opts.mode ?? 'keep', angle: Math.PI / 2 },
    })
    setClothMotionConstraints(world, cape, {
      maxDistance: Array.from({ length: 54 }, (_, i) => (i < 12 ? 0 : 0.05 * Math.floor(i / 6))),
      backstop: { distance: 0.02, radius: 0.5 },
      every: opts.every ?? 1,
      drive: opts.drive ?? 0,
    })
    const cloths = [cape]
    let sleeve = -1
    if (opts.skin !== false) {
      sleeve = skinnedSleeve(world, arm)
      cloths.push(sleeve)
    }
    const inputs = (f: number, variant = 0) => {
      const t = f / 60
      const p = [Math.sin(2 * t) + 2 * variant, 1.6, 0.5 * Math.cos(1.3 * t)]
      const yaw = 0.8 * Math.sin(t) + variant
      setTransform(world, hero, p, yawQuat(yaw))
      setTransform(world, arm[0], [p[0] + 0.2, 1.4, p[2]], yawQuat(yaw))
      const bend = Math.sin(3 * t + variant)
      setTransform(world, arm[1], [p[0] + 0.5, 1.4, p[2]], [0, 0, Math.sin(bend / 2), Math.cos(bend / 2)])
      return 1 / 60
    }
    return { world, cloths, inputs, hero, arm, cape, sleeve }
  }
}

type CapeScene = ReturnType<ReturnType<typeof capeScene>>

describe('character cloth rollback: teleports right after the restore', () => {
  for (const mode of ['keep', 'reset'] as const) {
    for (const kind of ['distance', 'angle'] as const) {
      it(`${mode}, by ${kind}, at the first frame after the restore`, () => {
        const build = () => {
          const s = capeScene({ mode })()
          const base = s.inputs
          s.inputs = (f, v = 0) => {
            const dt = base(f, v)
            if (f >= 40 && v === 0) {
              // from frame 40 on, the character stands 6 m away (distance) or turned round (angle)
              const t = f / 60
              const p = [Math.sin(2 * t) + (kind === 'distance' ? 6 : 0), 1.6, 0.5 * Math.cos(1.3 * t)]
              const yaw = 0.8 * Math.sin(t) + (kind === 'angle' ? Math.PI : 0)
              setTransform(s.world, s.hero, p, yawQuat(yaw))
              setTransform(s.world, s.arm[0], [p[0] + 0.2, 1.4, p[2]], yawQuat(yaw))
              const bend = Math.sin(3 * t)
              setTransform(s.world, s.arm[1], [p[0] + 0.5, 1.4, p[2]], [0, 0, Math.sin(bend / 2), Math.cos(bend / 2)])
            }
            return dt
          }
          return s
        }
        expect(rollback(build, 40, 15, 40)).toEqual({ first: -1, worst: 0 })
      })
    }
  }

  it('teleportCloth by hand at the first frame after the restore', () => {
    const build = capeScene({ mode: 'reset' })
    const r = rollback(build, 30, 10, 30, {
      both: (s, f) => {
        if (f === 30) teleportCloth(s.world, (s as CapeScene).cape, [3, 0, 0])
      },
    })
    expect(r).toEqual({ first: -1, worst: 0 })
  })

  it('teleportCloth by hand during the rolled-back frames, then a plain replay', () => {
    const build = capeScene({ mode: 'keep' })
    const r = rollback(build, 30, 10, 30, {
      messHook: (s, f) => {
        if (f === 35) teleportCloth(s.world, (s as CapeScene).cape, [3, 0, 0], yawQuat(1))
      },
    })
    expect(r).toEqual({ first: -1, worst: 0 })
  })
})

describe('character cloth rollback: settings', () => {
  for (const every of [1, 3]) {
    it(`plain rollback (every ${every}), drive ${every === 1 ? 0.05 : 0}`, () => {
      expect(rollback(capeScene({ every, drive: every === 1 ? 0.05 : 0 }), 33, 20, 60)).toEqual({ first: -1, worst: 0 })
    })
  }

  it('character options set right after the restore, as the twin does at that frame', () => {
    const r = rollback(capeScene(), 30, 10, 40, {
      both: (s, f) => {
        if (f === 30) {
          const c = s as CapeScene
          setClothInertia(s.world, c.cape, { frame: c.hero, linear: 0.2, angular: 0.9, centrifugal: 0.1, teleport: { mode: 'reset' } })
          setClothMotionConstraints(s.world, c.cape, { maxDistance: 0.1, every: 2 })
          setClothSkinning(s.world, c.sleeve, null)
        }
      },
    })
    expect(r).toEqual({ first: -1, worst: 0 })
  })

  it('snapshot taken before the skin was replaced by other bones, restored', () => {
    const r = rollback(capeScene(), 30, 10, 40, {
      messHook: (s, f) => {
        const c = s as CapeScene
        if (f === 31) {
          const joints: number[] = [], weights: number[] = []
          for (let i = 0; i < 14; i++) joints.push(0, 0, 0, 0), weights.push(1, 0, 0, 0)
          setClothSkinning(s.world, c.sleeve, { bones: [c.hero], joints, weights })
          setClothInertia(s.world, c.sleeve, { frame: c.arm[1] })
        }
      },
    })
    expect(r).toEqual({ first: -1, worst: 0 })
  })

  it('restoring twice (restore, run, restore again) replays the same run both times', () => {
    const s = capeScene()()
    for (let f = 0; f < 25; f++) stepCloth(s.world, s.inputs(f))
    const snaps = s.cloths.map((cl) => saveClothState(s.world, cl))
    const runs: Float64Array[][][] = []
    for (let r = 0; r < 3; r++) {
      s.cloths.forEach((cl, k) => restoreClothState(s.world, cl, snaps[k]))
      const run: Float64Array[][] = []
      for (let f = 25; f < 60; f++) {
        stepCloth(s.world, s.inputs(f))
        run.push(bytes(s.world, s.cloths))
      }
      runs.push(run)
    }
    for (let f = 0; f < runs[0].length; f++) {
      expect(maxDiff(runs[1][f], runs[0][f]), `frame ${f}`).toBe(0)
      expect(maxDiff(runs[2][f], runs[0][f]), `frame ${f}`).toBe(0)
    }
  })
})

describe('snapshots in the middle of a frame (between beginClothStep and endClothStep)', () => {
  it('saving or restoring between begin and end throws a ClothError (or is consistent)', () => {
    const s = capeScene()()
    stepCloth(s.world, s.inputs(0))
    const snap = saveClothState(s.world, s.cape)
    s.inputs(1)
    beginClothStep(s.world, 1 / 60)
    let err: unknown = null
    try {
      saveClothState(s.world, s.cape)
    } catch (e) {
      err = e
    }
    let err2: unknown = null
    try {
      restoreClothState(s.world, s.cape, snap)
    } catch (e) {
      err2 = e
    }
    endClothStep(s.world)
    expect(err === null || err instanceof ClothError).toBe(true)
    expect(err2).toBeInstanceOf(ClothError)
  })
})

describe('snapshots saved in an event listener', () => {
  // a game checkpoints the cape in its tear listener (a curtain tore); the snapshot kept the timing
  // of the still-open frame, and a restore outside a frame never sampled the next frame's
  // transforms (3.5 cm off at the first replayed frame)
  const scene = () => {
    const s = capeScene({ skin: false })()
    const curtain = createCloth(s.world, { width: 1, height: 1, resolution: 8, position: [5, 2, 0] })
    pinRow(s.world, curtain, 0)
    makeTearable(s.world, curtain, { strain: 1e-6, maxTearsPerStep: 1, hysteresis: 1 })
    return s
  }
  it("after the frame's last step: the replay repeats the run byte for byte", () => {
    const s = scene()
    let saved: ClothSnapshot | null = null, at = -1, frame = 0
    onClothTear(s.world, () => {
      if (frame < 20 || saved !== null) return
      saved = saveClothState(s.world, s.cape)
      at = frame
    })
    const run: Float64Array[][] = []
    for (frame = 0; frame < 60; frame++) {
      stepCloth(s.world, s.inputs(frame))
      run[frame] = bytes(s.world, [s.cape])
    }
    expect(at).toBe(20)
    restoreClothState(s.world, s.cape, saved!)
    for (let f = at + 1; f < 60; f++) {
      stepCloth(s.world, s.inputs(f))
      expect(maxDiff(bytes(s.world, [s.cape]), run[f])).toBe(0)
    }
  })
  it('after a step before the last of a frame (the frame goes on): a ClothError, not a snapshot that cannot replay', () => {
    const s = scene()
    const errors: unknown[] = []
    let saves = 0
    onClothTear(s.world, () => {
      try {
        saveClothState(s.world, s.cape)
        saves++ // (the listener of the frame's last step)
      } catch (e) {
        errors.push(e)
      }
    })
    for (let f = 0; f < 6; f++) {
      for (let q = 0; q < 2; q++) s.inputs(2 * f + q)
      stepCloth(s.world, 2 / 60) // two fixed steps a frame
    }
    expect(errors.length).toBeGreaterThan(1)
    expect(saves).toBeGreaterThan(1)
    for (const e of errors) expect(String(e)).toMatch(/between two fixed steps of one frame/)
  })
})

describe('snapshots of sleeping cloths', () => {
  const sheetWorld = () => {
    const world = installClothPlugin(createWorld())
    const sheet = createCloth(world, { width: 0.6, height: 0.6, resolution: [6, 6], position: [0, 1.5, 0], material: 'cotton' })
    pinRow(world, sheet, 0, null)
    return { world, sheet }
  }
  it('a sleeping cloth restored into a fresh twin world (a late join, a loaded game) stays asleep and replays byte for byte', () => {
    // observed: it woke at the first step (the fresh world's gravity record, [0, 0, 0], read as a change of gravity)
    const a = sheetWorld()
    for (let f = 0; f < 200 && !isClothSleeping(a.world, a.sheet); f++) stepCloth(a.world, 1 / 60)
    for (let f = 0; f < 30; f++) stepCloth(a.world, 1 / 60)
    expect(isClothSleeping(a.world, a.sheet)).toBe(true)
    const b = sheetWorld()
    restoreClothState(b.world, b.sheet, structuredClone(saveClothState(a.world, a.sheet)))
    for (let f = 0; f < 60; f++) {
      stepCloth(a.world, 1 / 60)
      stepCloth(b.world, 1 / 60)
      expect(isClothSleeping(b.world, b.sheet)).toBe(true)
      expect(maxDiff(bytes(b.world, [b.sheet]), bytes(a.world, [a.sheet]))).toBe(0)
    }
  })
  for (const change of [false, { delay: 0.2 }] as const) {
    it(`sleep settings changed after the save (setClothSleep(${JSON.stringify(change)})) are undone by the restore`, () => {
      const { world, sheet } = sheetWorld()
      stepCloth(world, 1 / 60)
      const snap = saveClothState(world, sheet)
      const run: Float64Array[][] = []
      for (let f = 0; f < 150; f++) {
        stepCloth(world, 1 / 60)
        run.push(bytes(world, [sheet]))
      }
      restoreClothState(world, sheet, snap)
      setClothSleep(world, sheet, change)
      restoreClothState(world, sheet, snap)
      for (let f = 0; f < 150; f++) {
        stepCloth(world, 1 / 60)
        expect(maxDiff(bytes(world, [sheet]), run[f])).toBe(0)
      }
    })
  }
})

describe('rollback with grabs, sleep, cloths added and removed', () => {
  it('a grab in progress on the cape: moved and released during the rolled-back frames, then moved again with the same handle', () => {
    let handle = -1
    const build = () => {
      const s = capeScene()()
      return s
    }
    const a = build(), b = build()
    const ha = grabParticle(a.world, a.cape, 50, [0, 1, -0.5])
    const hb = grabParticle(b.world, b.cape, 50, [0, 1, -0.5])
    expect(ha).toBe(hb)
    handle = ha
    for (let f = 0; f < 20; f++) {
      moveGrab(a.world, handle, [Math.sin(f / 10), 1, -0.5])
      moveGrab(b.world, handle, [Math.sin(f / 10), 1, -0.5])
      stepCloth(a.world, a.inputs(f))
      stepCloth(b.world, b.inputs(f))
    }
    const snaps = a.cloths.map((cl) => saveClothState(a.world, cl))
    for (let f = 20; f < 30; f++) {
      if (f < 25) moveGrab(a.world, handle, [3, 3, 3])
      if (f === 25) releaseGrab(a.world, handle)
      stepCloth(a.world, a.inputs(f, 1))
    }
    grabParticle(a.world, a.cape, 3, [0, 0, 0]) // a new grab, released by the restore
    a.cloths.forEach((cl, k) => restoreClothState(a.world, cl, snaps[k]))
    expect(isGrabActive(a.world, handle)).toBe(true)
    for (let f = 20; f < 60; f++) {
      if (f <= 45) {
        moveGrab(a.world, handle, [Math.sin(f / 10), 1, -0.5])
        moveGrab(b.world, handle, [Math.sin(f / 10), 1, -0.5])
      }
      if (f === 45) {
        releaseGrab(a.world, handle)
        releaseGrab(b.world, handle)
      }
      stepCloth(a.world, a.inputs(f))
      stepCloth(b.world, b.inputs(f))
      expect(maxDiff(bytes(a.world, a.cloths), bytes(b.world, b.cloths)), `frame ${f}`).toBe(0)
    }
  })

  it('a sleeping character cloth (standing hero): saved asleep, woken and moved during the rolled-back frames, restored', () => {
    const build = () => {
      const s = capeScene({ sleep: true, skin: false })()
      s.inputs = (f, v = 0) => {
        // the hero stands still, except in the variant frames (walks away)
        setTransform(s.world, s.hero, [v * (f - 100) * 0.1, 1.6, 0], yawQuat(0.3 * v))
        return 1 / 60
      }
      return s
    }
    const s = build()
    let asleep = -1
    for (let f = 0; f < 300 && asleep < 0; f++) {
      stepCloth(s.world, s.inputs(f))
      if (isClothSleeping(s.world, s.cape)) asleep = f
    }
    expect(asleep).toBeGreaterThan(0)
    const r = rollback(build, asleep + 5, 20, 60, {
      both: (sc, f) => {
        if (f === asleep + 40) setTransform(sc.world, (sc as CapeScene).hero, [1, 1.6, 0]) // (overwritten by inputs)
      },
    })
    expect(r).toEqual({ first: -1, worst: 0 })
  })

  it('a sleeping character cloth woken by its frame right after the restore', () => {
    const build = () => {
      const s = capeScene({ sleep: true, skin: false })()
      s.inputs = (f, v = 0) => {
        const x = f >= 200 ? 0.02 * (f - 200) : 0
        setTransform(s.world, s.hero, [x + v, 1.6, 0], yawQuat(f >= 200 ? 0.01 * (f - 200) : 0))
        return 1 / 60
      }
      return s
    }
    const r = rollback(build, 200, 20, 60)
    expect(r).toEqual({ first: -1, worst: 0 })
  })

  it('a cloth created after the save (and one removed after it) leaves the restored cloths as in the twin', () => {
    const extra: number[] = []
    const r = rollback(capeScene(), 30, 10, 40, {
      messHook: (s, f) => {
        if (f === 32) {
          const x = createCloth(s.world, { width: 0.3, height: 0.3, resolution: [4, 4], position: [5, 1, 0] })
          pinRow(s.world, x, 0, (s as CapeScene).hero)
          setClothInertia(s.world, x, { linear: 0.3 })
          extra.push(x)
        }
      },
    })
    expect(extra.length).toBe(1)
    expect(r).toEqual({ first: -1, worst: 0 })
  })
})

describe('rollback: the scale history of character frames and bones', () => {
  /** A cape held by max distance 0 on its top row (no pins), its frame the hero; a sleeve skinned on two bones. */
  function scaledScene(): Scene & { hero: number; arm: number[] } {
    const world = installClothPlugin(createWorld(), { sleep: false })
    const { hero, arm, cape } = heroWithCape(world)
    setClothInertia(world, cape, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5 })
    setClothMotionConstraints(world, cape, {
      maxDistance: Array.from({ length: 54 }, (_, i) => (i < 6 ? 0 : 0.05 * Math.floor(i / 6))),
    })
    const sleeve = skinnedSleeve(world, arm)
    const inputs = (f: number, variant = 0) => {
      const t = f / 60
      const p = [Math.sin(2 * t), 1.6, 0.5 * Math.cos(1.3 * t)]
      const yaw = 0.8 * Math.sin(t)
      const sc = 1 + variant // the rolled-back frames: everything twice as large
      setTransform(world, hero, p, yawQuat(yaw), [sc, sc, sc])
      setTransform(world, arm[0], [p[0] + 0.2, 1.4, p[2]], yawQuat(yaw), [sc, sc, sc])
      const bend = Math.sin(3 * t)
      setTransform(world, arm[1], [p[0] + 0.5, 1.4, p[2]], [0, 0, Math.sin(bend / 2), Math.cos(bend / 2)], [sc, sc, sc])
      return 1 / 60
    }
    return { world, cloths: [cape, sleeve], inputs, hero, arm }
  }

  it('frame and bones scaled during the rolled-back frames, the host puts the scale back: the replay matches the twin', () => {
    expect(rollback(scaledScene, 30, 10, 30)).toEqual({ first: -1, worst: 0 })
  })

  for (
    const [which, k] of [['the cape only (its frame is no pin target)', 0], [
      'the sleeve only (skinned on bones that are nothing else)',
      1,
    ]] as const
  ) {
    it(`the same for ${which}`, () => {
      const build = () => {
        const s = scaledScene()
        s.cloths = [s.cloths[k]]
        return s
      }
      expect(rollback(build, 30, 10, 30)).toEqual({ first: -1, worst: 0 })
    })
  }
})

describe('Transforms written between beginClothStep and endClothStep are read at the next begin', () => {
  /**
   * Two twins run frames of 2/60 s (two fixed steps each); before each begin both write the same
   * Transforms. Twin a then writes the next frame's Transforms between begin and end, twin b after
   * end: the README says the writes are read at the next begin, so the bytes must match.
   */
  function run(build: () => Scene, frames: number, write: (s: Scene, f: number) => void) {
    const a = build(), b = build()
    let first = -1, atFirst = 0, worst = 0
    write(a, 0)
    write(b, 0)
    for (let f = 0; f < frames; f++) {
      beginClothStep(a.world, 2 / 60)
      write(a, f + 1) // mid-frame: the game animates the next frame
      endClothStep(a.world)
      beginClothStep(b.world, 2 / 60)
      endClothStep(b.world)
      write(b, f + 1)
      const d = maxDiff(bytes(a.world, a.cloths), bytes(b.world, b.cloths))
      if (d !== 0 && first < 0) {
        first = f
        atFirst = posDiff(a.world, b.world, a.cloths, b.cloths) // positions only, m
      }
      worst = Math.max(worst, d)
    }
    return { first, atFirst, worst }
  }

  it('plain pinned cape (pins only): positions written mid-frame', () => {
    const r = run(capeScene({ skin: false }), 40, (s, f) => {
      setTransform(s.world, (s as CapeScene).hero, [0.1 * f, 1.6, 0], yawQuat(0.05 * f))
    })
    expect(r).toEqual({ first: -1, atFirst: 0, worst: 0 })
  })

  it('character cloth with a teleport angle: the character snapped round mid-frame', () => {
    const r = run(capeScene({ skin: false, mode: 'reset' }), 40, (s, f) => {
      setTransform(s.world, (s as CapeScene).hero, [0.05 * f, 1.6, 0], yawQuat(f >= 20 ? Math.PI : 0))
    })
    expect(r).toEqual({ first: -1, atFirst: 0, worst: 0 })
  })

  it('character cloth: the character moving on (no teleport) mid-frame', () => {
    const r = run(capeScene({ skin: false }), 40, (s, f) => {
      setTransform(s.world, (s as CapeScene).hero, [0.05 * f, 1.6, 0.02 * f], yawQuat(0.03 * f))
    })
    expect(r).toEqual({ first: -1, atFirst: 0, worst: 0 })
  })

  it('character cloth: the character scaled mid-frame', () => {
    const r = run(capeScene({ skin: false }), 40, (s, f) => {
      const sc = 1 + 0.02 * f
      setTransform(s.world, (s as CapeScene).hero, [0.05 * f, 1.6, 0], yawQuat(0.03 * f), [sc, sc, sc])
    })
    expect(r).toEqual({ first: -1, atFirst: 0, worst: 0 })
  })

  it('skinned sleeve: the bones bent and scaled mid-frame', () => {
    const r = run(capeScene(), 40, (s, f) => {
      const c = s as CapeScene
      const sc = 1 + 0.01 * f
      setTransform(s.world, c.hero, [0, 1.6, 0])
      setTransform(s.world, c.arm[0], [0.2, 1.4, 0], yawQuat(0.02 * f), [sc, sc, sc])
      const bend = Math.sin(0.2 * f)
      setTransform(s.world, c.arm[1], [0.5, 1.4, 0], [0, 0, Math.sin(bend / 2), Math.cos(bend / 2)], [sc, sc, sc])
    })
    expect(r).toEqual({ first: -1, atFirst: 0, worst: 0 })
  })
})

describe('kitchen sink rollback: character cloth with colliders, wind and gusts, self-collision, tearing, budget', () => {
  function sink(opts: { budget?: boolean; selfCollide?: boolean; tear?: boolean; target?: boolean }) {
    return (): Scene & { hero: number } => {
      const s = capeScene({ mode: 'reset', every: 2 })()
      const world = s.world
      const torso = addEntity(world)
      addCapsuleCollider(world, torso, { body: s.hero, offset: [0, -0.3, 0], radius: 0.18, halfHeight: 0.25 })
      const ball = addEntity(world)
      setTransform(world, ball, [0, 0, 0])
      addSphereCollider(world, ball, { radius: 0.2 })
      const zone = createWindZone(world, { direction: [1, 0, 0.3], strength: 3, turbulence: 0.5 })
      if (opts.selfCollide) enableSelfCollision(world, s.cape, { thickness: 0.01 })
      let flag = -1
      if (opts.tear) {
        flag = createCloth(world, { width: 0.6, height: 0.4, resolution: [8, 6], position: [0.5, 2, 0], material: 'cotton' })
        pinRow(world, flag, 0, s.hero)
        makeTearable(world, flag, { strain: 0.5 })
        setClothMotionConstraints(world, flag, { maxDistance: 0.3 })
        s.cloths.push(flag)
      }
      const viewer = addEntity(world)
      setTransform(world, viewer, [0, 2, 3])
      if (opts.budget)
        setClothBudget(world, { viewer, near: 3, far: 10, farStepEvery: 4, calibration: CHEAP_CALIBRATION, adapt: false, interval: 5 })
      if (opts.target) setClothQualityTarget(world, s.cape, { maxStretch: 0.01, calibration: CHEAP_CALIBRATION })
      const base = s.inputs
      s.inputs = (f, v = 0) => {
        base(f, v)
        const t = f / 60
        setTransform(world, ball, [Math.sin(3 * t) * 0.6 - 0.3, 1.2 + 0.3 * v, 0.3 * Math.cos(2 * t)])
        setTransform(world, viewer, [0, 2, 3 + 20 * Math.abs(Math.sin(t / 2)) + 10 * v])
        if (f % 23 === 0) gustWind(world, zone, { strength: 4 - 3 * v, duration: 0.4 })
        return (0.8 + 0.4 * ((f * 7919) % 11) / 11) / 60
      }
      return { ...s, hero: s.hero }
    }
  }

  const cases: [string, Parameters<typeof sink>[0]][] = [
    ['colliders, wind, gusts', {}],
    ['+ self-collision', { selfCollide: true }],
    ['+ tearable flag', { tear: true }],
    ['+ budget farStepEvery 4', { budget: true }],
    ['+ quality target', { target: true }],
    ['everything', { selfCollide: true, tear: true, budget: true, target: true }],
  ]
  for (const [name, opts] of cases) {
    it(name, () => {
      let compared = 0
      for (const at of [7, 31, 52]) {
        let r: { first: number; worst: number }
        try {
          r = rollback(sink(opts), at, 17, 60)
        } catch (e) {
          // a tear during the rolled-back frames makes the restore throw (documented); anything else is a bug
          expect(e, `saved at ${at}`).toBeInstanceOf(ClothError)
          console.log(`${name} saved at ${at}: ${(e as Error).message.slice(0, 200)}`)
          continue
        }
        expect(r, `saved at ${at}`).toEqual({ first: -1, worst: 0 })
        compared++
      }
      expect(compared).toBeGreaterThan(0)
    })
  }
})

describe('rollback across entity churn and pin changes', () => {
  it('a collider removed during the rolled-back frames and its id taken by a new static collider: the replay matches a twin that did the same at the save', () => {
    let ballA = -1
    const build = () => {
      const s = capeScene({ skin: false })()
      const ball = addEntity(s.world)
      setTransform(s.world, ball, [-0.3, 1.2, 0])
      addSphereCollider(s.world, ball, { radius: 0.2 })
      ballA = ball
      const base = s.inputs
      let current = ball
      const sc = s as CapeScene & { swap: () => void }
      sc.swap = () => {
        removeEntity(s.world, current)
        const fresh = addEntity(s.world)
        expect(fresh).toBe(ballA)
        setTransform(s.world, fresh, [-0.4, 1.1, 0.1])
        addSphereCollider(s.world, fresh, { radius: 0.15 })
        current = -1
      }
      s.inputs = (f, v = 0) => {
        const dt = base(f, v)
        if (current >= 0) setTransform(s.world, current, [-0.3 + 0.2 * Math.sin(f / 9), 1.2, 0])
        return dt
      }
      return sc
    }
    const a = build(), b = build()
    for (let f = 0; f < 30; f++) {
      stepCloth(a.world, a.inputs(f))
      stepCloth(b.world, b.inputs(f))
    }
    const snap = saveClothState(a.world, a.cape)
    a.swap()
    for (let f = 30; f < 42; f++) stepCloth(a.world, a.inputs(f, 1))
    restoreClothState(a.world, a.cape, snap)
    b.swap()
    for (let f = 30; f < 70; f++) {
      stepCloth(a.world, a.inputs(f))
      stepCloth(b.world, b.inputs(f))
      expect(maxDiff(bytes(a.world, a.cloths), bytes(b.world, b.cloths)), `frame ${f}`).toBe(0)
    }
  })

  it('a frozen pinned cape whose pins changed during the rolled-back frames: thaws like the twin', () => {
    const build = (): Scene & { hero: number; cape: number } => {
      const world = installClothPlugin(createWorld(), { sleep: false })
      const hero = addEntity(world)
      setTransform(world, hero, [0, 1.6, 0])
      const other = addEntity(world)
      setTransform(world, other, [5, 1.6, 0])
      const viewer = addEntity(world)
      setTransform(world, viewer, [0, 2, 3])
      const cape = capeBehind(world)
      pinRow(world, cape, 0, hero)
      setClothInertia(world, cape, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5 })
      setClothBudget(world, { viewer, near: 5, far: 20, cull: 40, calibration: CHEAP_CALIBRATION, adapt: false, interval: 3 })
      const inputs = (f: number, v = 0) => {
        setTransform(world, hero, [0.05 * f + v, 1.6, 0.3 * Math.sin(f / 60)], yawQuat(0.2 * Math.sin(f / 60)))
        setTransform(world, other, [5 + 0.2 * f, 1.6, 0])
        setTransform(world, viewer, [0.05 * f, 2, 3 + (f < 10 ? 0 : f < 80 ? 100 : 0)])
        return 1 / 60
      }
      return { world, cloths: [cape], inputs, hero, cape, other } as Scene & { hero: number; cape: number; other: number }
    }
    const r = rollback(build, 50, 10, 50, {
      messHook: (s, f) => {
        const sc = s as Scene & { cape: number; other: number }
        if (f === 52) {
          const pins = getPins(s.world, sc.cape)
          unpin(s.world, pins[0])
          unpin(s.world, pins[1])
          pinParticle(s.world, sc.cape, 8, sc.other)
        }
      },
    })
    expect(r).toEqual({ first: -1, worst: 0 })
  })
})

describe('call order of character settings', () => {
  function orderScene(order: number) {
    const world = installClothPlugin(createWorld(), { sleep: false })
    const { hero, arm, cape } = heroWithCape(world, 1)
    const joints: number[] = [], weights: number[] = []
    for (let i = 0; i < 54; i++) {
      const u = (i % 6) / 5
      joints.push(0, 1, 0, 0)
      weights.push(1 - u, u, 0, 0)
    }
    const steps = [
      () => pinRow(world, cape, 0, hero),
      () =>
        setClothInertia(world, cape, { frame: hero, linear: 0.5, angular: 0.4, centrifugal: 0.3, teleport: { mode: 'reset', angle: 1 } }),
      () =>
        setClothMotionConstraints(world, cape, {
          maxDistance: Array.from({ length: 54 }, (_, i) => (i < 12 ? 0 : 0.04 * Math.floor(i / 6))),
          backstop: { distance: 0.02, radius: 0.4 },
          drive: 0.03,
        }),
      () => setClothSkinning(world, cape, { bones: arm, joints, weights }),
      () => makeTearable(world, cape, { strain: 5 }),
      () => enableSelfCollision(world, cape),
    ]
    const perm = [
      [0, 1, 2, 3, 4, 5],
      [5, 4, 3, 2, 1, 0],
      [3, 2, 1, 0, 5, 4],
      [1, 3, 0, 5, 2, 4],
      [2, 0, 4, 1, 3, 5],
    ][order]
    for (const k of perm) steps[k]()
    for (let f = 0; f < 90; f++) {
      const t = f / 60
      const p = [Math.sin(2 * t), 1.6, 0.5 * Math.cos(1.3 * t)]
      const yaw = f === 60 ? 2 : 0.8 * Math.sin(t)
      setTransform(world, hero, p, yawQuat(yaw))
      setTransform(world, arm[0], [p[0] + 0.2, 1.4, p[2]], yawQuat(yaw))
      setTransform(world, arm[1], [p[0] + 0.5, 1.4, p[2]], yawQuat(yaw + 0.3 * Math.sin(3 * t)))
      stepCloth(world, 1 / 60)
    }
    return bytes(world, [cape])
  }

  it('pins, inertia, constraints, skinning, tearing and self-collision in any order give the same bytes', () => {
    const ref = orderScene(0)
    for (let o = 1; o < 5; o++) expect(maxDiff(orderScene(o), ref), `order ${o}`).toBe(0)
  })
})

describe('restoring character state into a cloth that lost all of it since the save', () => {
  for (const threads of [undefined, 1] as const) {
    it(`every character setting dropped during the rolled-back frames (${threads === undefined ? 'no threads' : `${threads} worker`})`, () => {
      const worlds: object[] = []
      const build = () => {
        const s = capeScene({ threads })()
        worlds.push(s.world)
        return s
      }
      try {
        const r = rollback(build, 30, 12, 40, {
          messHook: (s, f) => {
            const c = s as CapeScene
            if (f === 33) {
              setClothMotionConstraints(s.world, c.cape, null)
              setClothInertia(s.world, c.cape, null)
              setClothMotionConstraints(s.world, c.sleeve, null)
              setClothSkinning(s.world, c.sleeve, null)
              expect(getClothState(s.world, c.cape).character).toBeNull()
              expect(getClothState(s.world, c.sleeve).character).toBeNull()
            }
          },
        })
        expect(r).toEqual({ first: -1, worst: 0 })
      } finally {
        for (const w of worlds) disposeClothWorld(w)
      }
    })
  }

  it('threaded and unthreaded twins give the same bytes through a rollback that drops and restores character state', () => {
    const run = (threads: number | undefined) => {
      const s = capeScene({ threads })()
      try {
        const out: Float64Array[][] = []
        for (let f = 0; f < 30; f++) stepCloth(s.world, s.inputs(f))
        const snaps = s.cloths.map((cl) => saveClothState(s.world, cl))
        setClothInertia(s.world, s.cape, null)
        setClothMotionConstraints(s.world, s.cape, null)
        for (let f = 30; f < 40; f++) stepCloth(s.world, s.inputs(f, 1))
        s.cloths.forEach((cl, k) => restoreClothState(s.world, cl, snaps[k]))
        for (let f = 30; f < 60; f++) {
          stepCloth(s.world, s.inputs(f))
          out.push(bytes(s.world, s.cloths))
        }
        return out
      } finally {
        disposeClothWorld(s.world)
      }
    }
    const a = run(undefined), b = run(2)
    for (let f = 0; f < a.length; f++) expect(maxDiff(a[f], b[f]), `frame ${f}`).toBe(0)
  })
})

describe('far cloths stepping every n-th step: a frame jump right after the restore', () => {
  for (const pinned of [false, true]) {
    it(`character cloth ${pinned ? 'pinned to' : 'held by max distance 0 on'} its frame, farStepEvery 4, the frame jumps 5 m at the first replayed frame`, () => {
      const build = () => {
        const s = frozenAnchorScene()
        setClothBudget(s.world, {
          viewer: s.viewer,
          near: 1,
          far: 2,
          farStepEvery: 4,
          calibration: CHEAP_CALIBRATION,
          adapt: false,
          interval: 3,
        })
        if (pinned) pinRow(s.world, s.cloths[0], 0, s.hero)
        const base = s.inputs
        s.inputs = (f, v = 0) => {
          base(f, v)
          const t = f / 60
          setTransform(s.world, s.hero, [0.05 * f + 3 * v + (f >= 41 ? 5 : 0), 1.6, 0.3 * Math.sin(t)], yawQuat(0.2 * Math.sin(t)))
          setTransform(s.world, s.viewer, [0.05 * f, 2, 25])
          return 1 / 60
        }
        return s
      }
      const probe = build()
      for (let f = 0; f < 40; f++) stepCloth(probe.world, probe.inputs(f))
      expect(getClothLod(probe.world, probe.cloths[0]).stepEvery).toBe(4)
      for (const at of [38, 39, 40, 41]) expect(rollback(build, at, 9, 30), `saved at ${at}`).toEqual({ first: -1, worst: 0 })
    })
  }
})

describe('pin handles across a restore', () => {
  // Found by a hunt: a restore after any pin change made every pin anew, and bitECS handed the
  // recycled ids back in another order: the handles 3..8 of a collar named particles 5, 0, 1, …,
  // and a replay releasing a banner's left corner by its handle released the right one (2.1 m apart
  // after a second).
  it('the pins still there keep their entities, one made again gets its handle back, and a replay by handle repeats the run byte for byte', () => {
    const world = installClothPlugin(createWorld())
    const pole = addEntity(world)
    setTransform(world, pole, [0, 2, 0])
    const banner = createCloth(world, { width: 1, height: 1, resolution: [8, 8], position: [0, 2, 0], material: 'silk' })
    const held = [0, 2, 5, 7].map((i) => pinParticle(world, banner, i, pole))
    for (let f = 0; f < 30; f++) stepCloth(world, 1 / 60)
    const saved = saveClothState(world, banner)
    const run = () => {
      unpin(world, held[0]) // the left corner goes
      for (let f = 0; f < 60; f++) stepCloth(world, 1 / 60)
      return getClothState(world, banner).pos.slice()
    }
    const first = run()
    restoreClothState(world, banner, saved)
    expect(getPins(world, banner)).toEqual(held)
    const P = getClothComponents(world).Pin
    expect(held.map((pin) => P.particle[pin])).toEqual([0, 2, 5, 7])
    expect(run()).toEqual(first)
  })
})
