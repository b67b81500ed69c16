import { existsSync, mkdirSync } from 'node:fs'
import { join } from 'node:path'
import { chromium, type Browser, type Page } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { C_STATE } from '../../src/threads/pool'
// @ts-expect-error plain ESM helpers without types
import { serveDemo } from '../../demo/serve.mjs'
// @ts-expect-error plain ESM helpers without types
import { CHROMIUM_ARGS } from '../../demo/screenshots.mjs'

/**
 * The demo's crowd (64 shaped capes of 24 × 15 particles with character-cloth settings, three capsules each, the budget's levels by distance) with
 * its Workers switch on, in real Chromium: the page is cross-origin isolated, the crowd's world
 * runs on two Web Workers, the live loop draws frames (beginClothStep, then endClothStepAsync) with
 * no page error, and after 120 fixed steps the capes hold the same positions, bit for bit, as the
 * same crowd stepped without workers. Skips (does not fail) when no Chromium is installed.
 */
const exe = process.env.CHROMIUM_PATH ?? '/usr/bin/chromium'
const hasChromium = existsSync(exe)
if (!hasChromium) console.warn(`crowd threads e2e tests skipped: no Chromium at ${exe}`)

interface Demo {
  ready: boolean
  frame: number
  cloths: number[]
  world: object
  setPaused(p: boolean): void
  simulate(seconds: number): void
  positions(index?: number): number[]
  stats: { stepMs: number; waitMs: number; frameMs: number; fps: number }
  api: Record<string, (...args: unknown[]) => unknown>
}
declare const __demo: Demo

describe.skipIf(!hasChromium)('the crowd scene on workers in Chromium', () => {
  let browser: Browser
  let page: Page
  let url: string
  let server: { close(): void }
  const errors: string[] = []

  beforeAll(async () => {
    ;({ url, server } = await serveDemo(0))
    browser = await chromium.launch({ executablePath: exe, args: CHROMIUM_ARGS })
    page = await browser.newPage({ viewport: { width: 1100, height: 700 } })
    page.on('pageerror', (e) => errors.push(`pageerror: ${e.message}`))
    page.on('console', (m) => {
      if (m.type() === 'error') errors.push(`console: ${m.text()}`)
    })
    mkdirSync(join(__dirname, '..', '..', 'test-results', 'screenshots'), { recursive: true })
  })

  afterAll(async () => {
    await browser?.close()
    server?.close()
  })

  async function frames(n: number): Promise<void> {
    const start = await page.evaluate(() => __demo.frame)
    await page.waitForFunction((f) => __demo.frame >= f, start + n, { timeout: 120_000 })
  }

  /**
   * The crowd built afresh (paused: no real-time frame moves it) on `threads` workers, levels by
   * distance only (no timing in the levels).
   */
  async function crowd(threads: number): Promise<void> {
    await page.evaluate((n) => {
      __demo.setPaused(true)
      __demo.api.threads(n) // builds the scene again in a world with n workers
      __demo.api.byDistance()
    }, threads)
  }

  /** Every cape's positions after `seconds` of fixed 1/60 s steps (simulate: stepCloth, back to back). */
  async function positionsAfter(seconds: number): Promise<number[][]> {
    return page.evaluate((s) => {
      __demo.simulate(s)
      return __demo.cloths.map((_, i) => __demo.positions(i))
    }, seconds)
  }

  it('is cross-origin isolated, runs on two workers, and the capes match the crowd without workers bit for bit after 120 steps', async () => {
    errors.length = 0
    await page.goto(`${url}?scene=crowd`, { waitUntil: 'domcontentloaded', timeout: 120_000 })
    await page.waitForFunction(() => (window as unknown as { __demo?: Demo }).__demo?.ready === true, null, { timeout: 120_000 })
    await page.evaluate(() => __demo.setPaused(true))
    await frames(2) // (a frame in flight when the loop paused has finished)
    await crowd(0)
    const alone = await positionsAfter(2)
    expect(await page.evaluate(() => (__demo.world as { [k: symbol]: { threads: unknown } })[Symbol.for('bitecs-cloth')].threads))
      .toBeNull()

    await crowd(2)
    // the workers load their script through the page's event loop: wait until both say they are
    // ready before `simulate` blocks the page in stepCloth (otherwise the first step spins until
    // the pool reports them stuck, and only then do they start)
    await page.waitForFunction(
      (at) => {
        const t = (__demo.world as { [k: symbol]: { threads: { pool: { control: Int32Array; workers: unknown[] } } | null } })[
          Symbol.for('bitecs-cloth')
        ].threads
        return t !== null && t.pool.workers.every((_, w) => Atomics.load(t.pool.control, at + w) === 1)
      },
      C_STATE,
      { timeout: 120_000 },
    )
    expect(await page.evaluate(() => crossOriginIsolated)).toBe(true)
    const threads = () =>
      page.evaluate(() => {
        const t =
          (__demo.world as { [k: symbol]: { threads: { step: number; pool: { workers: unknown[] } } | null } })[Symbol.for('bitecs-cloth')]
            .threads
        return t === null ? null : { workers: t.pool.workers.length, step: t.step }
      })
    expect((await threads())?.workers).toBe(2)
    const shared = await positionsAfter(2)
    expect((await threads())!.step).toBeGreaterThanOrEqual(120) // the workers stepped them
    expect(shared).toHaveLength(64)
    let differing = 0
    for (let i = 0; i < 64; i++) {
      if (shared[i].length !== alone[i].length || shared[i].some((v, j) => !Object.is(v, alone[i][j]))) differing++
    }
    expect(differing, 'capes whose positions differ from the crowd without workers').toBe(0)

    // the live loop: frames drawn while the workers step, the main thread never blocked
    await page.evaluate(() => __demo.setPaused(false))
    await frames(30)
    const stats = await page.evaluate(() => __demo.stats)
    expect(stats.waitMs).toBeGreaterThan(0) // frames awaited the workers
    expect(await page.isVisible('#workers-2')).toBe(true)
    await page.screenshot({ path: join(__dirname, '..', '..', 'test-results', 'screenshots', 'crowd-workers.png') })
    console.log(
      `crowd on 2 workers: ${stats.fps} fps, main-thread step ${stats.stepMs.toFixed(2)} ms, awaited ${
        stats.waitMs.toFixed(2)
      } ms per frame`,
    )
    expect(errors).toEqual([])
  })
})
