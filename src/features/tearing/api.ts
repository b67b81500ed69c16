import { addComponent, hasComponent, observe, onRemove } from 'bitecs'
import { ClothError, checkInteger, checkPositive, checkKeys, keysOf } from '../../core/errors'
import { getCloth, getClothWorld, getClothWorldForChange } from '../../world/access'
import { growStores } from '../../world/capacity'
import type { ClothWorldState } from '../../world/state'
import { wakeClothState } from '../../world/wake'
import { MAX_MIN_PIECE, reserve } from './reserve'
import { EV, type TearWorld } from './types'
import { newArray } from '../../core/shared'
import { deferrable } from '../../world/flight'

/**
 * Tearing by vertex splitting, grown as cracks.
 *
 * After the solve on a cloth's last substep of a step, every mesh edge is measured (structural
 * edges and the triangles' diagonals, so a load that runs through a sheared diagonal breaks it
 * too); an edge longer than (1 + strain)·rest for `hysteresis` consecutive steps is a candidate.
 * Candidates are visited most strained first, at most `maxTearsPerStep` tears per step, and each
 * may split one of its ends, v (see `crack.ts`, all on the rest shape, where v's fan is
 * undistorted however far the cloth has stretched):
 * - the tension at v is the principal axis of its strained edges (Σ strain·u⊗u); the crack runs
 *   across it, in the cloth's plane;
 * - v's triangles, ordered round v, are cut along the edges of v that best follow the crack: at a
 *   crack's tip (an open fan) once, ahead of the opening, so the crack grows by one edge; inside
 *   the cloth (a closed fan) twice, on either side, which starts a new slit with two tips; where v
 *   only pinches pieces together, the smallest is let go;
 * - the triangles on one side get a new particle v′ (a copy of v: position, velocity, rest
 *   position; v's mass is shared by the rest area of the two sides) and are re-indexed to it. The
 *   renderer shows a real opening because the triangles no longer share the vertex.
 * Cracks grow from their tips: an end at a tip splits first, and a new crack starts at most once a
 * step, and not in a step after a crack grew (a running crack takes the load, as stress is relieved
 * round a real one) unless the edge has stayed over the threshold for four steps more than its
 * hysteresis (a lasting load). A particle splits at most once a step. No split cuts free a piece of
 * fewer than `minPiece` triangles (a bounded flood fill from both sides of the cut), unless an edge
 * is stretched past three times its breaking length: scraps stay attached instead of falling as
 * confetti, and a violent load is still relieved.
 *
 * Every constraint keeps a "support": for each of its particles, a (triangle, corner) it is read
 * from, and the corners that must still coincide for it to make sense. After the splits of a step,
 * one pass over each constraint list re-reads the particles from the triangles and drops what is
 * no longer supported:
 * - an edge constraint (stretch, shear diagonal, stretch measurement, mesh edge) lives in a
 *   triangle; when its two triangles no longer share the edge, it is duplicated, one per side;
 * - a constraint across an edge (quad cross diagonal, bending pair, dihedral hinge) needs its two
 *   triangles to still share that edge, else it is removed;
 * - a skip-one bending pair needs the two edges it spans to still meet at the same middle particle.
 * Tethers are then rebuilt from the split mesh (without allocating): a tether only ties particles
 * to anchors in the same connected piece, so two torn pieces are never held together.
 *
 * A tearable cloth owns a copy of its rest data (the shared topology stays read-only) with room
 * for `capacity` more particles and the constraints their splits add, reserved by `makeTearable`:
 * nothing is allocated in a step, tear or not.
 */

/** Options of `makeTearable`. */
export interface TearableOptions {
  /** Strain at which an edge breaks (0.3 = 30 % longer than rest). Default: the material's `tearStrain`. */
  strain?: number
  /** Most tears per step for this cloth. Default 4. */
  maxTearsPerStep?: number
  /** Extra particles reserved for tears (each tear adds one; tearing stops when they run out). Default: the particle count. */
  capacity?: number
  /** Consecutive steps an edge must stay over the threshold before it breaks. Default 2. */
  hysteresis?: number
  /**
   * Smallest piece, in triangles, a tear may cut free: a split that would leave a smaller piece
   * on its own is not made (such a scrap stays attached instead of falling as confetti). Default 12.
   */
  minPiece?: number
}

const TEARABLE_KEYS = keysOf<TearableOptions>({ strain: true, maxTearsPerStep: true, capacity: true, hysteresis: true, minPiece: true })

/** Creates the per-world tearing state. Called by `installClothPlugin`. */
export function createTearWorld(): TearWorld {
  return {
    pending: new Float64Array(0),
    pendingCount: 0,
    delivering: 0,
    draining: 0,
    queue: new Float64Array(256 * EV),
    queueCount: 0,
    dropped: 0,
    listeners: [],
    // doubles from the start, so refilling the fields never changes their representation
    event: { cloth: 0, x: 0.5, y: 0.5, z: 0.5, particle: 0, newParticle: 0, strain: 0.5 },
  }
}

/** Registers the tearing observers. Called by `installClothPlugin`. */
export function installTearing(world: object, state: ClothWorldState): void {
  // removing Tearable stops tearing; the split mesh stays as it is
  observe(
    world as never,
    onRemove(state.components.Tearable),
    deferrable(state, (eid: number) => {
      const c = state.components.Cloth.state[eid]
      if (c && c.tear) c.tear.enabled = false
    }),
  )
}

/**
 * Makes a cloth tearable (adds the Tearable component). The cloth gets its own copy of its rest
 * data with room for `capacity` more particles, so tearing never allocates. Calling it again
 * changes strain, maxTearsPerStep, hysteresis and minPiece (the capacity is fixed once reserved).
 *
 * @example
 * makeTearable(world, curtain, { strain: 0.25, maxTearsPerStep: 4 })
 * onClothTear(world, (e) => spawnDust(e.x, e.y, e.z))
 */
export function makeTearable(world: object, cloth: number, options: TearableOptions = {}): void {
  const state = getClothWorldForChange(world)
  const c = getCloth(state, cloth)
  if (typeof options !== 'object' || options === null) throw new ClothError('options', options, 'must be an object')
  checkKeys('options', options, TEARABLE_KEYS)
  const strain = options.strain === undefined ? c.material.tearStrain : checkPositive('options.strain', options.strain)
  const maxTears = options.maxTearsPerStep === undefined ? 4 : checkInteger('options.maxTearsPerStep', options.maxTearsPerStep, 1, 4096)
  const hysteresis = options.hysteresis === undefined ? 2 : checkInteger('options.hysteresis', options.hysteresis, 1, 255)
  const minPiece = options.minPiece === undefined ? 12 : checkInteger('options.minPiece', options.minPiece, 1, MAX_MIN_PIECE)
  const extra = options.capacity === undefined ? Math.max(16, c.count) : checkInteger('options.capacity', options.capacity, 0, 1 << 22)
  if (c.tear !== null) {
    if (options.capacity !== undefined && c.count + extra > c.tear.particleCapacity) {
      throw new ClothError('options.capacity', options.capacity, 'cannot grow once the cloth is tearable')
    }
    if (2 * maxTears + 4 > c.tear.cand.length) {
      c.tear.cand = newArray(Int32Array, 2 * maxTears + 4)
      c.tear.candRatio = newArray(Float64Array, 2 * maxTears + 4)
    }
  } else {
    reserve(state, c, extra, maxTears)
  }
  c.tear!.enabled = true
  growStores(state, cloth)
  const T = state.components.Tearable
  T.strain[cloth] = strain
  T.maxTearsPerStep[cloth] = maxTears
  T.hysteresis[cloth] = hysteresis
  T.minPiece[cloth] = minPiece
  if (!hasComponent(world as never, cloth, T)) {
    T.tears[cloth] = 0
    addComponent(world as never, cloth, T)
  }
  // room for one step's tears of every tearable cloth
  let total = 0
  for (const other of state.cloths) if (other.tear) total += state.components.Tearable.maxTearsPerStep[other.eid]
  const tw = state.tearing
  if (tw.pending.length < total * EV) {
    const grown = new Float64Array(total * EV)
    grown.set(tw.pending)
    tw.pending = grown
  }
  wakeClothState(state, c)
}

/** Tears so far of a tearable cloth (0 for any other cloth). */
export function getClothTearCount(world: object, cloth: number): number {
  const state = getClothWorld(world)
  const c = getCloth(state, cloth)
  if (!c.tear) return 0
  // (while the workers step, the last finished step's count: what a world without them gives)
  const th = state.threads
  return (th !== null && th.phase === 1 ? th.finishedTears : state.components.Tearable.tears)[cloth]
}
