import { buildSync } from 'esbuild'
import { mkdtempSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { dirname, join } from 'node:path'
import { fileURLToPath, pathToFileURL } from 'node:url'

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..')
let url: URL | null = null

/** The cloth worker (src/worker.ts) bundled once per test process, as the package build does. */
export function workerUrl(): URL {
  if (url !== null) return url
  const out = join(mkdtempSync(join(tmpdir(), 'cloth-worker-')), 'worker.mjs')
  buildSync({
    entryPoints: [join(root, 'src', 'worker.ts')],
    bundle: true,
    format: 'esm',
    platform: 'neutral',
    mainFields: ['module', 'main'],
    target: 'es2022',
    outfile: out,
    logLevel: 'warning',
  })
  url = pathToFileURL(out)
  return url
}
