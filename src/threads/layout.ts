import { isShared, sharedCopy, type TypedArray } from '../core/shared'
import type { ClothState, ClothWorldState } from '../world/state'
import { liveColliders } from '../features/collision/list'

/**
 * What a worker needs to know of a cloth besides its numbers: which arrays it holds. A cloth's
 * layout is the list of the arrays in its state, in a fixed walk order, with a marker for each
 * empty branch (no wind buffers, no tearing) and the values of its plain number lists (its pins):
 * two layouts are equal exactly when the cloth holds the same arrays and lists. When the layout
 * epoch moved (`src/core/shared.ts`), the main thread compares each cloth's layout with the one it
 * last sent and sends the cloth again where it differs.
 *
 * Sending a cloth structured-clones its state without the parts only the main thread uses (render
 * buffers, budget): arrays in shared memory arrive as views of the same memory. An array the walk
 * finds outside shared memory (rest data built before, a tether set from a snapshot) is first
 * replaced by a shared copy everywhere the cloth refers to it ("adopted").
 */

/**
 * Parts of a cloth only the main thread reads or writes: the budget, and the render buffers but
 * their texture coordinates (a tear copies them to the particle it makes).
 */
const MAIN_ONLY = new Set(['budget', 'render.positions', 'render.normals', 'render.indices', 'render.version', 'render.mesh'])
/** A cloth's `accel` is its wind buffer or null, set by the step itself: the handoff carries which. */
const DERIVED = 'accel'

/** Copies made by adoption, so an array referred to from several places gets one copy. */
export type AdoptCache = WeakMap<TypedArray, TypedArray>

/** The cloth's layout (see the module comment); with `adopt`, arrays outside shared memory are adopted first. */
export function clothLayout(c: ClothState, adopt: AdoptCache | null): unknown[] {
  const out: unknown[] = []
  walk(c as unknown as Record<string, unknown>, out, adopt, '', new Set())
  return out
}

function walk(o: Record<string, unknown>, out: unknown[], adopt: AdoptCache | null, path: string, seen: Set<object>): void {
  if (seen.has(o)) return
  seen.add(o)
  const frozen = Object.isFrozen(o)
  for (const key of Object.keys(o)) {
    const p = path + key
    if (MAIN_ONLY.has(p) || p === DERIVED) continue
    const v = o[key]
    if (v === null || v === undefined) out.push(null)
    else if (ArrayBuffer.isView(v)) {
      const a = adopt !== null && !frozen ? adoptArray(v as TypedArray, adopt) : v
      if (a !== v) o[key] = a
      out.push(a)
    } else if (Array.isArray(v)) walkList(v, out, adopt, seen)
    else if (typeof v === 'object') walk(v as Record<string, unknown>, out, adopt, p + '.', seen)
  }
}

function walkList(list: unknown[], out: unknown[], adopt: AdoptCache | null, seen: Set<object>): void {
  out.push(list.length)
  for (let i = 0; i < list.length; i++) {
    const v = list[i]
    if (typeof v === 'number') out.push(v)
    else if (v === null || v === undefined) out.push(null)
    else if (ArrayBuffer.isView(v)) {
      const a = adopt !== null ? adoptArray(v as TypedArray, adopt) : v
      if (a !== v) list[i] = a
      out.push(a)
    } else if (typeof v === 'object') walk(v as Record<string, unknown>, out, adopt, '[].', seen)
  }
}

function adoptArray(a: TypedArray, cache: AdoptCache): TypedArray {
  if (isShared(a)) return a
  let copy = cache.get(a)
  if (copy === undefined) {
    copy = sharedCopy(a)
    cache.set(a, copy)
  }
  return copy
}

/** Whether two layouts are equal. */
export function sameLayout(a: unknown[], b: unknown[]): boolean {
  if (a.length !== b.length) return false
  for (let i = 0; i < a.length; i++) if (a[i] !== b[i]) return false
  return true
}

/** The cloth as sent to the workers: its state without the main-thread parts. */
export function clothDescriptor(c: ClothState): object {
  return { ...c, budget: null, render: { uvs: c.render.uvs } }
}

/**
 * The world's part of what the workers read (arrays shared since the world was installed): gravity,
 * the Pin, Tearable and Collider stores, the colliders and wind zones in order, the kinematic step
 * poses and scales, the air density and the compiled wind zones. `pending` sizes the workers' tear
 * event buffers.
 */
export function worldDescriptor(state: ClothWorldState): Record<string, unknown> {
  const k = state.kinematics
  return {
    gravity: state.gravity,
    Pin: state.components.Pin,
    Tearable: state.components.Tearable,
    Collider: state.collision.Collider,
    colliders: liveColliders(state.collision),
    stepFrom: k.stepFrom,
    stepTo: k.stepTo,
    scaleStepFrom: k.scaleStepFrom,
    scaleStepTo: k.scaleStepTo,
    zones: state.wind.zones,
    airDensity: state.wind.airDensity,
    windParams: state.wind.params,
    pending: state.tearing.pending.length,
  }
}

/** The layout of `worldDescriptor(state)`. */
export function worldLayout(descriptor: Record<string, unknown>): unknown[] {
  const out: unknown[] = []
  walk(descriptor, out, null, 'world.', new Set())
  out.push(descriptor.pending)
  return out
}

/**
 * Every number, flag and string of a cloth's state (render buffers and budget aside), with its path,
 * and every array's length: what the main thread and a worker compare in verify mode
 * (`ClothThreads.verify`), so that a number that does not travel shows up as a difference. (The
 * arrays' contents are the same memory on both sides.)
 */
export function clothFingerprint(c: ClothState): string[] {
  const out: string[] = []
  fingerprint(c as unknown as Record<string, unknown>, '', out, new Set())
  return out
}

function fingerprint(o: Record<string, unknown>, path: string, out: string[], seen: Set<object>): void {
  if (seen.has(o)) return
  seen.add(o)
  for (const key of Object.keys(o)) {
    const p = path + '.' + key
    if (MAIN_ONLY.has(p.slice(1))) continue
    const v = o[key]
    if (v === null || v === undefined) out.push(`${p}=null`)
    else if (ArrayBuffer.isView(v)) out.push(`${p}=[${(v as TypedArray).length}]`)
    else if (typeof v === 'object') fingerprint(v as Record<string, unknown>, p, out, seen)
    else if (typeof v !== 'function') out.push(`${p}=${String(v)}`)
  }
}
