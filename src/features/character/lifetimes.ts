import { observe, onAdd, onRemove } from 'bitecs'
import { untrackEntity } from '../../world/kinematics'
import type { ClothWorldState } from '../../world/state'
import { deferrable } from '../../world/flight'
import { releaseAnchor } from '../budget/freeze'
import { adoptPinFrame, dropPinFrame, useDefaultFrame } from './frames'
import { M_PRIMED, S_FRAME_EXPLICIT } from './types'

/**
 * Registers the observers of character cloth: pins added or removed (the default frame follows
 * them), and frames and bones whose Transform goes away (removed entity, or component): the cloth
 * keeps their last pose, so a recycled id is never followed.
 * Called by `installClothPlugin`.
 */
export function installCharacter(world: object, state: ClothWorldState): void {
  observe(world as never, onAdd(state.components.Pin), (pin: number) => adoptPinFrame(state, pin))
  observe(world as never, onRemove(state.components.Pin), deferrable(state, (pin: number) => dropPinFrame(state, pin)))
  observe(
    world as never,
    onRemove(state.transforms.component),
    deferrable(state, (eid: number) => {
      for (const c of state.cloths) {
        const ch = c.character
        if (ch === null) continue
        const lostFrame = ch.frame === eid && ch.frameSlot >= 0
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
        if (skin === null) continue
        for (let b = 0; b < skin.bones.length; b++) {
          if (skin.bones[b] !== eid || skin.slots[b] < 0) continue
          releaseAnchor(state, c, skin.slots[b])
          untrackEntity(state, eid)
          skin.slots[b] = -1
          skin.bones[b] = 0
        }
        // a default frame that went (a skinned cloth's first bone) passes to the next default (the
        // next bone): left to the world, the part on the bone that went stayed where it went while
        // the rest walked on (2174 % stretch)
        if (lostFrame && ch.settings[S_FRAME_EXPLICIT] === 0) useDefaultFrame(state, c, ch)
      }
    }),
  )
}
