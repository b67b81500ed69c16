import type { ClothState } from './state'

/**
 * The core section of a cloth's per-step handoff between the main thread and a worker (see
 * `src/threads/handoff.ts`): the cloth's own numbers, its tether settings and the counts of its
 * rest data. The same pair of functions runs both ways: the main thread writes before a step and
 * the worker reads; the worker writes after it and the main thread reads.
 */

export const CORE_HANDOFF = 27

export function writeCoreHandoff(c: ClothState, io: Float64Array, o: number): void {
  io[o] = c.count
  io[o + 1] = c.pieceCount
  io[o + 2] = c.substeps
  io[o + 3] = c.iterations
  io[o + 4] = c.solver === 'pbd' ? 1 : 0
  io[o + 5] = c.damping
  io[o + 6] = c.stretchDamping
  io[o + 7] = c.h
  io[o + 8] = c.subIndex
  io[o + 9] = c.idle ? 1 : 0
  io[o + 10] = c.version
  io[o + 11] = c.accel !== null ? 1 : 0
  const ct = c.tethers
  io[o + 12] = ct.set.count
  io[o + 13] = ct.enabled ? 1 : 0
  io[o + 14] = ct.mode === 'geodesic' ? 1 : 0
  io[o + 15] = ct.slack
  io[o + 16] = ct.perParticle
  io[o + 17] = ct.dirty ? 1 : 0
  const t = c.topology
  io[o + 18] = t.particleCount
  io[o + 19] = t.triangleCount
  io[o + 20] = t.edgeCount
  io[o + 21] = t.stretchCount
  io[o + 22] = t.distCount
  io[o + 23] = t.compCount
  io[o + 24] = t.lineCount
  io[o + 25] = t.hingeCount
  io[o + 26] = ct.loosen ? 1 : 0
}

export function readCoreHandoff(io: Float64Array, o: number, c: ClothState): void {
  c.count = io[o]
  c.pieceCount = io[o + 1]
  c.substeps = io[o + 2]
  c.iterations = io[o + 3]
  c.solver = io[o + 4] === 1 ? 'pbd' : 'xpbd'
  c.damping = io[o + 5]
  c.stretchDamping = io[o + 6]
  c.h = io[o + 7]
  c.subIndex = io[o + 8]
  c.idle = io[o + 9] === 1
  c.version = io[o + 10]
  // the extra acceleration is the wind's buffer or nothing
  c.accel = io[o + 11] === 1 && c.wind !== null ? c.wind.accel : null
  const ct = c.tethers
  // (an empty set is shared and frozen: only a tearable cloth's reused set changes its count)
  if (ct.set.count !== io[o + 12]) ct.set.count = io[o + 12]
  ct.enabled = io[o + 13] === 1
  ct.mode = io[o + 14] === 1 ? 'geodesic' : 'euclidean'
  ct.slack = io[o + 15]
  ct.perParticle = io[o + 16]
  ct.dirty = io[o + 17] === 1
  ct.loosen = io[o + 26] === 1
  // only a tearable cloth's own rest data changes its counts (shared rest data is read-only)
  if (c.tear === null) return
  const t = c.tear.topology
  t.particleCount = io[o + 18]
  t.triangleCount = io[o + 19]
  t.edgeCount = io[o + 20]
  t.stretchCount = io[o + 21]
  t.distCount = io[o + 22]
  t.compCount = io[o + 23]
  t.lineCount = io[o + 24]
  t.hingeCount = io[o + 25]
}
