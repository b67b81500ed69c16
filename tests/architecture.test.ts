import { readFileSync, readdirSync, statSync } from 'node:fs'
import { dirname, join, relative, resolve } from 'node:path'
import { fileURLToPath } from 'node:url'
import ts from 'typescript'
import { describe, expect, it } from 'vitest'

/**
 * The library's layers (README, Layout). A file may import from a lower layer, or from its own
 * layer where no cycle results; features import only features before them in FEATURE_ORDER (and
 * their own folder). Type-only imports count: a cycle of types is still a cycle a reader must hold.
 */
const FEATURE_ORDER = ['pins', 'grab', 'wind', 'collision', 'budget', 'sleep', 'guard', 'character', 'tearing']

interface Place {
  layer: number
  name: string
  /** For features: position in FEATURE_ORDER. */
  feature?: number
}

export function placeOf(file: string): Place | null {
  const f = file.replace(/\\/g, '/')
  if (f.startsWith('src/core/')) return { layer: 0, name: 'core' }
  if (f.startsWith('src/kernels/')) return { layer: 1, name: 'kernels' }
  if (f.startsWith('components/')) return { layer: 2, name: 'components' }
  if (f.startsWith('src/model/')) return { layer: 3, name: 'model' }
  const feature = /^src\/features\/([^/]+)\/(.+)$/.exec(f)
  if (feature) {
    const order = FEATURE_ORDER.indexOf(feature[1])
    if (order < 0) return null
    if (feature[2] === 'types.ts') return { layer: 4, name: 'feature types', feature: order }
    return { layer: 6, name: 'features', feature: order }
  }
  if (f.startsWith('src/world/')) return { layer: 5, name: 'world' }
  if (
    ['src/cloth.ts', 'src/plugin.ts', 'src/snapshot.ts', 'src/mesh.ts', 'src/proxy.ts', 'src/draw.ts', 'src/teleport.ts'].includes(f) ||
    f.startsWith('src/threads/')
  )
    return { layer: 7, name: 'composition' }
  if (f.startsWith('systems/')) return { layer: 8, name: 'systems' }
  if (
    ['src/index.ts', 'src/simulation.ts', 'src/checked.ts', 'src/calibrate.ts', 'src/worker.ts'].includes(f) || f.startsWith('src/three/')
  ) {
    return { layer: 9, name: 'public entry' }
  }
  return null
}

/** Why an import from `a` to `b` breaks the table, or null when it is allowed. */
export function edgeProblem(a: Place, b: Place): string | null {
  if (b.layer > a.layer) return `${a.name} (layer ${a.layer}) imports ${b.name} (layer ${b.layer})`
  if (a.feature !== undefined && b.feature !== undefined && b.feature > a.feature) {
    return `feature ${FEATURE_ORDER[a.feature]} imports ${FEATURE_ORDER[b.feature]}, which comes after it`
  }
  return null
}

const root = resolve(dirname(fileURLToPath(import.meta.url)), '..')

function libraryFiles(): string[] {
  const out: string[] = []
  const walk = (d: string): void => {
    for (const n of readdirSync(d)) {
      const p = join(d, n)
      if (statSync(p).isDirectory()) walk(p)
      else if (n.endsWith('.ts') && !n.endsWith('.d.ts')) out.push(relative(root, p).replace(/\\/g, '/'))
    }
  }
  for (const d of ['src', 'systems', 'components']) walk(join(root, d))
  return out.sort()
}

/** Relative imports of a file (import, import type, export from, dynamic import), resolved to library files. */
function importsOf(file: string, known: Set<string>): string[] {
  const info = ts.preProcessFile(readFileSync(join(root, file), 'utf8'), true, true)
  const out: string[] = []
  for (const ref of info.importedFiles) {
    if (!ref.fileName.startsWith('.')) continue
    const base = relative(root, resolve(root, dirname(file), ref.fileName)).replace(/\\/g, '/').replace(/\.(js|ts)$/, '')
    const hit = [`${base}.ts`, `${base}/index.ts`].find((c) => known.has(c))
    if (hit) out.push(hit)
  }
  return out
}

function graph(): Map<string, string[]> {
  const files = libraryFiles()
  const known = new Set(files)
  return new Map(files.map((f) => [f, importsOf(f, known)]))
}

/** Strongly connected components with more than one file (Tarjan), plus files importing themselves. */
function cycles(g: Map<string, string[]>): string[][] {
  let index = 0
  const idx = new Map<string, number>(), low = new Map<string, number>(), on = new Set<string>(), stack: string[] = [], out: string[][] = []
  const strong = (v: string): void => {
    idx.set(v, index)
    low.set(v, index++)
    stack.push(v)
    on.add(v)
    for (const w of g.get(v)!) {
      if (!idx.has(w)) {
        strong(w)
        low.set(v, Math.min(low.get(v)!, low.get(w)!))
      } else if (on.has(w)) low.set(v, Math.min(low.get(v)!, idx.get(w)!))
    }
    if (low.get(v) === idx.get(v)) {
      const c: string[] = []
      let w: string
      do {
        w = stack.pop()!
        on.delete(w)
        c.push(w)
      } while (w !== v)
      if (c.length > 1 || g.get(v)!.includes(v)) out.push(c)
    }
  }
  for (const v of g.keys()) if (!idx.has(v)) strong(v)
  return out
}

describe('architecture', () => {
  const g = graph()

  it('every library file has a place in the layer table', () => {
    expect([...g.keys()].filter((f) => placeOf(f) === null)).toEqual([])
  })

  it('no import cycle among src/, systems/ and components/ (type-only imports included)', () => {
    expect(cycles(g)).toEqual([])
  })

  it('no import points against the layer table', () => {
    const bad: string[] = []
    for (const [file, deps] of g) {
      const a = placeOf(file)
      if (!a) continue
      for (const dep of deps) {
        const b = placeOf(dep)
        const problem = b && edgeProblem(a, b)
        if (problem) bad.push(`${file} → ${dep}: ${problem}`)
      }
    }
    expect(bad).toEqual([])
  })

  it('the checks catch what they are for: a backward import, a later feature, a cycle', () => {
    expect(edgeProblem(placeOf('src/world/state.ts')!, placeOf('src/features/sleep/step.ts')!)).toMatch(/imports features/)
    expect(edgeProblem(placeOf('src/features/pins/api.ts')!, placeOf('src/features/wind/api.ts')!)).toMatch(/comes after/)
    expect(edgeProblem(placeOf('src/features/wind/api.ts')!, placeOf('src/features/pins/api.ts')!)).toBeNull()
    expect(edgeProblem(placeOf('src/kernels/distance.ts')!, placeOf('components/Cloth.ts')!)).toMatch(/imports components/)
    const loop = new Map([['a', ['b']], ['b', ['c']], ['c', ['a']], ['d', ['a']]])
    expect(cycles(loop).map((c) => c.sort())).toEqual([['a', 'b', 'c']])
  })

  it('no library file over 600 lines', () => {
    const long = [...g.keys()].map((f) => [f, readFileSync(join(root, f), 'utf8').split('\n').length] as const).filter(([, n]) => n > 600)
    expect(long).toEqual([])
  })

  it('no function over 80 lines unless its comment says why it stays whole ("One long function on purpose")', () => {
    const long: string[] = []
    for (const file of g.keys()) {
      const text = readFileSync(join(root, file), 'utf8')
      const src = ts.createSourceFile(file, text, ts.ScriptTarget.ES2022, true)
      const visit = (n: ts.Node): void => {
        if (ts.isFunctionLike(n) && 'body' in n && n.body) {
          const lines = src.getLineAndCharacterOfPosition(n.getEnd()).line - src.getLineAndCharacterOfPosition(n.getStart()).line + 1
          const doc = text.slice(n.getFullStart(), n.getStart())
          if (lines > 80 && !/One long function on purpose/.test(doc))
            long.push(`${file}:${src.getLineAndCharacterOfPosition(n.getStart()).line + 1} (${lines} lines)`)
        }
        ts.forEachChild(n, visit)
      }
      visit(src)
    }
    expect(long).toEqual([])
  })

  it('the demo uses only the public entries', () => {
    const demoFiles: string[] = []
    const walk = (d: string): void => {
      for (const n of readdirSync(d)) {
        const p = join(d, n)
        if (n === 'dist' || n === 'screenshots') continue
        if (statSync(p).isDirectory()) walk(p)
        else if (n.endsWith('.ts')) demoFiles.push(p)
      }
    }
    walk(join(root, 'demo'))
    const bad: string[] = []
    for (const p of demoFiles) {
      for (const ref of ts.preProcessFile(readFileSync(p, 'utf8'), true, true).importedFiles) {
        const target = relative(root, resolve(dirname(p), ref.fileName)).replace(/\\/g, '/')
        if (target.startsWith('src/') && !/^src\/(index|three(\/index)?)(\.ts)?$/.test(target)) bad.push(`${relative(root, p)} → ${target}`)
      }
    }
    expect(bad).toEqual([])
  })
})
