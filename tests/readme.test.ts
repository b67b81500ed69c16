import { readFileSync } from 'node:fs'
import { join } from 'node:path'
import ts from 'typescript'
import { describe, expect, it } from 'vitest'

// Every ```ts block of README.md compiles against the package's source, each as its own module
// (strict, like the project). The convention:
// - A snippet that imports from 'bitecs-cloth' must import every library name it uses, as a user
//   copying it would. A snippet that imports nothing from it is a fragment of a larger program:
//   it sees every export of 'bitecs-cloth' without importing.
// - Every snippet sees the scene names of SCENE below (a world, a hero entity, a cape, ...) as
//   globals; a snippet that declares its own `world` or `cape` uses its own.
// - A block preceded by the line `<!-- readme-snippet: not compiled (why) -->` is skipped. Keep
//   these rare: today one, an excerpt of the test suite.

const root = join(__dirname, '..')
const SKIP = /^<!-- readme-snippet: not compiled \(.+\) -->$/

/** Names the README's fragments take from the scene they are part of. */
const SCENE = `
type Entity = number
declare const world: import('bitecs').World
declare const hero: Entity, cape: Entity, heroCape: Entity, curtain: Entity, flag: Entity, banner: Entity
declare const camera: Entity, cameraEntity: Entity, leftLegBone: Entity, rightLegBone: Entity, chest: Entity
declare const positions: number[], indices: number[], uvs: number[]
declare const heroPosition: [number, number, number], heroRotation: [number, number, number, number]
declare const options: import('bitecs-cloth').CreateClothOptions
declare const scene: import('three').Scene
declare function spawnDust(x: number, y: number, z: number): void
declare function log(event: unknown): void
`

interface Snippet {
  line: number
  code: string
}

/** The ```ts blocks of a markdown text, with the line each starts on, less the skipped ones. */
export function snippets(markdown: string): { checked: Snippet[]; skipped: Snippet[] } {
  const lines = markdown.split('\n')
  const checked: Snippet[] = [], skipped: Snippet[] = []
  for (let i = 0; i < lines.length; i++) {
    if (lines[i].trim() !== '```ts') continue
    const end = lines.indexOf('```', i + 1)
    if (end < 0) throw new Error(`README.md:${i + 1}: unclosed code block`)
    const snippet = { line: i + 1, code: lines.slice(i + 1, end).join('\n') }
    let before = i - 1
    while (before >= 0 && lines[before].trim() === '') before--
    ;(before >= 0 && SKIP.test(lines[before].trim()) ? skipped : checked).push(snippet)
    i = end
  }
  return { checked, skipped }
}

/** The names src/index.ts exports, as import specifiers (`name` or `type Name`). */
function libraryExports(): string[] {
  const file = join(root, 'src', 'index.ts')
  const source = ts.createSourceFile(file, readFileSync(file, 'utf8'), ts.ScriptTarget.ES2022)
  const names: string[] = []
  for (const statement of source.statements) {
    if (ts.isExportDeclaration(statement) && statement.exportClause && ts.isNamedExports(statement.exportClause)) {
      for (const element of statement.exportClause.elements) {
        names.push(statement.isTypeOnly || element.isTypeOnly ? `type ${element.name.text}` : element.name.text)
      }
    }
  }
  return names
}

/** Type-checks snippets as modules beside the sources; returns the diagnostics per snippet. */
export function checkSnippets(list: Snippet[]): Map<number, string[]> {
  const configFile = ts.readConfigFile(join(root, 'tsconfig.json'), ts.sys.readFile)
  const config = ts.parseJsonConfigFileContent(configFile.config, ts.sys, root)
  const options: ts.CompilerOptions = {
    ...config.options,
    noEmit: true,
    baseUrl: root,
    paths: { 'bitecs-cloth': ['src/index.ts'], 'bitecs-cloth/three': ['src/three/index.ts'] },
  }
  const dir = join(root, 'tests', '.readme-snippets') // virtual: nothing is written there
  const fragmentImport = `import { ${libraryExports().join(', ')} } from 'bitecs-cloth'\n`
  const files = new Map<string, string>()
  files.set(join(dir, 'scene.d.ts'), SCENE)
  const byFile = new Map<string, number>()
  for (const s of list) {
    const imports = /from\s+'bitecs-cloth'/.test(s.code)
    const file = join(dir, `readme-${s.line}.ts`)
    // the fragment import shares the snippet's first line, so diagnostics keep README line numbers
    files.set(file, `${imports ? '' : fragmentImport.trimEnd() + '; '}export {}\n${s.code}\n`)
    byFile.set(file, s.line)
  }
  const host = ts.createCompilerHost(options)
  const readFile = host.readFile.bind(host)
  const fileExists = host.fileExists.bind(host)
  const getSourceFile = host.getSourceFile.bind(host)
  host.readFile = (f) => files.get(f) ?? readFile(f)
  host.fileExists = (f) => files.has(f) || fileExists(f)
  host.getSourceFile = (f, language, onError, create) => {
    const text = files.get(f)
    return text !== undefined ? ts.createSourceFile(f, text, language) : getSourceFile(f, language, onError, create)
  }
  const program = ts.createProgram([...files.keys()], options, host)
  const result = new Map<number, string[]>()
  for (const [file, line] of byFile) {
    const source = program.getSourceFile(file)!
    const diagnostics = [...program.getSyntacticDiagnostics(source), ...program.getSemanticDiagnostics(source)]
    result.set(
      line,
      diagnostics.map((d) => {
        const at = d.start === undefined ? 0 : source.getLineAndCharacterOfPosition(d.start).line
        return `README.md:${line + at}: ${ts.flattenDiagnosticMessageText(d.messageText, '\n')}`
      }),
    )
  }
  return result
}

describe('README snippets', () => {
  const { checked, skipped } = snippets(readFileSync(join(root, 'README.md'), 'utf8'))

  it('every ```ts block of README.md type-checks against the source (fragments see the library and a scene)', () => {
    expect(checked.length).toBeGreaterThan(5)
    expect(skipped.length).toBeLessThanOrEqual(2) // exceptions stay rare
    const errors = [...checkSnippets(checked).values()].flat()
    expect(errors).toEqual([])
  })

  it('the check fails on a snippet that misuses the API, forgets an import or has a syntax error', () => {
    const bad = checkSnippets([
      { line: 1, code: "import { createCloth } from 'bitecs-cloth'\ncreateCloth(world, { width: 'wide' })" },
      { line: 2, code: "import { createCloth } from 'bitecs-cloth'\npinRow(world, createCloth(world, {}), 0)" },
      { line: 3, code: 'stepCloth(world, 1 / 60' },
      {
        line: 4,
        code: "import { createClothMesh } from 'bitecs-cloth/three'\ncreateClothMesh(world, cape).geometry.attributes.uv.itemSize",
      },
    ])
    expect(bad.get(1)!.join('\n')).toMatch(/README.md:3: .*'string' is not assignable to type 'number'/)
    expect(bad.get(2)!.join('\n')).toMatch(/README.md:4: Cannot find name 'pinRow'/)
    expect(bad.get(3)!.length).toBeGreaterThan(0)
    expect(bad.get(4)).toEqual([])
  })
})

describe('README API index', () => {
  /** The backticked names of the index: the list items of the `## API reference` section. */
  function indexNames(markdown: string): string[] {
    const from = markdown.indexOf('\n## API reference')
    const to = markdown.indexOf('\n## ', from + 1)
    expect(from).toBeGreaterThan(0)
    const items = markdown.slice(from, to < 0 ? undefined : to).split('\n').filter((l) => l.startsWith('- **'))
    return items.flatMap((l) => [...l.matchAll(/`([A-Za-z_$][\w$]*)`/g)].map((m) => m[1]))
  }

  it('lists exactly the runtime exports of bitecs-cloth and bitecs-cloth/three, each once', async () => {
    const exported = [...Object.keys(await import('../src/index')), ...Object.keys(await import('../src/three/index'))]
    const listed = indexNames(readFileSync(join(root, 'README.md'), 'utf8'))
    expect(listed.length).toBeGreaterThan(100)
    expect(listed.filter((name, i) => listed.indexOf(name) !== i)).toEqual([]) // each once
    expect(listed.filter((name) => !exported.includes(name))).toEqual([]) // nothing that is not exported
    expect(exported.filter((name) => !listed.includes(name))).toEqual([]) // nothing exported left out
  })

  it('the check fails on a name that is not exported, and on an export left out', () => {
    const names = indexNames('x\n## API reference\n- **Area**: `stepCloth`, `stepClothes`\n\n## Layout\n- **Not**: `other`\n')
    expect(names).toEqual(['stepCloth', 'stepClothes'])
  })
})
