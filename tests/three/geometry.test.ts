import { addEntity } from 'bitecs'
import { BufferAttribute, BufferGeometry, DoubleSide, MeshBasicMaterial, MeshStandardMaterial, Vector3 } from 'three'
import { describe, expect, it } from 'vitest'
import {
  ClothError,
  createCloth,
  createClothFromMesh,
  getClothLod,
  getClothMesh,
  getClothState,
  getClothTearCount,
  grabParticle,
  isClothSleeping,
  makeTearable,
  moveGrab,
  pinParticle,
  pinRow,
  removeCloth,
  setClothBudget,
  setClothVisible,
  setTransform,
  stepCloth,
} from '../../src/index'
import { createClothGeometry, createClothMesh, updateClothDrawMatrix, updateClothGeometry } from '../../src/three/index'
import { tornCapeOnGround } from '../character/scenes'
import { pinSidesToBars } from '../fixtures/bars'
import { makeWorld } from '../helpers'

type Geometry = ReturnType<typeof createClothGeometry>

/** The index a renderer draws: the draw range of the geometry's index. */
function drawnIndex(geometry: Geometry): number[] {
  return Array.from((geometry.getIndex()!.array as Uint32Array).subarray(0, geometry.drawRange.count))
}

/** Asserts that the geometry shows exactly the cloth's mesh (positions, normals, uvs, index, range, bounds). */
function expectFollows(world: object, cloth: number, geometry: Geometry) {
  const mesh = getClothMesh(world, cloth)
  const n = mesh.vertexCount
  const pos = geometry.getAttribute('position').array as Float32Array
  const nrm = geometry.getAttribute('normal').array as Float32Array
  const uv = geometry.getAttribute('uv').array as Float32Array
  const index = geometry.getIndex()!.array as Uint32Array
  expect(geometry.getAttribute('position').count).toBeGreaterThanOrEqual(n)
  expect(Array.from(pos.subarray(0, 3 * n))).toEqual(Array.from(mesh.positions))
  expect(Array.from(nrm.subarray(0, 3 * n))).toEqual(Array.from(mesh.normals))
  expect(Array.from(uv.subarray(0, 2 * n))).toEqual(Array.from(mesh.uvs))
  expect(geometry.drawRange.start).toBe(0)
  expect(geometry.drawRange.count).toBe(3 * mesh.triangleCount)
  expect(Array.from(index.subarray(0, 3 * mesh.triangleCount))).toEqual(Array.from(mesh.indices))
  // bounds: exactly the drawn vertices' box (not those no triangle uses), and a sphere holding every one of them
  const unused = getClothState(world, cloth).topology.unused
  const drawn = (i: number) => unused === null || unused[i] !== 1
  const min = [Infinity, Infinity, Infinity], max = [-Infinity, -Infinity, -Infinity]
  for (let i = 0; i < n; i++) {
    if (!drawn(i)) continue
    for (let a = 0; a < 3; a++) {
      min[a] = Math.min(min[a], mesh.positions[3 * i + a])
      max[a] = Math.max(max[a], mesh.positions[3 * i + a])
    }
  }
  expect(geometry.boundingBox!.min.toArray()).toEqual(min)
  expect(geometry.boundingBox!.max.toArray()).toEqual(max)
  const sphere = geometry.boundingSphere!
  const p = new Vector3()
  let far = 0
  for (let i = 0; i < n; i++) if (drawn(i)) far = Math.max(far, p.fromArray(mesh.positions, 3 * i).distanceTo(sphere.center))
  expect(far).toBeLessThanOrEqual(sphere.radius * (1 + 1e-6))
  expect(far).toBeGreaterThanOrEqual(sphere.radius * (1 - 1e-6)) // tight: the farthest vertex is on it
}

describe('bitecs-cloth/three', () => {
  it('the geometry follows a cape on a running, turning character: positions, normals, index and bounds equal getClothMesh every frame', () => {
    const world = makeWorld()
    const hero = addEntity(world)
    setTransform(world, hero, [0, 0, 0])
    const cape = createCloth(world, { width: 0.5, height: 0.8, resolution: [10, 16], position: [0, 1.5, -0.1] })
    pinRow(world, cape, 0, hero)
    const geometry = createClothGeometry(world, cape)
    expect(geometry).toBeInstanceOf(BufferGeometry)
    expect(geometry.getAttribute('position').itemSize).toBe(3)
    expect(geometry.getAttribute('normal').itemSize).toBe(3)
    expect(geometry.getAttribute('uv').itemSize).toBe(2)
    expectFollows(world, cape, geometry)
    const start = geometry.boundingSphere!.center.clone()
    for (let f = 1; f <= 120; f++) {
      const t = f / 60
      setTransform(world, hero, [3 * t, 0, Math.sin(2 * t)], [0, Math.sin(t), 0, Math.cos(t)])
      stepCloth(world, 1 / 60)
      expect(updateClothGeometry(world, cape, geometry)).toBe(geometry)
      if (f % 20 === 0) expectFollows(world, cape, geometry)
    }
    // the bounds moved with the cape (frustum culling would hide it otherwise)
    expect(geometry.boundingSphere!.center.x - start.x).toBeGreaterThan(5)
  })

  it('the bounds leave out a vertex no triangle uses (a stray one of an imported mesh stays where it was made)', () => {
    // found by a hunt: a 0.6 m sheet run 100 m from its stray vertex had a 50 m bounding sphere
    const world = makeWorld()
    const hero = addEntity(world)
    setTransform(world, hero, [0, 0, 0])
    const k = 6, positions: number[] = [], indices: number[] = []
    for (let r = 0; r < k; r++) for (let c = 0; c < k; c++) positions.push(-0.3 + (0.6 * c) / (k - 1), 1.5 - r / (k - 1), -0.2)
    for (let r = 0; r < k - 1; r++) {
      for (let c = 0; c < k - 1; c++) {
        const i = r * k + c
        indices.push(i, i + k, i + 1, i + 1, i + k, i + k + 1)
      }
    }
    positions.push(0, 1, -0.2) // the stray vertex
    const cloth = createClothFromMesh(world, { positions, indices })
    for (let c = 0; c < k; c++) pinParticle(world, cloth, c, hero)
    const geometry = createClothGeometry(world, cloth)
    for (let f = 1; f <= 600; f++) {
      setTransform(world, hero, [f / 6, 0, 0]) // 10 m/s
      stepCloth(world, 1 / 60)
      updateClothGeometry(world, cloth, geometry)
    }
    expect(getClothMesh(world, cloth).positions[3 * k * k]).toBe(0) // the stray vertex stayed
    expectFollows(world, cloth, geometry)
    expect(geometry.boundingSphere!.radius).toBeLessThan(1) // (50.2 m)
    expect(geometry.boundingSphere!.center.x).toBeGreaterThan(99)
  })

  it('after tears the geometry has the new vertices, the rewritten index and a longer draw range, and grows its arrays only when they are full', () => {
    const world = makeWorld()
    const n = 12
    const cloth = createCloth(world, { width: 1, height: 1, resolution: n, position: [0, 2, 0] })
    const [left, right] = pinSidesToBars(world, cloth, n)
    makeTearable(world, cloth, { maxTearsPerStep: 2 })
    const geometry = createClothGeometry(world, cloth)
    let disposals = 0
    geometry.addEventListener('dispose', () => disposals++)
    const room = geometry.getAttribute('position').count
    expect(room).toBe(n * n)
    const triangles = geometry.drawRange.count
    let tearsSeen = 0, grownAt = -1
    for (let f = 1; f <= 200; f++) {
      const d = Math.min(0.5, f * 0.01) // pull the bars apart
      setTransform(world, left, [-d, 0, 0])
      setTransform(world, right, [d, 0, 0])
      stepCloth(world, 1 / 60)
      updateClothGeometry(world, cloth, geometry)
      const tears = getClothTearCount(world, cloth)
      if (tears !== tearsSeen) {
        tearsSeen = tears
        expectFollows(world, cloth, geometry)
      }
      if (grownAt < 0 && geometry.getAttribute('position').count > room) grownAt = f
    }
    const mesh = getClothMesh(world, cloth)
    expect(mesh.vertexCount).toBeGreaterThan(n * n) // it tore
    expect(mesh.vertexCount).toBe(n * n + tearsSeen)
    expectFollows(world, cloth, geometry)
    expect(geometry.drawRange.count).toBe(3 * mesh.triangleCount)
    expect(geometry.drawRange.count).toBeGreaterThanOrEqual(triangles)
    // the first tear outgrew the exact-size arrays: they grew by half, once, through dispose()
    expect(grownAt).toBeGreaterThan(0)
    expect(disposals).toBe(1)
    expect(geometry.getAttribute('position').count).toBe(Math.ceil(1.5 * n * n))
    // the torn index is not the untorn one
    const sheetWorld = makeWorld()
    const untorn = createClothGeometry(sheetWorld, createCloth(sheetWorld, { width: 1, height: 1, resolution: n }))
    expect(drawnIndex(geometry)).not.toEqual(drawnIndex(untorn))
    expect(drawnIndex(geometry).length).toBe(drawnIndex(untorn).length)
  })

  it('a geometry handed to another cloth takes its topology; a larger cloth grows it', () => {
    const world = makeWorld()
    const small = createCloth(world, { width: 1, height: 1, resolution: 4 })
    const big = createCloth(world, { width: 2, height: 1, resolution: [9, 5], position: [3, 0, 0] })
    const geometry = createClothGeometry(world, small)
    stepCloth(world, 1 / 60)
    updateClothGeometry(world, big, geometry)
    expectFollows(world, big, geometry)
    updateClothGeometry(world, small, geometry)
    expectFollows(world, small, geometry)
  })

  it('a geometry moved to a cloth of another world with the same id takes it (a level reloaded into a new world keeps its meshes)', () => {
    // found by a hunt: it was refused as a removed cloth whose id names a new one
    const make = () => {
      const world = makeWorld()
      return { world, cloth: createCloth(world, { width: 1, height: 1, resolution: 6 }) }
    }
    const a = make(), b = make()
    expect(b.cloth).toBe(a.cloth)
    const geometry = createClothGeometry(a.world, a.cloth)
    stepCloth(b.world, 1 / 60)
    expect(updateClothGeometry(b.world, b.cloth, geometry)).toBe(geometry)
    expectFollows(b.world, b.cloth, geometry)
  })

  it('the geometry of a removed cloth does not silently show a new cloth that took its id (a ClothError, as a proxy gives)', () => {
    // observed: the old mesh, left in the scene, drew the respawned cloth a second time
    const world = makeWorld()
    const old = createCloth(world, { width: 1, height: 1, resolution: 4 })
    const geometry = createClothGeometry(world, old)
    removeCloth(world, old)
    const respawned = createCloth(world, { width: 1, height: 1, resolution: 4, position: [50, -1, 0] })
    expect(respawned).toBe(old) // bitECS gave the id back
    expect(() => updateClothGeometry(world, respawned, geometry)).toThrow(/not the cloth this geometry showed/)
    const fresh = createClothGeometry(world, respawned)
    stepCloth(world, 1 / 60)
    updateClothGeometry(world, respawned, fresh)
    expectFollows(world, respawned, fresh)
  })

  it('a disposed geometry lets go of its cloth: pooled, it keeps nothing of a removed cloth alive and takes a new cloth with the recycled id', async () => {
    // observed: each pooled mesh of a removed 14×24 cape kept the dead cloth's arrays alive, 235 kB
    const v8 = await import('node:v8')
    const vm = await import('node:vm')
    v8.setFlagsFromString('--expose-gc')
    const gc = vm.runInNewContext('gc') as () => void
    const world = makeWorld()
    const collected = async (dispose: boolean) => {
      const old = createCloth(world, { width: 1, height: 1, resolution: 8 })
      const mesh = createClothMesh(world, old)
      stepCloth(world, 1 / 60)
      updateClothGeometry(world, old, mesh.geometry)
      const ref = new WeakRef(getClothState(world, old))
      removeCloth(world, old)
      if (dispose) mesh.geometry.dispose()
      for (let k = 0; k < 3; k++) {
        await new Promise((r) => setTimeout(r, 0))
        gc()
      }
      return { gone: ref.deref() === undefined, mesh, old }
    }
    const kept = await collected(false)
    expect(kept.gone).toBe(false) // (in use, not disposed: it remembers its cloth, to refuse a recycled id)
    const pooled = await collected(true)
    expect(pooled.gone).toBe(true)
    const respawned = createCloth(world, { width: 2, height: 1, resolution: [12, 9], position: [3, 0, 0] }) // (larger: the arrays grow)
    expect(respawned).toBe(pooled.old) // bitECS gave the id back
    stepCloth(world, 1 / 60)
    updateClothGeometry(world, respawned, pooled.mesh.geometry)
    expectFollows(world, respawned, pooled.mesh.geometry)
    // a geometry grown by a larger cloth's topology still refuses a recycled id (growing is no release)
    removeCloth(world, respawned)
    const again = createCloth(world, { width: 1, height: 1, resolution: 4 })
    expect(again).toBe(respawned)
    expect(() => updateClothGeometry(world, again, pooled.mesh.geometry)).toThrow(/not the cloth this geometry showed/)
  })

  it('a sleeping cloth is not uploaded again (the attributes stay unchanged) until it moves', () => {
    // observed: 60 uploads of unchanged positions and normals in 60 frames of a sleeping cape
    const world = makeWorld({ sleep: { delay: 0.2 } })
    const hero = addEntity(world)
    setTransform(world, hero, [0, 1.5, 0])
    const cloth = createCloth(world, { width: 0.6, height: 0.6, resolution: 6, position: [0, 1.5, 0] })
    pinRow(world, cloth, 0, hero)
    const geometry = createClothGeometry(world, cloth)
    const position = () => geometry.getAttribute('position').version
    for (let f = 0; f < 300 && !isClothSleeping(world, cloth); f++) stepCloth(world, 1 / 60)
    expect(isClothSleeping(world, cloth)).toBe(true)
    updateClothGeometry(world, cloth, geometry)
    const asleep = position()
    for (let f = 0; f < 60; f++) {
      stepCloth(world, 1 / 60)
      updateClothGeometry(world, cloth, geometry)
    }
    expect(position()).toBe(asleep)
    setTransform(world, hero, [0.2, 1.5, 0]) // wakes it
    stepCloth(world, 1 / 60)
    updateClothGeometry(world, cloth, geometry)
    expect(position()).toBeGreaterThan(asleep)
    expectFollows(world, cloth, geometry)
  })

  it('createClothMesh draws the geometry with a double-sided standard material, or the material given', () => {
    const world = makeWorld()
    const cloth = createCloth(world, { width: 1, height: 1, resolution: 5 })
    const mesh = createClothMesh(world, cloth)
    expect(mesh.material).toBeInstanceOf(MeshStandardMaterial)
    expect(mesh.material.side).toBe(DoubleSide)
    stepCloth(world, 1 / 60)
    updateClothGeometry(world, cloth, mesh.geometry)
    expectFollows(world, cloth, mesh.geometry)
    const red = new MeshBasicMaterial({ color: 0xff0000 })
    const other = createClothMesh(world, cloth, red)
    expect(other.material).toBe(red)
    expect(other.geometry).not.toBe(mesh.geometry)
  })

  it('takes attributes of your own (vertex colours): the geometry type allows them and updates keep them', () => {
    const world = makeWorld()
    const cloth = createCloth(world, { width: 1, height: 1, resolution: 5 })
    const mesh = createClothMesh(world, cloth, new MeshBasicMaterial({ vertexColors: true }))
    const count = mesh.geometry.attributes.position.count
    // (a type error before: the geometry's attribute map named only position, normal and uv)
    mesh.geometry.setAttribute('color', new BufferAttribute(new Float32Array(3 * count).fill(0.5), 3))
    stepCloth(world, 1 / 60)
    updateClothGeometry(world, cloth, mesh.geometry)
    expectFollows(world, cloth, mesh.geometry)
    expect(mesh.geometry.getAttribute('color').count).toBe(count)
  })

  it('bad input is a ClothError naming the argument', () => {
    const world = makeWorld()
    const cloth = createCloth(world, { width: 1, height: 1, resolution: 3 })
    const geometry = createClothGeometry(world, cloth)
    const named = (fn: () => unknown, argument: string) => {
      let error: unknown
      try {
        fn()
      } catch (e) {
        error = e
      }
      expect(error).toBeInstanceOf(ClothError)
      expect((error as ClothError).argument).toBe(argument)
    }
    named(() => createClothGeometry(null as never, cloth), 'world')
    named(() => createClothGeometry({}, cloth), 'world')
    named(() => createClothGeometry(world, 99), 'cloth')
    named(() => createClothGeometry(world, NaN), 'cloth')
    named(() => updateClothGeometry(world, cloth, new BufferGeometry()), 'geometry')
    named(() => updateClothGeometry(world, cloth, undefined as never), 'geometry')
    named(() => updateClothGeometry(undefined as never, cloth, geometry), 'world')
    named(() => createClothMesh(world, cloth, {} as never), 'material')
    named(() => createClothMesh(world, cloth, null as never), 'material')
    removeCloth(world, cloth)
    named(() => updateClothGeometry(world, cloth, geometry), 'cloth')
  })
})

describe('a torn cloth under the draw matrix', () => {
  it('draws a piece torn off where it lies while its character walks on at 144 Hz, or hides, and the rest of it on the character (the piece followed the character: 61 mm between steps, 4 m hidden for a second)', () => {
    const s = tornCapeOnGround(null)
    expect(s.off.length).toBeGreaterThan(0)
    const mesh = createClothMesh(s.world, s.cape)
    // a hand on the part still on the character: the piece on the ground is no held piece
    grabParticle(
      s.world,
      s.cape,
      s.on[s.on.length - 1],
      Array.from(s.c.pos.subarray(3 * s.on[s.on.length - 1], 3 * s.on[s.on.length - 1] + 3)),
    )
    const drawn = (i: number) => new Vector3().fromBufferAttribute(mesh.geometry.getAttribute('position'), i).applyMatrix4(mesh.matrix)
    let z = s.z, worstOff = 0, worstPin = 0, moving = 0
    const frame = (dt: number) => {
      z += 4 * dt
      setTransform(s.world, s.hero, [0, 0, z])
      stepCloth(s.world, dt)
      updateClothGeometry(s.world, s.cape, mesh.geometry)
      updateClothDrawMatrix(s.world, s.cape, mesh)
      for (const i of s.off) worstOff = Math.max(worstOff, drawn(i).distanceTo(new Vector3().fromArray(s.c.pos, 3 * i)))
      // the pinned row is drawn on the character now (the draw matrix's job), a step's motion ahead of the mesh
      for (let col = 0; col < s.cols; col++) worstPin = Math.max(worstPin, Math.abs(drawn(col).z - (z - 0.2)))
      for (let k = 0; k < 16; k++) moving = Math.max(moving, Math.abs(mesh.matrix.elements[k] - (k % 5 === 0 ? 1 : 0)))
    }
    for (let f = 0; f < 144; f++) frame(1 / 144)
    expect(moving, 'the draw matrix moved the cloth between steps').toBeGreaterThan(0.01)
    expect(worstOff).toBeLessThan(1e-5) // (float32 vertices)
    expect(worstPin).toBeLessThan(1e-5)
    // hidden under a budget, frozen: drawn carried with its character, but not its piece
    const viewer = addEntity(s.world)
    setTransform(s.world, viewer, [0, 0, 0])
    setClothBudget(s.world, { viewer, near: 100, far: 200 })
    setClothVisible(s.world, s.cape, false)
    for (let f = 0; f < 60; f++) frame(1 / 60)
    expect(getClothLod(s.world, s.cape).frozen).toBe(true)
    expect(worstOff).toBeLessThan(1e-5)
  })

  it('draws a piece the character carries in its hand with the matrix, at the hand (written back as lying still, it was drawn 31 mm behind on average)', () => {
    const s = tornCapeOnGround(null)
    const held = s.off[0]
    let z = s.z
    const hand = () => [0.4, 1.0, z + 0.3]
    const grab = grabParticle(s.world, s.cape, held, hand())
    for (let f = 0; f < 120; f++) {
      moveGrab(s.world, grab, hand())
      stepCloth(s.world, 1 / 60)
    }
    expect(Array.from(s.c.detached.subarray(1, 1 + s.c.detached[0]))).toContain(held)
    const mesh = createClothMesh(s.world, s.cape)
    let worst = 0
    for (let f = 0; f < 288; f++) {
      z += 4 / 144
      setTransform(s.world, s.hero, [0, 0, z])
      moveGrab(s.world, grab, hand())
      stepCloth(s.world, 1 / 144)
      updateClothGeometry(s.world, s.cape, mesh.geometry)
      updateClothDrawMatrix(s.world, s.cape, mesh)
      const drawn = new Vector3().fromBufferAttribute(mesh.geometry.getAttribute('position'), held).applyMatrix4(mesh.matrix)
      if (f >= 144) worst = Math.max(worst, drawn.distanceTo(new Vector3().fromArray(hand())))
    }
    expect(worst).toBeLessThan(0.01) // (measured 6.8 mm: the grip's own lag)
  })
})
