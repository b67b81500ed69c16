import { buildSync } from 'esbuild'
import { existsSync, mkdtempSync, readFileSync } from 'node:fs'
import { createServer, type Server } from 'node:http'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { chromium, type Browser } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'

/**
 * The threaded mode in real Chromium: a page served cross-origin isolated (COOP same-origin, COEP
 * require-corp) steps a scene on two module Web Workers with beginClothStep / endClothStepAsync
 * (the main thread never blocks), then 10 frames of stepCloth (which spins there), and matches the
 * same scene stepped without workers, bit for bit; served without the headers, the page has no SharedArrayBuffer and the plugin
 * steps on the main thread (one warning), with `requireThreads` it throws a ClothError.
 * Skips (does not fail) when no Chromium is installed.
 */
const exe = process.env.CHROMIUM_PATH ?? '/usr/bin/chromium'
const hasChromium = existsSync(exe)
if (!hasChromium) console.warn(`threads e2e tests skipped: no Chromium at ${exe}`)

const dir = mkdtempSync(join(tmpdir(), 'cloth-threads-e2e-'))
const build = (entry: string, out: string) =>
  buildSync({
    entryPoints: [entry],
    bundle: true,
    format: 'esm',
    platform: 'browser',
    target: 'es2022',
    outfile: join(dir, out),
    logLevel: 'error',
  })

function serve(isolated: boolean): Promise<{ url: string; server: Server }> {
  const files: Record<string, [string, string]> = {
    '/': ['<!doctype html><script type="module" src="./page.js"></script>', 'text/html'],
    '/page.js': [readFileSync(join(dir, 'page.js'), 'utf8'), 'text/javascript'],
    '/worker.js': [readFileSync(join(dir, 'worker.js'), 'utf8'), 'text/javascript'],
  }
  const server = createServer((req, res) => {
    const f = files[new URL(req.url ?? '/', 'http://x').pathname]
    if (!f) return void res.writeHead(404).end()
    const headers: Record<string, string> = { 'content-type': f[1] }
    if (isolated) {
      headers['cross-origin-opener-policy'] = 'same-origin'
      headers['cross-origin-embedder-policy'] = 'require-corp'
    }
    res.writeHead(200, headers).end(f[0])
  })
  return new Promise((resolve) =>
    server.listen(0, '127.0.0.1', () => resolve({ url: `http://127.0.0.1:${(server.address() as { port: number }).port}/`, server }))
  )
}

describe.skipIf(!hasChromium)('threaded cloth in Chromium', () => {
  let browser: Browser
  const servers: Server[] = []

  beforeAll(async () => {
    build(join(__dirname, 'threads', 'page.ts'), 'page.js')
    build(join(__dirname, '..', '..', 'src', 'worker.ts'), 'worker.js')
    browser = await chromium.launch({
      executablePath: exe,
      args: ['--no-sandbox', '--disable-background-networking', '--disable-component-update', '--no-first-run'],
    })
  })
  afterAll(async () => {
    await browser?.close()
    for (const s of servers) s.close()
  })

  it('cross-origin isolated: two Web Workers, 120 awaited frames and 10 of stepCloth, the same positions as without workers', async () => {
    const { url, server } = await serve(true)
    servers.push(server)
    const page = await browser.newPage()
    const errors: string[] = []
    page.on('pageerror', (e) => errors.push(e.message))
    await page.goto(url)
    await page.waitForFunction(() => (globalThis as { pageReady?: boolean }).pageReady === true)
    const r = await page.evaluate(() =>
      (globalThis as unknown as { runThreads(n: number): Promise<Record<string, unknown>> }).runThreads(120)
    )
    expect(errors).toEqual([])
    expect(r.isolated).toBe(true)
    expect(r.threads).toBe(2)
    expect(r.handed).toBe(130) // 120 awaited frames, then 10 of stepCloth
    expect(r.tears).toBeGreaterThan(0)
    expect(r.same).toBe(true)
    expect(await page.evaluate(() => (globalThis as unknown as { requireThreads(): string | null }).requireThreads())).toBeNull()
  })

  it('stepCloth right after the world is made runs on the page until the workers are up, then on them (no stall)', async () => {
    const { url, server } = await serve(true)
    servers.push(server)
    const page = await browser.newPage()
    const errors: string[] = []
    page.on('pageerror', (e) => errors.push(e.message))
    await page.goto(url)
    await page.waitForFunction(() => (globalThis as { pageReady?: boolean }).pageReady === true)
    const r = await page.evaluate(() => (globalThis as unknown as { stepAtOnce(): Promise<Record<string, number | boolean>> }).stepAtOnce())
    console.log(
      `stepCloth at once: 20 frames in ${
        (r.syncMs as number).toFixed(0)
      } ms, ${r.handedAtOnce} handed over; workers took steps from frame ${r.frames as number - 10}`,
    )
    expect(errors).toEqual([])
    expect(r.syncMs).toBeLessThan(20000) // a spinning wait for workers that cannot start ran into the pool's one-minute stuck report
    expect(r.handed).toBeGreaterThan(r.handedAtOnce as number)
    expect(r.same).toBe(true)
  })

  it('not isolated: no SharedArrayBuffer, a warning and the main thread (or a ClothError with requireThreads)', async () => {
    const { url, server } = await serve(false)
    servers.push(server)
    const page = await browser.newPage()
    const warnings: string[] = []
    page.on('console', (m) => {
      if (m.type() === 'warning') warnings.push(m.text())
    })
    await page.goto(url)
    await page.waitForFunction(() => (globalThis as { pageReady?: boolean }).pageReady === true)
    const r = await page.evaluate(() =>
      (globalThis as unknown as { runThreads(n: number): Promise<Record<string, unknown>> }).runThreads(10)
    )
    expect(r.isolated).toBe(false)
    expect(r.threads).toBe(0)
    expect(r.same).toBe(true)
    expect(warnings.some((w) => /cross-origin isolated/.test(w))).toBe(true)
    const error = await page.evaluate(() => (globalThis as unknown as { requireThreads(): string | null }).requireThreads())
    expect(error).toMatch(/^ClothError: .*Cross-Origin-Embedder-Policy: require-corp/)
  })
})
