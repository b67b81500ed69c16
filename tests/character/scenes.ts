import { addEntity } from 'bitecs'
import { expect } from 'vitest'
import {
  ClothError,
  addPlaneCollider,
  createCloth,
  getClothState,
  makeTearable,
  pinParticle,
  pinRow,
  setClothInertia,
  setClothMotionConstraints,
  setTransform,
  stepCloth,
  unpin,
  type ClothInertiaOptions,
} from '../../src/index'
import { makeWorld } from '../helpers'

export const DT = 1 / 60

/** Yaw quaternion [x, y, z, w] about +y. */
export function yawQuat(a: number): [number, number, number, number] {
  return [0, Math.sin(a / 2), 0, Math.cos(a / 2)]
}

/** World point → the character's frame (position p, yaw a). */
export function toLocal(x: number, y: number, z: number, p: ArrayLike<number>, a: number, out: number[], o: number): void {
  const dx = x - p[0], dy = y - p[1], dz = z - p[2]
  const c = Math.cos(a), s = Math.sin(a)
  // inverse of a yaw by a: rotate by −a about y
  out[o] = c * dx - s * dz
  out[o + 1] = dy
  out[o + 2] = s * dx + c * dz
}

/**
 * The character's motion used by the tests, as position and yaw at time t (s) after the start:
 * standing 0.5 s; a sprint along +x at 10 m/s² to 5 m/s (0.5 s); 0.5 s at 5 m/s; 1 s running at
 * 5 m/s while turning at 3 rad/s; then a dead stop, standing from t = 2.5 s on.
 */
export function sprintTurnStop(t: number): { p: [number, number, number]; yaw: number } {
  const t0 = 0.5, t1 = 1.0, t2 = 1.5, t3 = 2.5
  let x = 0, z = 0, yaw = 0
  if (t <= t0) return { p: [0, 1.6, 0], yaw: 0 }
  const ta = Math.min(t, t1) - t0
  x = 5 * ta * ta // ½·10·t²
  if (t > t1) x += 5 * (Math.min(t, t2) - t1)
  if (t > t2) {
    // running at 5 m/s while turning at 3 rad/s: heading yaw, velocity along the heading
    const tt = Math.min(t, t3) - t2
    yaw = 3 * tt
    // ∫ 5·(cos(3s), 0, −sin(3s)) ds (the heading turns from +x toward −z for a positive yaw about +y)
    x += (5 / 3) * Math.sin(3 * tt)
    z += (5 / 3) * (Math.cos(3 * tt) - 1)
  }
  return { p: [x, 1.6, z], yaw }
}

/**
 * A 0.5 × 0.8 m cape behind a character standing at (0, 1.6, 0) facing +x, neither pinned nor held:
 * it hangs behind the character (−x), its front facing away from the body (−x: a sheet turned by
 * −90° about y), so a backstop (behind the front) lies toward the body.
 */
export function capeBehind(world: object, resolution: [number, number] = [6, 9], iterations = 1): number {
  return createCloth(world, {
    width: 0.5,
    height: 0.8,
    resolution,
    position: [-0.15, 1.55, 0],
    rotation: yawQuat(-Math.PI / 2),
    iterations,
  })
}

/** A cape pinned along its top edge to a character entity standing at the origin, facing +x. */
export function capeOnCharacter(inertia?: ClothInertiaOptions, world = makeWorld()) {
  const hero = addEntity(world)
  setTransform(world, hero, [0, 1.6, 0])
  const cape = capeBehind(world, [8, 12], 4)
  pinRow(world, cape, 0, hero)
  if (inertia) setClothInertia(world, cape, { frame: hero, ...inertia })
  return { world, hero, cape }
}

/** Steps a scene along a motion for `seconds`, calling `sample(f, t)` after each frame. */
export function drive(
  world: object,
  hero: number,
  motion: (t: number) => { p: number[]; yaw: number },
  seconds: number,
  sample?: (f: number, t: number) => void,
): void {
  const frames = Math.round(seconds / DT)
  for (let f = 1; f <= frames; f++) {
    const t = f * DT
    const m = motion(t)
    setTransform(world, hero, m.p, yawQuat(m.yaw))
    stepCloth(world, DT)
    sample?.(f, t)
  }
}

/** The cloth's particles in the character's frame. */
export function localShape(world: object, cloth: number, p: ArrayLike<number>, yaw: number): number[] {
  const c = getClothState(world, cloth)
  const out: number[] = new Array(3 * c.count)
  for (let i = 0; i < c.count; i++) toLocal(c.pos[3 * i], c.pos[3 * i + 1], c.pos[3 * i + 2], p, yaw, out, 3 * i)
  return out
}

/** RMS distance between two shapes (xyz interleaved). */
export function rms(a: ArrayLike<number>, b: ArrayLike<number>): number {
  let s = 0
  for (let j = 0; j < a.length; j++) s += (a[j] - b[j]) ** 2
  return Math.sqrt(s / (a.length / 3))
}

/** `sprintTurnStop`, then a jump at t = 3 s (3 m/s up, back down at t ≈ 3.61 s). */
export function sprintTurnStopJump(t: number): { p: [number, number, number]; yaw: number } {
  const m = sprintTurnStop(t)
  const tj = t - 3
  if (tj > 0) m.p[1] += Math.max(0, 3 * tj - 4.905 * tj * tj)
  return m
}

/** A copy of the cloth's positions now (before any step: its rest shape as placed). */
export function positionsNow(world: object, cloth: number): Float64Array {
  const c = getClothState(world, cloth)
  return c.pos.slice(0, 3 * c.count)
}

/**
 * The reference pose computed independently of the library: the rest shape carried rigidly from
 * the character's pose at bind time (position `p0`, yaw `a0`) to its pose now (`p`, yaw `a`).
 */
export function carriedRest(rest: Float64Array, p0: ArrayLike<number>, a0: number, p: ArrayLike<number>, a: number): Float64Array {
  const out = new Float64Array(rest.length)
  const local = [0, 0, 0]
  const c = Math.cos(a), s = Math.sin(a)
  for (let j = 0; j < rest.length; j += 3) {
    toLocal(rest[j], rest[j + 1], rest[j + 2], p0, a0, local, 0)
    // yaw by a about +y: x' = c·x + s·z, z' = −s·x + c·z
    out[j] = p[0] + c * local[0] + s * local[2]
    out[j + 1] = p[1] + local[1]
    out[j + 2] = p[2] - s * local[0] + c * local[2]
  }
  return out
}

/** Calls `call` with each bad input and expects a ClothError naming the argument given beside it. */
export function expectClothErrors<T>(cases: [T, string][], call: (input: T) => void): void {
  for (const [input, arg] of cases) {
    let error: unknown
    try {
      call(input)
    } catch (e) {
      error = e
    }
    expect(error, arg).toBeInstanceOf(ClothError)
    expect((error as ClothError).argument, arg).toBe(arg)
  }
}

/**
 * The README's cape (wool, 10 × 16, row 0 pinned along the collar) on a character at the origin
 * with inertia 0.5, row 1 held by max distance 0 and `paint(k)` below (k·v² m, v from the collar
 * to the hem, free at the hem): the scene of the mid-run changes in motion.test.ts.
 */
export const RUN_COLS = 10, RUN_ROWS = 16

/** The README's wool cape (0.55 × 1.05 m, cols × rows) behind a character standing at the origin, facing +z, not pinned. */
export function woolCape(world: object, cols: number, rows: number): number {
  return createCloth(world, {
    width: 0.55,
    height: 1.05,
    resolution: [cols, rows],
    position: [0, 1.47, -0.2],
    rotation: [0, 1, 0, 0],
    material: 'wool',
  })
}
/**
 * A 14 × 24 wool cape pinned to a hero at the origin over a ground plane, nailed to the world at
 * its middle row while the hero walks 2 m away (tearing the nailed part off), then unnailed and
 * left 2 s for the piece to fall and settle; `inertia` (shares) makes it a character cloth. `off`:
 * the particles of pieces other than the collar's, `on`: the collar's piece; `z`: where the hero stands.
 */
export function tornCapeOnGround(inertia: number | null) {
  const cols = 14, rows = 24
  const world = makeWorld({ sleep: false })
  const hero = addEntity(world)
  setTransform(world, hero, [0, 0, 0])
  const ground = addEntity(world)
  setTransform(world, ground, [0, 0, 0])
  addPlaneCollider(world, ground)
  const cape = woolCape(world, cols, rows)
  pinRow(world, cape, 0, hero)
  if (inertia !== null) setClothInertia(world, cape, { frame: hero, linear: inertia, angular: inertia, centrifugal: inertia })
  makeTearable(world, cape, { strain: 0.4, maxTearsPerStep: 8 })
  const nail = pinParticle(world, cape, (rows / 2) * cols)
  for (let f = 0; f < 60; f++) {
    setTransform(world, hero, [0, 0, (2 * f) / 60])
    stepCloth(world, DT)
  }
  unpin(world, nail)
  for (let f = 0; f < 120; f++) stepCloth(world, DT)
  const c = getClothState(world, cape)
  const off: number[] = [], on: number[] = []
  for (let i = 0; i < c.count; i++) (c.piece![i] !== c.piece![0] ? off : on).push(i)
  /** Positions of the listed particles now. */
  const at = (list: number[]) => list.map((i) => [c.pos[3 * i], c.pos[3 * i + 1], c.pos[3 * i + 2]])
  /** How far each listed particle is from where `before` had it. */
  const moved = (list: number[], before: number[][]) =>
    at(list).map((p, q) => Math.hypot(p[0] - before[q][0], p[1] - before[q][1], p[2] - before[q][2]))
  return { world, hero, cape, c, cols, off, on, at, moved, z: (2 * 59) / 60 }
}

export function paintRows(k: number): number[] {
  return Array.from({ length: RUN_COLS * RUN_ROWS }, (_, i) => {
    const r = Math.floor(i / RUN_COLS)
    return r === RUN_ROWS - 1 ? Infinity : r <= 1 ? 0 : k * (r / (RUN_ROWS - 1)) ** 2
  })
}
export function runningCape(maxDistance: number[] | null, every = 1, world = makeWorld({ sleep: false })) {
  const hero = addEntity(world)
  setTransform(world, hero, [0, 0, 0])
  const cape = woolCape(world, RUN_COLS, RUN_ROWS)
  pinRow(world, cape, 0, hero)
  setClothInertia(world, cape, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5 })
  if (maxDistance !== null) setClothMotionConstraints(world, cape, { maxDistance, every })
  return { world, hero, cape }
}
