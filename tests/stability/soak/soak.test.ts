import { join } from 'node:path'
import { describe, expect, it } from 'vitest'
import { runAllocationFixture } from '../../gc'
import { generateScript, runScript } from './driver'

describe('a seeded random game session (driver.ts)', () => {
  // 51 scavenges in 10,200 steps (4.5 KB a step) before the colliders' fast-particle test was
  // written out in their loops: after this session the compiler stopped inlining its helper,
  // whose double arguments were then boxed (1 and 300 session frames gave 0 or 1)
  it('after 3000 frames of it, plain steps of the same world allocate nothing (no scavenge with a 1 MB young generation)', async () => {
    const run = await runAllocationFixture(join(__dirname, 'allocationFixture.ts'))
    expect(run.status).toBe(0)
    expect(run.collections).toEqual([])
  }, 600_000)

  it('runs the same twice, byte for byte, with only ClothErrors and finite particles', () => {
    const script = generateScript(2, 1500)
    const a = runScript(script), b = runScript(script)
    expect(b.hashes).toEqual(a.hashes)
    expect(a.hashes.length).toBe(1500)
    expect(a.violations.filter((v) => v.what === 'non-ClothError' || v.what === 'nonFinite' || v.what === 'pin')).toEqual([])
  })
})
