// Bad thread options give a ClothError naming the option (the other cases checked were fine:
// threads '2', -1, 1.5, NaN, 33, true; workerUrl 5, a missing file, an http string, data:, '';
// threadMinStepMs -1, NaN, '1').
import { createWorld } from 'bitecs'
import { describe, expect, it } from 'vitest'
import { ClothError, installClothPlugin, disposeClothWorld } from '../../src/index'
import { workerUrl } from './helpers'

function outcome(fn: () => unknown): string {
  try {
    const w = fn()
    if (w) disposeClothWorld(w as object)
    return 'ok'
  } catch (e) {
    return e instanceof ClothError ? `ClothError(${e.argument})` : `${(e as Error).name}: ${(e as Error).message}`
  }
}

describe('thread options', () => {
  const cases: [string, Record<string, unknown>, string][] = [
    ['workerUrl http URL', { threads: 1, workerUrl: new URL('https://example.com/worker.js') }, 'ClothError(options.workerUrl)'],
    ['requireThreads string', { threads: 1, requireThreads: 'yes' }, 'ClothError(options.requireThreads)'],
    // (typed as anything with an href, so that the declarations need no DOM or Node types for URL)
    ['workerUrl object with an href', { threads: 1, workerUrl: { href: workerUrl().href } }, 'ok'],
    ['workerUrl object without a string href', { threads: 1, workerUrl: { href: 5 } }, 'ClothError(options.workerUrl)'],
    ['workerUrl object with a relative href', { threads: 1, workerUrl: { href: 'worker.js' } }, 'ClothError(options.workerUrl)'],
  ]
  for (const [name, opts, want] of cases) {
    it(name, () => {
      const o = { ...opts }
      if (!('workerUrl' in o)) o.workerUrl = workerUrl()
      expect(outcome(() => installClothPlugin(createWorld(), o as never))).toBe(want)
    })
  }
})

import { allocatingShared } from '../../src/core/shared'
import { createCloth, getClothState } from '../../src/index'

describe('a threaded install that fails', () => {
  it('leaves no threaded world behind: later plain worlds do not allocate in shared memory', () => {
    expect(allocatingShared()).toBe(false)
    expect(() => installClothPlugin(createWorld(), { threads: 2, workerUrl: 'file:///nonexistent/worker.js' })).toThrow(ClothError)
    const world = installClothPlugin(createWorld())
    const c = createCloth(world, { width: 1, height: 1, resolution: 4 })
    const shared = getClothState(world, c).pos.buffer instanceof SharedArrayBuffer
    expect({ allocatingShared: allocatingShared(), shared }).toEqual({ allocatingShared: false, shared: false })
  })
})
