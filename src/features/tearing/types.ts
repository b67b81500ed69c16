import type { AnchorScratch, TetherSet } from '../../model/tethers'
import type { ClothTopology } from '../../model/topology'

/** One tear: where and in which cloth a particle was split. */
export interface ClothTearEvent {
  /** The cloth entity. */
  cloth: number
  /** World position of the split, m. */
  x: number
  y: number
  z: number
  /** The particle that was split and the new particle made from it. */
  particle: number
  newParticle: number
  /** Strain of the edge that broke (0.35 = 35 % longer than rest). */
  strain: number
}

export type ClothTearListener = (event: Readonly<ClothTearEvent>) => void

/** Values per queued event: cloth, x, y, z, particle, newParticle, strain. */
export const EV = 7

/** Per-world tearing state: event buffers and listeners. */
export interface TearWorld {
  /** Tears of the current step, EV doubles each (sized for every tearable cloth's cap). */
  pending: Float64Array
  pendingCount: number
  /** Events of `pending` being handed to the listeners (after the step; 0 otherwise). */
  delivering: number
  /** Events waiting for `drainClothTears`. */
  queue: Float64Array
  queueCount: number
  /** Events of `queue` being handed to a `drainClothTears` callback (0 otherwise). */
  draining: number
  /** Events that found the drain queue full (nobody drained it). */
  dropped: number
  listeners: ClothTearListener[]
  /** The one event object handed to listeners (refilled for each event). */
  event: ClothTearEvent
}

export type Mutable<T> = { -readonly [K in keyof T]: T[K] }
export type TearTopology = Mutable<ClothTopology>

/**
 * A list of two-particle constraints with its support (see the module comment). `ids`, `f64` and
 * `u8` alias the topology's arrays; entries are re-read and compacted after splits.
 */
export interface PairSet {
  /** Particles, each stored as index × `scale` (3 for the distance constraints' position offsets). */
  ids: Int32Array
  scale: number
  f64: Float64Array[]
  u8: Uint8Array[]
  /** The hysteresis counters (the mesh edges, which the tear phase measures): reset on duplicates. */
  over: Uint8Array | null
  count: number
  cap: number
  /** Triangle and corner each particle is read from (−1: fixed particles, no support). */
  endT: Int32Array
  endC: Uint8Array
  /** Up to two checks (t, t′) whose corners (c, c′) must hold the same particle; −1 = none. */
  chkT: Int32Array
  chkC: Uint8Array
  /** Edge constraints: the second triangle of the edge (−1 none) and its corners. */
  twinT: Int32Array
  twinC: Uint8Array
}

/** Dihedral hinges with support: e0, e1, w0 from triangle A, w1 from triangle B. */
export interface HingeSet {
  ids: Int32Array
  f64: Float64Array[]
  count: number
  endT: Int32Array
  endC: Uint8Array
  chkT: Int32Array
  chkC: Uint8Array
}

/** Line-bending triples with support: a and v from triangle A (edge a–v), b from triangle B (edge v–b). */
export interface LineSet {
  ids: Int32Array
  f64: Float64Array[]
  count: number
  endT: Int32Array
  endC: Uint8Array
  /** v as seen from A and from B: the triple breaks when they differ. */
  chkT: Int32Array
  chkC: Uint8Array
}

/** Tearing state of one cloth (`ClothState.tear`). */
export interface ClothTear {
  enabled: boolean
  /** The cloth's own rest data (also `ClothState.topology`). */
  topology: TearTopology
  particleCapacity: number
  stretch: PairSet
  edges: PairSet
  dist: PairSet
  comp: PairSet
  lines: LineSet
  hinges: HingeSet
  over: Uint8Array
  /**
   * Triangles around each particle: vertTris[vertStart[p] .. vertStart[p] + vertLen[p]). A split
   * divides its particle's slice between the two (built once by `makeTearable`, kept current).
   */
  vertStart: Int32Array
  vertLen: Int32Array
  vertTris: Int32Array
  /** 1 for the particles at a crack's tip (reached by a crack, not split since): cracks grow from them. */
  tip: Uint8Array
  /** The tear step in which each particle was last split (a particle splits once per step). */
  splitAt: Int32Array
  /** Tear steps run (the stamp of `splitAt`). */
  stepCount: number
  /** The last tear step in which a crack grew at a tip. */
  grewAt: number
  /**
   * Split scratch (see `crack.ts`): the fan of the particle being split (triangle, v's corner, the
   * two other particles, which side it goes to), its order in chains, the seam's far ends.
   */
  fan: Int32Array
  fanCorner: Uint8Array
  fanSide: Uint8Array
  fanP: Int32Array
  fanQ: Int32Array
  fanCount: number
  walk: Int32Array
  walkW: Int32Array
  chains: Int32Array
  chainEntry: Int32Array
  chainCount: number
  seam: Int32Array
  /** Direction scratch (tension, normal, crack direction) and the tension matrix. */
  vec: Float64Array
  mat: Float64Array
  /** Flood-fill scratch of the smallest-piece test: side by triangle, visit stamps, queue. */
  triSide: Uint8Array
  seen: Int32Array
  stamp: number
  queue: Int32Array
  /** Candidate edges of the step, most strained first. */
  cand: Int32Array
  candRatio: Float64Array
  /** Strain-check parameters: (1 + strain)², hysteresis, max candidates. */
  params: Float64Array
  tethers: TetherSet
  scratch: AnchorScratch
  /** Union-find scratch for labelling the connected pieces (`ClothState.piece`). */
  pieceRoot: Int32Array
}
