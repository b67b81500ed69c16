// Bundles the demo (demo/main.ts → demo/dist/main.js) with esbuild.
import { build } from 'esbuild'
import { dirname, join } from 'node:path'
import { fileURLToPath } from 'node:url'

const here = dirname(fileURLToPath(import.meta.url))

export async function buildDemo() {
  await build({
    entryPoints: [join(here, 'main.ts')],
    bundle: true,
    format: 'esm',
    platform: 'browser', // resolves gl-matrix's module field
    target: 'es2022',
    sourcemap: true,
    outfile: join(here, 'dist', 'main.js'),
    logLevel: 'warning',
  })
  // the cloth worker of threaded worlds (the crowd's workers switch), beside main.js
  await build({
    entryPoints: [join(here, '..', 'src', 'worker.ts')],
    bundle: true,
    format: 'esm',
    platform: 'browser',
    target: 'es2022',
    sourcemap: true,
    outfile: join(here, 'dist', 'worker.js'),
    logLevel: 'warning',
  })
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
  await buildDemo()
  console.log('demo built: demo/dist/main.js')
}
