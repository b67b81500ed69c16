// The page of tests/e2e/threads.e2e.ts: the same scene (capes on running characters with body
// capsules, a torn curtain, a turbulent wind) stepped without workers and on two Web Workers,
// frame by frame with beginClothStep / endClothStepAsync, then the positions compared.
import { addEntity, createWorld } from 'bitecs'
import {
  addCapsuleCollider,
  beginClothStep,
  createCloth,
  createWindZone,
  disposeClothWorld,
  endClothStepAsync,
  getClothState,
  getClothStats,
  installClothPlugin,
  makeTearable,
  pinParticle,
  pinRow,
  setTransform,
  stepCloth,
} from '../../../src/index'
import { getClothWorld } from '../../../src/world/access'

function scene(threads: number, workerUrl: string) {
  const world = installClothPlugin(createWorld(), { threads, workerUrl, threadMinStepMs: 0 })
  const heroes = [0, 1, 2, 3].map((k) => {
    const hero = addEntity(world)
    setTransform(world, hero, [2 * k + 1, 1.6, 0])
    addCapsuleCollider(world, addEntity(world), { body: hero, offset: [0, -0.4, 0], radius: 0.17, halfHeight: 0.25 })
    pinRow(world, createCloth(world, { width: 0.6, height: 1, resolution: 12, position: [2 * k + 1, 1.62, -0.2] }), 0, hero)
    return hero
  })
  const hands = [addEntity(world), addEntity(world)]
  setTransform(world, hands[0], [-1.5, 2.5, 2])
  setTransform(world, hands[1], [-0.5, 2.5, 2])
  const curtain = createCloth(world, { width: 1, height: 1, resolution: 10, position: [-1, 2.5, 2] })
  pinParticle(world, curtain, 0, hands[0])
  pinParticle(world, curtain, 9, hands[1])
  makeTearable(world, curtain, { strain: 0.2, maxTearsPerStep: 2 })
  createWindZone(world, { direction: [0.3, 0, 1], strength: 5, turbulence: 0.4 })
  const animate = (f: number) => {
    heroes.forEach((h, k) => {
      const a = 0.05 * f + k
      setTransform(world, h, [2 * k + 1 + Math.cos(a), 1.6, Math.sin(a)], [0, Math.sin(-a / 2), 0, Math.cos(-a / 2)])
    })
    const spread = Math.min(1, 0.015 * f)
    setTransform(world, hands[0], [-1.5 - spread, 2.5, 2])
    setTransform(world, hands[1], [-0.5 + spread, 2.5, 2])
  }
  return { world, animate }
}

async function run(steps: number): Promise<unknown> {
  const workerUrl = new URL('./worker.js', import.meta.url).href
  const one = scene(0, workerUrl), two = scene(2, workerUrl)
  let mainMs = 0
  for (let f = 0; f < steps; f++) {
    for (const s of [one, two]) s.animate(f)
    beginClothStep(one.world, 1 / 60)
    const t0 = performance.now()
    beginClothStep(two.world, 1 / 60)
    mainMs += performance.now() - t0
    await endClothStepAsync(one.world)
    await endClothStepAsync(two.world)
  }
  // stepCloth waits for the workers too: on a page's main thread, which may not Atomics.wait, by spinning
  for (let f = steps; f < steps + 10; f++) {
    for (const s of [one, two]) {
      s.animate(f)
      stepCloth(s.world, 1 / 60)
    }
  }
  let same = true, particles = 0
  const cloths = (w: object) => getClothWorld(w).cloths
  const a = cloths(one.world), b = cloths(two.world)
  for (let i = 0; i < a.length; i++) {
    const pa = getClothState(one.world, a[i].eid).pos, pb = getClothState(two.world, b[i].eid).pos
    particles += a[i].count
    for (let j = 0; j < 3 * a[i].count; j++) if (!Object.is(pa[j], pb[j])) same = false
  }
  const threads = getClothWorld(two.world).threads
  const result = {
    isolated: crossOriginIsolated,
    threads: threads === null ? 0 : threads.pool.workers.length,
    handed: threads === null ? 0 : threads.step,
    same,
    particles,
    tears: getClothStats(one.world).tears,
    mainMsPerFrame: mainMs / steps,
  }
  disposeClothWorld(two.world)
  return result
}

/**
 * stepCloth right after a threaded world is made, before its workers could load their script
 * (which a page's workers do through the page's event loop, blocked while this runs): the steps
 * run on this thread until the workers are up, then on them, the same bytes as without workers.
 */
async function stepAtOnce(): Promise<unknown> {
  const workerUrl = new URL('./worker.js', import.meta.url).href
  const one = scene(0, workerUrl), two = scene(2, workerUrl)
  const threads = getClothWorld(two.world).threads!
  const t0 = performance.now()
  for (let f = 0; f < 20; f++) {
    for (const s of [one, two]) {
      s.animate(f)
      stepCloth(s.world, 1 / 60)
    }
  }
  const syncMs = performance.now() - t0
  const handedAtOnce = threads.step
  // then frames with the event loop running between them, until the workers take steps
  let f = 20
  for (; f < 400 && threads.step === handedAtOnce; f++) {
    await new Promise((resolve) => setTimeout(resolve, 20))
    for (const s of [one, two]) {
      s.animate(f)
      stepCloth(s.world, 1 / 60)
    }
  }
  for (const end = f + 10; f < end; f++) {
    for (const s of [one, two]) {
      s.animate(f)
      stepCloth(s.world, 1 / 60)
    }
  }
  let same = true
  const a = getClothWorld(one.world).cloths, b = getClothWorld(two.world).cloths
  for (let i = 0; i < a.length; i++) {
    const pa = getClothState(one.world, a[i].eid).pos, pb = getClothState(two.world, b[i].eid).pos
    for (let j = 0; j < 3 * a[i].count; j++) if (!Object.is(pa[j], pb[j])) same = false
  }
  const result = { syncMs, handedAtOnce, handed: threads.step, frames: f, same }
  disposeClothWorld(two.world)
  return result
}

/** The error `requireThreads` gives on this page (null when it gives none). */
function requireThreads(): string | null {
  try {
    disposeClothWorld(
      installClothPlugin(createWorld(), { threads: 2, requireThreads: true, workerUrl: new URL('./worker.js', import.meta.url).href }),
    )
    return null
  } catch (e) {
    return `${(e as Error).name}: ${(e as Error).message}`
  }
}

;(globalThis as { runThreads?: typeof run }).runThreads = run
;(globalThis as { requireThreads?: typeof requireThreads }).requireThreads = requireThreads
;(globalThis as { stepAtOnce?: typeof stepAtOnce }).stepAtOnce = stepAtOnce
;(globalThis as { pageReady?: boolean }).pageReady = true
