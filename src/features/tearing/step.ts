import { findOverstrained } from '../../kernels/strain'
import type { ClothState, ClothWorldState } from '../../world/state'
import { listLoosePieces } from '../../world/rigid'
import { applySplit, chooseCut, cutsSmallPiece, gatherFan, tensionAt } from './crack'
import { repairConstraints } from './repair'
import { releaseDetachedPieces } from '../character/api'
import { EV, type ClothTear } from './types'

/** New cracks a cloth may start per step; the rest of the step's tears grow cracks that exist. */
const NEW_CRACKS_PER_STEP = 1
/**
 * Steps beyond its hysteresis after which an edge that is still over the threshold counts as a
 * lasting load rather than a passing one: it may start a crack while another runs, and cut along
 * the best edges there are.
 */
const LASTING = 4
/**
 * An edge stretched past this many times its breaking length is torn whatever piece that cuts
 * free: a violent load (a 1000 m/s gust, a teleporting pin) is relieved rather than left to stretch
 * a small piece without bound.
 */
const OVERLOAD = 3

/**
 * Tear phase for one cloth on its last substep of the step: measure, split, repair. The mesh
 * edges over the threshold are visited most strained first; each may split one of its ends. An end
 * at a crack's tip grows that crack; an end elsewhere starts a new one (or a branch), at most
 * `NEW_CRACKS_PER_STEP` per step. A particle splits at most once per step.
 */
export function tearStep(state: ClothWorldState, c: ClothState): void {
  const T = c.tear!
  if (!T.enabled) return
  const store = state.components.Tearable
  const eid = c.eid
  const t = T.topology
  const S = T.edges
  const strain = store.strain[eid]
  const max = store.maxTearsPerStep[eid]
  const minPiece = store.minPiece[eid]
  const p = T.params
  p[0] = (1 + strain) * (1 + strain)
  p[1] = store.hysteresis[eid]
  // more candidates than tears allowed: an edge that cannot split yet must not block the others
  p[2] = Math.min(T.cand.length, 2 * max + 4)
  const n = findOverstrained(c.pos, t.edges, t.edgeRest, S.count, T.over, p, T.cand, T.candRatio)
  state.stats.strainChecks += S.count
  const step = ++T.stepCount
  if (n === 0) return
  // while a crack runs (it grew last step), it takes the load: no new crack starts
  const mayStart = step - T.grewAt > 1
  const tris = t.triangles
  let tears = 0, fresh = 0
  for (let q = 0; q < n; q++) {
    if (c.count >= T.particleCapacity || tears >= max) break
    const k = T.cand[q]
    // the edge's particles now (an earlier split this step may have re-indexed them)
    const tA = S.endT[2 * k]
    const a = tA >= 0 ? tris[3 * tA + S.endC[2 * k]] : t.edges[2 * k]
    const b = tA >= 0 ? tris[3 * S.endT[2 * k + 1] + S.endC[2 * k + 1]] : t.edges[2 * k + 1]
    // the end on a crack first, then the unpinned end
    let first = a, second = b
    if ((T.tip[b] === 1 && T.tip[a] === 0) || (T.tip[a] === T.tip[b] && c.pinCount[a] > 0 && c.pinCount[b] === 0)) {
      first = b
      second = a
    }
    let split = first
    const lasting = T.over[k] >= p[1] + LASTING
    const start = (mayStart || lasting) && fresh < NEW_CRACKS_PER_STEP
    const smallest = T.candRatio[q] > OVERLOAD * OVERLOAD ? 1 : minPiece
    let nv = trySplit(c, T, first, second, step, smallest, start, !lasting)
    if (nv < 0) nv = trySplit(c, T, split = second, first, step, smallest, start, !lasting)
    if (nv < 0 && lasting && tA >= 0) {
      // neither end can split (each holds only this edge's triangles): part the triangle's third
      // particle, where it hangs on to the rest
      const k3 = 3 * tA
      const w = tris[k3] !== a && tris[k3] !== b ? tris[k3] : tris[k3 + 1] !== a && tris[k3 + 1] !== b ? tris[k3 + 1] : tris[k3 + 2]
      nv = trySplit(c, T, split = w, first, step, smallest, start, false)
    }
    if (nv < 0) continue
    if (T.tip[split] === 0) fresh++
    else T.grewAt = step
    // the crack now ends at the seam's far ends; the split particle is no longer a tip
    for (let j = 0; j < 2; j++) if (T.seam[j] >= 0) T.tip[T.seam[j]] = 1
    T.tip[split] = 0
    T.tip[nv] = 0
    T.splitAt[split] = step
    T.splitAt[nv] = step
    T.over[k] = 0
    tears++
    recordTear(state, c, split, nv, q)
  }
  if (tears === 0) return
  repairConstraints(T)
  labelPieces(c, T)
  releaseDetachedPieces(state, c)
  listLoosePieces(state, c)
  if (c.tethers.enabled) c.tethers.dirty = true
  store.tears[eid] += tears
  state.stats.tears += tears
}

/** Queues the event of a tear (split → nv, for candidate q) for the events phase, while there is room. */
function recordTear(state: ClothWorldState, c: ClothState, split: number, nv: number, q: number): void {
  const tw = state.tearing
  if ((tw.pendingCount + 1) * EV > tw.pending.length) return
  const T = c.tear!
  const o = tw.pendingCount++ * EV
  const pos = c.pos
  tw.pending[o] = c.eid
  tw.pending[o + 1] = pos[3 * split]
  tw.pending[o + 2] = pos[3 * split + 1]
  tw.pending[o + 3] = pos[3 * split + 2]
  tw.pending[o + 4] = split
  tw.pending[o + 5] = nv
  tw.pending[o + 6] = Math.sqrt(T.candRatio[q] * T.params[0]) - 1
}

/**
 * Splits v, pulled toward o, with a cut across the tension at v (see `crack.ts`), unless v split
 * this step already, v starts a new crack and `mayStart` is false, no cut fits (`strict`: see
 * `chooseCut`), or the cut would free a piece of fewer than `minPiece` triangles. Returns the new particle or −1.
 */
function trySplit(
  c: ClothState,
  T: ClothTear,
  v: number,
  o: number,
  step: number,
  minPiece: number,
  mayStart: boolean,
  strict: boolean,
): number {
  if (T.splitAt[v] === step) return -1
  if (T.tip[v] === 0 && !mayStart) return -1
  if (gatherFan(T, v) === 0) return -1
  tensionAt(c, T, v, o)
  if (!chooseCut(T, v, strict)) return -1
  if (cutsSmallPiece(T, v, minPiece)) return -1
  return applySplit(c, T, v)
}

/**
 * Labels the connected pieces of the split mesh (triangles joined through shared particles):
 * union-find with the smaller index as root, so labels follow the lowest particle of each piece.
 */
export function labelPieces(c: ClothState, T: ClothTear): void {
  const count = c.count
  const t = T.topology
  const tris = t.triangles
  const root = T.pieceRoot, label = c.piece!
  for (let i = 0; i < count; i++) root[i] = i
  for (let k = 0; k < t.triangleCount; k++) {
    const a = findRoot(root, tris[3 * k])
    const b = findRoot(root, tris[3 * k + 1])
    const c = findRoot(root, tris[3 * k + 2])
    const m = a < b ? (a < c ? a : c) : b < c ? b : c
    root[a] = m
    root[b] = m
    root[c] = m
  }
  let n = 0
  for (let i = 0; i < count; i++) {
    const r = findRoot(root, i)
    label[i] = r === i ? n++ : label[r]
  }
  c.pieceCount = n
}

function findRoot(root: Int32Array, i: number): number {
  while (root[i] !== i) {
    root[i] = root[root[i]]
    i = root[i]
  }
  return i
}
