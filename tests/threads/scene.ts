// A scene with every feature the threaded step must reproduce: capes on running characters with
// body colliders, a tearing curtain pulled apart in a turbulent wind (and dragged by a grab), two self-colliding sheets
// folded onto the ground (they collide with each other), a sheet that falls asleep and is woken by a
// rolling ball, a world budget with distance levels, a guard reset, and cloths, pins, colliders and
// self-collision added and removed between steps.
import { addEntity, createWorld } from 'bitecs'
import {
  addCapsuleCollider,
  addSphereCollider,
  createCloth,
  createWindZone,
  disableSelfCollision,
  enableSelfCollision,
  getClothState,
  getClothStats,
  getCloths,
  grabParticle,
  gustWind,
  moveGrab,
  releaseGrab,
  installClothPlugin,
  makeTearable,
  onClothReset,
  onClothTear,
  pinParticle,
  removeCloth,
  removeCollider,
  setClothBudget,
  setClothVisible,
  setTransform,
  stepCloth,
  teleportCloth,
  unpin,
  wakeCloth,
  type ClothPluginOptions,
} from '../../src/index'
import { getClothWorld } from '../../src/world/access'
import { hashBytes, rng } from '../helpers'
import { heroWithBody, poseLegs } from '../stability/scenes'
import { accordionSheet, ground } from '../collision/scenes'
import { workerUrl } from './helpers'

export const CALIBRATION = { nsPerParticle: 30, nsPerProjection: 12, nsPerColliderTest: 9, nsPerClothSubstep: 400 }

export interface Run {
  world: object
  frame: (f: number) => void
  /** Tear and reset events seen so far, as text. */
  events: string[]
  hash: () => string
}

/** A tearable 1 m sheet held at its top corners by two hand entities 1 m apart, at x (default 3). */
export function sheetOnHands(world: object, strain: number, x = 3) {
  const hands = [addEntity(world as never), addEntity(world as never)]
  setTransform(world, hands[0], [x - 0.5, 2, 0])
  setTransform(world, hands[1], [x + 0.5, 2, 0])
  const sheet = createCloth(world, { width: 1, height: 1, resolution: 8, position: [x, 2, 0] })
  pinParticle(world, sheet, 0, hands[0])
  pinParticle(world, sheet, 7, hands[1])
  makeTearable(world, sheet, { strain, maxTearsPerStep: 2 })
  return { hands, sheet }
}

/** A world with `threads` workers (0: none), verify mode on, every step handed to the workers. */
export function threadedWorld(threads: number, options: ClothPluginOptions = {}): object {
  const world = installClothPlugin(createWorld(), { threads, workerUrl: workerUrl(), threadMinStepMs: 0, ...options })
  const th = getClothWorld(world).threads
  if (threads > 0 && th === null) throw new Error('no threads')
  if (th !== null) th.verify = true
  return world
}

/** A threaded world as a game makes it (no verify mode: for scenes that remove things mid-frame). */
export function gameWorld(threads: number, options: ClothPluginOptions = {}): object {
  const world = threadedWorld(threads, options)
  const th = getClothWorld(world).threads
  if (th !== null) th.verify = false
  return world
}

export function buildRun(threads: number, seed = 7): Run {
  const world = threadedWorld(threads)
  const r = rng(seed)
  const events: string[] = []
  onClothTear(world, (e) => events.push(`tear ${e.cloth} ${e.particle}>${e.newParticle} ${e.x} ${e.strain}`))
  onClothReset(world, (e) => events.push(`reset ${e.cloth} ${e.reason} ${e.step} ${e.particle} ${e.restoredTo}`))
  const floor = ground(world)
  const heroes = [0, 1, 2].map((k) => {
    const h = heroWithBody(world, { resolution: [7, 9] })
    setTransform(world, h.hero, [3 * k, 1.6, 0])
    return h
  })
  enableSelfCollision(world, heroes[0].cloths[0])
  // a curtain pulled apart by two hands, torn in the wind
  const hands = [addEntity(world), addEntity(world)]
  setTransform(world, hands[0], [-3.5, 2.5, 2])
  setTransform(world, hands[1], [-2.5, 2.5, 2])
  const curtain = createCloth(world, { width: 1, height: 1, resolution: 9, position: [-3, 2.5, 2], bending: 'both' })
  pinParticle(world, curtain, 0, hands[0])
  pinParticle(world, curtain, 8, hands[1])
  makeTearable(world, curtain, { strain: 0.15, maxTearsPerStep: 3 })
  // two folded sheets dropped on each other: particle contacts within and between them
  const folds = [
    accordionSheet(world, { cols: 6, rows: 12, layers: 3, d: 0.05, y0: 0.3, x0: 6 }),
    accordionSheet(world, { cols: 6, rows: 12, layers: 3, d: 0.05, y0: 0.5, x0: 6.1 }),
  ]
  for (const s of folds) enableSelfCollision(world, s)
  // a sheet that settles on the ground and sleeps until the ball rolls through it
  createCloth(world, { width: 0.6, height: 0.6, resolution: 6, position: [9, 0.3, 0], rotation: [-Math.SQRT1_2, 0, 0, Math.SQRT1_2] })
  const ball = addEntity(world)
  setTransform(world, ball, [12, 0.2, 0.3])
  addSphereCollider(world, ball, { radius: 0.2 })
  const breeze = createWindZone(world, {
    shape: 'box',
    position: [-0.5, 2, 1],
    size: [9, 4, 6],
    falloff: 0.2,
    direction: [0.2, 0, 1],
    strength: 5,
    turbulence: 0.4,
    seed: 3,
  })
  const fan = createWindZone(world, { shape: 'box', position: [-3, 2, 1.5], size: [1, 1, 1], direction: [0, 0.3, 1], strength: 10 })
  const camera = addEntity(world)
  setTransform(world, camera, [0, 2, 6])
  setClothBudget(world, { viewer: camera, near: 6, far: 14, msPerFrame: 2, adapt: false, interval: 10, calibration: CALIBRATION })
  let extra = -1, extraPin = -1, pinned = -1, arm = -1, hand = -1
  let t = 0
  const yaw = [0, 0, 0]
  const frame = (f: number): void => {
    const dt = (0.6 + 0.8 * r()) / 60
    t += dt
    heroes.forEach((h, k) => {
      if (k === 2 && f > 200) return // stands still: its cape falls asleep
      yaw[k] += 0.02 + 0.01 * k
      const p = [3 * k + Math.cos(yaw[k]), 1.6, Math.sin(yaw[k])]
      if (k === 1 && f === 333) p[0] += 6 // a teleport (detected: farther than teleportDistance)
      setTransform(world, h.hero, p, [0, Math.sin(-yaw[k] / 2), 0, Math.cos(-yaw[k] / 2)])
      poseLegs({ ...h, world }, p, -yaw[k], t)
    })
    const spread = f < 90 ? 0.015 * f : Math.max(0, 1.35 - 0.03 * (f - 90))
    setTransform(world, hands[0], [-3.5 - spread, 2.5, 2])
    setTransform(world, hands[1], [-2.5 + spread, 2.5, 2 + 0.1 * r()])
    setTransform(world, fan, [-3, 2 + 0.2 * Math.sin(t), 1.5])
    setTransform(world, ball, [f > 400 ? 12 - 0.03 * (f - 400) : 12, 0.2, 0.3])
    setTransform(world, camera, [2 * Math.sin(t / 3), 2, 6])
    if (f % 90 === 45) gustWind(world, breeze, { strength: 8 * r(), duration: 1 })
    // changes between steps: cloths, pins, colliders, self-collision, visibility, teleports
    // a hand grabs the curtain's hem, drags it about and lets go
    if (f === 60) hand = grabParticle(world, curtain, 76, [-3, 1.6, 2.2])
    if (hand >= 0 && f < 300) moveGrab(world, hand, [-3 + 0.3 * Math.sin(t * 2), 1.5, 2.3])
    if (f === 300) releaseGrab(world, hand)
    if (f === 120) {
      extra = createCloth(world, { width: 0.5, height: 0.5, resolution: 5, position: [0, 3, 3] })
      extraPin = pinParticle(world, extra, 0)
    }
    if (f === 150) unpin(world, heroes[1].cloths[0] === -1 ? 0 : getPinsOf(world, heroes[1].cloths[0])[0])
    if (f === 180) pinned = pinParticle(world, heroes[1].cloths[0], 0, heroes[1].hero, [-0.25, -0.1, -0.15])
    if (f === 210) enableSelfCollision(world, extra)
    if (f === 240) {
      arm = addEntity(world)
      addCapsuleCollider(world, arm, { body: heroes[0].hero, offset: [0.25, -0.3, 0], radius: 0.06, halfHeight: 0.25, layer: 2 })
    }
    if (f === 260) setClothVisible(world, heroes[2].cloths[0], false)
    if (f === 300) setClothVisible(world, heroes[2].cloths[0], true)
    if (f === 330) unpin(world, extraPin)
    if (f === 360) removeCollider(world, arm)
    if (f === 390) teleportCloth(world, heroes[0].cloths[0], [0, 0.01, 0])
    if (f === 420) disableSelfCollision(world, folds[1])
    if (f === 450) {
      // poison one cloth: the guard puts it back into its last good pose (a reset event)
      const c = getClothState(world, extra)
      c.vel[4] = NaN
      wakeCloth(world, extra)
    }
    if (f === 480) removeCloth(world, extra)
    if (f === 500) unpin(world, pinned)
    stepCloth(world, dt)
  }
  const hash = (): string => {
    const parts = getCloths(world).map((e) => {
      const c = getClothState(world, e)
      const n = 3 * c.count
      return `${e}:${c.count}:${hashBytes(c.pos.subarray(0, n))}${hashBytes(c.prev.subarray(0, n))}${
        hashBytes(c.vel.subarray(0, n))
      }:${c.sleep.asleep}:${c.substeps}`
    })
    return parts.join(' ') + ' ' + JSON.stringify(getClothStats(world)) + ' ' + floor
  }
  return { world, frame, events, hash }
}

function getPinsOf(world: object, cloth: number): number[] {
  return getClothState(world, cloth).pins.list
}
