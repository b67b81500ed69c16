import { allocation, sheets, throughput } from './core'
import { outOfRange, perCollider, selfShare } from './collision'

/** Benchmark suites by name; `npm run bench -- core` runs one. */
const suites: Record<string, () => void | Promise<void>> = {
  core: async () => {
    throughput()
    sheets()
    await allocation()
  },
  collision: () => {
    perCollider()
    selfShare()
    outOfRange()
  },
}

const wanted = process.argv.slice(2)
for (const [name, run] of Object.entries(suites)) {
  if (wanted.length === 0 || wanted.includes(name)) await run()
}
