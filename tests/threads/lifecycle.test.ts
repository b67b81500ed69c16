// Workers shut down cleanly: a process with a threaded world exits by itself, disposeClothWorld
// stops the workers (and the world goes on without them), and a dropped world's workers are
// terminated when it is collected (a safety net; the tests above do not rely on it).
import { buildSync } from 'esbuild'
import { spawnSync } from 'node:child_process'
import { mkdtempSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { createWorld } from 'bitecs'
import { describe, expect, it } from 'vitest'
import { ClothError, disposeClothWorld, installClothPlugin } from '../../src/index'
import { getClothWorld } from '../../src/world/access'
import { workerUrl } from './helpers'

const script = join(mkdtempSync(join(tmpdir(), 'cloth-life-')), 'scene.mjs')
buildSync({
  entryPoints: [join(__dirname, '..', 'fixtures', 'threads-lifecycle.ts')],
  bundle: true,
  platform: 'node',
  format: 'esm',
  outfile: script,
  logLevel: 'error',
})

const asyncScript = join(mkdtempSync(join(tmpdir(), 'cloth-async-')), 'asyncEnd.mjs')
buildSync({
  entryPoints: [join(__dirname, 'asyncEndProcess.ts')],
  bundle: true,
  platform: 'node',
  format: 'esm',
  outfile: asyncScript,
  logLevel: 'error',
})

function run(mode: string, flags: string[] = []) {
  const t0 = performance.now()
  const r = spawnSync(process.execPath, [...flags, script, workerUrl().href, mode], { encoding: 'utf8', timeout: 60_000 })
  return { ...r, ms: performance.now() - t0 }
}

describe('worker lifecycle', () => {
  it('a process whose threaded world is still alive exits by itself (the workers never hold it open)', () => {
    const r = run('keep')
    expect(r.stderr).toBe('')
    expect(r.status).toBe(0)
    expect(r.stdout).toMatch(/STEPPED [1-9]\d*/)
    expect(r.stdout).toContain('EXITED 0') // still running when the process ended, and it ended anyway
  })

  it('await endClothStepAsync keeps a Node process alive until the workers finish, and the idle world then lets it exit', () => {
    const t0 = performance.now()
    const r = spawnSync(process.execPath, [asyncScript, workerUrl().href, '5'], { encoding: 'utf8', timeout: 60_000 })
    const ms = performance.now() - t0
    expect(r.stderr).toBe('')
    expect(r.stdout).toContain('begun 4')
    expect(r.stdout).toContain('async ok 5') // five frames of one fixed step each, all awaited
    expect(r.status).toBe(0) // (before: exit code 13, the loop ended while the first wait was pending)
    expect(ms).toBeLessThan(30_000) // it exited by itself, not by the spawn's timeout
  })

  it('disposeClothWorld stops the workers; the world then steps on the calling thread', () => {
    const r = run('dispose')
    expect(r.stderr).toBe('')
    expect(r.status).toBe(0)
    expect(r.stdout).toContain('THREADS true')
    expect(r.stdout).toContain('EXITED 2')
  })

  it('a threaded world dropped without disposeClothWorld has its workers terminated when it is garbage-collected', () => {
    const r = run('gc', ['--expose-gc'])
    expect(r.stderr).toBe('')
    expect(r.status).toBe(0)
    expect(r.stdout).toMatch(/GC EXITED (2|collected)/)
  })

  it('without shared memory (a page that is not cross-origin isolated): a warning and the calling thread, or a ClothError with requireThreads', () => {
    const g = globalThis as { crossOriginIsolated?: boolean }
    const warnings: string[] = []
    const warn = console.warn
    console.warn = (m: string) => warnings.push(m)
    g.crossOriginIsolated = false
    try {
      expect(() => installClothPlugin(createWorld(), { threads: 2, requireThreads: true, workerUrl: workerUrl() })).toThrow(ClothError)
      expect(() => installClothPlugin(createWorld(), { threads: 2, requireThreads: true })).toThrow(
        /Cross-Origin-Embedder-Policy: require-corp/,
      )
      const world = installClothPlugin(createWorld(), { threads: 2, workerUrl: workerUrl() })
      expect(getClothWorld(world).threads).toBeNull()
      disposeClothWorld(world) // nothing to stop
      installClothPlugin(createWorld(), { threads: 2, workerUrl: workerUrl() })
      expect(warnings.length).toBe(1) // once
      expect(warnings[0]).toMatch(/cross-origin isolated/)
    } finally {
      delete g.crossOriginIsolated
      console.warn = warn
    }
  })
})
