// The explosion guard: a broken cloth is caught after the step it broke in, put back into a safe
// pose and reported; each of its three tests is needed (turn it off and the case goes NaN or flies
// apart).
import { addEntity, createWorld } from 'bitecs'
import { glMatrix, quat, vec3 } from 'gl-matrix'
import { describe, expect, it } from 'vitest'
import { restSize } from '../../src/features/guard/size'
import {
  ClothError,
  addCapsuleCollider,
  addSphereCollider,
  checkClothHealth,
  createCloth,
  clothGuard,
  createClothFromMesh,
  createWindZone,
  getClothTearCount,
  makeTearable,
  setWindZone,
  defineMaterial,
  drainClothResets,
  getClothGuard,
  getClothMesh,
  getClothState,
  getClothStats,
  installClothPlugin,
  onClothReset,
  pinParticle,
  setClothGuard,
  setTransform,
  stepCloth,
  type ClothGuardOptions,
  type ClothPluginOptions,
  type ClothResetEvent,
} from '../../src/index'
import {
  G_OUT_EXCESS,
  G_OUT_SPEED2,
  HEALTH_BOUNDS,
  HEALTH_NONFINITE,
  HEALTH_OK,
  HEALTH_SPEED,
  PIECE_STRIDE,
  checkPieceHealth,
  GUARD_PARAM_COUNT,
  clearGuardAnchor,
} from '../../src/kernels/guard'
import { getClothWorld } from '../../src/world/access'
import { hashBytes } from '../helpers'
import { geodesicDiameter, hangingSheet, inspect, inspectPieces } from './harness'
import { heroWithBody, heroWithCape, poseLegs, walk } from './scenes'
import { ground } from '../collision/scenes'

glMatrix.setMatrixArrayType(Array)

/** A world with one 1 m sheet hanging from its top row. */
function sheetWorld(options: ClothPluginOptions = {}, cloth: Parameters<typeof hangingSheet>[1] = {}) {
  const world = installClothPlugin(createWorld(), options)
  const sheet = hangingSheet(world, cloth)
  for (let f = 0; f < 30; f++) stepCloth(world, 1 / 60)
  return { world, sheet, c: getClothState(world, sheet) }
}

/** Rms particle speed relative to the cloth's mean velocity, m/s (what the guard measures). */
function relativeRmsSpeed(c: { vel: Float64Array; count: number }): number {
  let sx = 0, sy = 0, sz = 0, s2 = 0
  for (let i = 0; i < c.count; i++) {
    sx += c.vel[3 * i]
    sy += c.vel[3 * i + 1]
    sz += c.vel[3 * i + 2]
    s2 += c.vel[3 * i] ** 2 + c.vel[3 * i + 1] ** 2 + c.vel[3 * i + 2] ** 2
  }
  const n = c.count
  return Math.sqrt(Math.max(0, s2 / n - (sx * sx + sy * sy + sz * sz) / (n * n)))
}

/** True when the render mesh holds a non-finite number. */
function meshHasNaN(world: object, cloth: number): boolean {
  const m = getClothMesh(world, cloth)
  return !m.positions.every(Number.isFinite) || !m.normals.every(Number.isFinite)
}

/**
 * Soft in-plane, rigid dihedral bending, nothing holding it to its pins but the edges: the hinges'
 * corrections stretch the edges a little each substep and nothing pulls them back, so the sheet
 * gains energy until the speed limit (250 m/s) is all that holds it (a real instability of this
 * material, not an injected fault; see the README).
 */
const jelly = defineMaterial({
  name: 'jelly',
  stretchCompliance: 300,
  shearCompliance: 1e6,
  bendCompliance: 0,
  damping: 0,
  stretchDamping: 0,
})
const jellySheet = { material: jelly, bending: 'dihedral' as const, tethers: false }

describe('health check (one pass over the particles)', () => {
  it('passes a hanging sheet and flags NaN, a particle out of reach and runaway speed', () => {
    const { world, sheet, c } = sheetWorld()
    const g = Float64Array.from([1, 2, 100 * 100, 0, 0]) // finite on, 2 m of reach, 100 m/s
    expect(checkClothHealth(c.pos, c.vel, c.invMass, c.count, g)).toBe(0)
    const pos = Float64Array.from(c.pos), vel = Float64Array.from(c.vel)
    pos[3 * 40 + 1] = NaN
    expect(checkClothHealth(pos, vel, c.invMass, c.count, g)).toBe(1)
    pos[3 * 40 + 1] = Infinity
    expect(checkClothHealth(pos, vel, c.invMass, c.count, g)).toBe(1)
    pos[3 * 40 + 1] = 2 - 1.99 // the pinned row is at y = 2: 1.99 m below it is within reach...
    expect(checkClothHealth(pos, vel, c.invMass, c.count, g)).toBe(0)
    pos[3 * 40 + 1] = 2 - 2.01 // ...2.01 m is not
    expect(checkClothHealth(pos, vel, c.invMass, c.count, g)).toBe(2)
    pos.set(c.pos)
    for (let i = 0; i < c.count; i++) vel[3 * i] = i % 2 ? 150 : -150 // apart, not along
    expect(checkClothHealth(pos, vel, c.invMass, c.count, g)).toBe(3)
    vel.fill(0)
    for (let i = 0; i < c.count; i++) vel[3 * i] = 200 // the whole cloth fast: a vehicle, fine
    expect(checkClothHealth(pos, vel, c.invMass, c.count, g)).toBe(0)
    expect(getClothStats(world).guardChecks).toBe(30)
    expect(getClothGuard(world, sheet).size).toBeCloseTo(geodesicDiameter(world, sheet), 9)
  })
})

describe('health check of a torn cloth (per piece)', () => {
  it('measures pieces holding pins from the pins, pieces without pins by their own extent', () => {
    // particles 0-2: piece 0 (0 and 1 pinned at y = 2); 3-5: piece 1 (no pins); 6: piece 2 (alone)
    const pos = Float64Array.from([0, 2, 0, 1, 2, 0, 0.5, 1, 0, 0, -10, 0, 0.5, -10, 0, 0.2, -9.5, 0, 30, -40, 5])
    const vel = new Float64Array(pos.length)
    const invMass = Float64Array.from([0, 0, 1, 1, 1, 1, 1])
    const piece = Int32Array.from([0, 0, 0, 1, 1, 1, 2])
    const box = new Float64Array(PIECE_STRIDE * 3)
    const g = clearGuardAnchor(new Float64Array(GUARD_PARAM_COUNT)) // (no anchor box)
    g.set([1, 2, 100 * 100]) // finite on, 2 m of reach, 100 m/s
    const check = () => checkPieceHealth(pos, vel, invMass, 7, piece, 3, box, g)
    // piece 1 lies 12 m below the pins and particle 6 far off: each is judged by its own shape
    expect(check()).toBe(HEALTH_OK)
    expect(checkClothHealth(pos, vel, invMass, 7, g)).toBe(2) // (as one piece: out of bounds)
    pos[3 * 4] = 2.6 // piece 1 now spans 2.6 m in x: more than the reach
    expect(check()).toBe(HEALTH_BOUNDS)
    expect(g[G_OUT_EXCESS]).toBeCloseTo(0.6, 12)
    pos[3 * 4] = 0.5
    pos[3 * 2 + 1] = 2 - 2.01 // a free particle of the pinned piece 2.01 m below the pins' box
    expect(check()).toBe(HEALTH_BOUNDS)
    pos[3 * 2 + 1] = 2 - 1.99
    expect(check()).toBe(HEALTH_OK)
    vel[3 * 6 + 2] = NaN
    expect(check()).toBe(HEALTH_NONFINITE)
    vel[3 * 6 + 2] = 0
    for (let i = 0; i < 7; i++) vel[3 * i] = i % 2 ? 150 : -150
    expect(check()).toBe(HEALTH_SPEED)
    // pieces blown apart, each moving as a whole (one at rest, one at 200 m/s, one at 300 m/s):
    // speed is judged within each piece, so nothing runs away (as one piece: 144 m/s rms)
    vel.fill(0)
    for (const i of [3, 4, 5]) vel[3 * i] = 200
    vel[3 * 6 + 1] = -300
    expect(check()).toBe(HEALTH_OK)
    expect(g[G_OUT_SPEED2]).toBe(0)
    checkClothHealth(pos, vel, invMass, 7, g)
    expect(Math.sqrt(g[G_OUT_SPEED2])).toBeCloseTo(144.3, 1)
    vel[3 * 4 + 2] = 500 // one particle of piece 1 whipping across it: 154 m/s rms within pieces
    expect(check()).toBe(HEALTH_SPEED)
    expect(Math.sqrt(g[G_OUT_SPEED2])).toBeCloseTo(154.3, 1)
  })
})

describe('a mesh of several pieces', () => {
  it("the guard's size of the rest shape is its largest piece's geodesic diameter, whatever the pieces before it", () => {
    // (each Dijkstra sweep resets only what the last one reached: it cleared every particle, so
    // 20,000 separate quads took 0.8 s to build; measured 4.4× the time of 5,000 since, 9.2× before)
    // an n × n grid whose first vertex is its centre (the first sweep starts there, so only the
    // second, from the far corner it finds, measures the diameter)
    const grid = (x0: number, n: number, h: number, positions: number[], indices: number[]) => {
      const base = positions.length / 3
      const centre = n * (n >> 1) + (n >> 1)
      const at = (k: number) => base + (k === 0 ? centre : k === centre ? 0 : k)
      for (let k = 0; k < n * n; k++) {
        const v = k === 0 ? centre : k === centre ? 0 : k
        positions.push(x0 + h * (v % n), -h * Math.floor(v / n), 0)
      }
      for (let r = 0; r + 1 < n; r++) {
        for (let col = 0; col + 1 < n; col++) {
          const i = n * r + col
          indices.push(at(i), at(i + n), at(i + 1), at(i + 1), at(i + n), at(i + n + 1))
        }
      }
    }
    const build = (pieces: [number, number, number][], unused: number) => {
      const positions: number[] = [], indices: number[] = []
      for (const [x0, n, h] of pieces) grid(x0, n, h, positions, indices)
      for (let k = 0; k < unused; k++) positions.push(-5 - k, 0, 0)
      const world = installClothPlugin(createWorld())
      return restSize(getClothState(world, createClothFromMesh(world, { positions, indices })).topology)
    }
    const alone = build([[0, 9, 0.1]], 0)
    expect(alone).toBeGreaterThan(0.8 * Math.SQRT2 - 1e-9) // corner to corner along the diagonals
    for (const unused of [0, 50]) {
      expect(build([[3, 2, 0.1], [5, 3, 0.05], [0, 9, 0.1], [7, 2, 0.2]], unused)).toBe(alone)
    }
  })

  it('is checked piece by piece from its first step: its free second piece is judged by its own shape', () => {
    // two separate 3 × 3 grids of 0.5 m, the first pinned along its top; the second is free
    const positions: number[] = [], indices: number[] = []
    for (const x0 of [0, 2]) {
      const base = positions.length / 3
      for (let r = 0; r < 3; r++) for (let col = 0; col < 3; col++) positions.push(x0 + 0.25 * col, 2 - 0.25 * r, 0)
      for (let r = 0; r < 2; r++)
        for (let col = 0; col < 2; col++) {
          const i = base + 3 * r + col
          indices.push(i, i + 3, i + 1, i + 1, i + 3, i + 4)
        }
    }
    // the guard phase alone on a pose written after a step (the solver would pull it back)
    const run = (move: (pos: Float64Array) => void) => {
      const world = installClothPlugin(createWorld(), { gravity: [0, 0, 0] })
      const cloth = createClothFromMesh(world, { positions, indices, tethers: false })
      for (const i of [0, 1, 2]) pinParticle(world, cloth, i)
      const c = getClothState(world, cloth)
      expect(c.pieceCount).toBe(2)
      stepCloth(world, 1 / 60)
      move(c.pos)
      clothGuard(world)
      return getClothStats(world).guardResets
    }
    // the free piece 30 m away as a whole: its own shape is fine
    expect(run((pos) => {
      for (let i = 9; i < 18; i++) pos[3 * i + 2] += 30
    })).toBe(0)
    // the free piece flung apart along z (particles 5 m apart, 40 m across): reset
    expect(run((pos) => {
      for (let i = 9; i < 18; i++) pos[3 * i + 2] += 5 * (i - 9)
    })).toBe(1)
  })
})

describe('each guard is needed', () => {
  it('finite: a NaN written into one particle is caught; without the test it spreads to the mesh', () => {
    for (const finite of [true, false]) {
      const { world, sheet, c } = sheetWorld({ guard: { finite } })
      c.vel[3 * 27 + 2] = NaN // a host system's bug (e.g. a drag toward a degenerate ray)
      stepCloth(world, 1 / 60)
      if (finite) {
        expect(meshHasNaN(world, sheet)).toBe(false)
        expect(c.pos.every(Number.isFinite) && c.vel.every(Number.isFinite)).toBe(true)
        const events = drainClothResets(world)
        expect(events).toEqual([{ cloth: sheet, reason: 'nonfinite', step: 31, particle: events[0].particle, restoredTo: 'snapshot' }])
        expect(events[0].particle).toBeGreaterThanOrEqual(0) // the first non-finite one (it spread within the step)
      } else {
        expect(meshHasNaN(world, sheet)).toBe(true)
        for (let f = 0; f < 10; f++) stepCloth(world, 1 / 60)
        let nan = 0
        for (let i = 0; i < c.count; i++) if (!Number.isFinite(c.pos[3 * i])) nan++
        expect(nan).toBeGreaterThan(c.count / 2) // it has spread through the constraints
      }
    }
  })

  it('bounds: a particle thrown 1 km away is caught; without the test the cloth whips metres out of bounds', () => {
    // skip-one bending: line bending pulls the particle straight back by itself
    for (const bounds of [2, false] as const) {
      const { world, sheet, c } = sheetWorld({ guard: { bounds } }, { tethers: false, bending: 'distance' })
      const allowed = 1.25 * geodesicDiameter(world, sheet) + 0.05
      c.pos[3 * 60] += 1000 // a host system's bug moves one particle
      let worst = -Infinity
      for (let f = 0; f < 120; f++) {
        stepCloth(world, 1 / 60)
        worst = Math.max(worst, inspect(world, sheet, allowed).excess)
      }
      if (bounds) {
        expect(worst).toBeLessThan(0)
        const events = drainClothResets(world)
        expect(events.map((e) => e.reason)).toEqual(['bounds'])
        expect([59, 60, 61, 62, 63]).toContain(events[0].particle) // the farthest out: 60 or a neighbour it dragged
      } else {
        expect(worst).toBeGreaterThan(5) // it snaps back at the speed limit, metres out of bounds on the way
        expect(getClothStats(world).guardResets).toBe(0) // the speed test alone does not see it
      }
    }
  })

  it('speed: with bounds off (say, a cloth allowed to fall away from its pins), speed alone catches a runaway', () => {
    for (const speed of [undefined, false] as const) {
      const { world, sheet, c } = sheetWorld({ guard: { bounds: false, ...(speed === false ? { speed } : {}) } }, jellySheet)
      let fastFrames = 0, extent = 0
      for (let f = 0; f < 600; f++) {
        stepCloth(world, 1 / 60)
        if (relativeRmsSpeed(c) > 130) fastFrames++
        for (let i = 0; i < c.count; i++) extent = Math.max(extent, Math.hypot(c.pos[3 * i], c.pos[3 * i + 1] - 2, c.pos[3 * i + 2]))
      }
      const reasons = new Set(drainClothResets(world).map((e) => e.reason))
      if (speed === undefined) {
        expect(fastFrames).toBe(0) // never above the 125 m/s threshold after a step
        expect(extent).toBeLessThan(50)
        expect([...reasons]).toEqual(['speed'])
      } else {
        expect(fastFrames).toBeGreaterThan(200) // racing at the speed limit...
        expect(extent).toBeGreaterThan(100) // ...hundreds of metres from its pins
        expect(reasons.size).toBe(0)
      }
      expect(inspect(world, sheet, Infinity).finite).toBe(true)
    }
  })

  it('all together: an unstable material (soft stretch, rigid hinges) never leaves its bounds; unguarded it flies to kilometres', () => {
    for (const guard of [true, false]) {
      const { world, sheet } = sheetWorld({ guard }, jellySheet)
      const allowed = 2 * geodesicDiameter(world, sheet)
      let worst = -Infinity, finite = true
      for (let f = 0; f < 600; f++) {
        stepCloth(world, 1 / 60)
        const h = inspect(world, sheet, allowed)
        worst = Math.max(worst, h.excess)
        finite &&= h.finite
      }
      expect(finite).toBe(true) // the speed limit alone keeps it finite...
      if (guard) {
        expect(worst).toBeLessThanOrEqual(1e-9) // ...the guard keeps it within 2 sizes of its pins
        expect(getClothStats(world).guardResets).toBeGreaterThan(0)
      } else {
        expect(worst).toBeGreaterThan(100)
      }
    }
  })
})

describe('restore', () => {
  it('puts the last good pose back, moved with the pins, velocities cleared, pins exactly on their targets', () => {
    const world = installClothPlugin(createWorld())
    const { cloths: [cape], hero } = heroWithCape(world)
    for (let f = 0; f < 60; f++) stepCloth(world, 1 / 60)
    const c = getClothState(world, cape)
    const good = Float64Array.from(c.pos)
    setTransform(world, hero, [0.05, 1.6, 0]) // the character moves 5 cm in the failing step
    c.vel[3 * 20] = NaN
    stepCloth(world, 1 / 60)
    const [e] = drainClothResets(world)
    expect(e.restoredTo).toBe('snapshot')
    expect(c.vel.every((v) => v === 0)).toBe(true)
    for (let i = 0; i < c.count; i++) {
      const expected = [good[3 * i] + 0.05, good[3 * i + 1], good[3 * i + 2]]
      for (let k = 0; k < 3; k++) expect(c.pos[3 * i + k]).toBeCloseTo(expected[k], 9)
      expect(c.prev[3 * i]).toBe(c.pos[3 * i])
    }
    for (let i = 0; i < 6; i++) expect(c.pos[3 * i]).toBe(good[3 * i] + 0.05) // the pinned row, exactly
  })

  it('a fault that persists falls back to the rest shape, placed (rotation included) on the pins', () => {
    const world = installClothPlugin(createWorld())
    const { cloths: [cape], hero } = heroWithCape(world)
    const c = getClothState(world, cape)
    const initial = Float64Array.from(c.pos)
    const q = quat.setAxisAngle(quat.create(), [0, 1, 0], Math.PI / 2)
    const t = vec3.fromValues(3, 0.5, -2)
    setTransform(world, hero, [3, 2.1, -2], q) // the hero turned a quarter and moved
    for (let f = 0; f < 30; f++) stepCloth(world, 1 / 60)
    const events: string[] = []
    const off = onClothReset(world, (ev) => events.push(ev.restoredTo))
    for (let f = 0; f < 3; f++) {
      c.pos[3 * 30] = NaN // broken every step
      stepCloth(world, 1 / 60)
    }
    off()
    expect(events).toEqual(['snapshot', 'rest', 'rest'])
    // the rest shape, rotated about the hero like the pins: x' = q·(x − hero₀) + hero₁
    for (let i = 0; i < c.count; i++) {
      const local = vec3.fromValues(initial[3 * i], initial[3 * i + 1] - 1.6, initial[3 * i + 2])
      const want = vec3.add(vec3.create(), vec3.transformQuat(vec3.create(), local, q), [t[0], 1.6 + t[1], t[2]])
      for (let k = 0; k < 3; k++) expect(c.pos[3 * i + k]).toBeCloseTo(want[k], 9)
    }
  })

  it('the rigid fit recovers any rotation from three pins (Horn), also a half turn', () => {
    for (const [axis, angle] of [[[0.3, -0.8, 0.5], 2.1], [[1, 0, 0], Math.PI], [[0.2, 0.1, 1], -0.7]] as const) {
      const world = installClothPlugin(createWorld())
      const hero = addEntity(world)
      setTransform(world, hero, [0, 2, 0])
      const cloth = createCloth(world, { width: 1, height: 1, resolution: 6, position: [0, 2, 0] })
      const c = getClothState(world, cloth)
      const initial = Float64Array.from(c.pos)
      for (const i of [0, 5, 35]) pinParticle(world, cloth, i, hero)
      const q = quat.setAxisAngle(quat.create(), vec3.normalize(vec3.create(), axis as unknown as vec3), angle)
      setTransform(world, hero, [1, 3, -2], q)
      for (let f = 0; f < 2; f++) {
        c.pos[3 * 20] = NaN // twice in a row: the second reset places the rest shape
        stepCloth(world, 1 / 60)
      }
      for (let i = 0; i < c.count; i++) {
        const local = vec3.fromValues(initial[3 * i], initial[3 * i + 1] - 2, initial[3 * i + 2])
        const want = vec3.add(vec3.create(), vec3.transformQuat(vec3.create(), local, q), [1, 3, -2])
        for (let k = 0; k < 3; k++) expect(c.pos[3 * i + k]).toBeCloseTo(want[k], 9)
      }
    }
  })

  it('with a snapshot interval, the restored pose is the last copy (up to that many steps old)', () => {
    for (const interval of [1, 10]) {
      const world = installClothPlugin(createWorld(), { guard: { snapshotInterval: interval } })
      const sheet = hangingSheet(world)
      const c = getClothState(world, sheet)
      for (let i = 0; i < c.count; i++) c.vel[3 * i + 2] = 1 // swinging
      for (let f = 0; f < 30; f++) stepCloth(world, 1 / 60)
      const at30 = Float64Array.from(c.pos)
      for (let f = 0; f < 5; f++) stepCloth(world, 1 / 60)
      const at35 = Float64Array.from(c.pos)
      c.pos[3 * 50] = NaN
      stepCloth(world, 1 / 60)
      const want = interval === 10 ? at30 : at35
      for (let i = 0; i < 3 * c.count; i++) expect(c.pos[i]).toBeCloseTo(want[i], 12)
      expect(Math.abs(c.pos[3 * 60 + 2] - at30[3 * 60 + 2]) + Math.abs(c.pos[3 * 60 + 2] - at35[3 * 60 + 2])).toBeGreaterThan(1e-3)
    }
  })
})

describe('events and options', () => {
  it('listeners get a reused event object after the step; drain returns copies once; the queue keeps the latest 64', () => {
    const { world, sheet, c } = sheetWorld()
    const seen: ClothResetEvent[] = []
    const objects = new Set<object>()
    const off = onClothReset(world, (e) => {
      objects.add(e)
      seen.push({ ...e })
    })
    for (let f = 0; f < 70; f++) {
      c.pos[3 * (8 + (f % 56))] = NaN // (not the pinned row: pins put their particles back anyway)
      stepCloth(world, 1 / 60)
    }
    off()
    c.pos[3 * 20] = NaN
    stepCloth(world, 1 / 60)
    expect(seen.length).toBe(70)
    expect(objects.size).toBe(1)
    expect(seen[0]).toMatchObject({ cloth: sheet, reason: 'nonfinite', step: 31, restoredTo: 'snapshot' })
    expect(seen[1]).toMatchObject({ step: 32, restoredTo: 'rest' }) // broken again right after: the rest shape
    expect(getClothStats(world).guardResets).toBe(71)
    const drained = drainClothResets(world)
    expect(drained.length).toBe(64)
    expect(drained[63].step).toBe(101)
    expect(drainClothResets(world)).toEqual([])
  })

  it('a broken cloth never touches another: the other cloth’s bytes match a world without the fault', () => {
    const run = (fault: boolean) => {
      const world = installClothPlugin(createWorld())
      const a = hangingSheet(world, { position: [-2, 2, 0] })
      const b = hangingSheet(world, { position: [2, 2, 0], bending: 'both' })
      for (let f = 0; f < 90; f++) {
        if (fault && f === 40) getClothState(world, a).pos[3 * 30] = NaN
        stepCloth(world, 1 / 60)
      }
      expect(meshHasNaN(world, a)).toBe(false)
      return hashBytes(getClothState(world, b).pos)
    }
    expect(run(true)).toBe(run(false))
  })

  it('turns off per world, per cloth at creation and at run time; bad options are ClothErrors', () => {
    const off = sheetWorld({ guard: false })
    stepCloth(off.world, 1 / 60)
    expect(getClothStats(off.world).guardChecks).toBe(0)
    const world = installClothPlugin(createWorld())
    const a = hangingSheet(world, { guard: false })
    const b = hangingSheet(world, { guard: { speed: 10, bounds: 3 } })
    stepCloth(world, 1 / 60)
    expect(getClothStats(world).guardChecks).toBe(1)
    expect(getClothGuard(world, a).enabled).toBe(false)
    expect(getClothGuard(world, b)).toMatchObject({ enabled: true, finite: true, speed: 10, bounds: 3, snapshotInterval: 1 })
    setClothGuard(world, b, false)
    stepCloth(world, 1 / 60)
    expect(getClothStats(world).guardChecks).toBe(1)
    setClothGuard(world, a, { enabled: true, speed: false })
    stepCloth(world, 1 / 60)
    expect(getClothStats(world).guardChecks).toBe(2)
    const bad: [unknown, string][] = [
      [{ bounds: 0 }, 'options.bounds'],
      [{ speed: -1 }, 'options.speed'],
      [{ speed: NaN }, 'options.speed'],
      [{ snapshotInterval: 0 }, 'options.snapshotInterval'],
      [{ finite: 'yes' }, 'options.finite'],
      ['on', 'options'],
    ]
    for (const [options, argument] of bad) {
      expect(() => setClothGuard(world, a, options as ClothGuardOptions)).toThrow(ClothError)
      try {
        setClothGuard(world, a, options as ClothGuardOptions)
      } catch (e) {
        expect((e as ClothError).argument).toBe(argument)
      }
    }
    expect(() => installClothPlugin(createWorld(), { guard: { bounds: -2 } })).toThrow(/options\.guard\.bounds/)
    expect(() => onClothReset(world, 5 as never)).toThrow(ClothError)
  })
})

describe('with colliders, wind and tearing', () => {
  it('torn pieces that fall away from their pins are judged by their own shape: no reset', () => {
    // Before the bounds were measured per piece, the first piece to fall farther than 2 sizes from
    // the pins reset the whole cloth, and then every step after (the reset pose fell again)
    for (const capacity of [2000, undefined]) {
      const world = installClothPlugin(createWorld())
      ground(world)
      const sheet = hangingSheet(world, { position: [0, 5, 0] })
      for (let f = 0; f < 20; f++) stepCloth(world, 1 / 60)
      makeTearable(world, sheet, { strain: 1e-6, maxTearsPerStep: 4096, hysteresis: 1, capacity, minPiece: 1 })
      for (let f = 0; f < 300; f++) stepCloth(world, 1 / 60)
      const c = getClothState(world, sheet)
      expect(getClothTearCount(world, sheet)).toBeGreaterThanOrEqual(capacity ? 150 : 64)
      expect(c.pieceCount).toBeGreaterThan(capacity ? 50 : 1)
      let lowest = Infinity
      for (let i = 0; i < c.count; i++) lowest = Math.min(lowest, c.pos[3 * i + 1])
      expect(lowest).toBeLessThan(0.1) // pieces lie on the ground, 5 m below the pins
      expect(getClothStats(world).guardResets).toBe(0)
      // the labels the guard uses are the mesh's pieces
      expect(c.pieceCount).toBe(inspectPieces(world, sheet, Infinity, -Infinity, 0).pieces)
    }
  })

  it('a torn cloth that fails twice goes back to its rest layout, every piece in place (split particles included)', () => {
    const world = installClothPlugin(createWorld())
    const sheet = hangingSheet(world)
    const c = getClothState(world, sheet)
    const initial = Float64Array.from(c.pos.subarray(0, 3 * c.count))
    makeTearable(world, sheet, { strain: 1e-6, maxTearsPerStep: 4096, hysteresis: 1, minPiece: 1 })
    for (let f = 0; f < 30; f++) stepCloth(world, 1 / 60)
    // it tears no further (so the last good pose is a pose of this mesh), and a step keeps that pose
    makeTearable(world, sheet, { strain: 1e6 })
    stepCloth(world, 1 / 60)
    const torn = c.count
    expect(torn).toBeGreaterThan(64)
    // which original particle each split copy came from: the copies share its rest position
    const rest = c.topology.restPositions
    const origin = (i: number) => {
      for (let k = 0; k < 64; k++)
        if (rest[3 * k] === rest[3 * i] && rest[3 * k + 1] === rest[3 * i + 1] && rest[3 * k + 2] === rest[3 * i + 2]) return k
      return -1
    }
    for (let f = 0; f < 2; f++) {
      c.pos[3 * (torn - 1)] = NaN // broken twice in a row: the second reset places the rest layout
      stepCloth(world, 1 / 60)
    }
    expect(drainClothResets(world).map((e) => e.restoredTo)).toEqual(['snapshot', 'rest'])
    expect(c.count).toBe(torn)
    for (let i = 0; i < c.count; i++) {
      const k = origin(i)
      expect(k).toBeGreaterThanOrEqual(0)
      for (let a = 0; a < 3; a++) expect(c.pos[3 * i + a]).toBeCloseTo(initial[3 * k + a], 9)
    }
  })

  describe('no false positives in ordinary scenes (guard on, never fires)', () => {
    it('a cape with body colliders on a character walking, turning and running for 20 s', () => {
      const world = installClothPlugin(createWorld())
      const s = { ...heroWithBody(world, { resolution: [10, 14] }), world }
      for (let f = 0; f < 1200; f++) {
        const t = f / 60
        walk(s, t, f < 600 ? 2 : 6)
        const a = ((f < 600 ? 2 : 6) / 2) * t
        poseLegs(s, [2 * Math.cos(a) - 2, 1.6, 2 * Math.sin(a)], -a, t)
        stepCloth(world, 1 / 60)
      }
      expect(getClothStats(world).colliderTests).toBeGreaterThan(0)
      expect(getClothStats(world).guardChecks).toBe(1200)
      expect(getClothStats(world).guardResets).toBe(0)
    })

    it('flags in steady, turbulent and gusting wind (8 to 40 m/s, and 1000 m/s with the clamp on)', () => {
      for (const [strength, turbulence] of [[8, 0], [15, 0.4], [40, 0.5], [1000, 0.5]]) {
        const world = installClothPlugin(createWorld())
        const flag = createCloth(world, { width: 1.5, height: 1, resolution: [15, 10], position: [0.75, 3, 0], material: 'nylon' })
        for (let r = 0; r < 10; r++) pinParticle(world, flag, r * 15)
        const zone = createWindZone(world, { direction: [0.2, 0, 1], strength, turbulence })
        for (let f = 0; f < 600; f++) {
          if (f === 300) setWindZone(world, zone, { strength: 2 * strength })
          stepCloth(world, 1 / 60)
        }
        expect(getClothStats(world).windTriangles).toBeGreaterThan(0)
        expect(getClothStats(world).guardResets, `${strength} m/s`).toBe(0)
      }
    })

    it('a tearable curtain yanked apart, its pieces falling 2.5 m onto a ball and the floor', () => {
      const world = installClothPlugin(createWorld())
      ground(world)
      const ball = addEntity(world)
      setTransform(world, ball, [0.3, 0.3, 0.4])
      addSphereCollider(world, ball, { radius: 0.3 })
      const curtain = createCloth(world, { width: 2, height: 1.8, resolution: [24, 20], position: [0, 4.3, 0] })
      for (let col = 0; col < 24; col += 3) pinParticle(world, curtain, col)
      makeTearable(world, curtain, { strain: 0.3, maxTearsPerStep: 8 })
      const hand = addEntity(world)
      setTransform(world, hand, [0, 2.5, 0])
      pinParticle(world, curtain, 19 * 24 + 12, hand)
      for (let f = 0; f < 600; f++) {
        const u = Math.min(1, f / 40)
        setTransform(world, hand, [0.3 * u, 2.5 - 1.5 * u, 2.5 * u])
        stepCloth(world, 1 / 60)
      }
      const c = getClothState(world, curtain)
      expect(getClothTearCount(world, curtain)).toBeGreaterThan(10)
      expect(c.pieceCount).toBeGreaterThan(1)
      expect(getClothStats(world).guardResets).toBe(0)
    })
  })

  describe('fires when the features blow up', () => {
    it('wind: without the aerodynamic clamp a sheet in a 100 m/s wind races apart; the speed test catches it', () => {
      for (const guard of [true, false]) {
        const world = installClothPlugin(createWorld(), { guard: guard ? true : { speed: false } })
        getClothWorld(world).wind.clamp = false // the explicit drag overshoots the air (see kernels/aero.ts)
        const sheet = hangingSheet(world, { material: 'silk' })
        createWindZone(world, { direction: [0.3, 0.2, 1], strength: 100, turbulence: 0.3 })
        const c = getClothState(world, sheet)
        let fastFrames = 0
        for (let f = 0; f < 300; f++) {
          stepCloth(world, 1 / 60)
          if (relativeRmsSpeed(c) > 125) fastFrames++
        }
        expect(inspect(world, sheet, Infinity).finite).toBe(true) // the world's speed limit keeps it finite
        if (guard) {
          expect(fastFrames).toBe(0)
          expect(getClothStats(world).guardResets).toBeGreaterThan(0)
          expect(new Set(drainClothResets(world).map((e) => e.reason))).toEqual(new Set(['speed']))
        } else {
          expect(fastFrames).toBeGreaterThan(20)
        }
      }
      // with the clamp (always, in use), the same wind is calm: no reset
      const world = installClothPlugin(createWorld())
      hangingSheet(world, { material: 'silk' })
      createWindZone(world, { direction: [0.3, 0.2, 1], strength: 100, turbulence: 0.3 })
      for (let f = 0; f < 300; f++) stepCloth(world, 1 / 60)
      expect(getClothStats(world).guardResets).toBe(0)
    })

    it('collisions: a sphere sweeping 100 m through a pinned sheet in one step (teleport detection off) drags it out of bounds; the bounds test catches it', () => {
      for (const guard of [true, false]) {
        const world = installClothPlugin(createWorld(), { teleportDistance: 1e6, guard })
        const sheet = hangingSheet(world)
        const ball = addEntity(world)
        setTransform(world, ball, [0, 1.5, -50])
        addSphereCollider(world, ball, { radius: 0.2 })
        const allowed = 2 * geodesicDiameter(world, sheet)
        let worst = -Infinity
        for (let f = 0; f < 90; f++) {
          if (f === 30) setTransform(world, ball, [0, 1.5, 50])
          stepCloth(world, 1 / 60)
          worst = Math.max(worst, inspect(world, sheet, allowed).excess)
        }
        if (guard) {
          expect(worst).toBeLessThanOrEqual(1e-9)
          expect(drainClothResets(world).map((e) => e.reason)).toContain('bounds')
        } else {
          expect(worst).toBeGreaterThan(20) // carried along tens of metres by the sphere
        }
      }
    })

    it('tearing: no way found to make it blow up (every edge torn at once, the capacity exhausted, pieces on colliders): nothing to catch', () => {
      const world = installClothPlugin(createWorld())
      ground(world)
      const log = addEntity(world)
      setTransform(world, log, [0, 0.2, 0], [0, 0, Math.SQRT1_2, Math.SQRT1_2])
      addCapsuleCollider(world, log, { radius: 0.2, halfHeight: 0.6 })
      const sheet = hangingSheet(world, { position: [0, 3, 0], bending: 'both' })
      makeTearable(world, sheet, { strain: 1e-6, maxTearsPerStep: 4096, hysteresis: 1, capacity: 40 })
      let peak = 0
      const c = getClothState(world, sheet)
      for (let f = 0; f < 300; f++) {
        stepCloth(world, 1 / 60)
        peak = Math.max(peak, relativeRmsSpeed(c))
      }
      expect(c.count).toBe(64 + 40) // the capacity ran out
      expect(peak).toBeLessThan(10) // m/s: the pieces fall, nothing flies apart
      expect(getClothStats(world).guardResets).toBe(0)
    })
  })
})
