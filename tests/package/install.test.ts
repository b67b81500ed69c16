import { execFileSync, spawnSync } from 'node:child_process'
import { copyFileSync, mkdirSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { describe, expect, it } from 'vitest'

// `npm run test:package` (run by .ci/run): what a user does with the package. Packs it (npm pack
// runs the build through `prepare`), checks the tarball's type resolution with
// @arethetypeswrong/cli, installs it into an empty project with bitecs, three, @types/three and
// TypeScript (the versions this project uses, so npm finds them in the cache `npm ci` filled), then
// type-checks tests/package/consumer.ts there (strict, NodeNext, skipLibCheck false) and runs it.
// The build rewrites dist/ (ignored by git, and already written by `npm ci` through `prepare`);
// everything else happens in a temporary folder, removed afterwards. PACK_TIMES=1 prints how long
// each command took.

const root = join(__dirname, '..', '..')
const version = (name: string) =>
  (JSON.parse(readFileSync(join(root, 'node_modules', name, 'package.json'), 'utf8')) as { version: string }).version
const npm = process.platform === 'win32' ? 'npm.cmd' : 'npm'

function run(command: string, args: string[], cwd: string): string {
  const t0 = performance.now()
  const r = spawnSync(command, args, { cwd, encoding: 'utf8', env: { ...process.env, npm_config_update_notifier: 'false' } })
  if (r.status !== 0) throw new Error(`${command} ${args.join(' ')} failed (${r.status}):\n${r.stdout}\n${r.stderr}`)
  if (process.env.PACK_TIMES) console.log(`${((performance.now() - t0) / 1000).toFixed(1)} s: ${command} ${args[0]}`)
  return r.stdout
}

describe('the packed package, as a user installs it', () => {
  it('npm pack → install with bitecs, three, TypeScript → a strict NodeNext program importing bitecs-cloth and bitecs-cloth/three type-checks and runs', () => {
    const tmp = mkdtempSync(join(tmpdir(), 'bitecs-cloth-pack-'))
    try {
      const packed = JSON.parse(run(npm, ['pack', '--json', '--pack-destination', tmp], root)) as {
        filename: string
        files: { path: string }[]
      }[]
      const tarball = join(tmp, packed[0].filename)
      const files = packed[0].files.map((f) => f.path).sort()
      for (
        const f of [
          'dist/index.js',
          'dist/index.d.ts',
          'dist/three.js',
          'dist/three.d.ts',
          'dist/worker.js',
          'dist/worker.d.ts',
          'LICENSE',
          'README.md',
          'CHANGELOG.md',
          'package.json',
        ]
      )
        expect(files).toContain(f)
      expect(files.filter((f) => !f.startsWith('dist/') && !['LICENSE', 'README.md', 'CHANGELOG.md', 'package.json'].includes(f))).toEqual(
        [],
      )

      // type resolution of every entry for ESM users (node16/nodenext from ESM, bundler)
      run(join(root, 'node_modules', '.bin', 'attw'), [tarball, '--profile', 'esm-only'], root)

      const app = join(tmp, 'app')
      mkdirSync(app)
      writeFileSync(join(app, 'package.json'), JSON.stringify({ name: 'app', private: true, type: 'module' }))
      writeFileSync(
        join(app, 'tsconfig.json'),
        JSON.stringify({
          compilerOptions: {
            target: 'ES2022',
            module: 'NodeNext',
            moduleResolution: 'NodeNext',
            strict: true,
            skipLibCheck: false,
            outDir: 'out',
            types: [],
          },
          files: ['main.ts'],
        }),
      )
      copyFileSync(join(__dirname, 'consumer.ts'), join(app, 'main.ts'))
      const deps = ['bitecs', 'three', '@types/three', 'typescript'].map((name) => `${name}@${version(name)}`)
      run(npm, ['install', '--no-audit', '--no-fund', '--prefer-offline', tarball, ...deps], app)

      const tsc = spawnSync(process.execPath, [join(app, 'node_modules', 'typescript', 'bin', 'tsc'), '-p', app], {
        cwd: app,
        encoding: 'utf8',
      })
      expect(tsc.stdout + tsc.stderr).toBe('')
      expect(tsc.status).toBe(0)
      expect(execFileSync(process.execPath, [join(app, 'out', 'main.js')], { cwd: app, encoding: 'utf8' })).toContain('PACKAGE OK')
    } finally {
      rmSync(tmp, { recursive: true, force: true })
    }
  })
})
