// A user's program, type-checked and run by tests/package/install.test.ts in an empty project
// where the packed tarball was installed with bitecs, three and TypeScript (strict, NodeNext,
// skipLibCheck false). It imports both entries as a user would; not part of the project's build.
import { addEntity, createWorld } from 'bitecs'
import { BufferGeometry, type Mesh, MeshBasicMaterial } from 'three'
import {
  ClothError,
  beginClothStep,
  createCloth,
  disposeClothWorld,
  endClothStep,
  getClothState,
  getClothMesh,
  getClothTearCount,
  installClothPlugin,
  makeTearable,
  pinParticle,
  pinRow,
  setTransform,
  stepCloth,
  type ClothMesh,
} from 'bitecs-cloth'
import { createClothGeometry, createClothMesh, updateClothGeometry, type ClothGeometry } from 'bitecs-cloth/three'

function check(ok: boolean, what: string): void {
  if (!ok) throw new Error(`FAILED: ${what}`)
}

function sameArray(a: ArrayLike<number>, b: ArrayLike<number>, count: number): boolean {
  if (a.length < count || b.length < count) return false
  for (let i = 0; i < count; i++) if (a[i] !== b[i]) return false
  return true
}

/** The geometry shows the cloth: positions, normals and index equal the mesh, over the draw range. */
function follows(geometry: ClothGeometry, mesh: ClothMesh): boolean {
  return sameArray(geometry.attributes.position.array, mesh.positions, 3 * mesh.vertexCount) &&
    sameArray(geometry.attributes.normal.array, mesh.normals, 3 * mesh.vertexCount) &&
    geometry.index !== null && sameArray(geometry.index.array, mesh.indices, 3 * mesh.triangleCount) &&
    geometry.drawRange.count === 3 * mesh.triangleCount
}

// a cape on a running character, drawn with the default material
const world = installClothPlugin(createWorld())
const hero = addEntity(world)
setTransform(world, hero, [0, 1.6, 0])
const cape = createCloth(world, { width: 0.5, height: 0.8, resolution: [8, 12], position: [0, 1.5, -0.1] })
pinRow(world, cape, 0, hero)
const mesh: Mesh<ClothGeometry> = createClothMesh(world, cape)
const geometry: BufferGeometry = mesh.geometry
for (let f = 1; f <= 90; f++) {
  setTransform(world, hero, [f / 30, 1.6, 0])
  stepCloth(world, 1 / 60)
  updateClothGeometry(world, cape, geometry)
}
check(follows(mesh.geometry, getClothMesh(world, cape)), 'the geometry equals getClothMesh after 90 steps')
check(mesh.geometry.boundingSphere !== null && mesh.geometry.boundingSphere.center.x > 2, 'the bounds follow the cape')

// a tearable sheet pulled apart by its side pins
const n = 10
const sheet = createCloth(world, { width: 1, height: 1, resolution: n, position: [0, 2, 3] })
const left = addEntity(world), right = addEntity(world)
setTransform(world, left, [0, 0, 0])
setTransform(world, right, [0, 0, 0])
for (let r = 0; r < n; r++) {
  pinParticle(world, sheet, r * n, left)
  pinParticle(world, sheet, r * n + n - 1, right)
}
makeTearable(world, sheet)
const sheetMesh = createClothMesh(world, sheet, new MeshBasicMaterial({ color: 0x3366ff }))
const untornIndex = Array.from(sheetMesh.geometry.index?.array ?? [])
for (let f = 1; f <= 120; f++) {
  setTransform(world, left, [-Math.min(0.5, f * 0.01), 0, 0])
  setTransform(world, right, [Math.min(0.5, f * 0.01), 0, 0])
  stepCloth(world, 1 / 60)
  updateClothGeometry(world, sheet, sheetMesh.geometry)
}
const torn = getClothMesh(world, sheet)
check(getClothTearCount(world, sheet) > 0 && torn.vertexCount > n * n, 'the sheet tore')
check(follows(sheetMesh.geometry, torn), "after tearing, the geometry's index and positions equal the torn mesh's")
check(!sameArray(untornIndex, torn.indices, torn.indices.length), 'the torn index differs from the untorn one')

// one copy of the library behind both entries: an error from bitecs-cloth/three is the main entry's ClothError
try {
  updateClothGeometry(world, sheet, new BufferGeometry())
  check(false, 'a foreign geometry is rejected')
} catch (error) {
  check(error instanceof ClothError && error.argument === 'geometry', 'the error is a ClothError naming the geometry')
}

// threads: the package's own worker script (dist/worker.js) is found without workerUrl, and a
// threaded world steps to the same bytes as one without workers
const crowd = [0, 2].map((threads) => {
  const w = installClothPlugin(createWorld(), { threads, threadMinStepMs: 0 })
  const h = addEntity(w)
  setTransform(w, h, [0, 1.6, 0])
  const capes = [0, 1, 2].map((k) => {
    const c = createCloth(w, { width: 0.5, height: 0.8, resolution: 8, position: [k, 1.5, -0.1] })
    pinRow(w, c, 0, h)
    return c
  })
  for (let f = 1; f <= 60; f++) {
    setTransform(w, h, [f / 30, 1.6, 0])
    beginClothStep(w, 1 / 60)
    endClothStep(w)
  }
  return capes.map((c) => Array.from(getClothState(w, c).pos)).join() + (disposeClothWorld(w), '')
})
check(crowd[0] === crowd[1], 'two workers give the same positions as none')

// the declarations are real types, not any (type-checked, never called)
export function wrongCalls(): void {
  // @ts-expect-error a cloth is an entity number
  createClothGeometry(world, 'cape')
  // @ts-expect-error createCloth needs its options
  createCloth(world)
}

console.log('PACKAGE OK')
