import { build } from 'esbuild'
import { spawnSync } from 'node:child_process'
import { mkdtempSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { describe, expect, it } from 'vitest'

describe('allocation', () => {
  it('a step allocates nothing: no garbage collection in 50,000 steps with a 1 MB young generation (cape, pins, uneven frames, mesh reads)', async () => {
    const out = join(mkdtempSync(join(tmpdir(), 'cloth-alloc-')), 'scene.mjs')
    await build({ entryPoints: [join(__dirname, 'fixtures', 'allocation-scene.ts')], bundle: true, platform: 'node', format: 'esm', outfile: out, logLevel: 'error' })
    // synchronous recompilation: tier-up happens at the same point whatever the machine's load; no
    // memory reducer: on a loaded machine its timer runs a Mark-Compact that no allocation caused
    const run = spawnSync(process.execPath, ['--trace-gc', '--max-semi-space-size=1', '--no-concurrent-recompilation', '--no-memory-reducer', out], { encoding: 'utf8' })
    expect(run.status).toBe(0)
    const lines = run.stdout.split('\n')
    const during = lines.slice(lines.indexOf('START') + 1, lines.indexOf('END'))
    expect(lines).toContain('END')
    expect(during.filter((l) => /Scavenge|Mark-Compact|Mark-sweep/.test(l))).toEqual([])
    expect(lines).toContain('RESETS 2') // the guard checked every step and reset the cape twice before
  }, 300_000) // 50,000 steps in a child process: about 20 s on an idle core, several times that on a loaded one
})
