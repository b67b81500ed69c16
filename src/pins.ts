import { addComponent, addEntity, entityExists, hasComponent, removeEntity } from 'bitecs'
import type { quat, vec3 } from 'gl-matrix'
import { ClothError, checkIndex, checkInteger, checkNonNegative, checkObject, checkPoint, checkQuat } from './errors'
import { P_H, P_STEP_FRACTION } from './kernels/params'
import { quatToMatrix, rotateVec3 } from './math'
import { getClothWorld, type ClothState, type ClothWorldState } from './state'
import { checkEntity, readScale } from './transform'
import { interpolatePose, trackEntity, untrackEntity } from './kinematics'
import { growStores } from './plugin'
import { wakeClothState } from './sleep'

/** Options of `pinParticle`. */
export interface PinOptions {
  /**
   * When an explicit offset puts the pin away from where the particle is, the particle glides to
   * it over this many seconds instead of jumping. Default 0.25 s; 0 snaps.
   */
  blendTime?: number
}

const tmp = new Float64Array(16)
const pose = new Float64Array(7)

/**
 * Pins one particle. With a `target` entity (which must have a Transform), the particle follows
 * the target every substep at `offset` in the target's local frame (rotation and scale applied).
 * Without a target it stays at `offset` in world space. When `offset` is omitted the particle is
 * held where it is now, so pinning at runtime causes no jump; an explicit offset is blended in
 * over `blendTime`. Returns the pin entity (remove it, or call `unpin`, to release the particle).
 */
export function pinParticle(
  world: object,
  cloth: number,
  index: number,
  target?: number | null,
  offset?: Readonly<vec3> | ArrayLike<number>,
  options: PinOptions = {},
): number {
  const state = getClothWorld(world)
  const c = getCloth(state, cloth)
  checkIndex('index', index, c.count)
  const tgt = target ?? 0
  if (tgt !== 0) {
    checkEntity(world, 'target', tgt)
    if (!hasComponent(world as never, tgt, state.transforms.component)) {
      throw new ClothError('target', tgt, 'must have a Transform (call setTransform first)')
    }
  }
  if (offset !== undefined) checkPoint('offset', offset)
  checkObject('options', options)
  const blendTime = options.blendTime === undefined ? 0.25 : checkNonNegative('options.blendTime', options.blendTime)

  const pin = addEntity(world as never)
  growStores(state, pin)
  const P = state.components.Pin
  P.cloth[pin] = cloth
  P.particle[pin] = index
  P.target[pin] = tgt
  // the pin continues from the target's pose at the end of the last step (the simulation's now)
  const slot = tgt !== 0 ? trackEntity(state, tgt) : -1
  P.slot[pin] = slot
  const k = state.kinematics
  if (slot >= 0) for (let j = 0; j < 7; j++) tmp[8 + j] = k.stepTo[7 * slot + j]

  // where the particle is now, in the target's frame
  toLocal(state, tgt, tmp, 8, c.pos[3 * index], c.pos[3 * index + 1], c.pos[3 * index + 2], tmp, 0)
  P.blendFrom[3 * pin] = tmp[0]
  P.blendFrom[3 * pin + 1] = tmp[1]
  P.blendFrom[3 * pin + 2] = tmp[2]
  if (offset === undefined) {
    P.ox[pin] = tmp[0]
    P.oy[pin] = tmp[1]
    P.oz[pin] = tmp[2]
    P.blendLeft[pin] = 0
  } else {
    P.ox[pin] = offset[0]
    P.oy[pin] = offset[1]
    P.oz[pin] = offset[2]
    P.blendLeft[pin] = blendTime
  }
  P.blendTime[pin] = blendTime

  addComponent(world as never, pin, P)
  c.pins.push(pin)
  wakeClothState(state, c)
  if (c.pinCount[index]++ === 0) {
    c.invMass[index] = 0
    c.tethersDirty = true
  }
  return pin
}

/**
 * Pins every particle of one grid row (row 0 is the top edge) to `target`, or in place when no
 * target is given. Each particle keeps its current position relative to the target. Returns the
 * pin entities, left to right.
 */
export function pinRow(world: object, cloth: number, row: number, target?: number | null): number[] {
  const state = getClothWorld(world)
  const c = getCloth(state, cloth)
  const { columns, rows } = c.topology
  if (rows === 0) throw new ClothError('cloth', cloth, 'was not built as a grid (pinRow needs createCloth)')
  checkInteger('row', row, 0, rows - 1)
  const pins: number[] = []
  for (let col = 0; col < columns; col++) pins.push(pinParticle(world, cloth, row * columns + col, target))
  return pins
}

/** Releases a pin (removes its entity). The particle keeps its current velocity: no pop. */
export function unpin(world: object, pin: number): void {
  const state = getClothWorld(world)
  if (typeof pin !== 'number' || !entityExists(world as never, pin) || !hasComponent(world as never, pin, state.components.Pin)) {
    throw new ClothError('pin', pin, 'must be a pin entity of this world')
  }
  removeEntity(world as never, pin)
}

/** The pin entities holding a cloth, in creation order (a copy). */
export function getPins(world: object, cloth: number): number[] {
  return getCloth(getClothWorld(world), cloth).pins.slice()
}

/** Called when a Pin component goes away: frees the particle and forgets the pin. */
export function releasePin(state: ClothWorldState, pin: number): void {
  const P = state.components.Pin
  const c = state.components.Cloth.state[P.cloth[pin]]
  if (!c) return
  const k = c.pins.indexOf(pin)
  if (k < 0) return
  c.pins.splice(k, 1)
  wakeClothState(state, c)
  if (P.slot[pin] >= 0) untrackEntity(state, P.target[pin])
  P.slot[pin] = -1
  const i = P.particle[pin]
  if (--c.pinCount[i] === 0) {
    c.invMass[i] = c.baseInvMass[i]
    c.tethersDirty = true
  }
}

/** Looks up a cloth's state, or throws ClothError. */
export function getCloth(state: ClothWorldState, cloth: number): ClothState {
  const c = typeof cloth === 'number' ? state.components.Cloth.state[cloth] : undefined
  if (!c) throw new ClothError('cloth', cloth, 'must be a cloth entity of this world')
  return c
}

/** Writes the target-local coordinates of world point (x, y, z) into out[o..o+2]. */
function toLocal(
  state: ClothWorldState, target: number, pose: Float64Array, po: number,
  x: number, y: number, z: number, out: Float64Array, o: number,
): void {
  if (target === 0) {
    out[o] = x
    out[o + 1] = y
    out[o + 2] = z
    return
  }
  // inverse rotation: conjugate quaternion
  rotateVec3(-pose[po + 3], -pose[po + 4], -pose[po + 5], pose[po + 6], x - pose[po], y - pose[po + 1], z - pose[po + 2], out, o)
  out[o] /= readScale(state, target, 0)
  out[o + 1] /= readScale(state, target, 1)
  out[o + 2] /= readScale(state, target, 2)
}

// ---------------------------------------------------------------------------------------------
// Per-step and per-substep pin work (called by the sync and predict systems)

/**
 * At a frame sample: if one of the cloth's pin targets jumped (teleported), carry the whole cloth
 * along by the same rigid transform, keeping its shape and (rotated) velocity. The kinematics
 * module has already moved the target's earlier poses, so the pins continue from the new place.
 */
export function followTargetJumps(state: ClothWorldState, c: ClothState): void {
  const k = state.kinematics
  const P = state.components.Pin
  if (!c.skipTeleport) {
    for (let q = 0; q < c.pins.length; q++) {
      const slot = P.slot[c.pins[q]]
      if (slot < 0 || k.jumped[slot] === 0) continue
      const j = 10 * slot
      const cx = k.jump[j], cy = k.jump[j + 1], cz = k.jump[j + 2]
      transformCloth(c, cx, cy, cz, k.jump[j + 3], k.jump[j + 4], k.jump[j + 5], k.jump[j + 6], cx + k.jump[j + 7], cy + k.jump[j + 8], cz + k.jump[j + 9])
      state.stats.teleports++
      break
    }
  }
  c.skipTeleport = false
}

/**
 * Places the pinned particles of a cloth for local substep k of n: the target's pose is
 * interpolated (position lerp, rotation slerp) to (k + 1)/n of the way through the step, so a fast
 * character drags its cloth smoothly instead of in one jerk per step. Scalars travel in typed
 * arrays: calling helpers with double arguments would box them (allocate) on every call.
 * `advance` false places them as they stand (the guard, after a reset): the blends of pins added
 * or moved at run time do not move on, and no pin update is counted.
 */
export function placePins(state: ClothWorldState, c: ClothState, k: number, n: number, advance = true): void {
  const P = state.components.Pin
  const T = state.transforms
  const sxs = T.sx, sys = T.sy, szs = T.sz
  const h = c.params[P_H]
  c.params[P_STEP_FRACTION] = (k + 1) / n
  const pos = c.pos
  const from = state.kinematics.stepFrom, to = state.kinematics.stepTo
  let poseSlot = -1 // the target whose pose `pose` holds (a pinned row shares one target)
  for (let q = 0; q < c.pins.length; q++) {
    const pin = c.pins[q]
    let lx = P.ox[pin], ly = P.oy[pin], lz = P.oz[pin]
    const left = P.blendLeft[pin]
    if (left > 0) {
      const total = P.blendTime[pin]
      const nextLeft = !advance ? left : left > h ? left - h : 0
      P.blendLeft[pin] = nextLeft
      const u = total > 0 ? 1 - nextLeft / total : 1
      const s = u * u * (3 - 2 * u) // smoothstep: no velocity kick at either end
      const b = 3 * pin
      lx = P.blendFrom[b] + (lx - P.blendFrom[b]) * s
      ly = P.blendFrom[b + 1] + (ly - P.blendFrom[b + 1]) * s
      lz = P.blendFrom[b + 2] + (lz - P.blendFrom[b + 2]) * s
    }
    const i = 3 * P.particle[pin]
    const tgt = P.target[pin]
    if (tgt === 0) {
      pos[i] = lx
      pos[i + 1] = ly
      pos[i + 2] = lz
      continue
    }
    if (sxs && sys && szs) {
      const sx = sxs[tgt], sy = sys[tgt], sz = szs[tgt]
      if (sx > 0 && sx < Infinity) lx *= sx
      if (sy > 0 && sy < Infinity) ly *= sy
      if (sz > 0 && sz < Infinity) lz *= sz
    }
    // the target's pose (k + 1)/n of the way through the step
    const slot = P.slot[pin]
    if (slot !== poseSlot) {
      interpolatePose(from, to, 7 * slot, c.params, P_STEP_FRACTION, pose, 0)
      poseSlot = slot
    }
    const px = pose[0], py = pose[1], pz = pose[2], qx = pose[3], qy = pose[4], qz = pose[5], qw = pose[6]
    // v' = v + w·t + q × t, t = 2·q × v
    const tx = 2 * (qy * lz - qz * ly), ty = 2 * (qz * lx - qx * lz), tz = 2 * (qx * ly - qy * lx)
    pos[i] = px + lx + qw * tx + (qy * tz - qz * ty)
    pos[i + 1] = py + ly + qw * ty + (qz * tx - qx * tz)
    pos[i + 2] = pz + lz + qw * tz + (qx * ty - qy * tx)
  }
  if (advance) state.stats.pinUpdates += c.pins.length
}

/** Scratch of transformCloth: the rotation matrix in [0, 9), the quaternion in [9, 13). */
const ROTATION = new Float64Array(13)

/**
 * Moves a cloth rigidly: x' = to + R·(x − from) for positions and previous positions, v' = R·v,
 * so the motion carries no velocity and the shape is kept exactly.
 */
export function transformCloth(
  c: ClothState,
  fromX: number, fromY: number, fromZ: number,
  rx: number, ry: number, rz: number, rw: number,
  toX: number, toY: number, toZ: number,
): void {
  // rotation matrix of the unit quaternion, once
  const M = ROTATION
  M[9] = rx
  M[10] = ry
  M[11] = rz
  M[12] = rw
  quatToMatrix(M, 9, M, 0)
  const m00 = M[0], m01 = M[1], m02 = M[2], m10 = M[3], m11 = M[4], m12 = M[5], m20 = M[6], m21 = M[7], m22 = M[8]
  const { pos, prev, vel } = c
  for (let i = 0; i < 3 * c.count; i += 3) {
    let x = pos[i] - fromX, y = pos[i + 1] - fromY, z = pos[i + 2] - fromZ
    pos[i] = toX + m00 * x + m01 * y + m02 * z
    pos[i + 1] = toY + m10 * x + m11 * y + m12 * z
    pos[i + 2] = toZ + m20 * x + m21 * y + m22 * z
    x = prev[i] - fromX; y = prev[i + 1] - fromY; z = prev[i + 2] - fromZ
    prev[i] = toX + m00 * x + m01 * y + m02 * z
    prev[i + 1] = toY + m10 * x + m11 * y + m12 * z
    prev[i + 2] = toZ + m20 * x + m21 * y + m22 * z
    x = vel[i]; y = vel[i + 1]; z = vel[i + 2]
    vel[i] = m00 * x + m01 * y + m02 * z
    vel[i + 1] = m10 * x + m11 * y + m12 * z
    vel[i + 2] = m20 * x + m21 * y + m22 * z
  }
  c.version++
}

/**
 * Teleports a cloth: moves it rigidly by `translation`, rotated by `rotation` about `pivot`
 * (default: the cloth's centroid), keeping its shape and velocities (rotated). World-space pins
 * move with it. Pins on targets start the next step at their targets' new pose, without
 * interpolation and without the automatic teleport detection (so moving the character and calling
 * this does not move the cloth twice).
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
  const state = getClothWorld(world)
  const c = getCloth(state, cloth)
  checkPoint('translation', translation)
  let rx = 0, ry = 0, rz = 0, rw = 1
  if (rotation !== undefined) {
    checkQuat('rotation', rotation)
    const l = Math.hypot(rotation[0], rotation[1], rotation[2], rotation[3])
    rx = rotation[0] / l
    ry = rotation[1] / l
    rz = rotation[2] / l
    rw = rotation[3] / l
  }
  let px = 0, py = 0, pz = 0
  if (pivot !== undefined) {
    checkPoint('pivot', pivot)
    px = pivot[0]
    py = pivot[1]
    pz = pivot[2]
  } else if (c.count > 0) {
    for (let i = 0; i < c.count; i++) {
      px += c.pos[3 * i]
      py += c.pos[3 * i + 1]
      pz += c.pos[3 * i + 2]
    }
    px /= c.count
    py /= c.count
    pz /= c.count
  }
  transformCloth(c, px, py, pz, rx, ry, rz, rw, px + translation[0], py + translation[1], pz + translation[2])
  const P = state.components.Pin
  for (const pin of c.pins) {
    if (P.target[pin] !== 0) continue
    rotateVec3(rx, ry, rz, rw, P.ox[pin] - px, P.oy[pin] - py, P.oz[pin] - pz, tmp, 0)
    P.ox[pin] = px + translation[0] + tmp[0]
    P.oy[pin] = py + translation[1] + tmp[1]
    P.oz[pin] = pz + translation[2] + tmp[2]
    const b = 3 * pin
    rotateVec3(rx, ry, rz, rw, P.blendFrom[b] - px, P.blendFrom[b + 1] - py, P.blendFrom[b + 2] - pz, tmp, 0)
    P.blendFrom[b] = px + translation[0] + tmp[0]
    P.blendFrom[b + 1] = py + translation[1] + tmp[1]
    P.blendFrom[b + 2] = pz + translation[2] + tmp[2]
  }
  // the targets' next sample is a jump (whatever its size): the pins start from the new place
  const k = state.kinematics
  for (const pin of c.pins) if (P.slot[pin] >= 0) k.forceJump[P.slot[pin]] = 1
  c.skipTeleport = true
  state.stats.teleports++
  wakeClothState(state, c)
}
