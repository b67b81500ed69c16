import { join } from 'node:path'
import { describe, expect, it } from 'vitest'
import { runAllocationFixture } from '../gc'
import { workerUrl } from './helpers'

describe('allocation with workers', () => {
  // A step that allocated even 50 bytes would fill a 1 MB young generation every 20,000 frames; on
  // this scene each heap (the main thread's, each worker's) collects at most once in 150,000
  // measured frames, early: a path run for the first time (interpreted, it boxes numbers), such as
  // a wait that timed out on a loaded machine. So the test allows one collection per heap.
  it(
    'a threaded step allocates nothing, on the main thread or in the workers (character cloth included): at most one (first-time) garbage collection per heap in 20,000 frames with a 1 MB young generation',
    async () => {
      process.env.CLOTH_WORKER = workerUrl().href // (the child inherits the environment)
      const run = await runAllocationFixture(join(__dirname, '..', 'fixtures', 'allocation-threads.ts'))
      expect(run.status).toBe(0)
      const perHeap = new Map<string, number>()
      for (const line of run.collections) {
        const heap = /^\[\d+:(0x[0-9a-f]+)\]/.exec(line)?.[1] ?? line
        perHeap.set(heap, (perHeap.get(heap) ?? 0) + 1)
      }
      expect([...perHeap.values()].filter((n) => n > 1), run.collections.join('\n')).toEqual([])
      // the workers did the steps, and the sleeper slept and woke in the measured frames
      expect(Number(/HANDED (\d+)/.exec(run.lines.join('\n'))?.[1])).toBeGreaterThan(15_000)
      expect(Number(/WAKES (\d+)/.exec(run.lines.join('\n'))?.[1])).toBeGreaterThan(20)
      // the dancer's cape was reset to its reference at each of its snaps
      expect(Number(/TELEPORTS (\d+)/.exec(run.lines.join('\n'))?.[1])).toBeGreaterThan(90)
    },
    300_000,
  )
})
