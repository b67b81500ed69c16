import { build } from 'esbuild'
import { spawnSync } from 'node:child_process'
import { mkdtempSync, rmSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'

/**
 * Runs an allocation fixture (a script that prints START, steps, prints END and its own checks) in
 * a child process with a 1 MB young generation and GC tracing. Returns the lines it printed and
 * the garbage collections between START and END: a step that allocates shows up as a scavenge.
 * Recompilation is synchronous (tier-up at the same point whatever the machine's load) and the
 * memory reducer is off (on a loaded machine its timer runs a Mark-Compact no allocation caused).
 */
export async function runAllocationFixture(fixture: string): Promise<{ status: number | null; lines: string[]; collections: string[] }> {
  const dir = mkdtempSync(join(tmpdir(), 'cloth-alloc-'))
  const out = join(dir, 'scene.mjs')
  try {
    await build({ entryPoints: [fixture], bundle: true, platform: 'node', format: 'esm', outfile: out, logLevel: 'error' })
    const run = spawnSync(process.execPath, [
      '--trace-gc',
      '--max-semi-space-size=1',
      '--no-concurrent-recompilation',
      '--no-memory-reducer',
      out,
    ], { encoding: 'utf8' })
    const lines = run.stdout.split('\n')
    const start = lines.indexOf('START'), end = lines.indexOf('END')
    const collections = start >= 0 && end > start ? lines.slice(start + 1, end).filter((l) => /Scavenge|Mark-Compact|Mark-sweep/.test(l))
      : ['START/END missing']
    return { status: run.status, lines, collections }
  } finally {
    rmSync(dir, { recursive: true, force: true })
  }
}
