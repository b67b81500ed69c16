// Property-based tests (fast-check): random meshes, materials, pins, frame-time sequences,
// colliders (every shape, static and moving), wind zones and API calls. A failure prints the seed
// and the path of the shrunk counterexample; to replay it, pass them back: `it.prop([...], { seed,
// path, endOnFailure: true })`. STABILITY_RUNS=10 runs ten times as many cases (the default, 1,350
// in all, takes a few seconds); STABILITY_SEED picks the seed.
import { fc, it } from '@fast-check/vitest'
import { addEntity, createWorld } from 'bitecs'
import { describe, expect } from 'vitest'
import {
  ClothError,
  addBoxCollider,
  addCapsuleCollider,
  addConvexHullCollider,
  addPlaneCollider,
  addSphereCollider,
  createWindZone,
  enableSelfCollision,
  gustWind,
  makeTearable,
  removeCollider,
  setClothCollision,
  setWindZone,
  createCloth,
  createClothFromMesh,
  defineMaterial,
  getClothMesh,
  getClothState,
  installClothPlugin,
  pinParticle,
  restoreClothState,
  saveClothState,
  setClothGuard,
  setClothInertia,
  setClothMotionConstraints,
  setClothSkinning,
  setClothQuality,
  setClothTethers,
  setTransform,
  stepCloth,
  teleportCloth,
  unpin,
  removeCloth,
  grabParticle,
  moveGrab,
  releaseGrab,
  type BendSide,
  type BendingModel,
  type ClothMaterialSpec,
  type ClothOptions,
  type ShearModel,
} from '../../src/index'
import { hashBytes } from '../helpers'
import { prismPoints, signedDistance, type Shape } from '../collision/scenes'
import { glMatrix } from 'gl-matrix'

glMatrix.setMatrixArrayType(Array) // (signedDistance works in doubles)

const scale = Math.max(1, Number(process.env.STABILITY_RUNS ?? 1))
// A fixed seed by default, so CI runs the same 1,350 cases every time (a test that draws new cases
// on every run fails at random); STABILITY_SEED=<n> explores others, and a failure prints its seed.
const seed = process.env.STABILITY_SEED === undefined ? 20261121 : Number(process.env.STABILITY_SEED)
const runs = (n: number) => ({ numRuns: n * scale, seed })

// ---------------------------------------------------------------------------------------------
// Arbitraries

/** 10^x for x in [lo, hi], or exactly 0 now and then. */
const logOrZero = (lo: number, hi: number) =>
  fc.oneof({ arbitrary: fc.constant(0), weight: 1 }, {
    arbitrary: fc.double({ min: lo, max: hi, noNaN: true }).map((x) => 10 ** x),
    weight: 4,
  })

const materialArb: fc.Arbitrary<ClothMaterialSpec> = fc
  .record({
    density: fc.double({ min: -2, max: 1, noNaN: true }).map((x) => 10 ** x),
    stretchCompliance: logOrZero(-9, 307),
    shearCompliance: logOrZero(-9, 307),
    bendCompliance: logOrZero(-3, 307),
    damping: fc.oneof(fc.constant(0), fc.double({ min: 0, max: 50, noNaN: true })),
    stretchDamping: fc.oneof(fc.constant(0), fc.double({ min: 0, max: 200, noNaN: true })),
  })
  .map((m) => defineMaterial({ name: 'random', ...m }))

const solverArb = fc.record({
  material: materialArb,
  bending: fc.constantFrom<BendingModel>('line', 'distance', 'dihedral', 'both', 'none'),
  shear: fc.constantFrom<ShearModel>('distance', 'compression', 'none'),
  bendSide: fc.constantFrom<BendSide>('both', 'front', 'back'),
  solver: fc.constantFrom<'xpbd' | 'pbd'>('xpbd', 'pbd'),
  iterations: fc.integer({ min: 1, max: 4 }),
  substeps: fc.integer({ min: 1, max: 8 }),
  tethers: fc.boolean(),
})

/** A grid sheet, or a random triangle soup (coincident points, slivers, non-manifold edges and all). */
const meshArb = fc.oneof(
  fc.record({
    kind: fc.constant('grid' as const),
    width: fc.double({ min: 0.05, max: 5, noNaN: true }),
    height: fc.double({ min: 0.05, max: 5, noNaN: true }),
    columns: fc.integer({ min: 2, max: 6 }),
    rows: fc.integer({ min: 2, max: 6 }),
    topology: fc.constantFrom<'quad' | 'triangle'>('quad', 'triangle'),
  }),
  fc.integer({ min: 3, max: 14 }).chain((n) =>
    fc.record({
      kind: fc.constant('soup' as const),
      // points on a coarse lattice so coincident and collinear ones are common
      positions: fc.array(fc.integer({ min: -4, max: 4 }).map((k) => k * 0.125), { minLength: 3 * n, maxLength: 3 * n }),
      indices: fc
        .array(
          fc.tuple(fc.nat(n - 1), fc.nat(n - 1), fc.nat(n - 1)).filter(([a, b, c]) => a !== b && b !== c && a !== c),
          { minLength: 1, maxLength: 2 * n },
        )
        .map((ts) => ts.flat()),
    })
  ),
)

/** Frame times: stalls, normal and uneven frames, hitches. */
const dtsArb = fc.array(fc.oneof(fc.constant(0), fc.double({ min: 0, max: 0.1, noNaN: true }), fc.constant(1 / 60), fc.constant(10)), {
  minLength: 1,
  maxLength: 12,
})

/** A collider: shape, pose near where the random cloths hang, and a motion (none for about half). */
const colliderArb = fc.record({
  shape: fc.oneof(
    fc.record({ kind: fc.constant('sphere' as const), radius: fc.double({ min: 0.05, max: 0.5, noNaN: true }) }),
    fc.record({
      kind: fc.constant('capsule' as const),
      radius: fc.double({ min: 0.05, max: 0.3, noNaN: true }),
      halfHeight: fc.double({ min: 0, max: 0.4, noNaN: true }),
    }),
    fc.record({
      kind: fc.constant('box' as const),
      halfExtents: fc.tuple(...[0, 1, 2].map(() => fc.double({ min: 0.05, max: 0.4, noNaN: true }))) as fc.Arbitrary<
        [number, number, number]
      >,
    }),
    fc.record({
      kind: fc.constant('prism' as const),
      radius: fc.double({ min: 0.1, max: 0.4, noNaN: true }),
      halfHeight: fc.double({ min: 0.05, max: 0.3, noNaN: true }),
      sides: fc.integer({ min: 3, max: 8 }),
    }),
    fc.record({ kind: fc.constant('plane' as const) }),
  ),
  position: fc.tuple(
    fc.double({ min: -1, max: 1, noNaN: true }),
    fc.double({ min: 0.3, max: 2.5, noNaN: true }),
    fc.double({ min: -0.5, max: 0.5, noNaN: true }),
  ),
  rotation: fc.tuple(...[0, 1, 2, 3].map(() => fc.double({ min: -1, max: 1, noNaN: true }))).filter((q) => Math.hypot(...q) > 0.1),
  /** Velocity, m/s (0: static). */
  velocity: fc.oneof(fc.constant([0, 0, 0]), fc.tuple(...[0, 1, 2].map(() => fc.double({ min: -5, max: 5, noNaN: true })))),
})
type ColliderSpec = { shape: Shape; position: number[]; rotation: number[]; velocity: number[] }

/** No wind, a global zone, or a box zone around where the cloths hang. */
const windArb = fc.oneof(
  fc.constant(null),
  fc.record({
    shape: fc.constantFrom<'global' | 'box'>('global', 'box'),
    direction: fc.tuple(...[0, 1, 2].map(() => fc.double({ min: -1, max: 1, noNaN: true }))).filter((d) => Math.hypot(...d) > 0.1),
    strength: fc.oneof(fc.double({ min: 0, max: 40, noNaN: true }), fc.constant(1000)),
    turbulence: fc.double({ min: 0, max: 0.6, noNaN: true }),
  }),
)

function addCollider(world: object, spec: ColliderSpec, thickness = 0): number {
  const e = addEntity(world)
  setTransform(world, e, spec.position, spec.rotation)
  const sh = spec.shape
  if (sh.kind === 'sphere') addSphereCollider(world, e, { radius: sh.radius })
  else if (sh.kind === 'capsule') addCapsuleCollider(world, e, { radius: sh.radius, halfHeight: sh.halfHeight })
  else if (sh.kind === 'box') addBoxCollider(world, e, { halfExtents: sh.halfExtents })
  else if (sh.kind === 'prism') addConvexHullCollider(world, e, { points: prismPoints(sh.radius, sh.halfHeight, sh.sides) })
  else addPlaneCollider(world, e)
  void thickness
  return e
}

/** Moves the moving colliders to where they are at time t. */
function moveColliders(world: object, specs: ColliderSpec[], ids: number[], t: number): void {
  for (let k = 0; k < specs.length; k++) {
    const v = specs[k].velocity
    if (v[0] === 0 && v[1] === 0 && v[2] === 0) continue
    const u = Math.min(t, 2) // they stop after 2 s (so a 10 s frame is no teleport to infinity)
    setTransform(
      world,
      ids[k],
      [specs[k].position[0] + v[0] * u, specs[k].position[1] + v[1] * u, specs[k].position[2] + v[2] * u],
      specs[k].rotation,
    )
  }
}

type MeshSpec =
  | { kind: 'grid'; width: number; height: number; columns: number; rows: number; topology: 'quad' | 'triangle' }
  | { kind: 'soup'; positions: number[]; indices: number[] }

function buildCloth(world: object, mesh: MeshSpec, solver: ClothOptions): number {
  if (mesh.kind === 'grid') {
    return createCloth(world, {
      width: mesh.width,
      height: mesh.height,
      resolution: [mesh.columns, mesh.rows],
      topology: mesh.topology,
      position: [0, 2, 0],
      ...solver,
    })
  }
  return createClothFromMesh(world, { positions: mesh.positions, indices: mesh.indices, ...solver })
}

function allFinite(a: ArrayLike<number>, n = a.length): boolean {
  for (let i = 0; i < n; i++) if (!Number.isFinite(a[i])) return false
  return true
}

function kineticEnergy(c: { vel: Float64Array; invMass: Float64Array; count: number }): number {
  let e = 0
  for (let i = 0; i < c.count; i++) {
    if (c.invMass[i] === 0) continue
    e += (0.5 / c.invMass[i]) * (c.vel[3 * i] ** 2 + c.vel[3 * i + 1] ** 2 + c.vel[3 * i + 2] ** 2)
  }
  return e
}

// ---------------------------------------------------------------------------------------------

/** A random cloth pinned by particle 0, with colliders, a box wind zone and self-collision as given. */
function featureScene(
  mesh: MeshSpec,
  solver: ClothOptions,
  specs: ColliderSpec[],
  wind: Parameters<typeof createWindZone>[1] | null,
  self: boolean,
) {
  const world = installClothPlugin(createWorld())
  const cloth = buildCloth(world, mesh, solver)
  pinParticle(world, cloth, 0)
  const ids = specs.map((spec) => addCollider(world, spec))
  if (wind) createWindZone(world, { ...wind, position: [0, 1.5, 0], size: [2, 2, 2] })
  if (self) enableSelfCollision(world, cloth)
  return { world, cloth, specs, ids }
}

/**
 * No energy from nowhere: kinetic energy (started at the rest shape, so there is no stored energy)
 * never rises more than 2 % above its start in any step, and at the end it is no higher than at the
 * start (a part in 1e6). Gauss-Seidel sweeps over nonlinear constraints are not an exact solve, and
 * in rare configurations a step gains a little (seen: up to 0.8 %, then it falls away); a runaway
 * gains far more, and keeps gaining.
 */
function expectNoEnergyFromNowhere(e: number, e0: number, last: boolean): void {
  expect(e).toBeLessThanOrEqual(e0 * 1.02 + 1e-15)
  if (last) expect(e).toBeLessThanOrEqual(e0 * (1 + 1e-6) + 1e-15)
}

describe('properties', () => {
  it.prop([
    meshArb,
    solverArb,
    fc.array(fc.nat(), { maxLength: 4 }),
    fc.boolean(),
    dtsArb,
    fc.array(colliderArb, { maxLength: 3 }),
    windArb,
  ], runs(300))(
    'any valid mesh, material, pins, frame times, colliders (static and moving) and wind: positions, velocities and the mesh stay finite; pins hold their particles exactly',
    (mesh, solver, pinSeeds, moving, dts, colliders, wind) => {
      // the guard is off: this is about the solver itself
      const world = installClothPlugin(createWorld(), { guard: false })
      const cloth = buildCloth(world, mesh as MeshSpec, solver)
      const c = getClothState(world, cloth)
      const specs = colliders as ColliderSpec[]
      const ids = specs.map((spec) => addCollider(world, spec))
      if (wind) createWindZone(world, { ...wind, position: [0, 1.5, 0], size: [2, 2, 2] })
      const target = addEntity(world)
      setTransform(world, target, [0, 2, 0])
      const pinned: [number, number, number[]][] = [] // particle, target (0: world), offset
      for (const s of pinSeeds) {
        const i = s % c.count
        if (s % 2 === 0) {
          const offset = [c.pos[3 * i], c.pos[3 * i + 1] + 0.1, c.pos[3 * i + 2]]
          pinParticle(world, cloth, i, null, offset, { blendTime: 0 })
          pinned.push([i, 0, offset])
        } else {
          pinParticle(world, cloth, i, target, [0.1 * (i % 3), -0.05, 0], { blendTime: 0 })
          pinned.push([i, target, [0.1 * (i % 3), -0.05, 0]])
        }
      }
      let t = 0
      for (const dt of dts) {
        t += dt
        const p = moving ? [Math.min(t, 3), 2 + 0.1 * Math.min(t, 3), 0] : [0, 2, 0]
        setTransform(world, target, p)
        moveColliders(world, specs, ids, t)
        stepCloth(world, dt)
        expect(allFinite(c.pos, 3 * c.count) && allFinite(c.vel, 3 * c.count)).toBe(true)
        const m = getClothMesh(world, cloth)
        expect(allFinite(m.positions) && allFinite(m.normals)).toBe(true)
        // pinned particles sit exactly on their pins: world pins always, pins on the target while
        // it stands still (a moving target is interpolated within the frame); where several pins
        // hold one particle the last one wins, so those are skipped
        if (dt < 1 / 60) continue
        for (const [i, tgt, o] of pinned) {
          if (pinned.filter(([j]) => j === i).length !== 1 || (tgt !== 0 && moving)) continue
          const want = tgt === 0 ? o : [p[0] + o[0], p[1] + o[1], p[2] + o[2]]
          for (let k = 0; k < 3; k++) expect(Math.abs(c.pos[3 * i + k] - want[k])).toBeLessThanOrEqual(1e-12 * (1 + Math.abs(want[k])))
        }
      }
    },
  )

  it.prop([
    meshArb,
    solverArb,
    fc.array(fc.nat(), { maxLength: 3 }),
    fc.boolean(),
    dtsArb,
    fc.array(colliderArb, { minLength: 1, maxLength: 3 }),
    windArb,
  ], runs(200))(
    'no particle ends a step inside a static collider: every free particle is at least the thickness out of each static collider that no other collider comes near',
    (mesh, solver, pinSeeds, moving, dts, colliders, wind) => {
      const world = installClothPlugin(createWorld(), { guard: false })
      const cloth = buildCloth(world, mesh as MeshSpec, solver)
      const c = getClothState(world, cloth)
      const thickness = c.material.thickness
      const specs = colliders as ColliderSpec[]
      const ids = specs.map((spec) => addCollider(world, spec))
      if (wind) createWindZone(world, { ...wind, position: [0, 1.5, 0], size: [2, 2, 2] })
      const target = addEntity(world)
      setTransform(world, target, [0, 2, 0])
      for (const seed of pinSeeds) pinParticle(world, cloth, seed % c.count, seed % 2 ? target : null)
      // colliders pushed against each other would over-constrain the particles between them: the
      // check covers the static colliders no other collider comes within 4 thicknesses of (bounding
      // spheres over their whole motion; a plane counts as near anything that reaches it)
      const reach = (k: number) => boundingRadius(specs[k].shape)
      const isolated = specs.map((a, k) => {
        if (a.velocity.some((v) => v !== 0)) return false
        return specs.every((b, j) => {
          if (j === k) return true
          const path = Math.hypot(...b.velocity) * 2 // they move for at most 2 s
          if (a.shape.kind === 'plane' || b.shape.kind === 'plane') {
            if (a.shape.kind === 'plane' && b.shape.kind === 'plane') return false
            const [plane, other, r] = a.shape.kind === 'plane' ? [a, b, reach(j) + path] : [b, a, reach(k)]
            return other.position[1] - plane.position[1] > r + 4 * thickness
          }
          return Math.hypot(...a.position.map((x, i) => x - b.position[i])) > reach(k) + reach(j) + path + 4 * thickness
        })
      })
      let t = 0
      for (const dt of dts) {
        t += dt
        setTransform(world, target, moving ? [Math.min(t, 3), 2, 0] : [0, 2, 0])
        moveColliders(world, specs, ids, t)
        if (stepCloth(world, dt) === 0) continue // (no step ran: nothing has been pushed out yet)
        for (let k = 0; k < specs.length; k++) {
          if (!isolated[k]) continue
          for (let i = 0; i < c.count; i++) {
            if (c.invMass[i] === 0) continue
            const d = signedDistance(world, ids[k], specs[k].shape, c.pos[3 * i], c.pos[3 * i + 1], c.pos[3 * i + 2])
            expect(d, `particle ${i} against collider ${k} (${specs[k].shape.kind}) after a frame of ${dt} s`).toBeGreaterThanOrEqual(
              thickness - 1e-6,
            )
          }
        }
      }
    },
  )

  it.prop(
    [
      meshArb,
      solverArb.map((s) => ({ ...s, bending: s.bending === 'dihedral' || s.bending === 'both' ? ('distance' as const) : s.bending })),
      fc.integer({ min: 1, max: 1 << 30 }),
      fc.integer({ min: 5, max: 40 }),
    ],
    runs(250),
  )(
    'no energy from nowhere: a free cloth without gravity or air drag (distance constraints, any material, moving under half an edge per substep) ends with no more kinetic energy than it started with, never 2 % more in a step, and keeps its momentum',
    (mesh, solver, seed, frames) => {
      const material = defineMaterial({ ...solver.material, damping: 0 })
      const world = installClothPlugin(createWorld(), { gravity: [0, 0, 0], guard: false })
      const cloth = buildCloth(world, mesh as MeshSpec, { ...solver, material })
      const c = getClothState(world, cloth)
      // random velocities at the rest shape (no stored energy): up to 2 m/s per axis, and at most
      // half the shortest (non-zero) structural edge per substep. Faster than that, an edge can be
      // compressed past itself within one substep, and projecting it back out to its length
      // amplifies the sideways motion (Known limits: up to 17 % more kinetic energy in one step)
      const t = c.topology
      let edge = Infinity
      for (let k = 0; k < t.stretchCount; k++) if (t.stretchRest[k] > 0) edge = Math.min(edge, t.stretchRest[k])
      const amplitude = Math.min(2, (0.5 * edge * 60 * c.substeps) / Math.sqrt(3))
      let r = seed
      for (let i = 0; i < 3 * c.count; i++) {
        r = (Math.imul(r, 1103515245) + 12345) >>> 0
        c.vel[i] = ((r / 2 ** 32) - 0.5) * 2 * amplitude
      }
      const e0 = kineticEnergy(c)
      const p0 = momentum(c)
      for (let f = 0; f < frames; f++) {
        stepCloth(world, 1 / 60)
        expectNoEnergyFromNowhere(kineticEnergy(c), e0, f === frames - 1)
      }
      const p1 = momentum(c)
      const scaleP = Math.max(1e-12, Math.hypot(...p0), Math.sqrt(2 * e0 * totalMass(c)))
      for (let k = 0; k < 3; k++) expect(Math.abs(p1[k] - p0[k])).toBeLessThanOrEqual(1e-9 * scaleP)
    },
  )

  it.prop(
    [
      fc.record({
        columns: fc.integer({ min: 2, max: 6 }),
        rows: fc.integer({ min: 2, max: 6 }),
        width: fc.double({ min: 0.2, max: 5, noNaN: true }),
        height: fc.double({ min: 0.2, max: 5, noNaN: true }),
        density: fc.double({ min: -1.3, max: 0, noNaN: true }).map((x) => 10 ** x),
        stretchCompliance: fc.double({ min: -9, max: -2, noNaN: true }).map((x) => 10 ** x),
        shearCompliance: fc.double({ min: -9, max: 1, noNaN: true }).map((x) => 10 ** x),
        bendCompliance: fc.double({ min: 2, max: 8, noNaN: true }).map((x) => 10 ** x),
        stretchDamping: fc.oneof(fc.constant(0), fc.double({ min: 0, max: 200, noNaN: true })),
        iterations: fc.integer({ min: 1, max: 4 }),
        substeps: fc.integer({ min: 1, max: 8 }),
        bending: fc.constantFrom<BendingModel>('dihedral', 'both'),
        topology: fc.constantFrom<'quad' | 'triangle'>('quad', 'triangle'),
      }).filter((p) => {
        const aspect = p.width / (p.columns - 1) / (p.height / (p.rows - 1))
        // hinge stiffness relative to the particle masses is what matters: compliance × density
        return aspect <= 3 && aspect >= 1 / 3 && p.bendCompliance * p.density >= 300
      }),
      fc.integer({ min: 1, max: 1 << 30 }),
    ],
    runs(150),
  )(
    'no energy from nowhere with dihedral bending, within the documented range (bend compliance × density ≥ 300, stretch ≤ 0.01, elements ≤ 3:1)',
    (p, seed) => {
      const material = defineMaterial({
        name: 'random',
        density: p.density,
        stretchCompliance: p.stretchCompliance,
        shearCompliance: p.shearCompliance,
        bendCompliance: p.bendCompliance,
        damping: 0,
        stretchDamping: p.stretchDamping,
      })
      const world = installClothPlugin(createWorld(), { gravity: [0, 0, 0], guard: false })
      const cloth = createCloth(world, {
        width: p.width,
        height: p.height,
        resolution: [p.columns, p.rows],
        material,
        bending: p.bending,
        topology: p.topology,
        iterations: p.iterations,
        substeps: p.substeps,
      })
      const c = getClothState(world, cloth)
      let r = seed
      for (let i = 0; i < 3 * c.count; i++) {
        r = (Math.imul(r, 1103515245) + 12345) >>> 0
        c.vel[i] = (r / 2 ** 32 - 0.5) * 4
      }
      const e0 = kineticEnergy(c)
      for (let f = 0; f < 40; f++) {
        stepCloth(world, 1 / 60)
        expectNoEnergyFromNowhere(kineticEnergy(c), e0, f === 39)
      }
    },
  )

  it.prop([
    fc.array(
      fc.record({
        op: fc.nat(26),
        a: fc.anything({ withBigInt: false }),
        b: fc.oneof(fc.double(), fc.integer(), fc.constantFrom(NaN, Infinity, -Infinity, -1, 0, 1e308)),
        c: fc.nat(200),
      }),
      { minLength: 1, maxLength: 16 },
    ),
  ], runs(250))(
    'any sequence of API calls with garbage arguments (colliders, wind zones, tearing, self-collision, grabs and character cloth included): every error is a ClothError, and the world stays finite',
    (ops) => {
      const world = installClothPlugin(createWorld(), { guard: false })
      const hero = addEntity(world)
      setTransform(world, hero, [0, 1.6, 0])
      const cloths = [createCloth(world, { width: 1, height: 1, resolution: 4 })]
      const pins: number[] = []
      const zones: number[] = []
      const grabs: number[] = []
      for (const { op, a, b, c } of ops) {
        const cloth = cloths[c % cloths.length] ?? c
        const v = (x: unknown) => [x, b, 0] as unknown as number[]
        try {
          switch (op) {
            case 0:
              stepCloth(world, b)
              break
            case 1:
              pins.push(pinParticle(world, cloth, c % 20, c % 3 === 0 ? hero : null, c % 2 ? v(a) : undefined, { blendTime: b }))
              break
            case 2:
              unpin(world, pins.length > 0 && c % 2 ? pins.splice(c % pins.length, 1)[0] : (a as number))
              break
            case 3:
              setTransform(world, c % 2 ? hero : (a as number), v(b), c % 3 ? [0, b, 0, 1] : undefined)
              break
            case 4:
              teleportCloth(world, cloth, v(a), c % 2 ? [a, b, 0, 1] as number[] : undefined)
              break
            case 5:
              setClothQuality(world, cloth, { substeps: b, iterations: c % 2 ? (a as number) : undefined })
              break
            case 6:
              setClothTethers(world, cloth, a as boolean)
              break
            case 7:
              setClothGuard(world, cloth, a as boolean)
              break
            case 8:
              cloths.push(createCloth(world, { width: b, height: 1, resolution: (c % 6) as number, material: a as string }))
              break
            case 9:
              cloths.push(
                createClothFromMesh(world, {
                  positions: [0, 0, 0, 1, 0, 0, 0, b, 0],
                  indices: [0, 1, c % 4],
                  masses: c % 2 ? [1, b, 1] : undefined,
                }),
              )
              break
            case 10:
              restoreClothState(world, cloth, saveClothState(world, cloths[0]))
              break
            case 11:
              removeCloth(world, c % 2 ? cloth : (a as number))
              break
            // colliders, wind, tearing, self-collision
            case 12:
              addSphereCollider(world, c % 2 ? addEntity(world) : (a as number), {
                radius: b,
                body: c % 3 ? hero : undefined,
                offset: c % 5 ? v(a) : undefined,
              })
              break
            case 13:
              addCapsuleCollider(world, addEntity(world), {
                radius: c / 100,
                halfHeight: b,
                body: hero,
                axis: c % 2 ? v(a) : undefined,
                rotation: c % 3 ? [a, b, 0, 1] as number[] : undefined,
              })
              break
            case 14:
              addBoxCollider(world, addEntity(world), {
                halfExtents: v(b),
                body: hero,
                friction: c % 2 ? b : undefined,
                layer: c % 3 ? (a as number) : undefined,
              })
              break
            case 15:
              addConvexHullCollider(world, addEntity(world), {
                points: c % 2 ? (a as number[]) : [0, 0, 0, 1, 0, 0, 0, b, 0, 0, 0, 1],
                body: hero,
              })
              break
            case 16:
              addPlaneCollider(world, addEntity(world), { normal: c % 2 ? v(a) : undefined, distance: b, body: hero })
              break
            case 17:
              removeCollider(world, c % 2 ? (a as number) : c)
              break
            case 18:
              zones.push(
                createWindZone(world, {
                  direction: c % 2 ? v(a) : [1, 0, 0],
                  strength: b,
                  turbulence: c % 3 ? (a as number) : 0.2,
                  shape: (['global', 'box', 'sphere', a] as never[])[c % 4],
                  size: c % 5 ? b : undefined,
                }),
              )
              break
            case 19:
              if (c % 2) setWindZone(world, zones[c % Math.max(1, zones.length)] ?? (a as number), { strength: b })
              else gustWind(world, zones[c % Math.max(1, zones.length)] ?? (a as number), { strength: b, duration: a as number })
              break
            case 20:
              makeTearable(world, cloth, {
                strain: c % 2 ? b : 0.01,
                maxTearsPerStep: c % 3 ? (a as number) : undefined,
                capacity: c % 5 ? undefined : c,
                minPiece: c % 7 ? undefined : (a as number),
              })
              break
            case 21:
              grabs.push(
                grabParticle(world, cloth, c % 20, c % 2 ? v(a) : [b, 1, 0], {
                  maxForce: c % 3 ? undefined : b,
                  compliance: c % 5 ? undefined : (a as number),
                }),
              )
              break
            case 22:
              if (c % 2) moveGrab(world, grabs[c % Math.max(1, grabs.length)] ?? (a as number), c % 3 ? v(b) : v(a))
              else releaseGrab(world, grabs[c % Math.max(1, grabs.length)] ?? (a as number))
              break
            case 23:
              if (c % 2) enableSelfCollision(world, cloth, { thickness: c % 3 ? b : undefined })
              else setClothCollision(world, cloth, { layer: a as number, thickness: b })
              break
            // character cloth
            case 24:
              setClothInertia(
                world,
                cloth,
                c % 4 === 0 ? null : {
                  frame: c % 3 ? hero : (a as number),
                  linear: c % 2 ? b : 0.5,
                  angular: c % 5 ? 0.5 : b,
                  centrifugal: 0.5,
                  teleport: c % 5 ? undefined : { mode: (['keep', 'reset', a] as never[])[c % 3], angle: c % 2 ? b : 1.5 },
                },
              )
              break
            case 25:
              setClothMotionConstraints(
                world,
                cloth,
                c % 4 === 0 ? null : {
                  maxDistance: c % 2 ? Math.abs(b) : (a as number),
                  backstop: c % 3 ? { distance: 0.02, radius: c % 5 ? 0.4 : b } : undefined,
                  drive: c % 5 ? undefined : c % 2 ? 0.3 : b,
                  every: c % 7 ? (c % 4) + 1 : (a as number),
                },
              )
              break
            default: {
              const n = (() => {
                try {
                  return getClothState(world, cloth).count
                } catch {
                  return 4
                }
              })()
              setClothSkinning(
                world,
                cloth,
                c % 3 === 0 ? null : {
                  bones: c % 2 ? [hero, c % 5 ? hero : (a as number)] : (a as number[]),
                  joints: Array.from({ length: 4 * n }, (_, k) => (k % 4 === 1 && c % 4 ? 1 : 0)),
                  weights: Array.from(
                    { length: 4 * n },
                    (_, k) => (k % 4 === 0 ? 1 - (c % 3) / 4 : k % 4 === 1 ? (c % 3) / 4 : c % 11 ? 0 : b),
                  ),
                },
              )
            }
          }
        } catch (e) {
          expect(e).toBeInstanceOf(ClothError)
        }
        stepCloth(world, 1 / 60)
      }
      for (const cl of cloths) {
        try {
          const s = getClothState(world, cl)
          expect(allFinite(s.pos, 3 * s.count)).toBe(true)
        } catch (e) {
          expect(e).toBeInstanceOf(ClothError) // removed
        }
      }
    },
  )

  it.prop([meshArb, solverArb, dtsArb, fc.array(colliderArb, { maxLength: 2 }), windArb, fc.boolean()], runs(100))(
    'the same random scene (colliders, wind, self-collision) built and stepped twice gives the same bytes',
    (mesh, solver, dts, colliders, wind, self) => {
      const run = () => {
        const { world, cloth, specs, ids } = featureScene(mesh as MeshSpec, solver, colliders as ColliderSpec[], wind, self)
        let t = 0
        for (const dt of dts) {
          moveColliders(world, specs, ids, t += dt)
          stepCloth(world, dt)
        }
        for (let f = 0; f < 5; f++) stepCloth(world, 1 / 60)
        return hashBytes(getClothState(world, cloth).pos)
      }
      expect(run()).toBe(run())
    },
  )

  it.prop([meshArb, solverArb, dtsArb, dtsArb, fc.array(colliderArb, { maxLength: 2 }), windArb, fc.boolean()], runs(100))(
    'save, step, restore, step again (colliders moving, wind, self-collision): the same bytes',
    (mesh, solver, before, after, colliders, wind, self) => {
      const { world, cloth, specs, ids } = featureScene(mesh as MeshSpec, solver, colliders as ColliderSpec[], wind, self)
      let t = 0
      for (const dt of before) {
        moveColliders(world, specs, ids, t += dt)
        stepCloth(world, dt)
      }
      const snap = saveClothState(world, cloth)
      const c = getClothState(world, cloth)
      const t0 = t
      const trail = () => {
        t = t0
        return after.map((dt) => {
          moveColliders(world, specs, ids, t += dt)
          stepCloth(world, dt)
          return hashBytes(c.pos) + hashBytes(c.vel)
        })
      }
      const first = trail()
      moveColliders(world, specs, ids, t0) // the host puts its Transforms back too
      restoreClothState(world, cloth, snap)
      expect(trail()).toEqual(first)
    },
  )
})

/** Radius of a bounding sphere of the shape about the collider's position (planes: 0, handled apart). */
function boundingRadius(sh: Shape): number {
  if (sh.kind === 'sphere') return sh.radius
  if (sh.kind === 'capsule') return sh.radius + sh.halfHeight
  if (sh.kind === 'box') return Math.hypot(...sh.halfExtents)
  if (sh.kind === 'prism') return Math.hypot(sh.radius, sh.halfHeight)
  return 0
}

function momentum(c: { vel: Float64Array; invMass: Float64Array; count: number }): number[] {
  const p = [0, 0, 0]
  for (let i = 0; i < c.count; i++) {
    if (c.invMass[i] === 0) continue
    for (let k = 0; k < 3; k++) p[k] += c.vel[3 * i + k] / c.invMass[i]
  }
  return p
}

function totalMass(c: { invMass: Float64Array; count: number }): number {
  let m = 0
  for (let i = 0; i < c.count; i++) if (c.invMass[i] > 0) m += 1 / c.invMass[i]
  return m
}
