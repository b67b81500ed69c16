import { addEntity, createWorld, removeEntity } from 'bitecs'
import {
  addBoxCollider,
  addCapsuleCollider,
  addConvexHullCollider,
  addPlaneCollider,
  addSphereCollider,
  clothCollide,
  clothForces,
  clothPredict,
  clothSolve,
  clothSubstepCount,
  clothSync,
  clothTear,
  clothWriteback,
  createCloth,
  enableSelfCollision,
  getClothState,
  getClothStats,
  installClothPlugin,
  pinParticle,
  pinRow,
  resetClothStats,
  setClothSubstep,
  setTransform,
  stepCloth,
} from '../../src/index'
import { cpuMs, fmt, saveJson, table } from './harness'

const FLAT: [number, number, number, number] = [-Math.SQRT1_2, 0, 0, Math.SQRT1_2]

/** One fixed step run phase by phase, timing only the collide phase; returns its milliseconds. */
function stepTimingCollide(world: object): number {
  clothSync(world)
  let ms = 0
  const n = clothSubstepCount(world)
  for (let s = 0; s < n; s++) {
    setClothSubstep(world, s)
    clothForces(world)
    clothPredict(world)
    clothSolve(world)
    const t0 = cpuMs()
    clothCollide(world)
    ms += cpuMs() - t0
    clothTear(world)
    clothWriteback(world)
  }
  return ms
}

/** Median of an array. */
function median(a: number[]): number {
  const b = a.slice().sort((x, y) => x - y)
  return b[b.length >> 1]
}

/**
 * Collision cost per particle test, per collider type, collide phase alone: a 64×64 sheet (1 m)
 * draped over the collider (every particle tested, many touching), and the same sheet hanging
 * from its top row with the collider in range but not touching it (every test a miss).
 */
export function perCollider(): void {
  const rows: Record<string, string | number>[] = []
  const shapes: [string, (w: object, e: number) => void][] = [
    ['sphere', (w, e) => addSphereCollider(w, e, { radius: 0.3 })],
    ['capsule', (w, e) => addCapsuleCollider(w, e, { radius: 0.15, halfHeight: 0.3, axis: [1, 0, 0] })],
    ['box', (w, e) => addBoxCollider(w, e, { halfExtents: [0.3, 0.2, 0.25] })],
    ['hull, 18 planes', (w, e) => addConvexHullCollider(w, e, { points: prism(0.3, 0.15, 16) })],
    ['hull, 34 planes', (w, e) => addConvexHullCollider(w, e, { points: prism(0.3, 0.15, 32) })],
    ['plane', (w, e) => addPlaneCollider(w, e)],
  ]
  const measure = (world: object) => {
    resetClothStats(world)
    const times: number[] = []
    const steps = 200
    for (let f = 0; f < steps; f++) times.push(stepTimingCollide(world))
    const tests = getClothStats(world).colliderTests / steps
    return { tests, ms: median(times) }
  }
  for (const [name, add] of shapes) {
    const world = installClothPlugin(createWorld(), { sleep: false })
    const e = addEntity(world)
    setTransform(world, e, [0, 0.5, 0])
    add(world, e)
    createCloth(world, { width: 1, height: 1, resolution: 64, position: [0.03, 1, -0.48], rotation: FLAT })
    for (let f = 0; f < 120; f++) stepCloth(world, 1 / 60)
    const draped = measure(world)
    // beside a hanging sheet: in its bounds, 2 cm or more from every particle
    const near = installClothPlugin(createWorld(), { sleep: false })
    const cloth = createCloth(near, { width: 1, height: 1, resolution: 64, position: [0, 1.5, 0] })
    pinRow(near, cloth, 0)
    const f = addEntity(near)
    if (name === 'plane') setTransform(near, f, [0, 0.49 - 0.005, 0])
    else setTransform(near, f, [0.75, 1, 0.28])
    add(near, f)
    for (let k = 0; k < 60; k++) stepCloth(near, 1 / 60)
    const miss = measure(near)
    rows.push({
      collider: name,
      'draped: ms per step': fmt(draped.ms, 3),
      'draped over it: ns per particle test': fmt((draped.ms * 1e6) / draped.tests, 1),
      'in range: ms per step': fmt(miss.ms, 3),
      'in range, not touching: ns per test': fmt((miss.ms * 1e6) / Math.max(1, miss.tests), 1),
      'tests per step': draped.tests,
    })
  }
  table(
    'Collision cost per particle test (64×64 sheet, 8 substeps, collide phase only): draped over the collider, and hanging beside it in range',
    rows,
  )
  saveJson('collision-per-collider', rows)
}

function prism(radius: number, halfHeight: number, sides: number): number[] {
  const pts: number[] = []
  for (let k = 0; k < sides; k++) {
    const a = (2 * Math.PI * k) / sides
    pts.push(radius * Math.cos(a), -halfHeight, radius * Math.sin(a), radius * Math.cos(a), halfHeight, radius * Math.sin(a))
  }
  return pts
}

/**
 * Self-collision as a share of the step: a sheet laid in four accordion folds one particle
 * spacing apart drops onto the ground and settles; the same scene with and without
 * self-collision, stepped in alternation so both see the same machine load.
 */
export function selfShare(): void {
  const rows: Record<string, string | number>[] = []
  for (const n of [32, 64]) {
    const make = (self: boolean) => {
      const world = installClothPlugin(createWorld(), { sleep: false })
      const ground = addEntity(world)
      setTransform(world, ground, [0, 0, 0])
      addPlaneCollider(world, ground)
      const size = 1, s = size / (n - 1), layers = 4, per = n / layers
      const cloth = createCloth(world, { width: size, height: size, resolution: n })
      const c = getClothState(world, cloth)
      for (let r = 0; r < n; r++) {
        const layer = Math.floor(r / per), k = r % per
        for (let col = 0; col < n; col++) {
          const i = r * n + col
          c.pos[3 * i] = -size / 2 + col * s
          c.pos[3 * i + 1] = 0.1 + layer * s
          c.pos[3 * i + 2] = layer % 2 === 0 ? k * s : (per - 1 - k) * s
        }
      }
      c.prev.set(c.pos)
      if (self) enableSelfCollision(world, cloth)
      return world
    }
    const on = make(true), off = make(false)
    const tOn: number[] = [], tOff: number[] = [], tCollide: number[] = []
    for (let f = 0; f < 60; f++) {
      stepCloth(on, 1 / 60)
      stepCloth(off, 1 / 60)
    }
    resetClothStats(on)
    const steps = 240
    for (let f = 0; f < steps; f++) {
      let t0 = cpuMs()
      tCollide.push(stepTimingCollide(on))
      tOn.push(cpuMs() - t0)
      t0 = cpuMs()
      stepTimingCollide(off)
      tOff.push(cpuMs() - t0)
    }
    const stats = getClothStats(on)
    const msOn = median(tOn), msOff = median(tOff)
    rows.push({
      sheet: `${n}×${n}, 4 folds`,
      'ms per step without': fmt(msOff, 3),
      'ms per step with': fmt(msOn, 3),
      'self-collision share': `${fmt((100 * (msOn - msOff)) / msOn, 0)} %`,
      'collide phase ms': fmt(median(tCollide), 3),
      'pair tests per step': Math.round(stats.selfCollisionTests / steps),
    })
  }
  table('Self-collision cost (sheet dropped in folds onto the ground, 8 substeps, with vs without)', rows)
  saveJson('collision-self', rows)
}

/**
 * A cloth with colliders out of its range against the same cloth with none: a 64×64 sheet
 * hanging from two corners, eight colliders (all shapes) 10 m away. Blocks of steps alternate
 * between the two worlds; the ratio of medians is reported.
 */
export function outOfRange(): void {
  const make = (colliders: boolean) => {
    const world = installClothPlugin(createWorld(), { sleep: false })
    const cloth = createCloth(world, { width: 1, height: 1, resolution: 64 })
    pinParticle(world, cloth, 0)
    pinParticle(world, cloth, 63)
    if (colliders) {
      for (let k = 0; k < 8; k++) {
        const e = addEntity(world)
        setTransform(world, e, [10 + k, 1, 0])
        if (k % 4 === 0) addSphereCollider(world, e, { radius: 0.3 })
        else if (k % 4 === 1) addCapsuleCollider(world, e, { radius: 0.2, halfHeight: 0.3 })
        else if (k % 4 === 2) addBoxCollider(world, e, { halfExtents: [0.3, 0.3, 0.3] })
        else addConvexHullCollider(world, e, { points: prism(0.3, 0.3, 12) })
      }
      const ground = addEntity(world)
      setTransform(world, ground, [0, -5, 0])
      addPlaneCollider(world, ground)
    }
    for (let f = 0; f < 60; f++) stepCloth(world, 1 / 60)
    resetClothStats(world)
    return world
  }
  const none = make(false), far = make(true)
  const tNone: number[] = [], tFar: number[] = []
  const block = 10
  for (let b = 0; b < 60; b++) {
    for (const [world, out] of [[none, tNone], [far, tFar]] as const) {
      const t0 = cpuMs()
      for (let f = 0; f < block; f++) stepCloth(world, 1 / 60)
      out.push((cpuMs() - t0) / block)
    }
  }
  const a = median(tNone), b = median(tFar)
  const rows = [{
    scene: '64×64 hanging, 8 substeps',
    'ms per step, no colliders': fmt(a, 3),
    'ms per step, 9 colliders out of range': fmt(b, 3),
    ratio: fmt(b / a, 3),
    'collider tests': getClothStats(far).colliderTests,
  }]
  table('Colliders out of range cost nothing per particle (blocks of 10 steps alternating, medians)', rows)
  saveJson('collision-out-of-range', rows)
}

/**
 * A level unloading: N colliders on N/10 bodies (ten colliders on entities of their own per body,
 * as a character's), one cloth in the world; the bodies removed in creation order, then in
 * reverse. Reports the ms per collider unloaded at 2,500 and 20,000 and their ratio: a cost per
 * removal that grew with the world (a splice per collider, a pass over all of them per body) made
 * it 8× at 8× the colliders; linear, it stays near 1.
 */
export function unload(): void {
  const run = (n: number, reverse: boolean) => {
    const world = installClothPlugin(createWorld())
    createCloth(world, { width: 1, height: 1, resolution: 8, position: [0, 2, 0] })
    const bodies: number[] = []
    for (let b = 0; b < n / 10; b++) {
      const body = addEntity(world)
      setTransform(world, body, [b % 100, 0, Math.floor(b / 100)])
      bodies.push(body)
      for (let k = 0; k < 10; k++) addSphereCollider(world, addEntity(world), { body, radius: 0.2, offset: [0, 0.1 * k, 0] })
    }
    stepCloth(world, 1 / 60)
    if (reverse) bodies.reverse()
    const t0 = cpuMs()
    for (const body of bodies) removeEntity(world, body)
    stepCloth(world, 1 / 60) // (the list is compacted at the next read)
    return (cpuMs() - t0) / n
  }
  const rows = [false, true].map((reverse) => {
    const small: number[] = [], large: number[] = []
    for (let r = 0; r < 3; r++) {
      small.push(run(2500, reverse))
      large.push(run(20000, reverse))
    }
    const a = median(small), b = median(large)
    return {
      order: reverse ? 'newest body first' : 'oldest body first',
      'µs per collider, 2,500': fmt(1000 * a, 2),
      'µs per collider, 20,000': fmt(1000 * b, 2),
      ratio: fmt(b / a, 2),
    }
  })
  table('Unloading colliders: cost per collider removed (bodies of 10, medians of 3)', rows)
  saveJson('collision-unload', rows)
}
