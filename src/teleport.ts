import { wakeSelfNeighbours } from './features/collision/selfCollision'
import type { quat, vec3 } from 'gl-matrix'
import { checkPoint, checkQuat } from './core/errors'
import { normalizedQuat } from './core/math'
import { carryShownAnchor } from './draw'
import { carryFrozenReference } from './features/budget/freeze'
import { carryWorldFrame } from './features/character/frames'
import { carryPins } from './features/pins/api'
import { getCloth, getClothWorldForChange } from './world/access'
import { carryFrozen, moveClothRigidly } from './world/rigid'
import { wakeClothState } from './world/wake'

const IDENTITY = [0, 0, 0, 1]

/** Scratch: the teleport as a rigid-motion record. */
const motion = new Float64Array(10)

/**
 * Teleports a cloth: moves it rigidly by `translation`, rotated by `rotation` about `pivot`
 * (default: the cloth's centroid), keeping its shape and velocities (rotated). World-space pins
 * move with it, and so does the reference pose of character cloth whose frame is the world (no
 * frame entity and no skin: see `setClothMotionConstraints`). At the next frame sample the pins'
 * targets jump (however short the distance) and the cloth is not carried a second time. A cloth
 * whose pins all hold it to one target then follows that target's jump exactly as a detected
 * teleport does: its motion beyond what its velocity predicts is the jump, and the rest is
 * simulated, so moving the cloth by the target's whole displacement (this frame's running
 * included) or by the jump alone gives the same result, in a frame of any length.
 *
 * Moving a character far in one frame without calling this also works: the plugin detects the
 * jump (`teleportDistance`) and carries the cloth along by the target's motion.
 */
export function teleportCloth(
  world: object,
  cloth: number,
  translation: Readonly<vec3> | ArrayLike<number>,
  rotation?: Readonly<quat> | ArrayLike<number>,
  pivot?: Readonly<vec3> | ArrayLike<number>,
): void {
  const state = getClothWorldForChange(world)
  const c = getCloth(state, cloth)
  checkPoint('translation', translation)
  const [rx, ry, rz, rw] = rotation === undefined ? IDENTITY : normalizedQuat(checkQuat('rotation', rotation))
  if (pivot !== undefined) checkPoint('pivot', pivot)
  carryFrozen(c, state.kinematics.stepTo) // moved from where its pins have carried it
  wakeSelfNeighbours(state, c) // (what sleeps on it, where it was)
  let px = 0, py = 0, pz = 0
  if (pivot !== undefined) {
    px = pivot[0]
    py = pivot[1]
    pz = pivot[2]
  } else {
    // the centroid of the particles triangles use (a vertex no triangle uses is no part of the cloth)
    const unused = c.topology.unused
    let m = 0
    for (let i = 0; i < c.count; i++) {
      if (unused !== null && unused[i] === 1) continue
      px += c.pos[3 * i]
      py += c.pos[3 * i + 1]
      pz += c.pos[3 * i + 2]
      m++
    }
    if (m > 0) {
      px /= m
      py /= m
      pz /= m
    }
  }
  // the motion as a record (see `moveClothBy`): about the pivot, then the translation
  const m = motion
  m[0] = px
  m[1] = py
  m[2] = pz
  m[3] = rx
  m[4] = ry
  m[5] = rz
  m[6] = rw
  for (let a = 0; a < 3; a++) m[7 + a] = translation[a]
  moveClothRigidly(c, px, py, pz, rx, ry, rz, rw, px + m[7], py + m[8], pz + m[9], true) // (torn pieces too)
  carryShownAnchor(state, c, m) // (drawn from where the mesh now shows it)
  carryPins(state, c, m)
  carryWorldFrame(c, m)
  if (c.budget.frozen) {
    // a frozen cloth is carried by its reference (moved along above) until it thaws: no teleport is
    // left pending for its pins (kept, the thaw step moved the cloth back by the teleport and then
    // by its target's jump there, which its character frame had forced: 152 % stretch)
    carryFrozenReference(c, m)
    c.pins.skipTeleport = false
    c.pins.hand[10] = 0
  }
  state.stats.teleports++
  wakeClothState(state, c)
}
