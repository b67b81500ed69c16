// Straight-line tethers: each particle's K nearest anchors on its own piece of the mesh, by a
// pruned scan (anchors sorted along their widest axis). It must give exactly what comparing every
// particle with every anchor gives, ties to the lower anchor index, on any layout.
import fc from 'fast-check'
import { describe, expect, it } from 'vitest'
import { buildTethers } from '../src/index'

/** Every particle against every anchor, in anchor order, a strictly nearer one replacing: the reference. */
function bruteForce(rest: number[], n: number, edges: number[], anchors: number[], K: number) {
  const island = Array.from({ length: n }, (_, i) => i)
  const find = (i: number): number => (island[i] === i ? i : (island[i] = find(island[i])))
  for (let e = 0; e < edges.length; e += 2) island[find(edges[e])] = find(edges[e + 1])
  const isAnchor = new Set(anchors)
  const unique = [...isAnchor].sort((a, b) => a - b)
  const out: [number, number, number][] = []
  for (let i = 0; i < n; i++) {
    if (isAnchor.has(i)) continue
    const best: [number, number][] = []
    for (const a of unique) {
      if (find(a) !== find(i)) continue
      const d = Math.sqrt(
        (rest[3 * a] - rest[3 * i]) ** 2 + (rest[3 * a + 1] - rest[3 * i + 1]) ** 2 + (rest[3 * a + 2] - rest[3 * i + 2]) ** 2,
      )
      if (best.length === K && d >= best[K - 1][1]) continue
      let k = Math.min(best.length, K - 1)
      best[k] = [a, d]
      while (k > 0 && best[k - 1][1] > d) {
        best[k] = best[k - 1]
        best[k - 1] = [a, d]
        k--
      }
    }
    for (const [a, d] of best) out.push([i, a, d])
  }
  return out
}

describe('straight-line tethers', () => {
  it('are exactly the nearest anchors every pair would give, on grids (ties everywhere), scattered points and several pieces', () => {
    fc.assert(
      fc.property(
        fc.integer({ min: 2, max: 40 }),
        fc.boolean(),
        fc.integer({ min: 1, max: 4 }),
        fc.array(fc.nat(), { minLength: 1, maxLength: 12 }),
        fc.integer({ min: 0, max: 1_000_000 }),
        fc.constantFrom(0.001, 1, 1000),
        (n, onGrid, K, anchorSeeds, seed, size) => {
          let r = seed
          const rand = () => ((r = (r * 1103515245 + 12345) % 2147483648) / 2147483648)
          const rest: number[] = []
          for (let i = 0; i < n; i++) {
            // (sizes from a millimetre to a kilometre: squared distances below and above 1)
            if (onGrid) rest.push(size * (i % 5), size * (Math.floor(i / 5) % 3), 0) // repeated points and equal distances
            else rest.push(size * (rand() * 4 - 2), size * (rand() * 4 - 2), size * rand() * 0.5)
          }
          // a chain with a gap: two pieces, unless n is small
          const edges: number[] = []
          for (let i = 0; i + 1 < n; i++) if (i !== Math.floor(n / 2)) edges.push(i, i + 1)
          const anchors = anchorSeeds.map((a) => a % n)
          const set = buildTethers(rest, n, edges, edges.length / 2, anchors, 'euclidean', K, 0)
          const got = Array.from({ length: set.count }, (_, q) => [set.particle[q], set.anchor[q], set.rest[q]])
          expect(got).toEqual(bruteForce(rest, n, edges, anchors, K))
        },
      ),
      { numRuns: 300, seed: 20261129 },
    )
  })
})
