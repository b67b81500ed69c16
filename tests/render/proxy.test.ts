import { addEntity, createWorld } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  buildGridMesh,
  createCloth,
  createClothFromMesh,
  createRenderProxy,
  getClothMesh,
  getClothState,
  installClothPlugin,
  makeTearable,
  pinParticle,
  pinRow,
  removeCloth,
  removeRenderProxy,
  setTransform,
  stepCloth,
  updateRenderProxy,
  writeRenderMesh,
} from '../../src/index'
import { pinSidesToBars } from '../fixtures/bars'
import { allFinite, makeWorld, rejects } from '../helpers'
import { meshPieces, pieceCount } from '../tearing/util'
import { edgeStretch, surfaceDistances } from './surface'

/** A 0.6 × 1 m cape of 10 × 16 particles pinned by its top row to a hero that sways, turns and hops. */
function swingingCape() {
  const world = makeWorld()
  const hero = addEntity(world)
  setTransform(world, hero, [0, 2, 0])
  const cloth = createCloth(world, { width: 0.6, height: 1, resolution: [10, 16], position: [0, 2, 0] })
  pinRow(world, cloth, 0, hero)
  const drive = (f: number) => {
    const yaw = 0.8 * Math.sin(f * 0.07)
    const hop = f >= 120 && f < 150 ? 0.3 * Math.sin(((f - 120) / 30) * Math.PI) : 0
    setTransform(world, hero, [0.5 * Math.sin(f * 0.1), 2 + hop, 0.02 * f], [0, Math.sin(yaw / 2), 0, Math.cos(yaw / 2)])
  }
  return { world, cloth, hero, drive }
}

/** Largest angle between neighbouring simulated triangles of a cloth now, degrees. */
function maxFold(world: object, cloth: number): number {
  const mesh = getClothMesh(world, cloth)
  const normal = (k: number) => {
    const [a, b, c] = [3 * mesh.indices[3 * k], 3 * mesh.indices[3 * k + 1], 3 * mesh.indices[3 * k + 2]]
    const p = mesh.positions
    const u = [p[b] - p[a], p[b + 1] - p[a + 1], p[b + 2] - p[a + 2]], v = [p[c] - p[a], p[c + 1] - p[a + 1], p[c + 2] - p[a + 2]]
    const n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    const l = Math.hypot(n[0], n[1], n[2])
    return n.map((x) => x / l)
  }
  let worst = 0
  const byEdge = new Map<string, number>()
  for (let k = 0; k < mesh.triangleCount; k++) {
    for (let e = 0; e < 3; e++) {
      const a = mesh.indices[3 * k + e], b = mesh.indices[3 * k + ((e + 1) % 3)]
      const key = a < b ? `${a},${b}` : `${b},${a}`
      const other = byEdge.get(key)
      if (other === undefined) {
        byEdge.set(key, k)
        continue
      }
      const n = normal(k), m = normal(other)
      worst = Math.max(worst, Math.acos(Math.max(-1, Math.min(1, n[0] * m[0] + n[1] * m[1] + n[2] * m[2]))))
    }
  }
  return (worst * 180) / Math.PI
}

/** `buildGridMesh` of the cape 4× finer (each simulated edge in four), optionally pushed `dz` to the front. */
function fineCape(dz = 0) {
  const m = buildGridMesh({ width: 0.6, height: 1, resolution: [37, 61] })
  for (let i = 2; i < m.positions.length; i += 3) m.positions[i] += dz
  return m
}

/** Largest |distance to the cloth's surface now − expected| over a proxy's vertices. */
function worstDeparture(world: object, cloth: number, positions: Float32Array, expected: (i: number) => number): number {
  const c = getClothState(world, cloth)
  const d = surfaceDistances(positions, c.pos, c.topology.triangles, c.topology.triangleCount)
  let worst = 0
  for (let i = 0; i < d.length; i++) worst = Math.max(worst, Math.abs(d[i] - expected(i)))
  return worst
}

/**
 * A cylinder's arc as a mesh: the flat sheet of `buildGridMesh` wrapped around the y axis at radius
 * r (its front outward, the middle column at +z). With `facets`, each vertex is placed on the
 * chords between the columns of a coarser `facets`-column wrap instead (a finer grid lying on that
 * coarse faceted surface).
 */
function cylinder(r: number, width: number, columns: number, rows: number, facets = 0) {
  const m = buildGridMesh({ width, height: 1, resolution: [columns, rows] })
  const at = (x: number) => [r * Math.sin(x / r), r * Math.cos(x / r)]
  for (let i = 0; i < m.positions.length; i += 3) {
    const x = m.positions[i]
    let p = at(x)
    if (facets > 0) {
      const dx = width / (facets - 1)
      const k = Math.min(facets - 2, Math.floor((x + width / 2) / dx + 1e-9))
      const s = (x + width / 2 - k * dx) / dx
      const a = at(-width / 2 + k * dx), b = at(-width / 2 + (k + 1) * dx)
      p = [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])]
    }
    m.positions[i] = p[0]
    m.positions[i + 2] = p[1]
  }
  return m
}

describe('render proxies', () => {
  it('a proxy 4× finer than a swinging, turning, hopping cape stays on its surface: within 1 mm over the run', () => {
    const { world, cloth, drive } = swingingCape()
    const proxy = createRenderProxy(world, cloth, fineCape())
    let worst = 0
    for (let f = 0; f <= 240; f++) {
      if (f % 30 === 0) worst = Math.max(worst, worstDeparture(world, cloth, updateRenderProxy(world, proxy).positions, () => 0))
      drive(f)
      stepCloth(world, 1 / 60)
    }
    expect(allFinite(world, cloth)).toBe(true)
    expect(worst).toBeLessThan(1e-3)
    // the cape really swung and folded
    expect(maxFold(world, cloth)).toBeGreaterThan(60)
  })

  it('a 4 mm thick cape (front layer 2 mm ahead, back layer 2 mm behind, facing back) keeps its thickness on a walking character', () => {
    const { world, cloth, hero } = swingingCape()
    const front = fineCape(0.002)
    const back = fineCape(-0.002)
    for (let t = 0; t < back.indices.length; t += 3) [back.indices[t + 1], back.indices[t + 2]] = [back.indices[t + 2], back.indices[t + 1]]
    const layers = [createRenderProxy(world, cloth, front), createRenderProxy(world, cloth, back)]
    let worst = 0, fold = 0
    for (let f = 0; f <= 240; f++) {
      if (f % 30 === 0) {
        for (const layer of layers)
          worst = Math.max(
            worst,
            worstDeparture(world, cloth, updateRenderProxy(world, layer).positions, () => 0.002),
          )
        fold = Math.max(fold, maxFold(world, cloth))
        const a = layers[0].mesh, b = layers[1].mesh
        let opposite = 0
        for (let k = 0; k < a.normals.length; k++) opposite = Math.max(opposite, Math.abs(a.normals[k] + b.normals[k]))
        expect(opposite).toBeLessThan(1e-6)
      }
      const yaw = 0.3 * Math.sin(f * 0.03)
      setTransform(world, hero, [0.1 * Math.sin(f * 0.1), 2 + 0.03 * Math.abs(Math.sin(f * 0.15)), -f / 40], [
        0,
        Math.sin(yaw / 2),
        0,
        Math.cos(yaw / 2),
      ])
      stepCloth(world, 1 / 60)
    }
    expect(worst).toBeLessThan(1e-3)
    // the condition the README states: folds stayed below 90° (a layer at d sits d·cos(fold/2) inside a fold)
    expect(fold).toBeGreaterThan(30)
    expect(fold).toBeLessThan(90)
  })

  it("at a vertex it shares with the cloth, a proxy vertex has the cloth vertex's position and normal", () => {
    const { world, cloth, drive } = swingingCape()
    const proxy = createRenderProxy(world, cloth, fineCape())
    for (let f = 0; f < 90; f++) {
      drive(f)
      stepCloth(world, 1 / 60)
    }
    const mesh = updateRenderProxy(world, proxy)
    const sim = getClothMesh(world, cloth)
    for (let r = 0; r < 16; r++) {
      for (let col = 0; col < 10; col++) {
        const i = r * 10 + col, v = 4 * r * 37 + 4 * col
        for (let k = 0; k < 3; k++) {
          expect(mesh.positions[3 * v + k]).toBeCloseTo(sim.positions[3 * i + k], 5)
          expect(mesh.normals[3 * v + k]).toBeCloseTo(sim.normals[3 * i + k], 5)
        }
      }
    }
    for (let v = 0; v < mesh.vertexCount; v++)
      expect(Math.hypot(mesh.normals[3 * v], mesh.normals[3 * v + 1], mesh.normals[3 * v + 2])).toBeCloseTo(1, 5)
  })

  it('any mesh drives any mesh: a finer cylinder arc 2 mm outside a coarse one follows it (rest shape exact, then within 1 mm of its rest distance)', () => {
    const world = makeWorld()
    const sim = cylinder(0.3, 0.9, 12, 8)
    const cloth = createClothFromMesh(world, { positions: sim.positions, indices: sim.indices, bending: 'dihedral', material: 'leather' })
    const render = cylinder(0.302, 0.9 * 0.302 / 0.3, 45, 29) // off the coarse facets, 2–5 mm outside them
    const proxy = createRenderProxy(world, cloth, render)
    const mesh = updateRenderProxy(world, proxy)
    for (let k = 0; k < render.positions.length; k++) expect(mesh.positions[k]).toBeCloseTo(render.positions[k], 6)
    const restDistance = surfaceDistances(render.positions, sim.positions, sim.indices, sim.indices.length / 3)
    expect(Math.min(...restDistance)).toBeGreaterThan(0.0019)
    const hero = addEntity(world)
    setTransform(world, hero, [0, 0, 0])
    for (let i = 0; i < 12; i++) pinParticle(world, cloth, i, hero) // the top row
    let worst = 0, fold = 0
    for (let f = 0; f < 120; f++) {
      setTransform(world, hero, [0.1 * Math.sin(f * 0.1), 0, 0], [
        0,
        Math.sin(0.1 * Math.sin(f * 0.05)),
        0,
        Math.cos(0.1 * Math.sin(f * 0.05)),
      ])
      stepCloth(world, 1 / 60)
      if (f % 40 === 39) {
        worst = Math.max(worst, worstDeparture(world, cloth, updateRenderProxy(world, proxy).positions, (i) => restDistance[i]))
        fold = Math.max(fold, maxFold(world, cloth))
      }
    }
    expect(allFinite(world, cloth)).toBe(true)
    expect(worst).toBeLessThan(1e-3)
    expect(fold).toBeGreaterThan(10) // it flexed, with folds gentle enough for a 2–5 mm layer
    expect(fold).toBeLessThan(90)
  })

  it("normals are interpolated: smooth across the simulated triangles, where the render mesh's own triangles show their facets", () => {
    // a flat 6-column sheet bent onto a 0.3 m cylinder (columns 36° apart), and a 4× finer proxy
    const world = makeWorld()
    const r = 0.3, width = r * Math.PI
    const cloth = createCloth(world, { width, height: 1, resolution: [6, 4] })
    const c = getClothState(world, cloth)
    for (let i = 0; i < c.count; i++) {
      const x = c.topology.restPositions[3 * i]
      c.pos[3 * i] = r * Math.sin(x / r)
      c.pos[3 * i + 2] = r * Math.cos(x / r)
    }
    c.version++
    const fine = buildGridMesh({ width, height: 1, resolution: [21, 13] })
    const mesh = updateRenderProxy(world, createRenderProxy(world, cloth, fine))
    const own = new Float32Array(mesh.normals.length)
    writeRenderMesh(
      Float64Array.from(mesh.positions),
      mesh.vertexCount,
      fine.indices,
      fine.indices.length / 3,
      new Float32Array(own.length),
      own,
    )
    // angle to the cylinder's normal at the vertex's place around it, away from the sheet's side edges
    const error = (n: Float32Array) => {
      let worst = 0
      for (let v = 0; v < mesh.vertexCount; v++) {
        if (v % 21 < 4 || v % 21 > 16) continue
        const a = fine.positions[3 * v] / r
        worst = Math.max(worst, Math.acos(Math.min(1, n[3 * v] * Math.sin(a) + n[3 * v + 2] * Math.cos(a))))
      }
      return (worst * 180) / Math.PI
    }
    expect(error(own)).toBeGreaterThan(8) // flat facets: 9° off a quarter of the way across
    expect(error(mesh.normals)).toBeLessThan(1)
  })

  it("uvs: the cloth's own at each embedded point unless given; a finer grid of a grid cloth gets its own grid uvs", () => {
    const world = makeWorld()
    const cloth = createCloth(world, { width: 0.6, height: 1, resolution: [10, 16], position: [1, 2, 3], rotation: [0, 0.6, 0, 0.8] })
    const fine = fineCape()
    const mesh = updateRenderProxy(world, createRenderProxy(world, cloth, { positions: fine.positions, indices: fine.indices }))
    for (let k = 0; k < fine.uvs.length; k++) expect(mesh.uvs[k]).toBeCloseTo(fine.uvs[k], 6)
    const given = fine.uvs.map((x) => 2 * x)
    const mine = updateRenderProxy(world, createRenderProxy(world, cloth, { ...fine, uvs: given }))
    expect(Array.from(mine.uvs)).toEqual(Array.from(given))
  })

  it('a proxy of a tearable cloth: vertices ride with their torn triangles, render triangles spanning a tear are hidden', () => {
    const world = makeWorld()
    const n = 12
    const cloth = createCloth(world, { width: 1, height: 1, resolution: n, position: [0, 2, 0] })
    const [left, right] = pinSidesToBars(world, cloth, n)
    const fine = buildGridMesh({ width: 1, height: 1, resolution: 45 })
    const proxy = createRenderProxy(world, cloth, fine)
    makeTearable(world, cloth) // after the proxy: it follows the cloth's own copy of its triangles
    const { indices } = updateRenderProxy(world, proxy)
    for (let f = 0; f < 200; f++) {
      const d = Math.min(0.5, (f + 1) * 0.004)
      setTransform(world, left, [-d, 0, 0])
      setTransform(world, right, [d, 0, 0])
      stepCloth(world, 1 / 60)
      updateRenderProxy(world, proxy)
    }
    const mesh = updateRenderProxy(world, proxy)
    expect(mesh.indices).toBe(indices)
    expect(getClothMesh(world, cloth).vertexCount).toBeGreaterThan(n * n)
    expect(mesh.indexVersion).toBeGreaterThan(0)
    const visible: number[] = []
    let hidden = 0
    let stretch = 0
    for (let t = 0; t < mesh.triangleCount; t++) {
      const [a, b, c] = [mesh.indices[3 * t], mesh.indices[3 * t + 1], mesh.indices[3 * t + 2]]
      if (a === b && b === c) {
        hidden++
        continue
      }
      visible.push(a, b, c)
      for (const [p, q] of [[a, b], [b, c], [c, a]]) stretch = Math.max(stretch, edgeStretch(mesh.positions, fine.positions, p, q))
    }
    // a thin seam of render triangles along the tear is hidden; nothing drawn bridges the gap
    expect(hidden).toBeGreaterThan(0)
    expect(hidden).toBeLessThan(0.1 * mesh.triangleCount)
    expect(stretch).toBeLessThan(2)
    expect(pieceCount(meshPieces(Uint32Array.from(visible), mesh.vertexCount))).toBeGreaterThanOrEqual(2)
    expect(worstDeparture(world, cloth, mesh.positions, () => 0)).toBeLessThan(1e-3)
  })

  it("a render triangle over two cloth triangles that share only a crack's tip is hidden: the crack runs between them", () => {
    // a 3 × 3 vertex sheet (0.1 m apart, diagonals from top-left to bottom-right) cut from its
    // centre C to the middle of its right side, R: the triangles below the cut hold a copy of R
    const at = (i: number, j: number) => 3 * j + i
    const C = at(1, 1), R = at(2, 1), R2 = 9
    const positions: number[] = []
    for (let j = 0; j < 3; j++) for (let i = 0; i < 3; i++) positions.push(0.1 * i, -0.1 * j, 0)
    positions.push(0.2, -0.1, 0) // R's copy
    const above = [at(1, 0), R, C], below = [C, R2, at(2, 2)], beyond = [C, at(2, 2), at(1, 2)]
    const indices = [
      ...[at(0, 0), at(1, 0), C, at(0, 0), C, at(0, 1)],
      ...[at(1, 0), at(2, 0), R, ...above],
      ...[at(0, 1), C, at(1, 2), at(0, 1), at(1, 2), at(0, 2)],
      ...[...below, ...beyond],
    ]
    const world = makeWorld()
    const cloth = createClothFromMesh(world, { positions, indices })
    const centroid = (t: number[]) =>
      [0, 1, 2].map((k) => (positions[3 * t[0] + k] + positions[3 * t[1] + k] + positions[3 * t[2] + k]) / 3)
    // one render triangle with corners in `above` and `beyond` (they share only C, the cut's tip),
    // one within the sheet's left half, away from the cut
    const render = {
      positions: [...centroid(above), ...centroid(beyond), 0.12, -0.02, 0, 0.02, -0.05, 0, 0.05, -0.12, 0, 0.05, -0.02, 0],
      indices: [0, 1, 2, 3, 4, 5],
    }
    const mesh = updateRenderProxy(world, createRenderProxy(world, cloth, render))
    expect(Array.from(mesh.indices.subarray(0, 3))).toEqual([0, 0, 0]) // hidden (drawn across the opening before: 3.3× its size seen in a hunt)
    expect(Array.from(mesh.indices.subarray(3, 6))).toEqual([3, 4, 5])

    // the same sheet whole: both drawn
    const whole = createClothFromMesh(world, { positions, indices: indices.map((v) => (v === R2 ? R : v)) })
    const wholeMesh = updateRenderProxy(world, createRenderProxy(world, whole, render))
    expect(Array.from(wholeMesh.indices)).toEqual([0, 1, 2, 3, 4, 5])
  })

  it('entity lifetimes: a removed proxy, a removed cloth (its id recycled or not) and another world are ClothErrors', () => {
    const world = makeWorld()
    const cloth = createCloth(world, { width: 1, height: 1, resolution: 4 })
    const mesh = buildGridMesh({ width: 1, height: 1, resolution: 7 })
    const proxy = createRenderProxy(world, cloth, mesh)
    rejects(() => updateRenderProxy(makeWorld(), proxy), 'proxy', 'another world')
    removeRenderProxy(world, proxy)
    rejects(() => updateRenderProxy(world, proxy), 'proxy', 'not removed')
    rejects(() => removeRenderProxy(world, proxy), 'proxy')

    const second = createRenderProxy(world, cloth, mesh)
    removeCloth(world, cloth)
    rejects(() => updateRenderProxy(world, second), 'proxy', 'removed')
    const recycled = createCloth(world, { width: 1, height: 1, resolution: 4 })
    expect(recycled).toBe(cloth) // bitECS hands the id out again
    rejects(() => updateRenderProxy(world, second), 'proxy', 'removed')
    removeRenderProxy(world, second) // a proxy of a removed cloth can still be removed
    const third = createRenderProxy(world, recycled, mesh)
    expect(updateRenderProxy(world, third).vertexCount).toBe(49)
  })

  it('bad input is a ClothError naming it', () => {
    const world = makeWorld()
    const cloth = createCloth(world, { width: 1, height: 1, resolution: 4, position: [0, 2, 0] })
    const good = buildGridMesh({ width: 1, height: 1, resolution: 7 })
    rejects(() => createRenderProxy(world, cloth + 1, good), 'cloth')
    rejects(() => createRenderProxy(createWorld(), cloth, good), 'world')
    rejects(() => createRenderProxy(world, cloth, undefined as never), 'options')
    rejects(() => createRenderProxy(world, cloth, { ...good, positions: [0, 0, 0, 1, 0] }), 'options.positions')
    rejects(() => createRenderProxy(world, cloth, { ...good, positions: [0, 0, 0, 1, 0, 0, 0, NaN, 0] }), 'options.positions[7]', 'NaN')
    rejects(() => createRenderProxy(world, cloth, { ...good, indices: [0, 1, 49] }), 'options.indices[2]', '49')
    rejects(() => createRenderProxy(world, cloth, { ...good, indices: [0, 1, 1] }), 'options.indices[0..2]')
    rejects(() => createRenderProxy(world, cloth, { ...good, uvs: [0, 0] }), 'options.uvs')
    rejects(() => createRenderProxy(world, cloth, { ...good, maxOffset: 0 }), 'options.maxOffset')
    rejects(() => createRenderProxy(world, cloth, { ...good, maxOffset: NaN }), 'options.maxOffset')
    // world positions instead of the cloth's rest frame: 2 m above it
    const world2 = Float64Array.from(good.positions)
    for (let i = 1; i < world2.length; i += 3) world2[i] += 2
    rejects(() => createRenderProxy(world, cloth, { ...good, positions: world2 }), 'options.positions[0..2]', 'rest frame')
    // a thick layer is fine once maxOffset allows it
    const thick = Float64Array.from(good.positions)
    for (let i = 2; i < thick.length; i += 3) thick[i] += 0.2
    rejects(() => createRenderProxy(world, cloth, { ...good, positions: thick }), 'options.positions[0..2]')
    expect(createRenderProxy(world, cloth, { ...good, positions: thick, maxOffset: 0.25 }).binding.maxOffset).toBeCloseTo(0.2, 9)
    rejects(() => updateRenderProxy(world, {} as never), 'proxy')
    rejects(() => buildGridMesh({ width: 1, height: -1, resolution: 4 }), 'options.height')
    rejects(() => buildGridMesh({ width: 1, height: 1, resolution: [4, 1] }), 'options.resolution[1]')
  })
})

describe('buildGridMesh', () => {
  it("is createCloth's rest shape and uvs: a cloth made from it matches the grid cloth", () => {
    const world = installClothPlugin(createWorld())
    const grid = createCloth(world, { width: 0.8, height: 1.2, resolution: [5, 7] })
    const m = buildGridMesh({ width: 0.8, height: 1.2, resolution: [5, 7] })
    const t = getClothState(world, grid).topology
    expect(Array.from(m.positions)).toEqual(Array.from(t.restPositions))
    expect(Array.from(m.indices)).toEqual(Array.from(t.triangles))
    expect(Array.from(m.uvs)).toEqual(Array.from(getClothMesh(world, grid).uvs))
  })
})
