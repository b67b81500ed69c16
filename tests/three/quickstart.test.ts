// The README's Quick start, run as written: the program is taken from README.md, bundled with esbuild
// against the source (the package names mapped to src/), and run in Node with three.js for real
// (scene, geometry, materials) and only what needs a browser stubbed: the WebGL renderer, the page
// and requestAnimationFrame. 600 frames at 60 Hz; then the cape must be drawn as simulated, finite,
// behind its running character and streaming out (hem lifted).
import { mkdirSync, readFileSync, writeFileSync } from 'node:fs'
import { join } from 'node:path'
import { pathToFileURL } from 'node:url'
import { build } from 'esbuild'
import { afterAll, describe, expect, it, vi } from 'vitest'

const root = join(__dirname, '..', '..')

/** The first ```ts block after the `## Quick start` heading. */
function quickStart(): string {
  const readme = readFileSync(join(root, 'README.md'), 'utf8')
  const from = readme.indexOf('\n## Quick start')
  expect(from).toBeGreaterThan(0)
  const open = readme.indexOf('```ts\n', from)
  const close = readme.indexOf('\n```\n', open)
  return readme.slice(open + 6, close + 1)
}

/** three.js for Node: everything real but the renderer, which counts its frames. */
const THREE_STUB = `
export * from 'three'
export class WebGLRenderer {
  constructor() { this.domElement = { tagName: 'CANVAS' }; this.frames = 0; globalThis.__quickStartRenderer = this }
  setPixelRatio() {}
  setSize() {}
  render(scene, camera) { scene.updateMatrixWorld(); camera.updateMatrixWorld(); this.frames++ }
}
`

type Vec3 = [number, number, number]
interface Program {
  world: object
  hero: number
  cape: number
  capeMesh: import('three').Mesh
  character: import('three').Group
  getClothMesh: typeof import('../../src/index').getClothMesh
  getTransform: typeof import('../../src/index').getTransform
}

describe('README: Quick start', () => {
  afterAll(() => vi.unstubAllGlobals())

  it('the program runs: 600 frames drawn, the geometry is the cloth, finite, behind the running character', async () => {
    const code =
      `${quickStart()}\nexport { world, hero, cape, capeMesh, character }\nexport { getClothMesh, getTransform } from 'bitecs-cloth'\n`
    const stub = join(root, 'node_modules', '.cache', 'readme-quickstart', 'three-stub.mjs')
    mkdirSync(join(stub, '..'), { recursive: true })
    writeFileSync(stub, THREE_STUB)
    const out = await build({
      stdin: { contents: code, loader: 'ts', resolveDir: root, sourcefile: 'README-quick-start.ts' },
      bundle: true,
      format: 'esm',
      platform: 'node',
      write: false,
      external: ['three', 'bitecs', 'gl-matrix'],
      alias: { 'bitecs-cloth/three': './src/three/index.ts', 'bitecs-cloth': './src/index.ts' },
      plugins: [
        {
          name: 'three-without-webgl', // every import of three meets the stub, which imports the real one
          setup(b) {
            b.onResolve({ filter: /^three$/ }, (args) => (args.importer === stub ? { path: 'three', external: true } : { path: stub }))
          },
        },
      ],
      logLevel: 'silent',
    })
    const file = join(stub, '..', 'program.mjs')
    writeFileSync(file, out.outputFiles[0].text)

    let pending: ((now: number) => void) | null = null
    vi.stubGlobal('document', { body: { appendChild: () => undefined } })
    vi.stubGlobal('innerWidth', 1280)
    vi.stubGlobal('innerHeight', 720)
    vi.stubGlobal('devicePixelRatio', 1)
    vi.stubGlobal('requestAnimationFrame', (callback: (now: number) => void) => {
      pending = callback
      return 1
    })
    const start = performance.now()
    const program = (await import(pathToFileURL(file).href)) as Program
    const { world, hero, cape, capeMesh, character, getClothMesh, getTransform } = program

    const heroAt: Vec3 = [0, 0, 0]
    let worstBehind = Infinity, lowest = Infinity
    for (let f = 1; f <= 600; f++) {
      const callback = pending as ((now: number) => void) | null
      expect(callback).not.toBeNull()
      pending = null
      callback!(start + (1000 * f) / 60)
      if (f < 120) continue // the first two seconds: the cape swings out
      // each frame from the third second: the cape's lower half is behind the character (its local −z)
      const q: number[] = [0, 0, 0, 1]
      getTransform(world, hero, heroAt, q)
      const yaw = 2 * Math.atan2(q[1], q[3])
      const back: Vec3 = [-Math.sin(yaw), 0, -Math.cos(yaw)]
      const mesh = getClothMesh(world, cape)
      for (let i = 12 * 14; i < mesh.vertexCount; i++) {
        const behind = (mesh.positions[3 * i] - heroAt[0]) * back[0] + (mesh.positions[3 * i + 2] - heroAt[2]) * back[2]
        worstBehind = Math.min(worstBehind, behind)
        lowest = Math.min(lowest, mesh.positions[3 * i + 1])
      }
    }
    expect((globalThis as { __quickStartRenderer?: { frames: number } }).__quickStartRenderer?.frames).toBe(600)

    // the geometry drawn is the cloth simulated: positions, normals and index equal getClothMesh
    const mesh = getClothMesh(world, cape)
    const geometry = capeMesh.geometry
    expect(Array.from((geometry.getAttribute('position').array as Float32Array).subarray(0, 3 * mesh.vertexCount))).toEqual(
      Array.from(mesh.positions),
    )
    expect(Array.from((geometry.getAttribute('normal').array as Float32Array).subarray(0, 3 * mesh.vertexCount))).toEqual(
      Array.from(mesh.normals),
    )
    expect(Array.from((geometry.getIndex()!.array as Uint32Array).subarray(0, 3 * mesh.triangleCount))).toEqual(Array.from(mesh.indices))
    expect(mesh.positions.every(Number.isFinite)).toBe(true)
    // the character ran: 10 s at 3 m/s on a 3 m circle, and is drawn where it is
    character.position.toArray().forEach((x, k) => expect(x).toBeCloseTo(heroAt[k], 6))
    expect(Math.hypot(heroAt[0] - 3, heroAt[2]) - 3).toBeCloseTo(0, 6)
    // the cape's lower half stays behind the body (the torso capsule's back is 0.19 m behind its axis;
    // measured 0.58 m at least)
    expect(worstBehind).toBeGreaterThan(0.19)
    // and streams out behind the runner: its lower half stays above the hem's height at rest (0.42 m;
    // measured 0.81 m at least)
    expect(lowest).toBeGreaterThan(0.5)
  }, 60_000)
})
