import { join } from 'node:path'
import { describe, expect, it } from 'vitest'
import { runAllocationFixture } from '../gc'

describe('bitecs-cloth/three allocation', () => {
  it(
    'updateClothGeometry allocates nothing: no garbage collection in 10,000 frames with a 1 MB young generation (a moving cape, a sheet torn earlier, render proxies of both)',
    async () => {
      const run = await runAllocationFixture(join(__dirname, '..', 'fixtures', 'three-allocation-scene.ts'))
      expect(run.status).toBe(0)
      expect(run.collections).toEqual([])
      expect(run.lines).toContain('TEARS warm-up only')
      expect(run.lines).toContain('GROWN true')
      expect(run.lines).toContain('UPDATES 10000')
      expect(run.lines).toContain('PROXY UPDATES 10000')
      expect(run.lines).toContain('PROXY INDEX SENT true')
    },
    300_000,
  )
})
