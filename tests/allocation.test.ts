import { join } from 'node:path'
import { describe, expect, it } from 'vitest'
import { runAllocationFixture } from './gc'

describe('allocation', () => {
  it(
    'a step allocates nothing: no garbage collection in 50,000 steps with a 1 MB young generation (cape, pins, uneven frames, mesh reads)',
    async () => {
      const run = await runAllocationFixture(join(__dirname, 'fixtures', 'allocation-scene.ts'))
      expect(run.status).toBe(0)
      expect(run.collections).toEqual([])
      expect(run.lines).toContain('RESETS 2') // the guard checked every step and reset the cape twice before
    },
    300_000,
  ) // 50,000 steps in a child process: about 20 s on an idle core, several times that on a loaded one
})
