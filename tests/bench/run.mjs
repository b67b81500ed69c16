#!/usr/bin/env node
// `npm run bench [suite ...]`: bundles the TypeScript benchmark suites with esbuild and runs them
// in a fresh Node process with --expose-gc (for the allocation check). Results print as tables and
// are written as JSON to bench-results/.
import { build } from 'esbuild'
import { spawnSync } from 'node:child_process'
import { mkdirSync } from 'node:fs'
import { cpus } from 'node:os'
import { dirname, join } from 'node:path'
import { fileURLToPath } from 'node:url'

const here = dirname(fileURLToPath(import.meta.url))
const root = join(here, '..', '..')
const outDir = join(root, 'bench-results')
mkdirSync(outDir, { recursive: true })
const outfile = join(outDir, 'bench.mjs')
await build({
  entryPoints: [join(here, 'main.ts')],
  bundle: true,
  platform: 'node',
  format: 'esm',
  target: 'node20',
  outfile,
  logLevel: 'warning',
})
// the cloth worker of threaded worlds (tests/bench/threads.ts), beside the benchmark bundle
await build({
  entryPoints: [join(root, 'src', 'worker.ts')],
  bundle: true,
  platform: 'neutral',
  mainFields: ['module', 'main'],
  format: 'esm',
  target: 'es2022',
  outfile: join(outDir, 'worker.mjs'),
  logLevel: 'warning',
})
const hash = spawnSync('git', ['rev-parse', '--short=12', 'HEAD'], { cwd: root, encoding: 'utf8' }).stdout.trim()
const dirty = spawnSync('git', ['status', '--porcelain', '--untracked-files=no'], { cwd: root, encoding: 'utf8' }).stdout.trim() !== ''
const commit = hash ? `commit ${hash}${dirty ? ' with uncommitted changes' : ''}` : 'not a git checkout'
console.log(`bitecs-cloth benchmarks · ${commit} · node ${process.version} · ${cpus()[0]?.model ?? 'unknown CPU'} × ${cpus().length}`)
console.log("Times are CPU time of the benchmark process on one core (a busy machine's waiting for a core is not counted).")
const r = spawnSync(process.execPath, ['--expose-gc', outfile, ...process.argv.slice(2)], { stdio: 'inherit', cwd: root })
process.exit(r.status ?? 1)
