import type { ClothThreads, ClothWorldState } from '../world/state'
import { clothLayersMatch } from '../features/collision/reach'
import { configCost } from '../features/budget/levels'
import type { LevelConfig } from '../features/budget/types'

/**
 * Shares the cloths out among the workers for one step. Each cloth's cost is the budget's cost
 * model at the substeps and iterations it runs this step (0 when it sits the step out); cloths that
 * may collide with each other (self-colliding cloths whose layers match, transitively) form a group
 * that goes to one worker whole, because their particle–particle contacts interleave. A cloth stays
 * with its worker from step to step while that keeps the loads within 25 % of even (so the workers
 * keep their cloths' memory warm and their lists unchanged); otherwise the groups are shared out
 * again, most expensive first, each to the worker with the least work so far (longest processing
 * time first). Each worker's list keeps creation order, the order every phase visits cloths in.
 * Which worker steps a cloth never changes its result: its computation reads only its own arrays
 * (and its group's), the same code on the same data.
 */

/** Cost model numbers (ns: per particle, per projection, per collider test, per cloth and substep, per triangle in the wind) when the world has no calibration; only their ratios matter here. */
const DEFAULT_CALIBRATION = Float64Array.of(25, 12, 10, 400, 60)
const cfg: LevelConfig = { substeps: 0, iterations: 0, stepEvery: 0, cost: 0, logQuality: 0 }
/** Largest load over the mean load a kept partition may reach. */
const IMBALANCE = 1.25

/** Fills `th.lists` for this step; returns the predicted cost of the step, ns (all workers together). */
export function partitionCloths(state: ClothWorldState, th: ClothThreads): number {
  const cloths = state.cloths
  const n = cloths.length
  const cal = state.budget.calibration ?? DEFAULT_CALIBRATION
  const cost = th.cost, group = th.group, owner = th.order, assign = th.assign
  for (let ci = 0; ci < n; ci++) {
    const c = cloths[ci]
    group[ci] = ci
    if (c.idle) cost[ci] = 0
    else {
      configCost(c, c.substeps, c.iterations, 1, cal, cfg)
      cost[ci] = cfg.cost
    }
  }
  joinColliding(state, th)
  // group costs summed at each root (a root is its group's lowest index)
  for (let ci = 0; ci < n; ci++) {
    const r = find(group, ci)
    if (r !== ci) cost[r] += cost[ci]
  }
  const workers = th.lists.length
  const load = th.load
  load.fill(0)
  let total = 0
  // keep last step's workers when every group is on one worker and the loads stay near even
  let keep = true
  for (let ci = 0; ci < n && keep; ci++) {
    const w = assign[th.bindings.get(cloths[ci])!.slot]
    const r = find(group, ci)
    if (w < 0 || w >= workers) keep = false
    else if (r === ci) {
      owner[ci] = w
      load[w] += cost[ci]
      total += cost[ci]
    } else if (owner[r] !== w) keep = false
  }
  if (keep) { for (let w = 0; w < workers; w++) if (load[w] > (IMBALANCE * total) / workers) keep = false }
  if (!keep) total = shareOut(th, n)
  for (let w = 0; w < workers; w++) th.lists[w][0] = 0
  for (let ci = 0; ci < n; ci++) {
    const slot = th.bindings.get(cloths[ci])!.slot
    const w = owner[find(group, ci)]
    assign[slot] = w
    const list = th.lists[w]
    list[++list[0]] = slot
  }
  return total
}

/** Longest processing time first: each group, most expensive first, to the least loaded worker (into `owner` at the group's root). */
function shareOut(th: ClothThreads, n: number): number {
  const cost = th.cost, group = th.group, owner = th.order, load = th.load
  const order = th.sorted
  let roots = 0
  for (let ci = 0; ci < n; ci++) if (group[ci] === ci) order[roots++] = ci
  // roots by cost, largest first (insertion sort: a few dozen groups, no allocation)
  for (let i = 1; i < roots; i++) {
    const r = order[i]
    let j = i - 1
    while (j >= 0 && cost[order[j]] < cost[r]) {
      order[j + 1] = order[j]
      j--
    }
    order[j + 1] = r
  }
  const workers = th.lists.length
  load.fill(0)
  let total = 0
  for (let i = 0; i < roots; i++) {
    let best = 0
    for (let w = 1; w < workers; w++) if (load[w] < load[best]) best = w
    load[best] += cost[order[i]]
    total += cost[order[i]]
    owner[order[i]] = best
  }
  return total
}

/** Unites the groups of self-colliding cloths that may touch each other. */
function joinColliding(state: ClothWorldState, th: ClothThreads): void {
  const self = state.collision.selfCloths
  if (self.length < 2) return
  const cloths = state.cloths
  const group = th.group
  // index of each self-colliding cloth in `cloths` (both lists are in creation order)
  const at = th.sorted
  let ci = 0
  for (let a = 0; a < self.length; a++) {
    while (cloths[ci] !== self[a]) ci++
    at[a] = ci
  }
  for (let a = 0; a < self.length; a++) {
    for (let b = a + 1; b < self.length; b++) {
      if (!clothLayersMatch(self[a].collision, self[b].collision)) continue
      const ra = find(group, at[a]), rb = find(group, at[b])
      if (ra !== rb) group[ra < rb ? rb : ra] = ra < rb ? ra : rb
    }
  }
}

function find(group: Int32Array, i: number): number {
  while (group[i] !== i) {
    group[i] = group[group[i]]
    i = group[i]
  }
  return i
}
