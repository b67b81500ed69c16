// Character cloth in a threaded world: capes in their characters' frames (inertia shares 0.5 and
// speed limits, teleport keep and reset), painted motion constraints (max distance 0 at the collar
// growing to the hem, a backstop, a drive), a sleeve skinned by two turning bones, a tearable
// curtain with held particles; characters that sprint, turn, jump, teleport and snap round; a
// guard reset of a character cloth; character options set, changed and cleared between steps;
// character cloths removed and added.
import { addEntity, removeEntity } from 'bitecs'
import {
  createCloth,
  getClothState,
  getClothStats,
  getCloths,
  makeTearable,
  onClothReset,
  onClothTear,
  pinParticle,
  pinRow,
  removeCloth,
  restoreClothState,
  saveClothState,
  setClothInertia,
  setClothMotionConstraints,
  setClothSkinning,
  setTransform,
  stepCloth,
  teleportCloth,
  wakeCloth,
  type ClothInertiaOptions,
  type ClothMotionConstraints,
  type ClothSnapshot,
} from '../../src/index'
import { hashBytes, rng } from '../helpers'
import { threadedWorld } from './scene'

const yaw = (a: number): number[] => [0, Math.sin(a / 2), 0, Math.cos(a / 2)]

/** Row of each particle of a grid cloth of `cols` columns (0 at the top row). */
const rowsOf = (world: object, cloth: number, cols: number): number[] =>
  Array.from({ length: getClothState(world, cloth).count }, (_, i) => Math.floor(i / cols))

const INERTIA: ClothInertiaOptions = {
  linear: 0.5,
  angular: 0.5,
  centrifugal: 0.5,
  maxLinearSpeed: 4,
  maxAngularSpeed: 2.5,
  teleport: { mode: 'reset', angle: Math.PI / 2 },
}

/** Max distance 0 on the top row (held), growing to the hem; a backstop; a drive stronger at the top. */
function painted(world: object, cloth: number, cols: number, scale = 0.06): ClothMotionConstraints {
  const rows = rowsOf(world, cloth, cols)
  return {
    maxDistance: rows.map((r) => scale * r),
    backstop: { distance: rows.map((r) => 0.01 * r), radius: 0.6 },
    drive: rows.map((r) => Math.max(0, 0.3 - 0.04 * r)),
  }
}

/** Snapshot bytes (every array and number), as text. */
export function snapshotText(s: ClothSnapshot): string {
  return Object.entries(s).map(([k, v]) => {
    if (ArrayBuffer.isView(v)) return `${k}:${hashBytes(v)}`
    if (v !== null && typeof v === 'object')
      return `${k}:{${Object.entries(v).map(([a, b]) => `${a}=${ArrayBuffer.isView(b) ? hashBytes(b) : String(b)}`).join(',')}}`
    return `${k}:${String(v)}`
  }).sort().join(' ')
}

export interface CharacterRun {
  world: object
  /** The tearable curtain with held particles. */
  curtain: number
  frame: (f: number) => void
  events: string[]
  /** Positions, previous positions, velocities of every cloth, and the stats. */
  hash: () => string
  /** The snapshot bytes of every cloth. */
  snapshots: () => string
  /** Saves every cloth's state (by cloth entity) / restores it. */
  save: () => Map<number, ClothSnapshot>
  restore: (saved: Map<number, ClothSnapshot>) => void
}

export function buildCharacterRun(threads: number, seed = 11): CharacterRun {
  const world = threadedWorld(threads)
  const r = rng(seed)
  const events: string[] = []
  onClothTear(world, (e) => events.push(`tear ${e.cloth} ${e.particle}>${e.newParticle} ${e.x}`))
  onClothReset(world, (e) => events.push(`reset ${e.cloth} ${e.reason} ${e.step} ${e.particle} ${e.restoredTo}`))
  // three characters with capes pinned at two collar corners (the rest of the collar held by max distance 0)
  const heroes = [0, 1, 2].map((k) => {
    const e = addEntity(world)
    setTransform(world, e, [3 * k, 1.6, 0])
    return e
  })
  const capes = heroes.map((h, k) => {
    const cape = createCloth(world, {
      width: 0.5,
      height: 0.8,
      resolution: [7, 10],
      position: [3 * k - 0.15, 1.55, 0],
      rotation: yaw(-Math.PI / 2),
      iterations: 3,
    })
    pinParticle(world, cape, 0, h)
    pinParticle(world, cape, 6, h)
    return cape
  })
  setClothInertia(world, capes[0], { frame: heroes[0], ...INERTIA })
  setClothMotionConstraints(world, capes[0], painted(world, capes[0], 7))
  setClothInertia(world, capes[1], { ...INERTIA, teleport: { mode: 'keep', distance: 1.5 } })
  setClothMotionConstraints(world, capes[1], { maxDistance: rowsOf(world, capes[1], 7).map((r) => 0.1 * r) })
  setClothInertia(world, capes[2], { frame: heroes[2], linear: 0.3, angular: 0.7, centrifugal: 0.2 })
  // a sleeve skinned by a shoulder and an elbow bone that turn
  const bones = [addEntity(world), addEntity(world)]
  setTransform(world, bones[0], [-3, 1.4, 0])
  setTransform(world, bones[1], [-2.5, 1.4, 0])
  let sleeve = -1
  const skinSleeve = (): void => {
    const c = getClothState(world, sleeve)
    const joints: number[] = [], weights: number[] = []
    for (let i = 0; i < c.count; i++) {
      const u = Math.min(1, Math.max(0, (c.pos[3 * i] + 2.8) / 0.4))
      joints.push(0, 1, 0, 0)
      weights.push(1 - u, u, 0, 0)
    }
    setClothSkinning(world, sleeve, { bones, joints, weights })
  }
  const makeSleeve = (): void => {
    sleeve = createCloth(world, {
      width: 1,
      height: 0.3,
      resolution: [11, 4],
      position: [-2.5, 1.3, 0],
      rotation: [Math.SQRT1_2, 0, 0, Math.SQRT1_2],
    })
    skinSleeve()
    setClothMotionConstraints(world, sleeve, {
      maxDistance: Array.from({ length: 44 }, (_, i) => (i % 11 === 0 ? 0 : 0.02 * (i % 11))),
      backstop: { distance: 0.01, radius: 0.3 },
      drive: 0.2,
    })
  }
  makeSleeve()
  // a tearable curtain whose top row is held on a reference skinned by two hands pulled apart:
  // tears split held particles
  const hands = [addEntity(world), addEntity(world)]
  setTransform(world, hands[0], [-6.5, 2.5, 2])
  setTransform(world, hands[1], [-5.5, 2.5, 2])
  const curtain = createCloth(world, { width: 1, height: 1, resolution: 9, position: [-6, 2.5, 2] })
  makeTearable(world, curtain, { strain: 0.12, maxTearsPerStep: 3 })
  const u = Array.from({ length: 81 }, (_, i) => (i % 9) / 8)
  setClothSkinning(world, curtain, { bones: hands, joints: u.flatMap(() => [0, 1, 0, 0]), weights: u.flatMap((x) => [1 - x, x, 0, 0]) })
  setClothMotionConstraints(world, curtain, { maxDistance: Array.from({ length: 81 }, (_, i) => (i < 9 ? 0 : i < 18 ? 0.05 : Infinity)) })
  let extra = -1, extraHero = -1
  const heading = [0, 0, 0]
  const pos = [[0, 1.6, 0], [3, 1.6, 0], [6, 1.6, 0]]
  // every input is a function of the frame number (a snapshot's replay sees the same ones)
  const dts = Array.from({ length: 1000 }, () => (0.7 + 0.6 * r()) / 60)
  const frame = (f: number): void => {
    const dt = dts[f]
    const t = f / 60
    // hero 0 sprints and turns, then jumps; hero 1 runs a circle and teleports; hero 2 snaps round
    pos[0] = [0, 1.6, 0]
    heading[0] = 0
    for (let g = 0; g <= f; g++) {
      const sprint = g < 60 ? 0 : g < 120 ? 0.12 * (g - 60) / 60 : 0.12
      heading[0] += g > 150 ? 0.05 : 0
      pos[0][0] += sprint * Math.cos(heading[0])
      pos[0][2] -= sprint * Math.sin(heading[0])
    }
    pos[0][1] = 1.6 + (f > 200 && f < 240 ? 0.05 * (f - 200) - 0.00125 * (f - 200) ** 2 : 0)
    heading[1] = 0.04 * f
    pos[1] = [3 + Math.cos(heading[1]), 1.6, Math.sin(heading[1])]
    if (f >= 170) pos[1][0] += 5 // teleported (keep, 1.5 m)
    if (f >= 330) pos[1][2] += 4
    heading[2] = f < 100 ? 0.01 * f : f < 250 ? Math.PI + 0.01 * f : 0.01 * f // snapped round at 100 and 250 (reset by angle)
    for (let k = 0; k < 3; k++) setTransform(world, heroes[k], pos[k], yaw(heading[k]))
    // the sleeve's bones: the shoulder swings, the elbow bends
    const sw = 0.6 * Math.sin(2 * t), el = 0.9 * Math.sin(3 * t) + 0.9
    setTransform(world, bones[0], [-3, 1.4 + 0.05 * Math.sin(t), 0], [0, 0, Math.sin(sw / 2), Math.cos(sw / 2)])
    const ex = -3 + 0.5 * Math.cos(sw), ey = 1.4 + 0.05 * Math.sin(t) + 0.5 * Math.sin(sw)
    setTransform(world, bones[1], [ex, ey, 0], [0, 0, Math.sin((sw + el) / 2), Math.cos((sw + el) / 2)])
    if (f === 290) setTransform(world, bones[0], [-3, 5.4, 0]) // a bone jumps
    const spread = f < 80 ? 0.012 * f : 0.96
    setTransform(world, hands[0], [-6.5 - spread, 2.5, 2])
    setTransform(world, hands[1], [-5.5 + spread, 2.5, 2 + 0.05 * Math.sin(7 * f)])
    // character options set, changed and cleared between steps
    if (f === 50) makeTearable(world, capes[0], { strain: 0.4, maxTearsPerStep: 2 }) // (grows its character arrays)
    if (f === 90) setClothInertia(world, capes[2], { frame: heroes[2], ...INERTIA, maxLinearSpeed: 1 })
    if (f === 110) setClothMotionConstraints(world, capes[2], painted(world, capes[2], 7, 0.1))
    if (f === 130) setClothMotionConstraints(world, capes[0], { maxDistance: 0.3, drive: 0 })
    if (f === 140) setClothMotionConstraints(world, capes[0], painted(world, capes[0], 7))
    if (f === 160) setClothInertia(world, capes[1], null)
    if (f === 180) setClothInertia(world, capes[1], { ...INERTIA, linear: 0.8, teleport: { mode: 'reset', distance: 1 } })
    if (f === 190) setClothSkinning(world, sleeve, null)
    if (f === 220) skinSleeve()
    if (f === 230) setClothMotionConstraints(world, capes[2], null)
    if (f === 260) setClothInertia(world, capes[2], null) // no character state left
    if (f === 270) setClothMotionConstraints(world, capes[2], painted(world, capes[2], 7))
    if (f === 280) teleportCloth(world, capes[0], [0, 0.02, 0])
    if (f === 300) {
      extraHero = addEntity(world)
      setTransform(world, extraHero, [0, 3, 3])
      extra = createCloth(world, { width: 0.4, height: 0.5, resolution: [5, 6], position: [0, 2.9, 3] })
      pinRow(world, extra, 0, extraHero)
      setClothInertia(world, extra, { frame: extraHero, ...INERTIA })
      setClothMotionConstraints(world, extra, painted(world, extra, 5))
    }
    if (extraHero >= 0 && f > 300) setTransform(world, extraHero, [Math.sin(0.05 * f), 3, 3], yaw(0.03 * f))
    if (f === 320) {
      removeCloth(world, sleeve)
      makeSleeve() // (a recycled id, maybe)
    }
    if (f === 340) {
      // poison a character cloth: the guard puts it back into its last good pose, held particles on their reference
      const c = getClothState(world, capes[0])
      c.vel[40] = NaN
      wakeCloth(world, capes[0])
    }
    if (f === 360) removeCloth(world, capes[1])
    if (f === 370) {
      removeEntity(world, extraHero) // the frame goes away: the cloth keeps its last pose
      extraHero = -1
    }
    stepCloth(world, dt)
  }
  const hash = (): string => {
    const parts = getCloths(world).map((e) => {
      const c = getClothState(world, e)
      const n = 3 * c.count
      return `${e}:${c.count}:${hashBytes(c.pos.subarray(0, n))}${hashBytes(c.prev.subarray(0, n))}${
        hashBytes(c.vel.subarray(0, n))
      }:${c.sleep.asleep}`
    })
    return parts.join(' ') + ' ' + JSON.stringify(getClothStats(world))
  }
  const snapshots = (): string => getCloths(world).map((e) => `${e}=${snapshotText(saveClothState(world, e))}`).join('\n')
  const save = (): Map<number, ClothSnapshot> => new Map(getCloths(world).map((e) => [e, saveClothState(world, e)]))
  const restore = (saved: Map<number, ClothSnapshot>): void => {
    for (const [e, s] of saved) restoreClothState(world, e, s)
  }
  return { world, curtain, frame, events, hash, snapshots, save, restore }
}
