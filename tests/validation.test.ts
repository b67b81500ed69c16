// Input validation audit: the gaps found in the public API, each now a ClothError naming the
// argument (tests/errors.test.ts has the rest).
import { addEntity, createWorld } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  buildGridTopology,
  buildMeshTopology,
  buildTethers,
  checkClothHealth,
  clothSync,
  createCloth,
  createClothFromMesh,
  dampPairs,
  defineMaterial,
  dihedralAngle,
  getClothComponents,
  getClothState,
  getClothStretch,
  getTransform,
  installClothPlugin,
  measureStretch,
  pinParticle,
  pinRow,
  predictPositions,
  restoreClothState,
  saveClothState,
  setClothQuality,
  setClothSubstep,
  setClothTethers,
  setTransform,
  solveCompression,
  solveDihedrals,
  solveLineBending,
  solveDistances,
  solveDistancesXpbd,
  spreadInverseMasses,
  solveTethers,
  stepCloth,
  teleportCloth,
  updateVelocities,
  writeRenderMesh,
} from '../src/index'
import { createKernelParams } from '../src/kernels/params'
import { makeWorld, rejects } from './helpers'

const sheet = { width: 1, height: 1, resolution: 4 }
const tri = { positions: [0, 0, 0, 1, 0, 0, 0, 1, 0], indices: [0, 1, 2] }

describe('input validation gaps, closed', () => {
  it('plugin options: not an object, a fixed step outside [1e-6, 1] s, gravity beyond 1e9', () => {
    rejects(() => installClothPlugin(createWorld(), null as never), 'options')
    rejects(() => installClothPlugin(createWorld(), 5 as never), 'options')
    rejects(() => installClothPlugin(createWorld(), { fixedTimeStep: 1e-7 }), 'options.fixedTimeStep')
    rejects(() => installClothPlugin(createWorld(), { fixedTimeStep: 2 }), 'options.fixedTimeStep')
    rejects(() => installClothPlugin(createWorld(), { gravity: [0, -1e10, 0] }), 'options.gravity[1]')
    rejects(() => installClothPlugin(createWorld(), { guard: { speed: 0 } }), 'options.guard.speed')
  })

  it('sizes and coordinates beyond 1e9 m (their squares would overflow on the way to NaN)', () => {
    const world = makeWorld()
    rejects(() => createCloth(world, { ...sheet, width: 1e10 }), 'options.width')
    rejects(() => createCloth(world, { ...sheet, position: [0, 0, -2e9] }), 'options.position')
    rejects(() => createClothFromMesh(world, { ...tri, positions: [0, 0, 0, 1e10, 0, 0, 0, 1, 0] }), 'options.positions[3]')
    const cloth = createCloth(world, sheet)
    rejects(() => pinParticle(world, cloth, 0, null, [0, 1e10, 0]), 'offset')
    rejects(() => teleportCloth(world, cloth, [1e10, 0, 0]), 'translation')
    rejects(() => teleportCloth(world, cloth, [1, 0, 0], undefined, [0, 0, 1e12]), 'pivot')
    const e = addEntity(world)
    rejects(() => setTransform(world, e, [0, 0, 1e10]), 'position')
    rejects(() => setTransform(world, e, [0, 0, 0], undefined, [1, 1e7, 1]), 'scale')
  })

  it('particles lighter than 1e-12 kg: an inverse mass near Infinity turns the solve into NaN', () => {
    const world = makeWorld()
    rejects(() => createClothFromMesh(world, { ...tri, masses: [1, 1e-13, 1] }), 'options.masses[1]')
    rejects(() => createClothFromMesh(world, { ...tri, masses: [1, 5e-324, 1] }), 'options.masses[1]')
    rejects(() => createCloth(world, { ...sheet, mass: 1e-300 }), 'options.mass')
    rejects(() => createCloth(world, { ...sheet, material: defineMaterial({ density: 1e-300 }) }), 'options.material.density')
    // too heavy: past 1e300 kg a cloth's own snapshot could not be restored (its inverse masses under 1e-300)
    rejects(() => createCloth(world, { ...sheet, mass: 1e305 }), 'options.mass')
    rejects(() => createCloth(world, { ...sheet, material: defineMaterial({ density: 1e305 }) }), 'options.material.density')
    rejects(
      () => createClothFromMesh(world, { positions: [0, 0, 0, 1, 0, 0, 0, 1, 0], indices: [0, 1, 2], masses: [1, 1e301, 1] }),
      'options.masses[1]',
    )
  })

  it('options bags that are not objects', () => {
    const world = makeWorld()
    const cloth = createCloth(world, sheet)
    rejects(() => setClothQuality(world, cloth, null as never), 'quality')
    rejects(() => setClothTethers(world, cloth, 5 as never), 'tethers')
    rejects(() => setClothTethers(world, cloth, null as never), 'tethers')
    rejects(() => getClothStretch(world, cloth, null as never), 'out')
    rejects(() => pinParticle(world, cloth, 0, null, undefined, null as never), 'options')
    rejects(() => defineMaterial(null as never), 'fields')
    const e = addEntity(world)
    setTransform(world, e, [0, 0, 0])
    rejects(() => getTransform(world, e, 5 as never), 'outPosition')
    rejects(() => getTransform(world, e, undefined, [0, 0] as never), 'outRotation')
  })

  it('a host writing a non-finite or absurd transform into its own stores: caught where transforms enter the step', () => {
    const world = makeWorld()
    const hero = addEntity(world)
    setTransform(world, hero, [0, 1, 0])
    const cloth = createCloth(world, sheet)
    pinParticle(world, cloth, 0, hero)
    getClothComponents(world).Transform.px[hero] = 1e12
    rejects(() => stepCloth(world, 1 / 60), `transform of entity ${hero}`)
    getClothComponents(world).Transform.px[hero] = NaN
    rejects(() => stepCloth(world, 1 / 60), `transform of entity ${hero}`)
    getClothComponents(world).Transform.px[hero] = 0
    stepCloth(world, 1 / 60)
    expect(getClothState(world, cloth).pos.every(Number.isFinite)).toBe(true)
  })

  it('setClothSubstep: a substep index of the current step', () => {
    const world = makeWorld()
    createCloth(world, { ...sheet, substeps: 4 })
    clothSync(world)
    rejects(() => setClothSubstep(world, 1.5), 's')
    rejects(() => setClothSubstep(world, 4), 's')
    setClothSubstep(world, 3)
  })
})

describe('exported kernels and builders check their arguments', () => {
  const n = 4
  const pos = () => Float64Array.from([0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0])
  const w = () => new Float64Array(n).fill(1)
  const p = () => {
    const b = createKernelParams()
    b.fill(1)
    return b
  }
  const ids = (...v: number[]) => Int32Array.from(v)
  const f64 = (...v: number[]) => Float64Array.from(v)

  it('solvers: index ranges, indices, array sizes, finite values, the parameter block', () => {
    // the distance loops take position offsets (index × 3) and inverse masses spread to them
    const w3 = () => new Float64Array(3 * n).fill(1)
    rejects(() => solveDistances(pos(), w3(), ids(0, 27), f64(1), f64(0), p(), 0, 1), 'offsets[1]')
    rejects(() => solveDistances(pos(), w3(), ids(0, 1), f64(1), f64(0), p(), 0, 1), 'offsets[1]') // not a multiple of 3
    rejects(() => solveDistances(pos(), w3(), ids(0, 3), f64(1), f64(0), p(), 0, 2), 'end')
    rejects(() => solveDistances(pos(), f64(1, 0, 0, NaN, 0, 0), ids(0, 3), f64(1), f64(0), p(), 0, 1), 'invMass3[3]')
    rejects(() => solveDistances(pos(), w3(), ids(0, 3), f64(NaN), f64(0), p(), 0, 1), 'rest[0]')
    rejects(() => solveDistances(pos(), w3(), ids(0, 3), f64(1), f64(-1), p(), 0, 1), 'compliance[0]')
    rejects(() => solveDistances(pos(), w3(), ids(0, 3), f64(1), f64(0), new Float64Array(2), 0, 1), 'params')
    rejects(() => solveDistancesXpbd(pos(), w3(), ids(0, 3), f64(1), f64(0), new Float64Array(0), p(), 0, 1), 'lambda')
    rejects(() => spreadInverseMasses(w(), new Float64Array(3 * n - 1), n), 'invMass3')
    rejects(() => solveCompression(pos(), f64(1, 1, -1, 1), ids(0, 1), f64(1), f64(0), null, p(), 0, 1), 'invMass[2]')
    rejects(() => solveDihedrals(pos(), w(), ids(0, 1, 2, 3), f64(0), f64(0), null, 2, p(), 0, 1), 'side')
    rejects(() => solveDihedrals(pos().subarray(0, 9), w(), ids(0, 1, 2, 3), f64(0), f64(0), null, 0, p(), 0, 1), 'pos')
    rejects(() => solveTethers(pos(), w(), ids(0), ids(7), f64(1), 1), 'anchor[0]')
    rejects(() => dampPairs(pos(), pos(), w(), ids(0, 1), 2, p()), 'ids')
    rejects(() => solveLineBending(pos(), w(), ids(0, 1, 9), f64(0), f64(0), null, p(), 0, 1), 'ids[2]')
    rejects(() => solveLineBending(pos(), w(), ids(0, 1, 2), f64(-1), f64(0), null, p(), 0, 1), 'rest[0]')
    solveDistances(pos(), w3(), ids(0, 3), f64(1), f64(0), p(), 0, 1) // and valid calls run
  })

  it('integration, render and measure kernels', () => {
    rejects(() => predictPositions(pos(), pos(), pos(), w(), null, p(), 5), 'invMass')
    rejects(() => predictPositions(pos(), pos(), f64(NaN, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0), w(), null, p(), 4), 'vel[0]')
    rejects(() => updateVelocities(pos(), pos(), pos(), p(), -1), 'count')
    rejects(() => writeRenderMesh(pos(), 4, Uint32Array.from([0, 1, 4]), 1, new Float32Array(12), new Float32Array(12)), 'tris[2]')
    rejects(() => writeRenderMesh(pos(), 4, Uint32Array.from([0, 1, 2]), 1, new Float32Array(3), new Float32Array(12)), 'outPos')
    rejects(() => measureStretch([0, 0, NaN], ids(), f64(), 0), 'pos[2]')
    rejects(() => checkClothHealth(pos(), pos(), w(), 4, new Float64Array(1)), 'guard')
  })

  it('builders', () => {
    rejects(() => buildGridTopology(NaN, 1, 4, 4, 'cotton'), 'width')
    rejects(() => buildGridTopology(1, 1, 1, 4, 'cotton'), 'columns')
    rejects(() => buildGridTopology(1, 1, 4, 4, 'tweed'), 'material')
    rejects(() => buildGridTopology(1, 1, 4, 4, 'cotton', 'quad', { bending: 'springs' as never }), 'options.bending')
    rejects(() => buildMeshTopology([0, 0, 0, 1, 0, 0, 0, 1, Infinity], [0, 1, 2], 'cotton'), 'positions[8]')
    rejects(() => buildMeshTopology(tri.positions, [0, 1, 1], 'cotton'), 'indices[0..2]')
    rejects(() => dihedralAngle(pos(), 0, 1, 2, 9), 'w1')
    rejects(() => buildTethers(pos(), 4, [0, 1], 1, [7], 'euclidean', 2, 0), 'anchors[0]')
    rejects(() => buildTethers(pos(), 4, [0, 1], 1, [0], 'straight' as never, 2, 0), 'mode')
    expect(buildGridTopology(1, 1, 4, 4, 'cotton').particleCount).toBe(16)
    // every bending model createCloth accepts, the builders accept too (one shared check)
    for (const bending of ['line', 'distance', 'dihedral', 'both', 'none'] as const) {
      const t = buildGridTopology(1, 1, 4, 4, 'cotton', 'quad', { bending })
      expect(t.lineCount > 0).toBe(bending === 'line')
      expect(t.hingeCount > 0).toBe(bending === 'dihedral' || bending === 'both')
    }
  })
})

describe('snapshots of cloths past the API coordinate bound', () => {
  // the API takes points within ±1e9 m, but a cloth's extent, its pins and teleports carry it past
  // that: its own snapshot must restore (each threw a ClothError naming state.pos)
  const roundTrip = (world: object, cloth: number) => {
    const snap = saveClothState(world, cloth)
    stepCloth(world, 1 / 60)
    restoreClothState(world, cloth, snap)
    expect(Array.from(getClothState(world, cloth).pos)).toEqual(Array.from(snap.pos))
  }

  it('a sheet made at x = 1e9, a cape hanging below a hero at y = -1e9 + 0.5, a cloth teleported to 1.8e9', () => {
    const world = makeWorld()
    roundTrip(world, createCloth(world, { width: 2, height: 1, resolution: 8, position: [1e9, 0, 0] }))
    const hero = addEntity(world)
    setTransform(world, hero, [0, -1e9 + 0.5, 0])
    const cape = createCloth(world, { width: 0.55, height: 1.05, resolution: [14, 24], position: [0, -1e9 + 0.5, -0.2] })
    pinRow(world, cape, 0, hero)
    for (let f = 0; f < 30; f++) stepCloth(world, 1 / 60)
    expect(getClothState(world, cape).pos[3 * 14 * 23 + 1]).toBeLessThan(-1e9)
    roundTrip(world, cape)
    const far = createCloth(world, { width: 1, height: 1, resolution: 8, position: [9e8, 0, 0] })
    pinRow(world, far, 0)
    teleportCloth(world, far, [9e8, 0, 0])
    stepCloth(world, 1 / 60)
    expect(getClothState(world, far).pos[0]).toBeGreaterThan(1e9)
    roundTrip(world, far)
  })
})
