// `npm run screenshots`: photographs every scene of the demo at rest and in motion, in headless
// Chromium, into demo/screenshots/<scene>-<moment>.jpg (the README's pictures). Each picture is
// taken after simulating a fixed number of 60 Hz frames, so it does not depend on the machine's
// speed. Options: --out <dir> (default demo/screenshots), --scenes a,b (default all), --all (also
// the extra moments, e.g. the cape walking, sprinting and jumping),
// --width/--height (default 960×540).
import { existsSync, mkdirSync } from 'node:fs'
import { join, resolve } from 'node:path'
import { parseArgs } from 'node:util'
import { chromium } from 'playwright-core'
import { serveDemo } from './serve.mjs'

/** The launch options the browser tests use too: software WebGL2 and a quiet browser. */
export const CHROMIUM_ARGS = [
  '--no-sandbox',
  '--use-angle=swiftshader',
  '--enable-unsafe-swiftshader',
  '--disable-background-networking',
  '--disable-component-update',
  '--disable-sync',
  '--no-first-run',
]

/** Loads every scene (or `only`) and saves one PNG per moment into `out`; returns the files. */
export async function photograph(
  {
    out,
    only,
    all = false,
    width = 960,
    height = 540,
    executablePath = process.env.CHROMIUM_PATH ?? '/usr/bin/chromium',
    log = console.log,
  },
) {
  mkdirSync(out, { recursive: true })
  const { url, server } = await serveDemo(0)
  const browser = await chromium.launch({ executablePath, args: CHROMIUM_ARGS })
  const files = []
  try {
    const page = await browser.newPage({ viewport: { width, height } })
    const errors = []
    page.on('pageerror', (e) => errors.push(e.message))
    page.on('console', (m) => m.type() === 'error' && errors.push(m.text()))
    await page.goto(url)
    await page.waitForFunction(() => window.__demo?.ready === true, null, { timeout: 60_000 })
    const moments = await page.evaluate(() => window.__demo.moments)
    for (const [scene, list] of Object.entries(moments)) {
      if (only && !only.includes(scene)) continue
      for (const m of list) {
        if (m.extra && !all) continue
        await page.goto(`${url}?scene=${scene}&pr=1`, { waitUntil: 'domcontentloaded', timeout: 180_000 })
        await page.waitForFunction(() => window.__demo?.ready === true, null, { timeout: 180_000 })
        await page.evaluate(({ seconds, action, actionAt }) => {
          const d = window.__demo
          // live timings mean nothing after a simulated run; hidden first, so the picture is
          // framed as without them (the view frames it in the canvas the overlays leave free)
          document.getElementById('stats-box').style.display = 'none'
          d.setPaused(true)
          d.loadScene(d.scene, true)
          if (action && !actionAt) d.api[action]()
          if (action && actionAt) {
            d.simulate(actionAt)
            d.api[action]()
            d.simulate(seconds - actionAt)
          } else d.simulate(seconds)
        }, m)
        const file = join(out, `${scene}-${m.name}.jpg`)
        await page.screenshot({ path: file, type: 'jpeg', quality: 82 })
        files.push(file)
        log(`  ${file}`)
      }
    }
    if (errors.length) throw new Error(`errors in the page:\n${errors.join('\n')}`)
  } finally {
    await browser.close()
    server.close()
  }
  return files
}

if (process.argv[1] && resolve(process.argv[1]) === resolve(new URL(import.meta.url).pathname)) {
  const { values } = parseArgs({
    options: {
      all: { type: 'boolean' },
      out: { type: 'string' },
      scenes: { type: 'string' },
      width: { type: 'string' },
      height: { type: 'string' },
    },
  })
  const exe = process.env.CHROMIUM_PATH ?? '/usr/bin/chromium'
  if (!existsSync(exe)) {
    console.error(`no Chromium at ${exe}: install Debian's chromium package or set CHROMIUM_PATH`)
    process.exit(1)
  }
  const out = values.out ?? join(new URL('.', import.meta.url).pathname, 'screenshots')
  console.log(`photographing the demo into ${out}`)
  await photograph({
    out,
    only: values.scenes?.split(','),
    all: values.all,
    width: Number(values.width ?? 960),
    height: Number(values.height ?? 540),
  })
}
