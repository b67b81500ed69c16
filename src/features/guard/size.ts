import type { ClothTopology } from '../../model/topology'

/**
 * Longest shortest path along the edges of the rest shape (the geodesic diameter), estimated by a
 * double sweep of Dijkstra per connected piece: from any particle to the farthest one, then from
 * there. Exact on grids and convex sheets; never less than half the true value.
 */
export function restSize(t: ClothTopology): number {
  const n = t.particleCount
  if (n === 0 || t.edgeCount === 0) return 0
  const start = new Int32Array(n + 1)
  for (let e = 0; e < t.edgeCount; e++) {
    start[t.edges[2 * e] + 1]++
    start[t.edges[2 * e + 1] + 1]++
  }
  for (let i = 0; i < n; i++) start[i + 1] += start[i]
  const adj = new Int32Array(start[n])
  const adjLen = new Float64Array(start[n])
  const fill = start.slice(0, n)
  for (let e = 0; e < t.edgeCount; e++) {
    const a = t.edges[2 * e], b = t.edges[2 * e + 1], L = t.edgeRest[e]
    adj[fill[a]] = b
    adjLen[fill[a]++] = L
    adj[fill[b]] = a
    adjLen[fill[b]++] = L
  }
  const dist = new Float64Array(n).fill(Infinity)
  const seen = new Uint8Array(n)
  const heap = new DistHeap(start[n] + n)
  // the particles the last sweep reached ([0] = count): each sweep resets only those, so a mesh of
  // many pieces (or unused vertices, pieces of one) is not quadratic (20,000 quads took 0.8 s)
  const reached = new Int32Array(n + 1)
  let size = 0
  for (let s = 0; s < n; s++) {
    if (seen[s]) continue
    const far = sweep(s, start, adj, adjLen, dist, heap, seen, reached)
    const d = dist[far]
    const back = sweep(far, start, adj, adjLen, dist, heap, null, reached)
    size = Math.max(size, d, dist[back])
  }
  return size
}

/**
 * Dijkstra from `s`; returns the farthest reached particle (distances left in `dist`, Infinity
 * elsewhere: the particles the previous sweep reached, listed in `reached`, are reset first).
 */
function sweep(
  s: number,
  start: Int32Array,
  adj: Int32Array,
  adjLen: Float64Array,
  dist: Float64Array,
  heap: DistHeap,
  seen: Uint8Array | null,
  reached: Int32Array,
): number {
  for (let q = 1; q <= reached[0]; q++) dist[reached[q]] = Infinity
  reached[0] = 0
  dist[s] = 0
  reached[++reached[0]] = s
  heap.clear()
  heap.push(0, s)
  let far = s
  while (heap.size > 0) {
    const d = heap.topKey()
    const i = heap.pop()
    if (d > dist[i]) continue
    if (seen) seen[i] = 1
    if (d > dist[far]) far = i
    for (let k = start[i]; k < start[i + 1]; k++) {
      const j = adj[k]
      const nd = d + adjLen[k]
      if (nd < dist[j]) {
        if (dist[j] === Infinity) reached[++reached[0]] = j
        dist[j] = nd
        heap.push(nd, j)
      }
    }
  }
  return far
}

class DistHeap {
  keys: Float64Array
  vals: Int32Array
  size = 0
  constructor(capacity: number) {
    this.keys = new Float64Array(capacity)
    this.vals = new Int32Array(capacity)
  }
  clear(): void {
    this.size = 0
  }
  topKey(): number {
    return this.keys[0]
  }
  push(key: number, val: number): void {
    if (this.size === this.keys.length) {
      const k = new Float64Array(2 * this.size), v = new Int32Array(2 * this.size)
      k.set(this.keys)
      v.set(this.vals)
      this.keys = k
      this.vals = v
    }
    let i = this.size++
    while (i > 0) {
      const p = (i - 1) >> 1
      if (this.keys[p] <= key) break
      this.keys[i] = this.keys[p]
      this.vals[i] = this.vals[p]
      i = p
    }
    this.keys[i] = key
    this.vals[i] = val
  }
  pop(): number {
    const top = this.vals[0]
    const n = --this.size
    const key = this.keys[n], val = this.vals[n]
    let i = 0
    for (;;) {
      let c = 2 * i + 1
      if (c >= n) break
      if (c + 1 < n && this.keys[c + 1] < this.keys[c]) c++
      if (this.keys[c] >= key) break
      this.keys[i] = this.keys[c]
      this.vals[i] = this.vals[c]
      i = c
    }
    this.keys[i] = key
    this.vals[i] = val
    return top
  }
}
