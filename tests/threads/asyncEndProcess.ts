// Run by tests/threads/lifecycle.test.ts in a child process: `node asyncEnd.mjs <workerUrl> <frames>`.
// Awaits endClothStepAsync on a threaded world with nothing else keeping Node's event loop alive:
// the wait itself must keep the process running until the workers finish, then let it exit.
import { addEntity, createWorld } from 'bitecs'
import { beginClothStep, createCloth, endClothStepAsync, installClothPlugin, pinRow, setTransform } from '../../src/index'

const [url, frames] = process.argv.slice(2)
const world = installClothPlugin(createWorld(), { threads: 2, requireThreads: true, workerUrl: url })
const hero = addEntity(world)
setTransform(world, hero, [0, 0, 0])
const c = createCloth(world, { width: 1, height: 1, resolution: 24, position: [0, 2, 0] })
pinRow(world, c, 0, hero)
let steps = 0
for (let f = 0; f < Number(frames); f++) {
  setTransform(world, hero, [f / 60, 0, 0])
  beginClothStep(world, 1 / 60)
  console.log('begun', f)
  steps += await endClothStepAsync(world)
}
console.log('async ok', steps)
// (the world is not disposed: with no wait pending, its workers must not hold the process open)
