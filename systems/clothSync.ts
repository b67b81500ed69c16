import { rebuildTethers } from '../src/cloth'
import { beginKinematicStep, sampleFrame } from '../src/world/kinematics'
import { markScaleLeaps } from '../src/world/scaleJump'
import { getClothWorld } from '../src/world/access'
import { followTargetJumps, jumpedPinTarget } from '../src/features/pins/step'
import { advanceGrabs, beginGrabFrame, sampleGrabTargets } from '../src/features/grab/step'
import { advanceWind } from '../src/features/wind/step'
import { sweepColliders } from '../src/features/collision/step'
import { updateBudget, wantStepTiming } from '../src/features/budget/allocate'
import { wakeSleepers } from '../src/features/sleep/step'
import { carryWithFrames, markCarriedSlots } from '../src/features/character/carry'
import { beginCharacterStep, characterJumped, markFrameTeleports, noteIdle, wakeMovedCharacters } from '../src/features/character/step'

/**
 * Sync phase, once per fixed step before the substeps: advances the tracked transforms (pin
 * targets, collider bodies, grab targets) to this step's time slice, taking a new frame sample on a frame's
 * first step, sweeps the colliders' bounds over the step and advances the wind; then wakes the
 * sleeping cloths that any of this disturbs, carries cloths along when their targets jumped,
 * applies quality targets and the world budget, rebuilds tethers of cloths whose pins changed and
 * picks the step's substep count (the most of any running cloth). Character cloths get their
 * frame's jumps (tested before the sample), motion and reference pose for the step. This is the
 * only phase that reads transforms.
 */
export function clothSync<W extends object>(world: W): W {
  const state = getClothWorld(world)
  const k = state.kinematics
  const frameStart = !k.framed || k.newFrame
  if (frameStart) {
    markFrameTeleports(state) // per-cloth teleport thresholds (nothing without character cloths)
    const withFrames = markCarriedSlots(state) // what dropped frame time's motion carries (nothing without a hitch)
    sampleFrame(state)
    if (withFrames) carryWithFrames(state) // a skinned cloth's bones, by its frame's carry
    markScaleLeaps(state) // scales that snapped: taken at once, not swept
    // inside a frame, its later steps interpolate this sample; a step outside frames
    // (`clothFixedStep`, the phases run by hand) leaves the next frame to sample anew (it took
    // none, and its pins stood still for its first step: 6.7 cm behind at 4 m/s)
    if (k.framed) k.newFrame = false
  }
  beginKinematicStep(k)
  if (state.collision.entries.length > 0) sweepColliders(state) // (compacts the list first)
  advanceWind(state) // wind time, gusts and zone poses for this step (nothing without zones)
  wakeSleepers(state) // nothing while no cloth sleeps
  wakeMovedCharacters(state) // likewise
  updateBudget(state, frameStart) // quality targets and the world budget (nothing without them)
  wantStepTiming(state)
  let total = 0
  const cloths = state.cloths
  for (let ci = 0; ci < cloths.length; ci++) {
    const c = cloths[ci]
    if (frameStart && c.grab.count > 0) beginGrabFrame(c) // idle or not: the frame's motion starts now
    const lod = c.budget
    let idle = c.sleep.asleep || lod.frozen
    if (!idle && lod.stepEvery > 1) {
      // a far cloth runs one step of stepEvery × the fixed step, then sits the others out; a jump
      // of what it follows makes it step now, so that it handles the jump (as a teleport) when
      // it happens rather than being dragged across it by its next step
      const jumped = frameStart && (jumpedPinTarget(state, c) >= 0 || characterJumped(state, c))
      // (a cloth about to freeze steps now too, to freeze where its pins and frame are, and one just
      // thawed, from where the thaw carried it, whatever level it thawed into: `dueNow`)
      if (++lod.phase < lod.stepEvery && !jumped && !lod.freezing && !lod.dueNow) {
        idle = true
        lod.waited++
      } else lod.phase = 0
    }
    c.idle = idle
    lod.dueNow = false
    if (idle) {
      noteIdle(c)
      c.subIndex = -1 // sits the whole step out (read by the guard, which runs after the substeps)
      if (c.sleep.asleep) state.stats.sleepingSteps++
      else state.stats.lodSkippedSteps++
      continue
    }
    // the step covers the steps the cloth sat out too, at whatever rate it now runs: its pins and
    // frame moved on meanwhile (a far cape back at full rate took their two steps' motion in one
    // step's time, at twice their speed)
    c.h = (state.fixedTimeStep * (lod.waited + 1)) / c.substeps
    lod.waited = 0
    if (c.substeps > total) total = c.substeps
    const pinJump = frameStart ? followTargetJumps(state, c) : 0
    if (c.character !== null) beginCharacterStep(state, c, frameStart, pinJump)
    // (a teleportCloth is taken by now as its target's jump: the mesh moves on from the step's start)
    lod.shownCarried = false
    c.pins.fresh = false
    // (after the jumps carried the cloth and its grabs' targets so far: the hand's new target is not
    // carried again; a cape held by its frame alone had its hand's target moved twice by a 10 m jump)
    if (c.grab.count > 0) advanceGrabs(state, c)
    if (c.tethers.dirty) rebuildTethers(state, c)
  }
  // (after the jumps carried the targets so far: the hand's target now is where the next frame's glide starts)
  if (frameStart) { for (let ci = 0; ci < cloths.length; ci++) if (cloths[ci].grab.count > 0) sampleGrabTargets(cloths[ci]) }
  state.substepCount = total
  state.substep = 0
  state.frame.stepping = true // (until the guard: cloths may not change in between)
  state.stats.steps++
  return world
}
