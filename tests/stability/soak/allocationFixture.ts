// Child of soak.test.ts (run by tests/gc.ts's runAllocationFixture: --trace-gc, 1 MB young
// generation): a random game session of SESSION frames from the soak driver, then the same world
// stepped with nothing but Transform writes and stepCloth (pre-boxed frame times), as the
// project's allocation fixture does. Any scavenge between START and END is allocation in a step.
import { setFlagsFromString } from 'node:v8'
import { runInNewContext } from 'node:vm'
import { getClothComponents, getClothStats, stepCloth } from '../../../src/index'
import { generateScript, runScript } from './driver'

const seed = 1
const SESSION = 3000
let world: object | null = null
runScript(generateScript(seed, SESSION), {
  lean: true,
  hash: false,
  checkPins: false,
  onFrame: (_f, w) => {
    world = w
  },
})
const w = world!
const { Transform } = getClothComponents(w)
const heroes = [2, 4, 6]
const FRAMES: unknown[] = [0.015, 0.015, 0.021, 'keeps the elements tagged']
let frame = 0
const step = () => {
  frame++
  for (let k = 0; k < 3; k++) {
    Transform.pz[heroes[k]] += 0.05
    if (Transform.pz[heroes[k]] > 25) Transform.pz[heroes[k]] -= 0.05 * 600 // walks 30 m, then back by 0.05 m steps (no teleport)
  }
  stepCloth(w, FRAMES[frame % 3] as number)
}
for (let f = 0; f < 3000; f++) step() // warm the plain stepping too
// a full collection first: the session's garbage in the old generation had started a major
// collection whose end fell in the window, and the young generation starts empty
setFlagsFromString('--expose-gc')
const gc = runInNewContext('gc') as () => void
gc()
gc()
const s0 = getClothStats(w).steps
console.log('START')
for (let f = 0; f < 10000; f++) step()
console.log('END')
console.log('STEPS ' + (getClothStats(w).steps - s0))
