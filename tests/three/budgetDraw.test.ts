// Cloths the budget holds back, drawn with updateClothDrawMatrix: a frozen cloth's mesh shows it
// where it froze and a far one's its own last step, while the draw transform was measured from the
// world's last step. A cape frozen while its character walked 6 m was drawn 6 m off its character,
// so a game hiding cloths its camera cannot see (the README's frustum loop) never saw it again, and
// a far cape stepping every 4th step was drawn up to 15 cm off its pins at 3 m/s.
import { addEntity } from 'bitecs'
import { Frustum, Matrix4, PerspectiveCamera } from 'three'
import { describe, expect, it } from 'vitest'
import { createCloth, getClothLod, getClothMesh, pinRow, setClothBudget, setClothVisible, setTransform, stepCloth } from '../../src/index'
import { createClothMesh, updateClothDrawMatrix, updateClothGeometry } from '../../src/three/index'
import { makeWorld } from '../helpers'

/** A cape on a hero walking at 3 m/s; the largest distance between its drawn pinned row and where its pins hold it. */
function walk(mode: 'frozen' | 'every 4th') {
  const world = makeWorld({ sleep: false })
  const viewer = addEntity(world)
  setTransform(world, viewer, [0, 0, 0])
  const hero = addEntity(world)
  const z0 = mode === 'every 4th' ? 50 : 0
  setTransform(world, hero, [0, 0, z0])
  const cols = 8
  const cape = createCloth(world, { width: 0.5, height: 0.8, resolution: [cols, 12], position: [0, 1.5, z0 - 0.1] })
  pinRow(world, cape, 0, hero)
  const mesh = createClothMesh(world, cape)
  const rest = Array.from(getClothMesh(world, cape).positions.slice(0, 3 * cols))
  setClothBudget(world, mode === 'frozen' ? { viewer, near: 100, far: 200 } : { viewer, near: 5, far: 10, farStepEvery: 4 })
  for (let f = 0; f < 30; f++) stepCloth(world, 1 / 60)
  if (mode === 'frozen') setClothVisible(world, cape, false)
  let worst = 0
  for (let f = 1; f <= 120; f++) {
    const x = 0.05 * f
    setTransform(world, hero, [x, 0, z0])
    stepCloth(world, 1 / 60)
    updateClothGeometry(world, cape, mesh.geometry)
    updateClothDrawMatrix(world, cape, mesh)
    mesh.updateMatrixWorld(true)
    const e = mesh.matrixWorld.elements
    const p = mesh.geometry.getAttribute('position').array as Float32Array
    for (let i = 0; i < cols; i++) {
      const px = p[3 * i], py = p[3 * i + 1], pz = p[3 * i + 2]
      const dx = e[0] * px + e[4] * py + e[8] * pz + e[12]
      const dy = e[1] * px + e[5] * py + e[9] * pz + e[13]
      const dz = e[2] * px + e[6] * py + e[10] * pz + e[14]
      worst = Math.max(worst, Math.hypot(dx - (rest[3 * i] + x), dy - rest[3 * i + 1], dz - rest[3 * i + 2]))
    }
  }
  return { worst, lod: getClothLod(world, cape) }
}

describe('drawing cloths the budget holds back', () => {
  it('frozen while its character walks 6 m: drawn on its pins (was 6 m off)', () => {
    const r = walk('frozen')
    expect(r.lod.frozen).toBe(true)
    expect(r.worst).toBeLessThan(1e-5) // (float32 mesh positions)
  })

  it('stepping every 4th step: drawn on its pins between its steps (was 15 cm off)', () => {
    const r = walk('every 4th')
    expect(r.lod.stepEvery).toBe(4)
    expect(r.worst).toBeLessThan(1e-5)
  })

  it("a game hiding what its camera cannot see (the README's loop) sees the cape again when it looks back", () => {
    const world = makeWorld({ sleep: false })
    const viewer = addEntity(world)
    setTransform(world, viewer, [0, 0, 0])
    const hero = addEntity(world)
    setTransform(world, hero, [0, 0, 0])
    const cape = createCloth(world, { width: 0.5, height: 0.8, resolution: [8, 12], position: [0, 1.5, -0.1] })
    pinRow(world, cape, 0, hero)
    setClothBudget(world, { viewer, near: 100, far: 200 })
    const mesh = createClothMesh(world, cape)
    const camera = new PerspectiveCamera(50, 1, 0.1, 100)
    const frustum = new Frustum(), m = new Matrix4()
    let x = 0, seen = 0
    for (let f = 1; f <= 360; f++) {
      if (f > 60 && f <= 180) x += 0.05 // walks 6 m while the camera looks up at the sky
      setTransform(world, hero, [x, 0, 0])
      stepCloth(world, 1 / 60)
      updateClothGeometry(world, cape, mesh.geometry)
      updateClothDrawMatrix(world, cape, mesh)
      mesh.updateMatrixWorld(true)
      camera.position.set(x, 1.5, 4)
      if (f >= 50 && f <= 200) camera.lookAt(x, 50, 4.01)
      else camera.lookAt(x, 1.2, 0)
      camera.updateMatrixWorld(true)
      frustum.setFromProjectionMatrix(m.multiplyMatrices(camera.projectionMatrix, camera.matrixWorldInverse))
      const visible = frustum.intersectsObject(mesh)
      setClothVisible(world, cape, visible)
      if (f > 260 && visible) seen++
    }
    expect(getClothLod(world, cape).frozen).toBe(false)
    expect(seen).toBe(100) // (was 0: its bounds stayed where it froze, 6 m away)
  })
})
