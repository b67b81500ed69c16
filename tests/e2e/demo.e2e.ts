import { existsSync, mkdirSync } from 'node:fs'
import { join } from 'node:path'
import { chromium, type Browser, type Page } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
// @ts-expect-error plain ESM helper without types
import { serveDemo } from '../../demo/serve.mjs'

/**
 * The demo in real Chromium: every scene loads without console errors, draws something, moves;
 * the iteration slider changes the stretch readout; screenshots go to demo/screenshots/.
 * Skips (does not fail) when no Chromium is installed: set CHROMIUM_PATH or install Debian's
 * `chromium` package (.ci/run does).
 */
const exe = process.env.CHROMIUM_PATH ?? '/usr/bin/chromium'
const hasChromium = existsSync(exe)
if (!hasChromium) console.warn(`demo e2e tests skipped: no Chromium at ${exe}`)

interface Demo {
  ready: boolean
  frame: number
  scene: string
  scenes: string[]
  stats: { particles: number; constraints: number; maxStretch: number; stepMs: number; fps: number }
  snapshot(): { coverage: number; colors: number }
  positions(index?: number): number[]
}
declare const __demo: Demo

describe.skipIf(!hasChromium)('demo in Chromium', () => {
  let browser: Browser
  let page: Page
  let url: string
  let server: { close(): void }
  const errors: string[] = []
  const shots = join(__dirname, '..', '..', 'demo', 'screenshots')

  beforeAll(async () => {
    ;({ url, server } = await serveDemo(0))
    browser = await chromium.launch({
      executablePath: exe,
      // software WebGL2 (SwiftShader) and no background network traffic on closed machines
      args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run'],
    })
    page = await browser.newPage({ viewport: { width: 1100, height: 700 } })
    page.on('pageerror', (e) => errors.push(`pageerror: ${e.message}`))
    page.on('console', (m) => {
      if (m.type() === 'error') errors.push(`console: ${m.text()}`)
    })
    mkdirSync(shots, { recursive: true })
  })

  afterAll(async () => {
    await browser?.close()
    server?.close()
  })

  async function open(scene: string): Promise<void> {
    await page.goto(`${url}?scene=${scene}`)
    await page.waitForFunction(() => (window as unknown as { __demo?: Demo }).__demo?.ready === true, null, { timeout: 30_000 })
  }

  it('lists the scenes in the menu', async () => {
    await open('cape')
    const options = await page.$$eval('#scene option', (els) => els.map((e) => (e as HTMLOptionElement).value))
    const scenes = await page.evaluate(() => __demo.scenes)
    expect(options).toEqual(scenes)
    expect(scenes.length).toBeGreaterThanOrEqual(2)
  })

  it('every scene loads without errors, draws, moves, and is photographed', async () => {
    await open('cape')
    const scenes = await page.evaluate(() => __demo.scenes)
    for (const scene of scenes) {
      errors.length = 0
      await open(scene)
      await page.waitForTimeout(1500)
      const snap = await page.evaluate(() => __demo.snapshot())
      expect(snap.coverage, `${scene}: canvas coverage`).toBeGreaterThan(0.02)
      expect(snap.colors, `${scene}: colours`).toBeGreaterThan(8)
      const a = await page.evaluate(() => __demo.positions())
      await page.waitForTimeout(400)
      const b = await page.evaluate(() => __demo.positions())
      let moved = 0
      for (let i = 0; i < a.length; i++) moved = Math.max(moved, Math.abs(a[i] - b[i]))
      expect(moved, `${scene}: cloth moves`).toBeGreaterThan(1e-4)
      expect(a.every(Number.isFinite), `${scene}: finite`).toBe(true)
      await page.screenshot({ path: join(shots, `${scene}.png`) })
      expect(errors, `${scene}: console errors`).toEqual([])
    }
  })

  it('changing iterations changes the max-stretch readout', async () => {
    // top row pinned, tethers off, one substep: iterations alone decide how much the sheet stretches
    const readout = async (iterations: number) => {
      await open('sheet')
      await page.evaluate((n) => {
        const set = (id: string, v: number) => {
          const el = document.getElementById(id) as HTMLInputElement
          el.value = String(v)
          el.dispatchEvent(new Event('input', { bubbles: true }))
        }
        set('substeps', 1)
        set('iterations', n)
        const t = document.getElementById('tethers') as HTMLInputElement
        if (t.checked) t.click()
      }, iterations)
      await page.click('#reset')
      await page.waitForTimeout(3000)
      const text = await page.textContent('#stats')
      const m = /max stretch\s+([\d.]+) %/.exec(text ?? '')
      expect(m, 'stats overlay shows max stretch').not.toBeNull()
      return Number(m![1])
    }
    errors.length = 0
    const one = await readout(1)
    const many = await readout(16)
    expect(one).toBeGreaterThan(3 * many)
    expect(errors).toEqual([])
  })
})
