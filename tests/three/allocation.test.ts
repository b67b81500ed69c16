import { build } from 'esbuild'
import { spawnSync } from 'node:child_process'
import { mkdtempSync, rmSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { describe, expect, it } from 'vitest'

describe('bitecs-cloth/three allocation', () => {
  it('updateClothGeometry allocates nothing: no garbage collection in 10,000 frames with a 1 MB young generation (a moving cape, a sheet torn earlier)', async () => {
    const dir = mkdtempSync(join(tmpdir(), 'cloth-three-alloc-'))
    const out = join(dir, 'scene.mjs')
    try {
      await build({
        entryPoints: [join(__dirname, '..', 'fixtures', 'three-allocation-scene.ts')],
        bundle: true,
        platform: 'node',
        format: 'esm',
        outfile: out,
        logLevel: 'error',
      })
      const run = spawnSync(process.execPath, ['--trace-gc', '--max-semi-space-size=1', '--no-concurrent-recompilation', out], {
        encoding: 'utf8',
      })
      expect(run.status).toBe(0)
      const lines = run.stdout.split('\n')
      expect(lines).toContain('END')
      const during = lines.slice(lines.indexOf('START') + 1, lines.indexOf('END'))
      expect(during.filter((l) => /Scavenge|Mark-Compact|Mark-sweep/.test(l))).toEqual([])
      expect(lines).toContain('TEARS warm-up only')
      expect(lines).toContain('GROWN true')
      expect(lines).toContain('UPDATES 10000')
    } finally {
      rmSync(dir, { recursive: true, force: true })
    }
  })
})
