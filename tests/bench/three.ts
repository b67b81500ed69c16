import { createWorld } from 'bitecs'
import { createCloth, getClothMesh, installClothPlugin, pinRow, stepCloth } from '../../src/index'
import { createClothGeometry, updateClothGeometry } from '../../src/three/index'
import { cpuMs, fmt, saveJson, table } from './harness'

/**
 * Per-frame cost of keeping a three.js geometry up to date (bitecs-cloth/three) on a 64×64 sheet
 * hanging from its top row and swinging: each frame steps the world (not timed), then times
 * getClothMesh (the render normals, which any renderer pays) and updateClothGeometry (its copy of
 * positions and normals and the bounds) apart, and updateClothGeometry alone on other frames.
 */
export function threeCost(): void {
  const n = 64
  const world = installClothPlugin(createWorld(), { sleep: false })
  const cloth = createCloth(world, { width: 2, height: 2, resolution: n, position: [0, 2, 0], rotation: [0.2, 0, 0, 0.98] })
  pinRow(world, cloth, 0)
  const geometry = createClothGeometry(world, cloth)
  let step = 0, mesh = 0, copy = 0, whole = 0, steps = 0, frames = 0
  for (let f = 0; f < 1200; f++) {
    const t0 = cpuMs()
    stepCloth(world, 1 / 60)
    const t1 = cpuMs()
    if (f % 2 === 0) {
      getClothMesh(world, cloth)
      const t2 = cpuMs()
      updateClothGeometry(world, cloth, geometry)
      const t3 = cpuMs()
      if (f >= 200) {
        mesh += t2 - t1
        copy += t3 - t2
      }
    } else {
      updateClothGeometry(world, cloth, geometry)
      const t2 = cpuMs()
      if (f >= 200) {
        whole += t2 - t1
        frames++
      }
    }
    if (f >= 200) {
      step += t1 - t0
      steps++
    }
  }
  const us = (ms: number, count: number) => (1000 * ms) / count
  const row = {
    cloth: `${n}×${n}`,
    'step, µs': fmt(us(step, steps), 1),
    'updateClothGeometry, µs': fmt(us(whole, frames), 1),
    'of which getClothMesh, µs': fmt(us(mesh, steps - frames), 1),
    'copy + bounds µs': fmt(us(copy, steps - frames), 1),
    'update / step ratio': fmt(us(whole, frames) / us(step, steps), 3),
  }
  table('three.js adapter: updateClothGeometry per frame after one step (500 frames each, mean)', [row])
  saveJson('three', row)
}
