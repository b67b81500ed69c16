import { defineConfig } from 'vitest/config'

/** Browser tests of the demo (`npm run test:e2e`): real Chromium through playwright-core. */
export default defineConfig({
  test: {
    include: ['tests/e2e/**/*.e2e.ts'],
    testTimeout: 900_000, // every scene in software WebGL on a shared 2-core machine
    hookTimeout: 120_000,
    fileParallelism: false,
  },
})
