import { solveLineBending } from '../src/kernels/bending'
import { solveDihedrals } from '../src/kernels/dihedral'
import { solveCompression, solveDistances, solveDistancesXpbd, spreadInverseMasses } from '../src/kernels/distance'
import { solveTethers } from '../src/kernels/tether'
import { solveLines } from '../src/kernels/lines'
import { solveGrabs } from '../src/kernels/grab'
import { beginGrabSubstep, endGrabSubstep } from '../src/features/grab/step'
import { anchorsMoveTogether } from '../src/features/pins/step'
import { getClothWorld } from '../src/world/access'
import type { ClothState, ClothWorldState } from '../src/world/state'
import type { ClothLines } from '../src/model/lines'

/**
 * Solve phase, every substep: Gauss-Seidel sweeps over each cloth's constraints, `iterations`
 * times. Within a sweep: grabs first (soft pulls toward a hand, `src/features/grab/`), then
 * bending (line triples, dihedral hinges), the softest, so the stiff constraints after them have
 * the last word, then distance constraints (stretch, shear, bend springs) and compression-only
 * diagonals. Tethers run once, after the last sweep: they are one-sided limits
 * whose job is that no particle ends the substep beyond its long-range distance; within the
 * sweeps the distance constraints already carry the load, so repeating them there buys nothing.
 * With `lineSolve`, the edges that form lines (rows and columns) are solved a line at a time
 * (`src/kernels/lines.ts`) in place of their place in the distance sweep, after the other distance
 * constraints of the iteration, and once more after the tethers, last, their multipliers carried
 * over so a compliant edge keeps its compliance: the tethers pull particles toward their anchors
 * and stretch the lines they cross (a 64×64 sheet swinging from two corners at 3 substeps: 19.6 %
 * at its worst edge with one pass, 4.8 % with the last; see `tests/lineSolve.test.ts`).
 */
export function clothSolve<W extends object>(world: W): W {
  const state = getClothWorld(world)
  const cloths = state.cloths
  for (let ci = 0; ci < cloths.length; ci++) solveOfCloth(state, cloths[ci])
  return world
}

/** The solve phase of one cloth at the world's substep. */
export function solveOfCloth(state: ClothWorldState, c: ClothState): void {
  const stats = state.stats
  if (c.subIndex < 0) return
  const t = c.topology
  const p = c.params
  const tethers = c.tethers.set
  // XPBD with several iterations accumulates multipliers from zero each substep; with one
  // iteration (or classic PBD) they are always zero and the cheaper loops skip them
  const accumulate = c.solver === 'xpbd' && c.iterations > 1
  // the distance loops read inverse masses at position offsets; masses change only between
  // steps (pins, unpins, tears, restores), so one copy per step keeps them current
  if (c.subIndex === 0) spreadInverseMasses(c.invMass, c.invMass3, c.count)
  // lines of edges solved at once (`lineSolve`; not on a tearable cloth: a tear splits particles)
  const lines = c.tear === null ? c.lines : null
  // (with XPBD the lines' multipliers always: their last pass, after the iterations, goes on from
  // them; classic PBD projects afresh each time, its stiffness per projection)
  if (lines !== null && c.solver === 'xpbd') lines.lambda.fill(0)
  if (accumulate && lines !== null) lines.sweepLambda.fill(0)
  if (accumulate) {
    // the live constraints only (a tearable cloth reserves room for more)
    c.distLambda.fill(0, 0, t.distCount)
    c.compLambda.fill(0, 0, t.compCount)
    c.lineLambda.fill(0, 0, 3 * t.lineCount)
    c.hingeLambda.fill(0, 0, t.hingeCount)
  }
  const hingeLambda = accumulate ? c.hingeLambda : null
  const lineLambda = accumulate ? c.lineLambda : null
  const compLambda = accumulate ? c.compLambda : null
  const grabs = c.grab
  if (grabs.count > 0) beginGrabSubstep(c)
  for (let it = 0; it < c.iterations; it++) {
    if (grabs.count > 0) solveGrabs(c.pos, c.invMass, grabs.particle, grabs.data, grabs.count, p)
    if (t.lineCount > 0) {
      solveLineBending(c.pos, c.invMass, t.lineIds, t.lineRest, t.lineCompliance, lineLambda, p, 0, t.lineCount)
    }
    if (t.hingeCount > 0) {
      solveDihedrals(c.pos, c.invMass, t.hingeIds, t.hingeRest, t.hingeCompliance, hingeLambda, t.hingeSide, p, 0, t.hingeCount)
    }
    if (lines !== null) solveLinesAndSweep(c, lines, accumulate)
    else if (accumulate) solveDistancesXpbd(c.pos, c.invMass3, t.distOffsets, t.distRest, t.distCompliance, c.distLambda, p, 0, t.distCount)
    else solveDistances(c.pos, c.invMass3, t.distOffsets, t.distRest, t.distCompliance, p, 0, t.distCount)
    if (t.compCount > 0) {
      solveCompression(c.pos, c.invMass, t.compIds, t.compRest, t.compCompliance, compLambda, p, 0, t.compCount)
    }
  }
  if (tethers.count > 0) {
    const apart = anchorsMoveTogether(state, c) ? null : t.restPositions
    solveTethers(c.pos, c.invMass, tethers.particle, tethers.anchor, tethers.rest, apart, tethers.count)
  }
  // the lines once more, last: the stretch the tethers and the sweep left along them; not the
  // segments held at both ends: between two pins moved apart the tethers spread the stretch evenly,
  // and swept again after them a banner's top row pulled 5 % wider zigzagged between 2 and 8 %
  if (lines !== null) solveLinePass(c, lines, 2)
  if (grabs.count > 0) endGrabSubstep(c)
  stats.dihedralProjections += t.hingeCount * c.iterations
  stats.lineProjections += t.lineCount * c.iterations
  stats.distanceProjections += (t.distCount + t.compCount) * c.iterations
  stats.tetherProjections += tethers.count
}

/** One iteration's distance constraints with `lineSolve`: those in no line swept, then each line at once. */
function solveLinesAndSweep(c: ClothState, L: ClothLines, accumulate: boolean): void {
  const p = c.params
  if (accumulate) solveDistancesXpbd(c.pos, c.invMass3, L.sweepOffsets, L.sweepRest, L.sweepCompliance, L.sweepLambda, p, 0, L.sweepCount)
  else solveDistances(c.pos, c.invMass3, L.sweepOffsets, L.sweepRest, L.sweepCompliance, p, 0, L.sweepCount)
  solveLinePass(c, L, 1)
}

/**
 * One pass of the lines (`solveLines`): `pass` 1 in an iteration, 2 the substep's last (after the
 * tethers; a row pulled taut between two pins left to them). Their multipliers accumulate over a
 * substep's passes with XPBD; classic PBD projects afresh.
 */
function solveLinePass(c: ClothState, L: ClothLines, pass: number): void {
  const lambda = c.solver === 'xpbd' ? L.lambda : null
  solveLines(c.pos, c.invMass, L.start, L.ids, L.rest, L.compliance, c.params, L.count, lambda, L.n, L.cc, L.dd, pass)
}
