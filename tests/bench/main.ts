import { accuracy } from './accuracy'
import { swingingSheet } from './swinging'
import { allocation, sheets, throughput } from './core'
import { windCost } from './wind'
import { tearCost } from './tearing'
import { guardCost, snapshotCost } from './stability'
import { outOfRange, perCollider, selfShare, unload } from './collision'
import { capes, clothByCloth, payForUse, sleepingCost } from './budget'
import { demoScenes } from './demo'
import { threeCost } from './three'
import { proxyCost } from './render'
import { characterCost } from './character'
import { isMainThread, parentPort, workerData } from 'node:worker_threads'
import { runSplitWorker, threadsCharacterCost, threadsCost } from './threads'

/**
 * Benchmark suites by name. `npm run bench` runs the default ones; `npm run bench -- <name>` runs
 * one; `npm run bench:accuracy` runs the (slow) accuracy-versus-time sweeps: the swinging 64×64
 * sheet against the textbook loop (also alone: `npm run bench -- swinging`), then the 24×24
 * settings sweep.
 */
const suites: Record<string, { run: () => void | Promise<void>; byDefault: boolean }> = {
  core: {
    byDefault: true,
    run: async () => {
      throughput()
      sheets()
      await allocation()
    },
  },
  accuracy: {
    byDefault: false,
    run: () => {
      swingingSheet()
      accuracy()
    },
  },
  swinging: { byDefault: false, run: () => swingingSheet() },
  wind: { byDefault: true, run: () => windCost() },
  tearing: { byDefault: true, run: () => tearCost() },
  stability: {
    byDefault: true,
    run: () => {
      guardCost()
      snapshotCost()
    },
  },
  budget: {
    byDefault: true,
    run: () => {
      payForUse()
      sleepingCost()
      capes()
      clothByCloth()
    },
  },
  collision: {
    byDefault: true,
    run: () => {
      perCollider()
      selfShare()
      outOfRange()
      unload()
    },
  },
  render: { byDefault: true, run: () => proxyCost() },
  character: { byDefault: true, run: () => characterCost() },
  demo: { byDefault: false, run: () => demoScenes() },
  three: { byDefault: true, run: () => threeCost() },
  threads: { byDefault: false, run: () => threadsCost() },
  'threads-character': { byDefault: false, run: () => threadsCharacterCost() },
}

if (isMainThread) {
  const wanted = process.argv.slice(2)
  for (const [name, suite] of Object.entries(suites)) {
    if (wanted.length === 0 ? suite.byDefault : wanted.includes(name)) await suite.run()
  }
} else if (workerData?.kind === 'split') {
  // this bundle as a worker thread of the threads suite's split by hand
  runSplitWorker(workerData, () => parentPort?.postMessage('ready'))
}
