import { observe, onAdd, onRemove } from 'bitecs'
import { untrackEntity } from '../../world/kinematics'
import type { ClothWorldState } from '../../world/state'
import { deferrable } from '../../world/flight'
import { releaseAnchor } from '../budget/freeze'
import { liftMotionConstraints } from './api'
import { adoptPinFrame, dropPinFrame, useDefaultFrame } from './frames'
import { M_POSE, M_PRIMED, S_FRAME_EXPLICIT, type ClothCharacter } from './types'
import { carryPose, trackedPose } from './reference'
import { relativeRotationAt } from '../../core/math'

/**
 * Registers the observers of character cloth: pins added or removed (the default frame follows
 * them), and frames and bones whose Transform goes away (removed entity, or component): the cloth
 * keeps their last pose, so a recycled id is never followed.
 * Called by `installClothPlugin`.
 */
export function installCharacter(world: object, state: ClothWorldState): void {
  observe(world as never, onAdd(state.components.Pin), (pin: number) => adoptPinFrame(state, pin))
  observe(world as never, onRemove(state.components.Pin), deferrable(state, (pin: number) => pinGone(state, pin)))
  observe(
    world as never,
    onRemove(state.transforms.component),
    deferrable(state, (eid: number) => {
      for (const c of state.cloths) {
        const ch = c.character
        if (ch === null) continue
        const lostFrame = ch.frame === eid && ch.frameSlot >= 0
        if (ch.skin !== null) keepBonePoses(state, ch, eid, lostFrame)
        if (lostFrame) {
          releaseAnchor(state, c, ch.frameSlot)
          untrackEntity(state, eid)
          ch.frameSlot = -1
          ch.frame = 0
          // the world as the frame from here on, still: without its motion history, which the next
          // step took for the frame stopping dead (a cape running at 5 m/s was jolted by 4.4 m/s)
          ch.motion[M_PRIMED] = 0
        }
        const skin = ch.skin
        if (skin === null) {
          // a rigid reference left with the world as its frame lets the cloth go, as the frame's
          // pins do: its motion constraints are lifted (kept, max distance 0 nailed the cape of a
          // character removed at 5 or 50 m/s where it vanished, in mid-air)
          if (lostFrame) liftMotionConstraints(state, c)
          continue
        }
        for (let b = 0; b < skin.bones.length; b++) {
          if (skin.bones[b] !== eid || skin.slots[b] < 0) continue
          releaseAnchor(state, c, skin.slots[b])
          untrackEntity(state, eid)
          skin.slots[b] = -1
          skin.bones[b] = 0
        }
        // a frame that went passes to the next default (the next pin target or bone), an explicit
        // one too: left to the world, the part on a bone that went stayed where it went while the
        // rest walked on (2174 % stretch; a dead hero given as the frame, whose ragdoll's bones slid
        // on at 4 m/s, left its cape's collar 8.2 m behind them: 12,702 %)
        if (lostFrame) useDefaultFrame(state, c, ch)
      }
    }),
  )
}

/**
 * A pin went: the default frame follows the pins (`dropPinFrame`). Pins going with their target
 * that was the frame leave a rigid reference with the world as its frame: the cloth is let go, its
 * motion constraints with it, as when an explicit frame goes.
 */
function pinGone(state: ClothWorldState, pin: number): void {
  const P = state.components.Pin
  const going = P.target[pin] !== 0 && P.target[pin] === state.kinematics.losing
  dropPinFrame(state, pin)
  const c = state.components.Cloth.state[P.cloth[pin]]
  const ch = c?.character
  // (a frame that is the world by choice, `frame: null`, was never the entity that went)
  if (going && ch && ch.skin === null && ch.frame === 0 && ch.settings[S_FRAME_EXPLICIT] === 0) liftMotionConstraints(state, c)
}

/** The frame's pose now (10 values), then its turn (4): scratch of `keepBonePoses`. */
const now = new Float64Array(14)

/**
 * Before the bone `eid` goes (its slot still tracked): the cloth keeps its pose, and carries it
 * with its frame from then on. Kept poses are in the terms of the frame's pose at the cloth's last
 * step (`M_POSE`), which is what carries them (step by step, and over a gap: asleep or frozen): the
 * bone's pose now, carried back by the frame's motion since that step. When the frame itself goes
 * (`lostFrame`), every kept pose is carried by its motion until now, the time at which the next
 * frame's pose is taken. (The pose of the cloth's last step, kept as it was, rode the frame's
 * motion again from then: a cape frozen 30 steps before its frame bone went was pulled 2 m long,
 * 1667 % stretch for good after its thaw.)
 */
function keepBonePoses(state: ClothWorldState, ch: ClothCharacter, eid: number, lostFrame: boolean): void {
  const skin = ch.skin!
  const m = ch.motion
  const frame = ch.frameSlot >= 0
  if (frame) {
    trackedPose(state, ch.frameSlot, now, 0)
    relativeRotationAt(m, M_POSE + 3, now, 3, now, 10) // (the turn from now back to M_POSE)
  }
  for (let b = 0; b < skin.bones.length; b++) {
    if (skin.bones[b] !== eid || skin.slots[b] < 0) continue
    trackedPose(state, skin.slots[b], skin.pose, 10 * b)
    if (frame) carryPose(skin.pose, 10 * b, now, 0, m, M_POSE, now, 10)
  }
  if (!lostFrame) return
  relativeRotationAt(now, 3, m, M_POSE + 3, now, 10) // (the turn from M_POSE to now)
  for (let b = 0; b < skin.bones.length; b++) {
    if (skin.slots[b] < 0 || skin.bones[b] === eid) carryPose(skin.pose, 10 * b, m, M_POSE, now, 0, now, 10)
  }
}
