// Torture suite, part 3: extreme materials. See harness.ts for what every case must show.
import { describe, it } from 'vitest'
import { defineMaterial, getClothState } from '../../src/index'
import { expectStable, hangingSheet, runTorture } from './harness'

describe('extreme materials', () => {
  const cases: [string, Parameters<typeof defineMaterial>[0], 'drape' | 'rest' | 'bounded'][] = [
    ['zero compliance (rigid in every mode)', { stretchCompliance: 0, shearCompliance: 0, bendCompliance: 0 }, 'rest'],
    ['huge compliance (1e12 in every mode)', { stretchCompliance: 1e12, shearCompliance: 1e12, bendCompliance: 1e12 }, 'rest'],
    [
      'compliance near the top of the float range (1e306)',
      { stretchCompliance: 1e306, shearCompliance: 1e306, bendCompliance: 1e306 },
      'rest',
    ],
    ['zero damping (air drag off, stretch damping on)', { damping: 0 }, 'bounded'],
    ['zero stretch damping', { stretchDamping: 0 }, 'rest'],
    ['no damping at all', { damping: 0, stretchDamping: 0 }, 'bounded'],
    ['very heavy and stiff (chainmail)', { density: 60, stretchCompliance: 1e-9 }, 'rest'],
  ]
  for (const [name, fields, recover] of cases) {
    for (const bending of ['distance', 'both'] as const) {
      it(`${name}, ${bending} bending, shaken`, () => {
        const material = defineMaterial({ name, ...fields })
        expectStable(runTorture({
          build: (world) => ({ cloths: [hangingSheet(world, { material, bending, iterations: 2 })] }),
          abuse: (s, f) => {
            if (f === 0) {
              const c = getClothState(s.world, s.cloths[0])
              for (let i = 0; i < c.count; i++) c.vel[3 * i + 2] = 5 * Math.sin(i) // a slap
            }
          },
          frames: 30,
          settle: 600,
          recover,
        }))
      })
    }
  }
})
