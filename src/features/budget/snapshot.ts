import type { ClothState, ClothWorldState } from '../../world/state'

/**
 * The budget's part of restoring a snapshot: without a world budget, the quality a restored cloth
 * runs (its substeps and iterations, in the core section) is also the quality it wants.
 */
export function restoreBudget(state: ClothWorldState, c: ClothState): void {
  if (state.budget.settings !== null) return
  c.budget.wantSubsteps = c.substeps
  c.budget.wantIterations = c.iterations
}
