import { addEntity, createWorld } from 'bitecs'
import { describe, it } from 'vitest'
import {
  ClothSimulation,
  createCloth,
  createClothFromMesh,
  defineMaterial,
  installClothPlugin,
  pinParticle,
  pinRow,
  setClothQuality,
  setTransform,
  stepCloth,
  teleportCloth,
  unpin,
} from '../src/index'
import { makeWorld, rejects } from './helpers'

const sheet = { width: 1, height: 1, resolution: 4 }

describe('bad input is rejected at the API edge with ClothError', () => {
  it('plugin options', () => {
    rejects(() => installClothPlugin(createWorld(), { gravity: [0, NaN, 0] }), 'options.gravity', 'NaN')
    rejects(() => installClothPlugin(createWorld(), { fixedTimeStep: 0 }), 'options.fixedTimeStep', '0')
    rejects(() => installClothPlugin(createWorld(), { fixedTimeStep: -1 / 60 }), 'options.fixedTimeStep')
    rejects(() => installClothPlugin(createWorld(), { maxStepsPerFrame: 0.5 }), 'options.maxStepsPerFrame', '0.5')
    rejects(() => installClothPlugin(createWorld(), { teleportDistance: Infinity }), 'options.teleportDistance', 'Infinity')
  })

  it('dt: NaN, infinite or negative', () => {
    const world = makeWorld()
    rejects(() => stepCloth(world, NaN), 'dt', 'NaN')
    rejects(() => stepCloth(world, Infinity), 'dt', 'Infinity')
    rejects(() => stepCloth(world, -0.01), 'dt', '-0.01')
  })

  it('sheet sizes, resolution, counts and unknown materials', () => {
    const world = makeWorld()
    rejects(() => createCloth(world, { ...sheet, width: 0 }), 'options.width', '0')
    rejects(() => createCloth(world, { ...sheet, height: -2 }), 'options.height', '-2')
    rejects(() => createCloth(world, { ...sheet, width: NaN }), 'options.width', 'NaN')
    rejects(() => createCloth(world, { ...sheet, resolution: 1 }), 'options.resolution', '1')
    rejects(() => createCloth(world, { ...sheet, resolution: 3.5 }), 'options.resolution', '3.5')
    rejects(() => createCloth(world, { ...sheet, resolution: [4, 0] }), 'options.resolution[1]', '0')
    rejects(() => createCloth(world, { ...sheet, iterations: 0 }), 'options.iterations', '0')
    rejects(() => createCloth(world, { ...sheet, substeps: -1 }), 'options.substeps', '-1')
    rejects(() => createCloth(world, { ...sheet, material: 'tweed' }), 'options.material', 'tweed')
    rejects(() => createCloth(world, { ...sheet, position: [0, Infinity, 0] }), 'options.position')
    rejects(() => createCloth(world, { ...sheet, rotation: [0, 0, 0, 0] }), 'options.rotation')
    rejects(() => createCloth(world, { ...sheet, mass: -1 }), 'options.mass', '-1')
    rejects(() => createCloth(world, { ...sheet, topology: 'hex' as never }), 'options.topology', 'hex')
    rejects(() => createCloth(world, { ...sheet, tethers: { slack: -0.1 } }), 'options.tethers.slack', '-0.1')
  })

  it('materials: negative density or compliance, missing fields', () => {
    rejects(() => defineMaterial({ density: -0.2 }), 'material.density', '-0.2')
    rejects(() => defineMaterial({ stretchCompliance: NaN }), 'material.stretchCompliance', 'NaN')
    rejects(() => createCloth(makeWorld(), { ...sheet, material: { name: 'half' } as never }), 'options.material.density')
  })

  it('meshes: NaN positions, bad or repeated indices, negative masses', () => {
    const world = makeWorld()
    const positions = [0, 0, 0, 1, 0, 0, 0, 1, 0]
    rejects(
      () => createClothFromMesh(world, { positions: [0, 0, NaN, 1, 0, 0, 0, 1, 0], indices: [0, 1, 2] }),
      'options.positions[2]',
      'NaN',
    )
    rejects(() => createClothFromMesh(world, { positions: [0, 0, 0, 1], indices: [0, 1, 2] }), 'options.positions')
    rejects(() => createClothFromMesh(world, { positions, indices: [0, 1, 3] }), 'options.indices[2]', '3')
    rejects(() => createClothFromMesh(world, { positions, indices: [0, 1, -1] }), 'options.indices[2]', '-1')
    rejects(() => createClothFromMesh(world, { positions, indices: [0, 1] }), 'options.indices')
    rejects(() => createClothFromMesh(world, { positions, indices: [0, 1, 1] }), 'options.indices[0..2]')
    rejects(() => createClothFromMesh(world, { positions, indices: [0, 1, 2], masses: [1, -1, 1] }), 'options.masses[1]', '-1')
    rejects(() => createClothFromMesh(world, { positions, indices: [0, 1, 2], masses: [1, 1] }), 'options.masses')
  })

  it('pins: indices out of range, missing entities, targets without a transform, NaN offsets', () => {
    const world = makeWorld()
    const cloth = createCloth(world, sheet)
    rejects(() => pinParticle(world, cloth, 16), 'index', '16')
    rejects(() => pinParticle(world, cloth, -1), 'index', '-1')
    rejects(() => pinParticle(world, 999, 0), 'cloth', '999')
    rejects(() => pinParticle(world, cloth, 0, 12345), 'target', '12345')
    const bare = addEntity(world)
    rejects(() => pinParticle(world, cloth, 0, bare), 'target')
    rejects(() => pinParticle(world, cloth, 0, null, [0, NaN, 0]), 'offset')
    rejects(() => pinRow(world, cloth, 4), 'row', '4')
    rejects(() => unpin(world, bare), 'pin')
    const mesh = createClothFromMesh(world, { positions: [0, 0, 0, 1, 0, 0, 0, 1, 0], indices: [0, 1, 2] })
    rejects(() => pinRow(world, mesh, 0), 'cloth')
  })

  it('transforms, quality and teleports', () => {
    const world = makeWorld()
    const e = addEntity(world)
    rejects(() => setTransform(world, e, [0, 0, NaN]), 'position')
    rejects(() => setTransform(world, e, [0, 0, 0], [0, 0, 0, 0]), 'rotation')
    rejects(() => setTransform(world, 4242, [0, 0, 0]), 'eid', '4242')
    const cloth = createCloth(world, sheet)
    rejects(() => setClothQuality(world, cloth, { substeps: 0 }), 'quality.substeps', '0')
    rejects(() => teleportCloth(world, cloth, [NaN, 0, 0]), 'translation')
  })

  it('the facade forwards the same checks', () => {
    rejects(() => new ClothSimulation({ width: 1, height: 1, resolution: 0 }), 'options.resolution', '0')
    const sim = new ClothSimulation(sheet)
    rejects(() => sim.pinParticle(100), 'index', '100')
    rejects(() => sim.step(NaN), 'dt', 'NaN')
  })
})
