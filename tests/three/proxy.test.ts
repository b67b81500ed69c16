import { addEntity } from 'bitecs'
import { BufferGeometry, DoubleSide, MeshBasicMaterial, MeshStandardMaterial, Vector3 } from 'three'
import { describe, expect, it } from 'vitest'
import {
  buildGridMesh,
  createCloth,
  createRenderProxy,
  makeTearable,
  pinRow,
  removeRenderProxy,
  setTransform,
  stepCloth,
  updateRenderProxy,
} from '../../src/index'
import { createClothGeometry, createProxyGeometry, createProxyMesh, updateProxyGeometry } from '../../src/three/index'
import { pinSidesToBars } from '../fixtures/bars'
import { makeWorld, rejects } from '../helpers'

type Geometry = ReturnType<typeof createProxyGeometry>

/** Asserts that the geometry draws the proxy's mesh as it is now, inside its bounds. */
function expectShows(world: object, proxy: Parameters<typeof updateRenderProxy>[1], geometry: Geometry) {
  const mesh = updateRenderProxy(world, proxy)
  expect(geometry.getAttribute('position').array).toBe(mesh.positions)
  expect(geometry.getAttribute('normal').array).toBe(mesh.normals)
  expect(geometry.getAttribute('uv').array).toBe(mesh.uvs)
  expect(geometry.getIndex()!.array).toBe(mesh.indices)
  const box = geometry.boundingBox!, sphere = geometry.boundingSphere!
  const p = new Vector3()
  for (let i = 0; i < mesh.vertexCount; i++) {
    p.fromArray(mesh.positions, 3 * i)
    expect(box.containsPoint(p)).toBe(true)
    expect(p.distanceTo(sphere.center)).toBeLessThanOrEqual(sphere.radius * (1 + 1e-6))
  }
}

/** A cape pinned to a hero standing at (0, 1.6, 0), with a 4× finer proxy and its geometry. */
function capeWithProxy() {
  const world = makeWorld()
  const hero = addEntity(world)
  setTransform(world, hero, [0, 1.6, 0])
  const cape = createCloth(world, { width: 0.5, height: 0.8, resolution: [8, 12], position: [0, 1.5, -0.1] })
  pinRow(world, cape, 0, hero)
  const proxy = createRenderProxy(world, cape, buildGridMesh({ width: 0.5, height: 0.8, resolution: [29, 45] }))
  return { world, hero, proxy, geometry: createProxyGeometry(world, proxy) }
}

describe('bitecs-cloth/three render proxies', () => {
  it("a proxy geometry draws the proxy's own arrays, flagged for upload and bounded anew each frame of a running cape", () => {
    const { world, hero, proxy, geometry } = capeWithProxy()
    expect(geometry).toBeInstanceOf(BufferGeometry)
    expectShows(world, proxy, geometry)
    const uploads = geometry.getAttribute('position').version, indexUploads = geometry.getIndex()!.version
    const start = geometry.boundingSphere!.center.clone()
    for (let f = 1; f <= 60; f++) {
      setTransform(world, hero, [3 * (f / 60), 1.6, 0], [0, Math.sin(f / 60), 0, Math.cos(f / 60)])
      stepCloth(world, 1 / 60)
      expect(updateProxyGeometry(world, proxy, geometry)).toBe(geometry)
      if (f % 20 === 0) expectShows(world, proxy, geometry)
    }
    expect(geometry.getAttribute('position').version - uploads).toBe(60)
    expect(geometry.getAttribute('normal').version - uploads).toBe(60)
    expect(geometry.getIndex()!.version).toBe(indexUploads) // nothing tore: the index is never sent again
    expect(geometry.boundingSphere!.center.x - start.x).toBeGreaterThan(2)
  })

  it('a proxy of a cloth that did not change (a frame that ran no step, or asleep) is not uploaded again', () => {
    const { world, hero, proxy, geometry } = capeWithProxy()
    const uploads = () => geometry.getAttribute('position').version
    let ran = 0
    const before = uploads()
    for (let f = 1; f <= 144; f++) {
      setTransform(world, hero, [3 * (f / 144), 1.6, 0])
      ran += stepCloth(world, 1 / 144) > 0 ? 1 : 0 // (144 Hz: some frames run no fixed step)
      updateProxyGeometry(world, proxy, geometry)
    }
    expect(ran).toBeLessThan(144)
    expect(uploads() - before).toBe(ran) // (it was 144)
    expectShows(world, proxy, geometry)
  })

  it('the index is sent again when a tear hides render triangles', () => {
    const world = makeWorld()
    const n = 10
    const cloth = createCloth(world, { width: 1, height: 1, resolution: n, position: [0, 2, 0] })
    const [left, right] = pinSidesToBars(world, cloth, n)
    makeTearable(world, cloth)
    const proxy = createRenderProxy(world, cloth, buildGridMesh({ width: 1, height: 1, resolution: 37 }))
    const mesh = createProxyMesh(world, proxy)
    const indexUploads = mesh.geometry.getIndex()!.version
    let versions = 0
    for (let f = 1; f <= 200; f++) {
      const d = Math.min(0.5, f * 0.004)
      setTransform(world, left, [-d, 0, 0])
      setTransform(world, right, [d, 0, 0])
      stepCloth(world, 1 / 60)
      const before = updateRenderProxy(world, proxy).indexVersion // the update below finds the proxy current
      updateProxyGeometry(world, proxy, mesh.geometry)
      versions = before
    }
    expect(versions).toBeGreaterThan(0)
    expect(mesh.geometry.getIndex()!.version - indexUploads).toBe(versions)
    expectShows(world, proxy, mesh.geometry)
  })

  it('createProxyMesh: a double-sided standard material, or the material given', () => {
    const world = makeWorld()
    const cloth = createCloth(world, { width: 1, height: 1, resolution: 4 })
    const proxy = createRenderProxy(world, cloth, buildGridMesh({ width: 1, height: 1, resolution: 10 }))
    const mesh = createProxyMesh(world, proxy)
    expect(mesh.material).toBeInstanceOf(MeshStandardMaterial)
    expect(mesh.material.side).toBe(DoubleSide)
    const red = new MeshBasicMaterial({ color: 0xff0000 })
    expect(createProxyMesh(world, proxy, red).material).toBe(red)
  })

  it('bad input is a ClothError naming the argument', () => {
    const world = makeWorld()
    const cloth = createCloth(world, { width: 1, height: 1, resolution: 4 })
    const grid = buildGridMesh({ width: 1, height: 1, resolution: 7 })
    const proxy = createRenderProxy(world, cloth, grid)
    const other = createRenderProxy(world, cloth, grid)
    const geometry = createProxyGeometry(world, proxy)
    rejects(() => createProxyGeometry(null as never, proxy), 'world')
    rejects(() => createProxyGeometry(world, {} as never), 'proxy')
    rejects(() => updateProxyGeometry(world, proxy, new BufferGeometry()), 'geometry')
    rejects(() => updateProxyGeometry(world, proxy, createClothGeometry(world, cloth)), 'geometry')
    rejects(() => updateProxyGeometry(world, other, geometry), 'geometry', 'another render proxy')
    rejects(() => createProxyMesh(world, proxy, {} as never), 'material')
    removeRenderProxy(world, proxy)
    rejects(() => updateProxyGeometry(world, proxy, geometry), 'proxy')
  })
})
