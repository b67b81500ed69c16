import { allFinite, fit32, fit64 } from '../../core/arrays'
import { ClothError, MAX_SNAPSHOT_COORDINATE } from '../../core/errors'
import { GRAB_STRIDE, G_AT, G_COMPLIANCE, G_MAX_FORCE, G_SAMPLE, G_TO } from '../../kernels/grab'
import type { ClothState, ClothWorldState } from '../../world/state'
import { growGrabs } from './api'

/**
 * The grabs' section of a snapshot: every grab the cloth holds, with its handle, particle, targets
 * (requested, and where the frame's and step's motion stand), grip settings and last force.
 * Restoring makes the cloth's grabs exactly these, under the same handles: a grab released since
 * is active again (its old handle works), a grab made since is released.
 */
export interface GrabSnapshot {
  /** Per grab: handle, particle. */
  grabs: Int32Array
  /** Per grab: `GRAB_STRIDE` doubles (see `kernels/grab.ts`). */
  grabData: Float64Array
}

export function saveGrabs(c: ClothState, s: GrabSnapshot): void {
  const G = c.grab
  const n = G.count
  s.grabs = fit32(s.grabs, 2 * n)
  s.grabData = fit64(s.grabData, GRAB_STRIDE * n)
  for (let g = 0; g < n; g++) {
    s.grabs[2 * g] = G.id[g]
    s.grabs[2 * g + 1] = G.particle[g]
  }
  for (let k = 0; k < GRAB_STRIDE * n; k++) s.grabData[k] = G.data[k]
}

/**
 * Throws ClothError unless the grabs' section is complete and usable for cloth `c` of `n` particles:
 * sizes, finite values, particles in range, and no handle held by another cloth of this world.
 */
export function checkGrabs(state: ClothWorldState, c: ClothState, s: GrabSnapshot, arg: string, n: number): void {
  if (
    !(s.grabs instanceof Int32Array) || !(s.grabData instanceof Float64Array) || s.grabs.length % 2 !== 0 ||
    (s.grabData.length !== (GRAB_STRIDE * s.grabs.length) / 2 && s.grabData.length !== (OLD_STRIDE * s.grabs.length) / 2)
  ) {
    throw new ClothError(arg, s, 'is not a complete snapshot (grab state missing)')
  }
  if (!allFinite(s.grabData)) throw new ClothError(arg, s, 'holds a non-finite number')
  const count = s.grabs.length / 2, stride = strideOf(s)
  for (let g = 0; g < count; g++) {
    const id = s.grabs[2 * g], particle = s.grabs[2 * g + 1]
    const o = stride * g
    if (
      !(id >= 1) || !(particle >= 0 && particle < n) || !(s.grabData[o + G_COMPLIANCE] >= 0 && s.grabData[o + G_COMPLIANCE] <= 1e9) ||
      !(s.grabData[o + G_MAX_FORCE] > 0)
    ) {
      throw new ClothError(arg, s, `holds a bad grab at ${g} (handle, particle out of range, or grip settings grabParticle refuses)`)
    }
    // the targets (requested, frame, step ends, where the hand is): points, as grabParticle takes them
    for (let j = 0; j < stride; j++) {
      if (j === G_AT + 3) {
        if (stride === OLD_STRIDE) break
        j = G_SAMPLE // (grip settings and forces between: checked above or not points)
      }
      if (!(Math.abs(s.grabData[o + j]) <= MAX_SNAPSHOT_COORDINATE))
        throw new ClothError(arg, s, `holds a grab target beyond ±${MAX_SNAPSHOT_COORDINATE} m at ${g}`)
    }
    for (const other of state.cloths) {
      if (other === c) continue
      const G = other.grab
      for (let q = 0; q < G.count; q++) {
        if (G.id[q] === id)
          throw new ClothError(arg, s, `holds grab ${id}, which another cloth (entity ${other.eid}) holds now: release it first`)
      }
    }
  }
}

export function restoreGrabs(state: ClothWorldState, c: ClothState, s: GrabSnapshot): void {
  const G = c.grab
  const n = s.grabs.length / 2
  if (G.id.length < n) growGrabs(G, n)
  G.count = n
  for (let g = 0; g < n; g++) {
    G.id[g] = s.grabs[2 * g]
    G.particle[g] = s.grabs[2 * g + 1]
    // handles stay unique: the world's next handle comes after every restored one
    if (G.id[g] >= state.grab.next) state.grab.next = G.id[g] + 1
  }
  const stride = strideOf(s)
  for (let g = 0; g < n; g++) {
    for (let j = 0; j < stride; j++) G.data[GRAB_STRIDE * g + j] = s.grabData[stride * g + j]
    // (a snapshot of the version before the frame sample was kept: the target asked for)
    if (stride === OLD_STRIDE) { for (let j = 0; j < 3; j++) G.data[GRAB_STRIDE * g + G_SAMPLE + j] = s.grabData[stride * g + G_TO + j] }
  }
}

/** Doubles per grab in snapshots of the version before `G_SAMPLE`, which still restore. */
const OLD_STRIDE = G_SAMPLE

/** Doubles per grab in the snapshot `s` (checked: `GRAB_STRIDE` or `OLD_STRIDE`). */
function strideOf(s: GrabSnapshot): number {
  return s.grabs.length === 0 || s.grabData.length === (GRAB_STRIDE * s.grabs.length) / 2 ? GRAB_STRIDE : OLD_STRIDE
}
