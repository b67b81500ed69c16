import type { vec3 } from 'gl-matrix'
import {
  ClothError,
  checkAtMost,
  checkIndex,
  checkNonNegative,
  checkObject,
  checkOut,
  checkPoint,
  checkPositive,
  checkKeys,
  keysOf,
} from '../../core/errors'
import { GRAB_STRIDE, G_AT, G_COMPLIANCE, G_FORCE, G_FRAME, G_MAX_FORCE, G_SAMPLE, G_STEP_FROM, G_STEP_TO, G_TO } from '../../kernels/grab'
import { grownArray } from '../../core/store'
import { getCloth, getClothWorld, getClothWorldForChange } from '../../world/access'
import type { ClothState, ClothWorldState } from '../../world/state'
import { wakeClothState } from '../../world/wake'
import type { ClothGrabs, GrabWorld } from './types'
import { newArray } from '../../core/shared'

/**
 * Grabbing: a hand (or a mouse) holding one particle of a cloth and pulling it toward a point.
 *
 * A grab is a soft point constraint solved with the cloth's constraints (XPBD, before them in each
 * sweep, so the cloth's own constraints have the last word): it pulls with the stiffness of its
 * `compliance` and never harder than `maxForce`, nor faster than `maxSpeed`. When the cloth pulls
 * back harder than that (a running character whose cape is held), the cloth slips through the grip
 * instead of stretching without bound, the way cloth slips through a hand. A pin, by contrast,
 * holds its particle at any cost.
 *
 * The target moves when `moveGrab` is called; within a frame the grab's target glides from where
 * it stood at the last frame to the new point over the frame's fixed steps and substeps (as pin
 * targets do), so a hand moving at a steady speed pulls at a steady speed whatever the frame rate.
 */

/** Options of `grabParticle`. */
export interface GrabOptions {
  /**
   * Compliance of the grip, m/N: how far the particle trails its target per newton of pull. 0 is
   * a rigid grip (up to `maxForce`), at most 1e9. Default 1e-3 (1 mm per newton).
   */
  compliance?: number
  /**
   * Largest force the grip applies, N. Default: twice the cloth's weight (its mass × 9.81 m/s²):
   * enough to lift the cloth, little enough that a 1-iteration solver holds the load (the running
   * cape of `tests/grab.test.ts` stretches at most 23–31 %). More iterations carry a harder pull.
   * A cloth held by motion constraints (`setClothMotionConstraints`) cannot follow the grip, so it
   * saturates: on the demo cape of a running character, at 1 iteration, twice the weight stretches
   * its worst edge 61 % (median of 12 moments of the run, at most 75 %), the cloth's weight 37 %
   * (at most 41 %; `tests/character/grab.test.ts` bounds the medians under 70 and 43 %, every
   * moment under 85 and 70 %).
   */
  maxForce?: number
}

const GRAB_KEYS = keysOf<GrabOptions>({ compliance: true, maxForce: true })

const DEFAULT_COMPLIANCE = 1e-3
const DEFAULT_FORCE_WEIGHTS = 2
const G0 = 9.81

/** Creates a cloth's (empty) grab list. */
export function createClothGrabs(): ClothGrabs {
  return { count: 0, id: newArray(Int32Array, 0), particle: newArray(Int32Array, 0), data: newArray(Float64Array, 0) }
}

/** Creates the per-world grab state. */
export function createGrabWorld(): GrabWorld {
  return { next: 1 }
}

/**
 * Grabs particle `index` of `cloth` and pulls it toward the world point `target` (see the options
 * for the grip's stiffness and limits). Returns a grab handle for `moveGrab` and `releaseGrab`.
 * A pinned particle stays on its pin (the grab pulls it once it is unpinned); after a tear the
 * grab holds the particle with this index, which keeps the triangles on one side of the tear.
 *
 * @example
 * const hand = grabParticle(world, flag, nearest, hitPoint)
 * moveGrab(world, hand, pointUnderMouse) // every frame while dragging
 * releaseGrab(world, hand) // the particle keeps its velocity
 */
export function grabParticle(
  world: object,
  cloth: number,
  index: number,
  target: Readonly<vec3> | ArrayLike<number>,
  options: GrabOptions = {},
): number {
  const state = getClothWorldForChange(world)
  const c = getCloth(state, cloth)
  checkIndex('index', index, c.count)
  checkPoint('target', target)
  checkObject('options', options)
  checkKeys('options', options, GRAB_KEYS)
  const compliance = options.compliance === undefined ? DEFAULT_COMPLIANCE
    : checkAtMost('options.compliance', checkNonNegative('options.compliance', options.compliance), 1e9, ' m/N')
  const maxForce = options.maxForce === undefined ? defaultMaxForce(c) : checkPositive('options.maxForce', options.maxForce)
  const G = c.grab
  if (G.count === G.id.length) growGrabs(G, Math.max(2, 2 * G.count))
  const g = G.count++
  const id = nextGrabId(state.grab)
  G.id[g] = id
  G.particle[g] = index
  const o = GRAB_STRIDE * g
  G.data.fill(0, o, o + GRAB_STRIDE)
  for (const slot of [G_TO, G_FRAME, G_STEP_FROM, G_STEP_TO, G_AT, G_SAMPLE]) for (let j = 0; j < 3; j++) G.data[o + slot + j] = target[j]
  G.data[o + G_COMPLIANCE] = compliance
  G.data[o + G_MAX_FORCE] = maxForce
  wakeClothState(state, c)
  return id
}

/** Moves a grab's target to the world point `target` (it glides there over the next frame's steps). */
export function moveGrab(world: object, grab: number, target: Readonly<vec3> | ArrayLike<number>): void {
  const state = getClothWorldForChange(world)
  const c = findGrab(state, grab)
  const g = indexOf(c.grab, grab)
  checkPoint('target', target)
  const o = GRAB_STRIDE * g + G_TO
  for (let j = 0; j < 3; j++) c.grab.data[o + j] = target[j]
  wakeClothState(state, c)
}

/**
 * Lets go: the particle keeps its velocity (no pop). Returns false, doing nothing, when the grab is
 * no longer active (released already, or its cloth was removed), so a host may release on every
 * pointer-up without tracking what happened meanwhile.
 */
export function releaseGrab(world: object, grab: number): boolean {
  const state = getClothWorldForChange(world)
  checkHandle(grab)
  const c = locateGrab(state, grab)
  if (c === null) return false
  const G = c.grab
  const g = indexOf(G, grab)
  // keep the others in order (the order they are solved in)
  for (let q = g + 1; q < G.count; q++) {
    G.id[q - 1] = G.id[q]
    G.particle[q - 1] = G.particle[q]
    G.data.copyWithin(GRAB_STRIDE * (q - 1), GRAB_STRIDE * q, GRAB_STRIDE * (q + 1))
  }
  G.count--
  wakeClothState(state, c)
  return true
}

/** Whether `grab` is an active grab of this world (not released, its cloth not removed). */
export function isGrabActive(world: object, grab: number): boolean {
  const state = getClothWorld(world)
  checkHandle(grab)
  return locateGrab(state, grab) !== null
}

/** The active grabs of a cloth, in the order they were made (a copy). */
export function getGrabs(world: object, cloth: number): number[] {
  const G = getCloth(getClothWorld(world), cloth).grab
  return Array.from(G.id.subarray(0, G.count))
}

/** The grabbed particle of an active grab. */
export function getGrabParticle(world: object, grab: number): number {
  const c = findGrab(getClothWorld(world), grab)
  return c.grab.particle[indexOf(c.grab, grab)]
}

/**
 * The force the grab applied to its particle, averaged over the last fixed step, N (a vector,
 * written into `out`). Its length never exceeds the grab's `maxForce`; by Newton's third law the
 * hand feels the opposite force.
 */
export function getGrabForce(world: object, grab: number, out: vec3 | number[] = [0, 0, 0]): vec3 | number[] {
  const c = findGrab(getClothWorld(world), grab)
  const g = indexOf(c.grab, grab)
  checkOut('out', out, 3)
  const o = GRAB_STRIDE * g + G_FORCE
  // (while the workers step, the last finished step's force: what a world without them gives)
  const th = getClothWorld(world).threads
  const data = th !== null && th.phase === 1 ? th.finishedGrabs.get(c)! : c.grab.data
  for (let j = 0; j < 3; j++) out[j] = data[o + j]
  return out
}

/** Default grip limit: twice the cloth's weight (its particles' masses, pinned ones included: a given `mass` or `masses` too). */
function defaultMaxForce(c: ClothState): number {
  const w = c.baseInvMass
  let total = 0
  for (let i = 0; i < c.count; i++) if (w[i] > 0) total += 1 / w[i] // (a vertex no triangle uses has none)
  return DEFAULT_FORCE_WEIGHTS * total * G0
}

function checkHandle(grab: unknown): asserts grab is number {
  if (typeof grab !== 'number' || !Number.isInteger(grab) || grab < 1)
    throw new ClothError('grab', grab, 'must be a grab handle returned by grabParticle')
}

/** The cloth holding an active grab, or null. */
function locateGrab(state: ClothWorldState, grab: number): ClothState | null {
  const cloths = state.cloths
  for (let ci = 0; ci < cloths.length; ci++) if (indexOf(cloths[ci].grab, grab) >= 0) return cloths[ci]
  return null
}

function indexOf(G: ClothGrabs, grab: number): number {
  for (let g = 0; g < G.count; g++) if (G.id[g] === grab) return g
  return -1
}

/** The cloth holding an active grab, or a ClothError naming `grab`. */
function findGrab(state: ClothWorldState, grab: number): ClothState {
  checkHandle(grab)
  const c = locateGrab(state, grab)
  if (c === null) throw new ClothError('grab', grab, 'is not an active grab (it was released, or its cloth was removed)')
  return c
}

/** A new handle: unique in the world for its lifetime (2³¹ − 1 grabs), so a stale handle never finds a later grab. */
function nextGrabId(w: GrabWorld): number {
  if (w.next >= 0x7fffffff) throw new ClothError('grab', w.next, 'handles of this world are used up (2³¹ − 1 grabs)')
  return w.next++
}

/** Grows a cloth's grab arrays to hold `n` grabs (API time). */
export function growGrabs(G: ClothGrabs, n: number): void {
  G.id = grownArray(G.id, n)
  G.particle = grownArray(G.particle, n)
  G.data = grownArray(G.data, GRAB_STRIDE * n)
}
