import type { ClothThreads } from '../world/state'
import { clothFingerprint } from './layout'

/**
 * Verify mode (`ClothThreads.verify`, a test hook): after each step, the main thread compares its
 * fingerprint of every cloth a worker stepped (every number and flag, every array's bytes) with
 * the worker's, before the step (what the worker read) and after it (what it wrote back). A number
 * the handoff forgets, or an array the worker holds a stale copy of, shows up as a difference.
 */

/** Parts of a cloth only the main thread keeps current. */
const MAIN_ONLY = ['.pins.skipTeleport', '.pins.hand', '.character.frame', '.character.frameSlot']

/** Throws when worker `w`'s copies of its cloths differ from the main thread's (call after reading the handoff back). */
export function verifyWorker(th: ClothThreads, w: number): void {
  const buf = th.verifyText[w]
  let text = ''
  for (let i = 0; i < buf[0]; i++) text += String.fromCharCode(buf[i + 1])
  const worker = JSON.parse(text) as { before: Record<number, string[]>; after: Record<number, string[]> }
  const list = th.lists[w]
  for (let i = 1; i <= list[0]; i++) {
    const slot = list[i]
    const b = th.slots[slot]!
    compare(`cloth ${b.cloth.eid} before the step`, th.verifyBefore.get(slot)!, worker.before[slot])
    compare(`cloth ${b.cloth.eid} after the step`, clothFingerprint(b.cloth), worker.after[slot])
  }
}

function compare(what: string, main: string[], worker: string[]): void {
  const keep = (l: string): boolean => !MAIN_ONLY.some((p) => l.startsWith(p + '='))
  const a = main.filter(keep), b = worker.filter(keep)
  const diff: string[] = []
  for (let i = 0; i < Math.max(a.length, b.length); i++) if (a[i] !== b[i]) diff.push(`main ${a[i]} / worker ${b[i]}`)
  if (diff.length > 0) throw new Error(`bitecs-cloth verify: ${what}: ${diff.slice(0, 8).join('; ')}`)
}
