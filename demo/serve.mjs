// `npm start`: builds the demo and serves demo/ on localhost with a tiny static server, with the
// headers a deployment needs for cross-origin isolation (SharedArrayBuffer for worker threads):
// every response is same-origin only for openers and embeds.
import { createServer } from 'node:http'
import { readFile } from 'node:fs/promises'
import { dirname, extname, join, normalize } from 'node:path'
import { fileURLToPath } from 'node:url'
import { buildDemo } from './build.mjs'

const here = dirname(fileURLToPath(import.meta.url))
/** Cross-origin isolation: `crossOriginIsolated` is true in the page. */
export const ISOLATION_HEADERS = {
  'cross-origin-opener-policy': 'same-origin',
  'cross-origin-embedder-policy': 'require-corp',
  'cross-origin-resource-policy': 'same-origin',
}
const types = {
  '.html': 'text/html; charset=utf-8',
  '.js': 'text/javascript',
  '.map': 'application/json',
  '.css': 'text/css',
  '.png': 'image/png',
  '.svg': 'image/svg+xml',
}

/** Starts the server on `port` (0 = any free port) and resolves to its URL. */
export async function serveDemo(port = Number(process.env.PORT ?? 8080)) {
  await buildDemo()
  const server = createServer(async (req, res) => {
    const path = normalize(decodeURIComponent(new URL(req.url ?? '/', 'http://x').pathname)).replace(/^([/\\])+/, '')
    const file = join(here, path === '' ? 'index.html' : path)
    if (!file.startsWith(here)) {
      res.writeHead(403, ISOLATION_HEADERS).end()
      return
    }
    try {
      const body = await readFile(file)
      res.writeHead(200, {
        ...ISOLATION_HEADERS,
        'content-type': types[extname(file)] ?? 'application/octet-stream',
        'cache-control': 'no-store',
      })
      res.end(body)
    } catch {
      res.writeHead(404, ISOLATION_HEADERS).end('not found')
    }
  })
  await new Promise((resolve, reject) => {
    server.once('error', reject)
    server.listen(port, '127.0.0.1', resolve)
  }).catch(async (err) => {
    if (err.code !== 'EADDRINUSE' || port === 0) throw err
    await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve))
  })
  const { port: actual } = server.address()
  return { url: `http://127.0.0.1:${actual}/`, server }
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
  const { url } = await serveDemo()
  console.log(`bitecs-cloth demo: ${url}`)
}
