/**
 * Long-range attachments (Kim, Chentanez, Müller-Fischer, SCA 2012): every free particle is tied
 * to its nearest pinned particles by a one-sided constraint that only acts when the particle is
 * farther from the pin than its rest distance (times 1 + slack). Tension reaches the hem within a
 * single projection, so a hanging cloth cannot stretch away from its pins however few iterations
 * run, while folds and wrinkles (which bring particles closer) are untouched.
 */

export type TetherMode = 'euclidean' | 'geodesic'

/** Tether list: particle i is kept within `rest` of anchor particle `anchor`. */
export interface TetherSet {
  particle: Int32Array
  anchor: Int32Array
  rest: Float64Array
  count: number
}

export const EMPTY_TETHERS: TetherSet = Object.freeze({
  particle: new Int32Array(0),
  anchor: new Int32Array(0),
  rest: new Float64Array(0),
  count: 0,
}) as TetherSet

/**
 * Builds tethers from every non-anchor particle to its `perParticle` nearest anchors.
 * Distances are measured on the rest shape: straight-line ('euclidean') or along mesh edges
 * ('geodesic', which follows a curved or folded rest shape). Only anchors reachable through
 * `edges` count, so separate pieces (islands, torn parts) are never tied together.
 *
 * @param rest rest positions, xyz interleaved
 * @param count live particle count
 * @param edges mesh edges, 2 indices each
 * @param anchors particle indices of the pinned particles
 */
export function buildTethers(
  rest: ArrayLike<number>,
  count: number,
  edges: ArrayLike<number>,
  edgeCount: number,
  anchors: ArrayLike<number>,
  mode: TetherMode,
  perParticle: number,
  slack: number,
): TetherSet {
  if (anchors.length === 0 || perParticle <= 0) return EMPTY_TETHERS
  const isAnchor = new Uint8Array(count)
  for (let k = 0; k < anchors.length; k++) isAnchor[anchors[k]] = 1
  const uniqueAnchors: number[] = []
  for (let i = 0; i < count; i++) if (isAnchor[i]) uniqueAnchors.push(i)

  const adj = adjacency(count, edges, edgeCount)
  const K = perParticle
  const bestAnchor = new Int32Array(count * K).fill(-1)
  const bestDist = new Float64Array(count * K).fill(Infinity)

  if (mode === 'geodesic') {
    kNearestDijkstra(rest, count, adj, uniqueAnchors, K, bestAnchor, bestDist)
  } else {
    const island = islands(count, adj)
    for (let i = 0; i < count; i++) {
      if (isAnchor[i]) continue
      for (const a of uniqueAnchors) {
        if (island[a] !== island[i]) continue
        const d = distance(rest, i, a)
        insertBest(bestAnchor, bestDist, i * K, K, a, d)
      }
    }
  }

  let total = 0
  for (let i = 0; i < count; i++) {
    if (isAnchor[i]) continue
    for (let k = 0; k < K; k++) if (bestAnchor[i * K + k] >= 0) total++
  }
  const out: TetherSet = {
    particle: new Int32Array(total),
    anchor: new Int32Array(total),
    rest: new Float64Array(total),
    count: total,
  }
  let t = 0
  for (let i = 0; i < count; i++) {
    if (isAnchor[i]) continue
    for (let k = 0; k < K; k++) {
      const a = bestAnchor[i * K + k]
      if (a < 0) continue
      out.particle[t] = i
      out.anchor[t] = a
      out.rest[t] = bestDist[i * K + k] * (1 + slack)
      t++
    }
  }
  return out
}

function distance(p: ArrayLike<number>, a: number, b: number): number {
  const x = p[3 * b] - p[3 * a], y = p[3 * b + 1] - p[3 * a + 1], z = p[3 * b + 2] - p[3 * a + 2]
  return Math.sqrt(x * x + y * y + z * z)
}

/** Keeps the K smallest (distance, anchor) entries in a sorted slot list, without duplicates. */
function insertBest(anchor: Int32Array, dist: Float64Array, base: number, K: number, a: number, d: number): boolean {
  for (let k = 0; k < K; k++) if (anchor[base + k] === a) return false
  if (d >= dist[base + K - 1]) return false
  let k = K - 1
  while (k > 0 && dist[base + k - 1] > d) {
    dist[base + k] = dist[base + k - 1]
    anchor[base + k] = anchor[base + k - 1]
    k--
  }
  dist[base + k] = d
  anchor[base + k] = a
  return true
}

interface Adjacency {
  start: Int32Array
  list: Int32Array
}

function adjacency(n: number, edges: ArrayLike<number>, edgeCount: number): Adjacency {
  const start = new Int32Array(n + 1)
  for (let e = 0; e < edgeCount; e++) {
    start[edges[2 * e] + 1]++
    start[edges[2 * e + 1] + 1]++
  }
  for (let i = 0; i < n; i++) start[i + 1] += start[i]
  const list = new Int32Array(start[n])
  const fill = start.slice(0, n)
  for (let e = 0; e < edgeCount; e++) {
    const a = edges[2 * e], b = edges[2 * e + 1]
    list[fill[a]++] = b
    list[fill[b]++] = a
  }
  return { start, list }
}

/** Connected-component label per particle. */
function islands(n: number, adj: Adjacency): Int32Array {
  const label = new Int32Array(n).fill(-1)
  const stack = new Int32Array(n)
  let next = 0
  for (let s = 0; s < n; s++) {
    if (label[s] >= 0) continue
    let top = 0
    stack[top++] = s
    label[s] = next
    while (top > 0) {
      const i = stack[--top]
      for (let k = adj.start[i]; k < adj.start[i + 1]; k++) {
        const j = adj.list[k]
        if (label[j] < 0) {
          label[j] = next
          stack[top++] = j
        }
      }
    }
    next++
  }
  return label
}

/**
 * Multi-source Dijkstra that settles each particle up to K times, once per distinct anchor, so
 * every particle learns its K geodesically nearest anchors in O(K·E·log E).
 */
function kNearestDijkstra(
  rest: ArrayLike<number>,
  n: number,
  adj: Adjacency,
  anchors: number[],
  K: number,
  bestAnchor: Int32Array,
  bestDist: Float64Array,
): void {
  const settled = new Int32Array(n)
  const heap = new MinHeap()
  for (const a of anchors) heap.push(0, a, a)
  while (heap.size > 0) {
    const d = heap.topKey()
    const node = heap.topNode()
    const src = heap.topSource()
    heap.pop()
    if (settled[node] >= K) continue
    const base = node * K
    let seen = false
    for (let k = 0; k < settled[node]; k++) if (bestAnchor[base + k] === src) seen = true
    if (seen) continue
    bestAnchor[base + settled[node]] = src
    bestDist[base + settled[node]] = d
    settled[node]++
    for (let k = adj.start[node]; k < adj.start[node + 1]; k++) {
      const j = adj.list[k]
      if (settled[j] < K) heap.push(d + distance(rest, node, j), j, src)
    }
  }
  // anchors record themselves first; the caller skips anchors, so nothing else to undo
}

/** Binary min-heap over (key, node, source) triples in parallel growable arrays. */
class MinHeap {
  private keys: number[] = []
  private nodes: number[] = []
  private sources: number[] = []
  get size(): number {
    return this.keys.length
  }
  topKey(): number {
    return this.keys[0]
  }
  topNode(): number {
    return this.nodes[0]
  }
  topSource(): number {
    return this.sources[0]
  }
  push(key: number, node: number, source: number): void {
    const k = this.keys, nd = this.nodes, s = this.sources
    let i = k.length
    k.push(key)
    nd.push(node)
    s.push(source)
    while (i > 0) {
      const p = (i - 1) >> 1
      if (k[p] <= key) break
      k[i] = k[p]
      nd[i] = nd[p]
      s[i] = s[p]
      i = p
    }
    k[i] = key
    nd[i] = node
    s[i] = source
  }
  pop(): void {
    const k = this.keys, nd = this.nodes, s = this.sources
    const lastK = k.pop()!, lastN = nd.pop()!, lastS = s.pop()!
    const size = k.length
    if (size === 0) return
    let i = 0
    for (;;) {
      let c = 2 * i + 1
      if (c >= size) break
      if (c + 1 < size && k[c + 1] < k[c]) c++
      if (k[c] >= lastK) break
      k[i] = k[c]
      nd[i] = nd[c]
      s[i] = s[c]
      i = c
    }
    k[i] = lastK
    nd[i] = lastN
    s[i] = lastS
  }
}
