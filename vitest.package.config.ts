import { defineConfig } from 'vitest/config'

/** The package as a user installs it (`npm run test:package`): npm pack, install, type-check, run. */
export default defineConfig({
  test: {
    include: ['tests/package/**/*.test.ts'],
    testTimeout: 600_000,
  },
})
