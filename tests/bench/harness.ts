import { mkdirSync, writeFileSync } from 'node:fs'

/**
 * This process's CPU time, ms (user + system, all its threads). On a machine shared with other
 * work this counts only the time spent on our own computation, where the wall clock also counts
 * time waiting for a core; the timed code allocates nothing, so no collector threads add to it.
 */
export function cpuMs(): number {
  const u = process.cpuUsage()
  return (u.user + u.system) / 1000
}

/** Runs `fn` `count` times and returns the mean CPU milliseconds per call (after `warmup` calls). */
export function timeIt(fn: () => void, count: number, warmup = Math.min(50, count)): number {
  for (let i = 0; i < warmup; i++) fn()
  const t0 = cpuMs()
  for (let i = 0; i < count; i++) fn()
  return (cpuMs() - t0) / count
}

/** Prints rows as an aligned table. */
export function table(title: string, rows: Record<string, string | number>[]): void {
  console.log(`\n${title}`)
  if (rows.length === 0) return
  const keys = Object.keys(rows[0])
  const cells = rows.map((r) => keys.map((k) => String(r[k])))
  const width = keys.map((k, i) => Math.max(k.length, ...cells.map((c) => c[i].length)))
  const line = (c: string[]) => '  ' + c.map((s, i) => s.padStart(width[i])).join('  ')
  console.log(line(keys))
  console.log('  ' + width.map((w) => '-'.repeat(w)).join('  '))
  for (const c of cells) console.log(line(c))
}

/** Writes a suite's raw results to bench-results/<name>.json. */
export function saveJson(name: string, data: unknown): void {
  mkdirSync('bench-results', { recursive: true })
  writeFileSync(`bench-results/${name}.json`, JSON.stringify(data, null, 2))
}

/** Formats a number with `digits` decimals. */
export const fmt = (x: number, digits = 2): string => x.toFixed(digits)
