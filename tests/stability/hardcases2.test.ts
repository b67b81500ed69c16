// Hard cases, round two: scale as an input, host transform stores, the order of setup calls,
// garbage written straight into the transform stores, and meshes with vertices no triangle uses.
// Public API only, as a host would use it.
import { addComponent, addEntity, createWorld, getAllEntities, removeEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  ClothError,
  addPlaneCollider,
  addSphereCollider,
  createCloth,
  createClothFromMesh,
  getClothLod,
  createWindZone,
  enableSelfCollision,
  getClothComponents,
  getPins,
  getClothMesh,
  getClothState,
  getClothStats,
  getTransform,
  installClothPlugin,
  isClothSleeping,
  makeTearable,
  pinParticle,
  pinRow,
  restoreClothState,
  sampleWind,
  saveClothState,
  setClothBudget,
  setClothCollision,
  setClothGuard,
  setClothQuality,
  setClothSleep,
  setClothTethers,
  setTransform,
  stepCloth,
  teleportCloth,
  unpin,
  type ClothPluginOptions,
  type TransformSource,
} from '../../src/index'
import { hashBytes, rng } from '../helpers'
import { heroWithCape } from './scenes'
import { gridMesh } from './harness'

const frame = 1 / 60

/** Positions, previous positions and velocities of a cloth, hashed. */
function clothHash(world: object, cloth: number): string {
  const c = getClothState(world, cloth)
  const n = 3 * c.count
  return hashBytes(c.pos.subarray(0, n)) + hashBytes(c.prev.subarray(0, n)) + hashBytes(c.vel.subarray(0, n)) + ':' + c.count
}

function meshFinite(world: object, cloth: number): boolean {
  const m = getClothMesh(world, cloth)
  return m.positions.every(Number.isFinite) && m.normals.every(Number.isFinite)
}

/** Steps until the cloth sleeps (at most `limit` frames); returns the frames taken. */
function stepUntilAsleep(world: object, cloth: number, limit = 1200): number {
  for (let f = 0; f < limit; f++) {
    if (isClothSleeping(world, cloth)) return f
    stepCloth(world, frame)
  }
  throw new Error('the cloth never fell asleep')
}

// ---------------------------------------------------------------------------------------------

describe('scale is an input like position and rotation: changing it wakes what it reaches', () => {
  /** The cape of heroWithCape: its top row, pinned, and where each pinned particle sits in the hero's frame. */
  function capeOnHero(options: ClothPluginOptions = {}) {
    const world = installClothPlugin(createWorld(), options)
    const { hero, cloths } = heroWithCape(world)
    const cape = cloths[0]
    const c = getClothState(world, cape)
    const top = [...Array(6).keys()]
    const local = top.map((i) => [c.pos[3 * i], c.pos[3 * i + 1] - 1.6, c.pos[3 * i + 2]])
    return { world, hero, cape, top, local }
  }

  /** Largest distance of the pinned top row from the hero's position + scale × its local offset. */
  function pinError(world: object, cape: number, hero: number, top: number[], local: number[][], s: number): number {
    const c = getClothState(world, cape)
    const p = [0, 0, 0]
    getTransform(world, hero, p)
    let err = 0
    for (let k = 0; k < top.length; k++) {
      const i = top[k]
      err = Math.max(
        err,
        Math.hypot(
          c.pos[3 * i] - (p[0] + s * local[k][0]),
          c.pos[3 * i + 1] - (p[1] + s * local[k][1]),
          c.pos[3 * i + 2] - (p[2] + s * local[k][2]),
        ),
      )
    }
    return err
  }

  for (const [label, s] of [['grows 1.5×', 1.5], ['shrinks to 0.5×', 0.5]] as const) {
    it(`a sleeping cape wakes when its character ${label} (setTransform) and its pins follow the scaled offsets`, () => {
      const { world, hero, cape, top, local } = capeOnHero()
      stepUntilAsleep(world, cape)
      setTransform(world, hero, [0, 1.6, 0], [0, 0, 0, 1], [s, s, s])
      stepCloth(world, frame)
      expect(isClothSleeping(world, cape)).toBe(false)
      for (let f = 0; f < 30; f++) stepCloth(world, frame)
      expect(pinError(world, cape, hero, top, local, s)).toBeLessThan(1e-9)
    })
  }

  it('a scale written straight into the Transform store wakes the cape too', () => {
    const { world, hero, cape, top, local } = capeOnHero()
    stepUntilAsleep(world, cape)
    const T = getClothComponents(world).Transform
    T.sx[hero] = T.sy[hero] = T.sz[hero] = 1.5
    for (let f = 0; f < 30; f++) stepCloth(world, frame)
    expect(pinError(world, cape, hero, top, local, 1.5)).toBeLessThan(1e-9)
  })

  it('a character growing over a second (a spawn animation) carries its cape smoothly: the pins follow every frame, no pop', () => {
    const { world, hero, cape, top, local } = capeOnHero()
    stepUntilAsleep(world, cape)
    let worst = 0
    for (let f = 1; f <= 60; f++) {
      const s = 1 + f / 60
      setTransform(world, hero, [0, 1.6, 0], [0, 0, 0, 1], [s, s, s])
      stepCloth(world, frame)
      worst = Math.max(worst, pinError(world, cape, hero, top, local, s))
    }
    expect(worst).toBeLessThan(1e-9)
    // scale is interpolated across the substeps like position: the hem does not jerk
    const c = getClothState(world, cape)
    let fastest = 0
    for (let i = 0; i < c.count; i++) fastest = Math.max(fastest, Math.hypot(c.vel[3 * i], c.vel[3 * i + 1], c.vel[3 * i + 2]))
    expect(fastest).toBeLessThan(2)
  })

  it('a collider whose body is scaled into a sleeping sheet (the offset grows) wakes it and pushes it out', () => {
    const world = installClothPlugin(createWorld())
    const sheet = createCloth(world, { width: 1, height: 1, resolution: 10, position: [0, 2, 0] })
    pinRow(world, sheet, 0)
    const body = addEntity(world)
    setTransform(world, body, [0, 1.5, -1])
    const ball = addEntity(world)
    addSphereCollider(world, ball, { body, offset: [0, 0, 0.45], radius: 0.3 })
    stepUntilAsleep(world, sheet)
    // scaled 2.2×: the ball's centre moves from z = −0.55 to z = −0.01, through the sheet's plane
    setTransform(world, body, [0, 1.5, -1], [0, 0, 0, 1], [2.2, 2.2, 2.2])
    for (let f = 0; f < 60; f++) stepCloth(world, frame)
    const c = getClothState(world, sheet)
    const thickness = c.material.thickness
    let deepest = Infinity
    for (let i = 0; i < c.count; i++)
      deepest = Math.min(deepest, Math.hypot(c.pos[3 * i], c.pos[3 * i + 1] - 1.5, c.pos[3 * i + 2] + 0.01) - 0.3)
    expect(deepest).toBeGreaterThan(thickness - 0.005)
  })

  it('host stores: a scale written into the host arrays wakes the cape', () => {
    const host = hostStores(64)
    const world = installClothPlugin(createWorld(), { transforms: host.source })
    const hero = host.add(world, [0, 1.6, 0])
    const cape = createCloth(world, { width: 0.5, height: 0.8, resolution: [6, 8], position: [0, 1.5, -0.15], bending: 'distance' })
    pinRow(world, cape, 0, hero)
    stepUntilAsleep(world, cape)
    host.T.sx[hero] = host.T.sy[hero] = host.T.sz[hero] = 2
    stepCloth(world, frame)
    expect(isClothSleeping(world, cape)).toBe(false)
    for (let f = 0; f < 30; f++) stepCloth(world, frame)
    const c = getClothState(world, cape)
    // the top corners were at x = ±0.25 in the hero's frame: now ±0.5
    expect(c.pos[0]).toBeCloseTo(-0.5, 9)
    expect(c.pos[15]).toBeCloseTo(0.5, 9)
  })
})

// ---------------------------------------------------------------------------------------------

/** An engine's own transform stores: one component object holding entity-indexed arrays. */
function hostStores(n: number, Arr: Float64ArrayConstructor | Float32ArrayConstructor | ArrayConstructor = Float64Array) {
  const make = (fill: number) => {
    const a = Arr === Array ? new Array<number>(n).fill(fill) : new (Arr as Float64ArrayConstructor)(n).fill(fill)
    return a as unknown as Float64Array
  }
  const T = {
    px: make(0),
    py: make(0),
    pz: make(0),
    qx: make(0),
    qy: make(0),
    qz: make(0),
    qw: make(1),
    sx: make(1),
    sy: make(1),
    sz: make(1),
  }
  const source: TransformSource = { component: T, ...T }
  return {
    T,
    source,
    /** A host entity with a transform at `p`. */
    add(world: object, p: ArrayLike<number>, q: ArrayLike<number> = [0, 0, 0, 1]): number {
      const e = addEntity(world)
      addComponent(world, e, T)
      T.px[e] = p[0]
      T.py[e] = p[1]
      T.pz[e] = p[2]
      T.qx[e] = q[0]
      T.qy[e] = q[1]
      T.qz[e] = q[2]
      T.qw[e] = q[3]
      T.sx[e] = T.sy[e] = T.sz[e] = 1
      return e
    },
  }
}

describe('host transform stores: every feature works with them', () => {
  for (const shape of ['global', 'box', 'sphere'] as const) {
    it(`a ${shape} wind zone can be created, blows, and follows the host's transform`, () => {
      const host = hostStores(64)
      const world = installClothPlugin(createWorld(), { transforms: host.source })
      const sheet = createCloth(world, { width: 1, height: 1, resolution: 8, position: [0, 2, 0] })
      pinRow(world, sheet, 0)
      const zone = createWindZone(world, { shape, position: [0, 1.5, 0], size: 3, direction: [0, 0, 1], strength: 8 })
      // the zone's entity got the host's transform component and its position
      expect(host.T.py[zone]).toBe(1.5)
      const p = [0, 0, 0]
      expect(getTransform(world, zone, p)).toBe(true)
      expect(p).toEqual([0, 1.5, 0])
      for (let f = 0; f < 60; f++) stepCloth(world, frame)
      const c = getClothState(world, sheet)
      expect(c.pos[3 * (c.count - 1) + 2]).toBeGreaterThan(0.1) // the hem blown downwind
      if (shape !== 'global') {
        // the host moves the zone away: the air at the sheet goes still
        host.T.px[zone] = 100
        stepCloth(world, frame)
        expect(sampleWind(world, [0, 1.5, 0])).toEqual([0, 0, 0])
      }
    })
  }

  /** Every feature on: a cape on a character with a body collider, a box wind zone, a tearable self-colliding sheet, a budget viewer. */
  function kitchenSink(world: object, spawn: (p: number[]) => number) {
    const hero = spawn([0, 1.6, 0])
    const camera = spawn([0, 1.6, 5])
    const cape = createCloth(world, { width: 0.5, height: 0.8, resolution: [6, 8], position: [0, 1.5, -0.15], bending: 'distance' })
    pinRow(world, cape, 0, hero)
    const torso = addEntity(world)
    addSphereCollider(world, torso, { body: hero, offset: [0, -0.5, 0.05], radius: 0.15 })
    const fan = createWindZone(world, {
      shape: 'box',
      position: [3, 1.5, 0],
      size: [2, 2, 2],
      direction: [0, 0, 1],
      strength: 6,
      turbulence: 0.3,
    })
    const hands = [spawn([2.5, 2, 0]), spawn([3.5, 2, 0])]
    const sheet = createCloth(world, { width: 1, height: 1, resolution: 8, position: [3, 2, 0], bending: 'both' })
    pinParticle(world, sheet, 0, hands[0])
    pinParticle(world, sheet, 7, hands[1])
    enableSelfCollision(world, sheet)
    makeTearable(world, sheet, { strain: 0.2, maxTearsPerStep: 2 })
    setClothBudget(world, {
      viewer: camera,
      near: 3,
      far: 20,
      farStepEvery: 2,
      interval: 5,
      adapt: false,
      calibration: { nsPerParticle: 10, nsPerProjection: 2, nsPerColliderTest: 3, nsPerClothSubstep: 100 },
    })
    return { hero, camera, cape, sheet, hands, fan, cloths: [cape, sheet] }
  }

  it('the same scene with host stores and with the plugin’s own stores gives the same bytes, frame after frame (pins, colliders, zones, budget, tearing, teleports, snapshots)', () => {
    const host = hostStores(256)
    const a = installClothPlugin(createWorld(), { transforms: host.source })
    const b = installClothPlugin(createWorld())
    const sa = kitchenSink(a, (p) => host.add(a, p))
    const sb = kitchenSink(b, (p) => {
      const e = addEntity(b)
      setTransform(b, e, p)
      return e
    })
    const r = rng(5)
    let savedA = saveClothState(a, sa.cape), savedB = saveClothState(b, sb.cape)
    for (let f = 0; f < 240; f++) {
      const x = 0.5 * Math.sin(f / 20), yaw = f / 40, spread = Math.min(0.6, f / 100)
      const q = [0, Math.sin(yaw / 2), 0, Math.cos(yaw / 2)]
      const s = f > 120 ? 1.3 : 1
      // host: writes its arrays; plugin world: setTransform
      host.T.px[sa.hero] = x
      host.T.qy[sa.hero] = q[1]
      host.T.qw[sa.hero] = q[3]
      host.T.sx[sa.hero] = host.T.sy[sa.hero] = host.T.sz[sa.hero] = s
      setTransform(b, sb.hero, [x, 1.6, 0], q, [s, s, s])
      host.T.px[sa.hands[0]] = 2.5 - spread
      host.T.px[sa.hands[1]] = 3.5 + spread
      setTransform(b, sb.hands[0], [2.5 - spread, 2, 0])
      setTransform(b, sb.hands[1], [3.5 + spread, 2, 0])
      host.T.pz[sa.camera] = 5 + 0.2 * f
      setTransform(b, sb.camera, [0, 1.6, 5 + 0.2 * f])
      if (f === 60) {
        teleportCloth(a, sa.cape, [0, 0, 0.5])
        teleportCloth(b, sb.cape, [0, 0, 0.5])
      }
      if (f === 90) {
        savedA = saveClothState(a, sa.cape, savedA)
        savedB = saveClothState(b, sb.cape, savedB)
      }
      if (f === 150) {
        restoreClothState(a, sa.cape, savedA)
        restoreClothState(b, sb.cape, savedB)
      }
      const dt = (0.5 + r()) / 60
      stepCloth(a, dt)
      stepCloth(b, dt)
      for (let k = 0; k < 2; k++) expect(clothHash(a, sa.cloths[k]), `frame ${f}`).toBe(clothHash(b, sb.cloths[k]))
    }
    expect(getClothStats(a).tears).toBeGreaterThan(0)
    expect(getClothStats(a).guardResets).toBe(0)
  })

  it('setTransform on an entity without the host’s component adds it (identity scale), as it does with the plugin’s own store', () => {
    const host = hostStores(64)
    const world = installClothPlugin(createWorld(), { transforms: host.source })
    const e = addEntity(world)
    host.T.sx[e] = 7 // stale data of an earlier entity with this id
    setTransform(world, e, [1, 2, 3])
    const p = [0, 0, 0], q = [0, 0, 0, 0]
    expect(getTransform(world, e, p, q)).toBe(true)
    expect(p).toEqual([1, 2, 3])
    expect(q).toEqual([0, 0, 0, 1])
    expect(host.T.sx[e]).toBe(1)
  })

  it('a host store too short for an entity is refused with a ClothError naming it (not a silent NaN in the step)', () => {
    const host = hostStores(4)
    const world = installClothPlugin(createWorld(), { transforms: host.source })
    for (let k = 0; k < 6; k++) addEntity(world)
    const e = addEntity(world)
    expect(() => setTransform(world, e, [0, 1, 0])).toThrow(ClothError)
    // the zone's entity does not stay behind, and the error names the world (not an `eid` the call has not)
    const before = getAllEntities(world).length
    for (let k = 0; k < 5; k++) {
      let error: unknown
      try {
        createWindZone(world, { direction: [1, 0, 0], strength: 1 })
      } catch (x) {
        error = x
      }
      expect(error).toBeInstanceOf(ClothError)
      expect((error as ClothError).argument).toBe('world')
    }
    expect(getAllEntities(world).length).toBe(before) // (was 5 more)
  })

  it('a pin or collider refused for a bad host transform leaves nothing tracked: the world steps on once the entity is gone', () => {
    // observed: the refused target stayed tracked, and every later step threw for its transform
    const host = hostStores(64)
    const world = installClothPlugin(createWorld(), { transforms: host.source })
    const cloth = createCloth(world, { width: 1, height: 1, resolution: 6, position: [0, 2, 0] })
    const hero = host.add(world, [0, 2, 0]), body = host.add(world, [0, 1, 0])
    host.T.px[hero] = NaN // the host's uninitialised entities
    host.T.py[body] = Infinity
    expect(() => pinParticle(world, cloth, 0, hero)).toThrow(ClothError)
    expect(() => addSphereCollider(world, addEntity(world), { body, radius: 0.2 })).toThrow(ClothError)
    for (let k = 0; k < 10; k++) addEntity(world) // an id beyond the host arrays
    const far = addEntity(world)
    expect(() => pinParticle(world, cloth, 1, far)).toThrow(ClothError)
    removeEntity(world, hero)
    removeEntity(world, body)
    expect(() => stepCloth(world, 1 / 60)).not.toThrow()
  })

  it('host arrays replaced when they grow: the plugin reads them through the object it was given, so updating its fields is enough', () => {
    const host = hostStores(8)
    const world = installClothPlugin(createWorld(), { transforms: host.source })
    const hero = host.add(world, [0, 1.6, 0])
    const cape = createCloth(world, { width: 0.5, height: 0.8, resolution: [6, 8], position: [0, 1.5, -0.15], bending: 'distance' })
    pinRow(world, cape, 0, hero)
    stepCloth(world, frame)
    // the engine grows its stores (new arrays) and updates the source object's fields
    const src = host.source as unknown as Record<string, Float64Array>
    for (const key of ['px', 'py', 'pz', 'qx', 'qy', 'qz', 'qw', 'sx', 'sy', 'sz']) {
      const grown = new Float64Array(256)
      grown.set(src[key])
      src[key] = grown
    }
    let e = addEntity(world)
    while (e < 100) e = addEntity(world) // ids beyond the old length
    const zone = createWindZone(world, { shape: 'sphere', size: 2, position: [0, 1, 0], direction: [0, 0, -1], strength: 5 })
    expect(zone).toBeGreaterThan(8)
    src.px[hero] = 0.3
    for (let f = 0; f < 30; f++) stepCloth(world, frame)
    expect(getClothState(world, cape).pos[0]).toBeCloseTo(0.05, 9) // the top-left pin followed to x = 0.3 − 0.25
    expect(meshFinite(world, cape)).toBe(true)
  })

  for (const [label, Arr] of [['Float32Array', Float32Array], ['plain Array', Array]] as const) {
    it(`host stores of ${label}: a cape, a collider and a zone run, finite, guard quiet`, () => {
      const host = hostStores(64, Arr)
      const world = installClothPlugin(createWorld(), { transforms: host.source })
      const hero = host.add(world, [0, 1.6, 0])
      const cape = createCloth(world, { width: 0.5, height: 0.8, resolution: [6, 8], position: [0, 1.5, -0.15], bending: 'distance' })
      pinRow(world, cape, 0, hero)
      addSphereCollider(world, addEntity(world), { body: hero, offset: [0, -0.5, 0.05], radius: 0.15 })
      createWindZone(world, { shape: 'sphere', size: 2, position: [0, 1, 0], direction: [0, 0, -1], strength: 5 })
      for (let f = 0; f < 120; f++) {
        host.T.px[hero] = Math.sin(f / 10)
        stepCloth(world, frame)
      }
      expect(meshFinite(world, cape)).toBe(true)
      expect(getClothStats(world).guardResets).toBe(0)
    })
  }
})

// ---------------------------------------------------------------------------------------------

describe('setup order: every feature’s per-particle arrays follow the cloth’s capacity, whatever the order of calls', () => {
  type Setup = { name: string; run: (world: object, s: { sheet: number; ball: number; hands: number[] }) => void }
  const setups: Setup[] = [
    { name: 'tearable', run: (w, s) => makeTearable(w, s.sheet, { strain: 0.12, maxTearsPerStep: 6, capacity: 60 }) },
    { name: 'self-collision', run: (w, s) => enableSelfCollision(w, s.sheet) },
    { name: 'wind', run: (w) => void createWindZone(w, { direction: [0.3, 0, 1], strength: 5, turbulence: 0.3 }) },
    { name: 'guard', run: (w, s) => setClothGuard(w, s.sheet, { bounds: 3 }) },
    { name: 'sleep', run: (w, s) => setClothSleep(w, s.sheet, { speed: 0.02 }) },
    { name: 'collider', run: (w, s) => void addSphereCollider(w, s.ball, { radius: 0.25 }) },
    { name: 'quality', run: (w, s) => setClothQuality(w, s.sheet, { substeps: 6 }) },
    { name: 'tethers', run: (w, s) => setClothTethers(w, s.sheet, { perParticle: 3 }) },
    { name: 'collision settings', run: (w, s) => setClothCollision(w, s.sheet, { thickness: 0.01 }) },
    {
      name: 'pins',
      run: (w, s) => {
        pinParticle(w, s.sheet, 0, s.hands[0])
        pinParticle(w, s.sheet, 9, s.hands[1])
      },
    },
  ]

  /** A sheet pulled apart at its corners, torn, its pieces falling onto a ball and each other on the ground. */
  function run(order: Setup[]): { hash: string; overlaps: number; tears: number } {
    const world = installClothPlugin(createWorld())
    const sheet = createCloth(world, { width: 1, height: 1, resolution: 10, position: [0, 1.5, 0], bending: 'both' })
    const ball = addEntity(world)
    setTransform(world, ball, [0, 0.6, 0.1])
    addPlaneCollider(world, setGround(world))
    const hands = [addEntity(world), addEntity(world)]
    setTransform(world, hands[0], [-0.5, 1.5, 0])
    setTransform(world, hands[1], [0.5, 1.5, 0])
    const s = { sheet, ball, hands }
    for (const o of order) o.run(world, s)
    for (let f = 0; f < 200; f++) {
      // the hands pull the pinned corners apart: the sheet tears; then they let go
      if (f >= 20 && f < 40) {
        setTransform(world, hands[0], [-0.5 - 0.04 * (f - 19), 1.5, 0])
        setTransform(world, hands[1], [0.5 + 0.04 * (f - 19), 1.5, 0])
      }
      if (f === 60) { for (const pin of getPins(world, sheet)) unpin(world, pin) }
      stepCloth(world, frame)
    }
    expect(capacityProblems(world, sheet), order.map((o) => o.name).join(', ')).toEqual([])
    return { hash: clothHash(world, sheet), overlaps: overlappingPairs(world, sheet), tears: getClothStats(world).tears }
  }

  /** Per-particle arrays of the cloth and its features shorter than its particle capacity (names). */
  function capacityProblems(world: object, cloth: number): string[] {
    const c = getClothState(world, cloth)
    const P = c.pos.length / 3
    const arrays: [string, ArrayLike<number> | null | undefined, number][] = [
      ['prev', c.prev, 3],
      ['vel', c.vel, 3],
      ['invMass', c.invMass, 1],
      ['baseInvMass', c.baseInvMass, 1],
      ['invMass3', c.invMass3, 3],
      ['pinCount', c.pinCount, 1],
      ['render.positions', c.render.positions, 3],
      ['render.normals', c.render.normals, 3],
      ['guard.rest', c.guard.rest, 3],
      ['guard.safe', c.guard.safe, 3],
      ['guard.pieceBox', c.guard.pieceBox, 7],
      ['topology.restPositions', c.topology.restPositions, 3],
      ['topology.masses', c.topology.masses, 1],
      ['piece', c.piece, 1],
    ]
    if (c.topology.unused) arrays.push(['topology.unused', c.topology.unused, 1])
    if (c.wind)
      arrays.push(['wind.air', c.wind.air, 4], ['wind.accel', c.wind.accel, 3], ['wind.normals', c.wind.normals, 3], [
        'wind.scratch',
        c.wind.scratch,
        3,
      ])
    const self = c.collision.self
    if (self) {
      arrays.push(['self.entries', self.entries, 1], ['self.bucket', self.bucket, 1], ['self.sorted', self.sorted, 3], [
        'self.touched',
        self.touched,
        1,
      ])
      if (self.capacity < 48 * P) arrays.push(['self.pairs', null, 1])
      if (self.crossCapacity > 0 && self.crossCapacity < 48 * P) arrays.push(['self.cross', null, 1])
    }
    return arrays.filter(([, a, k]) => !a || a.length < k * P).map(([n]) => n)
  }

  function setGround(world: object): number {
    const g = addEntity(world)
    setTransform(world, g, [0, 0, 0])
    return g
  }

  /** Particle pairs (not mesh neighbours at rest) closer than half the self-collision thickness. */
  function overlappingPairs(world: object, cloth: number): number {
    const c = getClothState(world, cloth)
    const t = c.topology
    const D = c.collision.self ? c.collision.self.thickness : 0.1
    let n = 0
    for (let i = 0; i < c.count; i++) {
      for (let j = i + 1; j < c.count; j++) {
        const rest = Math.hypot(
          t.restPositions[3 * i] - t.restPositions[3 * j],
          t.restPositions[3 * i + 1] - t.restPositions[3 * j + 1],
          t.restPositions[3 * i + 2] - t.restPositions[3 * j + 2],
        )
        if (rest < 1.5 * D) continue
        const d = Math.hypot(c.pos[3 * i] - c.pos[3 * j], c.pos[3 * i + 1] - c.pos[3 * j + 1], c.pos[3 * i + 2] - c.pos[3 * j + 2])
        if (d < 0.5 * D) n++
      }
    }
    return n
  }

  it('self-collision before tearing and after: the same bytes, and torn pieces do not pass through each other', () => {
    const tear = setups[0], self = setups[1], pins = setups[9]
    const after = run([pins, tear, self])
    const before = run([pins, self, tear])
    expect(after.tears).toBeGreaterThan(5)
    expect(after.overlaps).toBeLessThan(10)
    expect(before.overlaps).toBe(after.overlaps)
    expect(before.hash).toBe(after.hash)
  })

  it('every feature set up before tearing gives the same bytes as after it (each on its own)', () => {
    const tear = setups[0], pins = setups[9]
    for (const o of setups.slice(1, 9)) {
      const a = run([pins, tear, o])
      const b = run([pins, o, tear])
      expect(b.hash, o.name).toBe(a.hash)
    }
  })

  it('two self-colliding cloths, one made tearable after both had self-collision: its cloth–cloth pair list grows with it', () => {
    const twoSheets = (tearFirst: boolean) => {
      const world = installClothPlugin(createWorld())
      const a = createCloth(world, { width: 1, height: 1, resolution: 10, position: [0, 1.5, 0] })
      const b = createCloth(world, { width: 1, height: 1, resolution: 10, position: [0, 1.5, 0.05] })
      pinRow(world, a, 0)
      pinRow(world, b, 0)
      if (tearFirst) makeTearable(world, a, { strain: 0.2 })
      enableSelfCollision(world, a)
      enableSelfCollision(world, b)
      if (!tearFirst) makeTearable(world, a, { strain: 0.2 })
      for (let f = 0; f < 60; f++) stepCloth(world, frame)
      expect(capacityProblems(world, a)).toEqual([])
      return clothHash(world, a) + clothHash(world, b)
    }
    expect(twoSheets(false)).toBe(twoSheets(true))
  })

  it('all features in random orders give the same bytes', () => {
    const r = rng(17)
    const reference = run(setups)
    for (let k = 0; k < 6; k++) {
      const order = setups.slice()
      for (let i = order.length - 1; i > 0; i--) {
        const j = Math.floor(r() * (i + 1))
        ;[order[i], order[j]] = [order[j], order[i]]
      }
      expect(run(order).hash, order.map((o) => o.name).join(', ')).toBe(reference.hash)
    }
  })
})

// ---------------------------------------------------------------------------------------------

describe('huge but finite values written into the Transform store', () => {
  function capeScene() {
    const world = installClothPlugin(createWorld())
    const { hero, cloths } = heroWithCape(world)
    const ball = addEntity(world)
    addSphereCollider(world, ball, { body: hero, offset: [0, -0.5, 0.05], radius: 0.15 })
    const viewer = addEntity(world)
    setTransform(world, viewer, [0, 1.6, 4])
    setClothBudget(world, {
      viewer,
      adapt: false,
      calibration: { nsPerParticle: 10, nsPerProjection: 2, nsPerColliderTest: 3, nsPerClothSubstep: 100 },
    })
    createWindZone(world, { shape: 'sphere', position: [0, 1, 0], size: 2, direction: [1, 0, 0], strength: 3 })
    for (let f = 0; f < 30; f++) stepCloth(world, frame)
    return { world, hero, cape: cloths[0], viewer, T: getClothComponents(world).Transform }
  }

  it('a rotation component of 1e200 (or every component huge, or all tiny) is a rotation: normalised without overflow, mesh finite', () => {
    for (const q of [[1e200, 0, 0, 1], [1e300, 1e300, 1e300, 1e300], [0, 1e-300, 0, 1e-300], [-1e308, 0, 1e308, 0]]) {
      const { world, hero, cape, T } = capeScene()
      const twin = capeScene()
      T.qx[hero] = q[0]
      T.qy[hero] = q[1]
      T.qz[hero] = q[2]
      T.qw[hero] = q[3]
      // the twin gets the same rotation, normalised by hand
      const m = Math.max(...q.map(Math.abs))
      const u = q.map((v) => v / m)
      const l = Math.hypot(...u)
      setTransform(twin.world, twin.hero, [0, 1.6, 0], u.map((v) => v / l))
      for (let f = 0; f < 60; f++) {
        stepCloth(world, frame)
        stepCloth(twin.world, frame)
        expect(meshFinite(world, cape)).toBe(true)
      }
      const a = getClothState(world, cape), b = getClothState(twin.world, twin.cape)
      for (let i = 0; i < 3 * a.count; i++) expect(Math.abs(a.pos[i] - b.pos[i])).toBeLessThan(1e-9)
      expect(getClothStats(world).guardResets).toBe(0)
    }
  })

  for (
    const [what, write] of [
      ['a scale of 1e300 on a pin target', (s: ReturnType<typeof capeScene>) => (s.T.sy[s.hero] = 1e300)],
      ['a scale of 1e7 on a pin target', (s: ReturnType<typeof capeScene>) => (s.T.sx[s.hero] = 1e7)],
      ['a position of 1e200 on a pin target', (s: ReturnType<typeof capeScene>) => (s.T.pz[s.hero] = 1e200)],
      ['a position of 1e200 on the budget viewer', (s: ReturnType<typeof capeScene>) => (s.T.px[s.viewer] = 1e200)],
    ] as const
  ) {
    it(`${what}: refused by the step with a ClothError naming the entity; nothing reaches the mesh; fixed, it runs on`, () => {
      const s = capeScene()
      const before = clothHash(s.world, s.cape)
      write(s)
      let error: unknown
      for (let f = 0; f < 20 && !error; f++) {
        try {
          stepCloth(s.world, frame)
        } catch (e) {
          error = e
        }
      }
      expect(error).toBeInstanceOf(ClothError)
      expect((error as ClothError).argument).toMatch(/^transform of entity \d+$/)
      expect(clothHash(s.world, s.cape)).toBe(before)
      expect(meshFinite(s.world, s.cape)).toBe(true)
      setTransform(s.world, s.hero, [0, 1.6, 0], [0, 0, 0, 1], [1, 1, 1])
      setTransform(s.world, s.viewer, [0, 1.6, 4])
      for (let f = 0; f < 30; f++) stepCloth(s.world, frame)
      expect(meshFinite(s.world, s.cape)).toBe(true)
    })
  }

  it('garbage of every kind in every field, frame after frame: each step either runs with the mesh finite or throws a ClothError naming an entity', () => {
    const r = rng(99)
    const values = [NaN, Infinity, -Infinity, 1e308, -1e308, 1e200, 1e-320, -0, 0, 5e-324, 1e9, 1e10, -1, 1e6, 2e6]
    const s = capeScene()
    const fields = ['px', 'py', 'pz', 'qx', 'qy', 'qz', 'qw', 'sx', 'sy', 'sz'] as const
    let errors = 0
    for (let f = 0; f < 300; f++) {
      const e = r() < 0.5 ? s.hero : s.viewer
      const field = fields[Math.floor(r() * fields.length)]
      const old = s.T[field][e]
      s.T[field][e] = values[Math.floor(r() * values.length)]
      try {
        stepCloth(s.world, frame)
      } catch (err) {
        expect(err).toBeInstanceOf(ClothError)
        expect((err as ClothError).argument).toMatch(/^transform of entity \d+$/)
        errors++
        s.T[field][e] = old
      }
      expect(meshFinite(s.world, s.cape)).toBe(true)
    }
    expect(errors).toBeGreaterThan(10)
    expect(errors).toBeLessThan(300)
  })
})

// ---------------------------------------------------------------------------------------------

describe('mesh vertices no triangle uses: kept where they are, outside the simulation', () => {
  /** A 9×9 grid mesh 2 m up (top row at y = 2), plus `loose` vertices no triangle uses, appended. */
  function meshWithLoose(loose: number[][]) {
    const g = gridMesh(9, 0.125)
    const positions = g.positions.map((v, i) => (i % 3 === 1 ? v + 2 : v))
    for (const p of loose) positions.push(...p)
    return { positions, indices: g.indices, used: 81 }
  }
  const LOOSE = [[0, -30, 0], [40, 2, 5], [0.2, 1.5, 0.3]]

  /** The same scene with and without the loose vertices: pinned top corners on a swaying target, wind, a ball. */
  function scene(loose: number[][], extra: (world: object, cloth: number) => void = () => {}) {
    const world = installClothPlugin(createWorld())
    const m = meshWithLoose(loose)
    const cloth = createClothFromMesh(world, { positions: m.positions, indices: m.indices })
    const hand = addEntity(world)
    setTransform(world, hand, [0, 2, 0])
    pinParticle(world, cloth, 0, hand)
    pinParticle(world, cloth, 8, hand)
    createWindZone(world, { direction: [0, 0, 1], strength: 4, turbulence: 0.3 })
    const ball = addEntity(world)
    setTransform(world, ball, [0, 1.2, 0.4])
    addSphereCollider(world, ball, { radius: 0.2 })
    extra(world, cloth)
    return { world, cloth, hand }
  }

  it('the cloth moves exactly as the same mesh without them (byte for byte), they stay where they are, the guard never fires', () => {
    const a = scene(LOOSE), b = scene([])
    for (let f = 0; f < 300; f++) {
      const p = [0.3 * Math.sin(f / 20), 2, 0.2 * Math.cos(f / 25)]
      setTransform(a.world, a.hand, p)
      setTransform(b.world, b.hand, p)
      stepCloth(a.world, frame)
      stepCloth(b.world, frame)
      const ca = getClothState(a.world, a.cloth), cb = getClothState(b.world, b.cloth)
      expect(hashBytes(ca.pos.subarray(0, 3 * 81)), `frame ${f}`).toBe(hashBytes(cb.pos.subarray(0, 3 * 81)))
      expect(hashBytes(ca.vel.subarray(0, 3 * 81))).toBe(hashBytes(cb.vel.subarray(0, 3 * 81)))
    }
    const c = getClothState(a.world, a.cloth)
    for (let k = 0; k < LOOSE.length; k++) for (let j = 0; j < 3; j++) expect(c.pos[3 * (81 + k) + j]).toBe(LOOSE[k][j])
    expect(getClothStats(a.world).guardResets).toBe(0)
    expect(meshFinite(a.world, a.cloth)).toBe(true)
    // their mass is no part of the cloth's
    expect([...c.invMass.subarray(81, 84)]).toEqual([0, 0, 0])
  })

  it('an unpinned mesh with a loose vertex far away falls onto the ground like one without: no guard reset', () => {
    const drop = (loose: number[][]) => {
      const world = installClothPlugin(createWorld())
      const m = meshWithLoose(loose)
      const cloth = createClothFromMesh(world, { positions: m.positions, indices: m.indices })
      const g = addEntity(world)
      setTransform(world, g, [0, 0, 0])
      addPlaneCollider(world, g)
      for (let f = 0; f < 300; f++) stepCloth(world, frame)
      return { world, cloth }
    }
    const a = drop([[30, 40, 0]]), b = drop([])
    expect(getClothStats(a.world).guardResets).toBe(0)
    const ca = getClothState(a.world, a.cloth), cb = getClothState(b.world, b.cloth)
    expect(hashBytes(ca.pos.subarray(0, 3 * 81))).toBe(hashBytes(cb.pos.subarray(0, 3 * 81)))
    expect([ca.pos[243], ca.pos[244], ca.pos[245]]).toEqual([30, 40, 0])
  })

  it('with self-collision, a loose vertex in the cloth’s path is no obstacle; the pieces of a tearable one tear and land without resets', () => {
    const fall = (loose: number[][], tear: boolean) => {
      const world = installClothPlugin(createWorld())
      const m = meshWithLoose(loose)
      const cloth = createClothFromMesh(world, { positions: m.positions, indices: m.indices })
      enableSelfCollision(world, cloth)
      if (tear) {
        makeTearable(world, cloth, { strain: 0.05 })
        const g = addEntity(world)
        setTransform(world, g, [0, 0.5, 0])
        addSphereCollider(world, g, { radius: 0.3 })
      }
      for (let f = 0; f < 120; f++) stepCloth(world, frame)
      return { world, cloth }
    }
    // the loose vertex sits right where the middle of the falling sheet passes
    const a = fall([[0, 1.0, 0]], false), b = fall([], false)
    const ca = getClothState(a.world, a.cloth), cb = getClothState(b.world, b.cloth)
    let worst = 0
    for (let i = 0; i < 81; i++)
      worst = Math.max(
        worst,
        Math.hypot(ca.pos[3 * i] - cb.pos[3 * i], ca.pos[3 * i + 1] - cb.pos[3 * i + 1], ca.pos[3 * i + 2] - cb.pos[3 * i + 2]),
      )
    expect(worst).toBeLessThan(1e-6)
    const t = fall([[0, 1.0, 0], [5, 5, 5]], true)
    expect(getClothStats(t.world).tears).toBeGreaterThan(0)
    expect(getClothStats(t.world).guardResets).toBe(0)
    expect(meshFinite(t.world, t.cloth)).toBe(true)
  })

  it('level of detail measures the cloth, not a loose vertex 1 km away', () => {
    const world = installClothPlugin(createWorld())
    const m = meshWithLoose([[1000, 2, 0]])
    const cloth = createClothFromMesh(world, { positions: m.positions, indices: m.indices })
    pinParticle(world, cloth, 0)
    const viewer = addEntity(world)
    setTransform(world, viewer, [0, 1.5, 3])
    setClothBudget(world, {
      viewer,
      near: 5,
      far: 50,
      adapt: false,
      calibration: { nsPerParticle: 10, nsPerProjection: 2, nsPerColliderTest: 3, nsPerClothSubstep: 100 },
    })
    stepCloth(world, frame)
    expect(getClothLod(world, cloth).distance).toBeLessThan(4)
  })

  it('teleporting rotates about the cloth’s own centre; pinning a loose vertex moves it, unpinning leaves it where it is', () => {
    const a = scene(LOOSE), b = scene([])
    for (const s of [a, b]) teleportCloth(s.world, s.cloth, [1, 0, 0], [0, Math.sin(0.5), 0, Math.cos(0.5)])
    const ca = getClothState(a.world, a.cloth), cb = getClothState(b.world, b.cloth)
    expect(hashBytes(ca.pos.subarray(0, 3 * 81))).toBe(hashBytes(cb.pos.subarray(0, 3 * 81)))
    const hand = addEntity(a.world)
    setTransform(a.world, hand, [0, 1.5, 0.3])
    const pin = pinParticle(a.world, a.cloth, 83, hand)
    setTransform(a.world, hand, [0, 1.0, 0.3])
    for (let f = 0; f < 10; f++) stepCloth(a.world, frame)
    const held = [ca.pos[3 * 83], ca.pos[3 * 83 + 1], ca.pos[3 * 83 + 2]]
    unpin(a.world, pin)
    for (let f = 0; f < 60; f++) stepCloth(a.world, frame)
    expect([ca.pos[3 * 83], ca.pos[3 * 83 + 1], ca.pos[3 * 83 + 2]]).toEqual(held)
    expect(getClothStats(a.world).guardResets).toBe(0)
  })

  it('the cloth’s mass option is shared among the vertices triangles use; a snapshot round trip is exact', () => {
    const world = installClothPlugin(createWorld())
    const m = meshWithLoose(LOOSE)
    const cloth = createClothFromMesh(world, { positions: m.positions, indices: m.indices, mass: 2 })
    const c = getClothState(world, cloth)
    let total = 0
    for (let i = 0; i < 81; i++) total += 1 / c.invMass[i]
    expect(total).toBeCloseTo(2, 9)
    pinParticle(world, cloth, 0)
    for (let f = 0; f < 30; f++) stepCloth(world, frame)
    const saved = saveClothState(world, cloth)
    const run = () => {
      for (let f = 0; f < 60; f++) stepCloth(world, frame)
      return clothHash(world, cloth)
    }
    const first = run()
    restoreClothState(world, cloth, saved)
    expect(run()).toBe(first)
    // per-vertex masses: those of unused vertices are not read (0 is fine, as an exporter may write)
    const masses = m.positions.map((_, i): number => (i < 3 * 81 ? 0.01 : 0)).filter((_, i) => i % 3 === 0)
    const other = createClothFromMesh(world, { positions: m.positions, indices: m.indices, masses })
    expect([...getClothState(world, other).invMass.subarray(80, 84)]).toEqual([100, 0, 0, 0])
    masses[82] = -1
    expect(() => createClothFromMesh(world, { positions: m.positions, indices: m.indices, masses })).toThrow(/masses\[82\]/)
    masses[82] = 0
    masses[5] = 0
    expect(() => createClothFromMesh(world, { positions: m.positions, indices: m.indices, masses })).toThrow(/masses\[5\]/)
  })
})

describe('meshes of several pieces', () => {
  /** Two 6×6 grids side by side in one mesh, 2 m up: the first pinned at its top corners, the second free. */
  function twoPieces(bending: 'line' | 'dihedral', tearable: boolean) {
    const g = gridMesh(6, 0.1)
    const positions = [
      ...g.positions.map((v, i) => (i % 3 === 1 ? v + 2 : v)),
      ...g.positions.map((v, i) => (i % 3 === 0 ? v + 1 : i % 3 === 1 ? v + 2 : v)),
    ]
    const indices = [...g.indices, ...g.indices.map((i) => i + 36)]
    const world = installClothPlugin(createWorld())
    const cloth = createClothFromMesh(world, { positions, indices, bending })
    if (tearable) makeTearable(world, cloth)
    pinParticle(world, cloth, 0)
    pinParticle(world, cloth, 5)
    const ground = addEntity(world)
    setTransform(world, ground, [0, 0, 0])
    addPlaneCollider(world, ground)
    for (let f = 0; f < 300; f++) stepCloth(world, frame)
    return { world, c: getClothState(world, cloth) }
  }

  for (const bending of ['line', 'dihedral'] as const) {
    for (const tearable of [false, true]) {
      it(`a free piece falls onto the ground while the pinned one hangs: judged by its own shape, no guard reset (${bending}${tearable ? ', tearable' : ''})`, () => {
        const { world, c } = twoPieces(bending, tearable)
        expect(getClothStats(world).guardResets).toBe(0)
        let low = Infinity, high = -Infinity
        for (let i = 36; i < 72; i++) {
          low = Math.min(low, c.pos[3 * i + 1])
          high = Math.max(high, c.pos[3 * i + 1])
        }
        expect(low).toBeGreaterThan(-0.01) // on the ground
        expect(high).toBeLessThan(0.6) // fallen from 2 m (it may stand on its edge)
        expect(meshFinite(world, c.eid)).toBe(true)
      })
    }
  }
})

// ---------------------------------------------------------------------------------------------

describe('pin churn', () => {
  /** A cape on a character swaying ±1 m; a pin on `particle` toggled every other frame (world point or the character). */
  function churn(particle: number, target: 'world' | 'character' | null) {
    const world = installClothPlugin(createWorld())
    const { hero, cloths } = heroWithCape(world)
    const cape = cloths[0]
    const c = getClothState(world, cape)
    for (let f = 0; f < 120; f++) stepCloth(world, frame)
    let fastest = 0, highest = -Infinity, pin = -1
    for (let f = 0; f < 300; f++) {
      setTransform(world, hero, [Math.sin(f / 60), 1.6, 0])
      if (target !== null) {
        if (f % 2 === 0) pin = pinParticle(world, cape, particle, target === 'world' ? null : hero)
        else unpin(world, pin)
      }
      stepCloth(world, frame)
      for (let i = 42; i < 48; i++) {
        fastest = Math.max(fastest, Math.hypot(c.vel[3 * i], c.vel[3 * i + 1], c.vel[3 * i + 2]))
        highest = Math.max(highest, c.pos[3 * i + 1])
      }
    }
    expect(getClothStats(world).guardResets).toBe(0)
    return { fastest, highest }
  }

  it('a snapshot taken between a pin change and the next step (tethers still to rebuild) replays byte for byte', () => {
    const world = installClothPlugin(createWorld())
    const { hero, cloths } = heroWithCape(world)
    const cape = cloths[0]
    for (let f = 0; f < 60; f++) {
      setTransform(world, hero, [Math.sin(f / 20), 1.6, 0])
      stepCloth(world, frame)
    }
    pinParticle(world, cape, 21)
    const saved = saveClothState(world, cape)
    const run = () => {
      for (let f = 0; f < 30; f++) {
        setTransform(world, hero, [Math.sin((60 + f) / 20), 1.6, 0])
        stepCloth(world, frame)
      }
      return clothHash(world, cape)
    }
    const first = run()
    restoreClothState(world, cape, saved)
    setTransform(world, hero, [Math.sin(59 / 20), 1.6, 0])
    expect(run()).toBe(first)
  })

  for (const target of ['world', 'character'] as const) {
    for (const particle of [21, 45]) {
      it(`a pin toggled every other frame (particle ${particle}, on the ${target}) pumps no energy into a swaying cape: the hem stays as slow and as low as without it`, () => {
        const calm = churn(0, null), toggled = churn(particle, target)
        // (the toggled pin holds its particle for a frame at a time: some extra motion, not a pump)
        expect(toggled.fastest).toBeLessThan(2 * calm.fastest)
        expect(toggled.highest).toBeLessThan(calm.highest + 0.08)
      })
    }
  }
})
