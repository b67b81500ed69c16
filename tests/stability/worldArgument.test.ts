// Every public function that takes a world rejects a missing or wrong one with ClothError('world'),
// never a TypeError. The list is generated from the module's exports (the first parameter's name),
// so a new export cannot be forgotten; exports that take no world are listed by name below, and an
// export in neither list fails the test until it is classified.
import { createWorld } from 'bitecs'
import { describe, expect, it } from 'vitest'
import * as api from '../../src/index'

/** Exported functions and classes whose first parameter is not a world. */
const NO_WORLD = new Set([
  'ClothError',
  'ClothSimulation',
  'defineMaterial',
  'resolveMaterial',
  'calibrateClothCost',
  'predictPositions',
  'updateVelocities',
  'solveDistances',
  'solveDistancesXpbd',
  'spreadInverseMasses',
  'solveCompression',
  'dampPairs',
  'solveDihedrals',
  'solveLineBending',
  'solveTethers',
  'writeRenderMesh',
  'measureStretch',
  'buildGridTopology',
  'buildMeshTopology',
  'buildGridMesh',
  'dihedralAngle',
  'buildTethers',
  'checkClothHealth',
  'buildConvexHull',
])

/** Name of a function's first parameter, from its source (undefined for a class or no parameter). */
function firstParameter(fn: (...args: unknown[]) => unknown): string | undefined {
  const src = Function.prototype.toString.call(fn)
  if (src.startsWith('class')) return undefined
  const m = /^(?:async\s+)?function\s*\*?\s*[\w$]*\s*\(\s*([A-Za-z_$][\w$]*)/.exec(src) ?? /^\(\s*([A-Za-z_$][\w$]*)[^)]*\)\s*=>/.exec(src) // (or an arrow)
  return m?.[1]
}

const exported = Object.entries(api).filter(([, v]) => typeof v === 'function') as [string, (...args: unknown[]) => unknown][]
const takesWorld = exported.filter(([name, fn]) => firstParameter(fn) === 'world' && !NO_WORLD.has(name))

describe('the world argument', () => {
  it('every exported function is classified: it takes a world first, or is listed as taking none', () => {
    const unclassified = exported.filter(([name, fn]) => firstParameter(fn) !== 'world' && !NO_WORLD.has(name)).map(([n]) => n)
    expect(unclassified).toEqual([])
    const listedButTakesWorld = exported.filter(([name, fn]) => NO_WORLD.has(name) && firstParameter(fn) === 'world').map(([n]) => n)
    expect(listedButTakesWorld).toEqual([])
    // the systems, the stepping, the cloth, pin, collider, wind, tearing, guard, sleep, budget and snapshot calls
    expect(takesWorld.length).toBeGreaterThan(60)
  })

  const bad: [string, unknown][] = [
    ['null', null],
    ['undefined', undefined],
    ['a number', 42],
    ['a string', 'world'],
    ['a plain object', {}],
    ['a bitECS world without the plugin', createWorld()],
  ]
  for (const [label, world] of bad) {
    it(`${label} as the world: every function that takes one throws ClothError('world'), whatever follows`, () => {
      const wrong: string[] = []
      for (const [name, fn] of takesWorld) {
        // installClothPlugin accepts any object (it installs on it)
        if (name === 'installClothPlugin' && typeof world === 'object' && world !== null) continue
        for (const args of [[world], [world, 1, 0, {}, {}, {}], [world, undefined, undefined]]) {
          try {
            fn(...args)
            wrong.push(`${name}: no error`)
          } catch (e) {
            if (!(e instanceof api.ClothError)) wrong.push(`${name}: ${(e as Error)?.constructor?.name} ${(e as Error)?.message}`)
            else if (e.argument !== 'world') wrong.push(`${name}: ClothError('${e.argument}')`)
          }
        }
      }
      expect(wrong).toEqual([])
    })
  }
})
