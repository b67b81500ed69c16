import { ClothError, MAX_COORDINATE, MAX_SCALE } from '../core/errors'
import { multiplyQuatAt, normalizeQuatAt, relativeRotationAt, rotateVecAt } from '../core/math'
import { K_DROPPED, K_LAST_SPAN, K_SCALED, K_SINCE_SAMPLE, K_STEP_FRACTION, type ClothWorldState, type Kinematics } from './state'
import { newArray, newArrayLike, type TypedArray } from '../core/shared'

export { K_DROPPED, K_LAST_SPAN, K_SINCE_SAMPLE, K_STEP_FRACTION }

/**
 * Kinematic tracking of entities whose Transform drives the simulation (pin targets, collider
 * bodies, wind zones): each tracked entity gets a slot; its pose is sampled once per frame and
 * interpolated in time across the fixed steps of that frame and across the substeps of each step
 * (see `Kinematics`).
 */

export function createKinematics(): Kinematics {
  return {
    slotOf: new Int32Array(64).fill(-1),
    generation: new Uint32Array(64),
    losing: -1,
    foreign: false,
    eid: new Int32Array(0),
    refs: new Int32Array(0),
    count: 0,
    free: [],
    live: [],
    liveAt: [],
    sampleFrom: new Float64Array(0),
    sampleTo: new Float64Array(0),
    stepFrom: newArray(Float64Array, 0),
    stepTo: newArray(Float64Array, 0),
    scaleSampleFrom: newArray(Float64Array, 0),
    scaleSampleTo: newArray(Float64Array, 0),
    scaleStepFrom: newArray(Float64Array, 0),
    scaleStepTo: newArray(Float64Array, 0),
    jumped: new Uint8Array(0),
    moved: new Uint8Array(0),
    forceJump: new Uint8Array(0),
    carry: new Int32Array(0),
    jump: new Float64Array(0),
    time: Float64Array.from([0, 1, 0, 1]),
    newFrame: true,
    framed: false,
  }
}

const pose = new Float64Array(7)
const scale = new Float64Array(3)
/** Scratch of `sampleFrame`: a jumping entity's last step velocity, turned by its jump, then the simulated span in steps. */
const turned = new Float64Array(4)

/**
 * Starts tracking `eid` (or adds a reference) and returns its slot. A new slot starts at rest at
 * the entity's current pose, read first: a transform that throws (NaN, an id beyond a host store)
 * leaves nothing tracked (a refused pin left its target tracked, and every later step threw).
 */
export function trackEntity(state: ClothWorldState, eid: number): number {
  const k = state.kinematics
  if (!(eid < k.slotOf.length && k.slotOf[eid] >= 0)) {
    readPoseInto(state, eid, pose)
    readScaleInto(state, eid, scale, 0)
  }
  if (eid >= k.slotOf.length) {
    let n = k.slotOf.length
    while (n <= eid) n *= 2
    const grown = new Int32Array(n).fill(-1)
    grown.set(k.slotOf)
    k.slotOf = grown
  }
  // the generations grow with the slots, when an entity is first tracked, rather than when it is
  // removed: code that reads them (snapshots) is optimized against the array it will keep using
  growGenerations(k, eid)
  let slot = k.slotOf[eid]
  if (slot >= 0) {
    k.refs[slot]++
    return slot
  }
  slot = k.free.length > 0 ? k.free.pop()! : k.count++
  if (slot >= k.eid.length) growSlots(k, Math.max(8, 2 * k.eid.length))
  k.slotOf[eid] = slot
  k.eid[slot] = eid
  k.refs[slot] = 1
  k.liveAt[slot] = k.live.length
  k.live.push(slot)
  k.jumped[slot] = 0
  k.moved[slot] = 0
  k.forceJump[slot] = 0
  const o = 7 * slot
  for (let j = 0; j < 7; j++) {
    k.sampleFrom[o + j] = pose[j]
    k.sampleTo[o + j] = pose[j]
    k.stepFrom[o + j] = pose[j]
    k.stepTo[o + j] = pose[j]
  }
  for (let j = 0; j < 3; j++) {
    k.scaleSampleFrom[3 * slot + j] = scale[j]
    k.scaleSampleTo[3 * slot + j] = scale[j]
    k.scaleStepFrom[3 * slot + j] = scale[j]
    k.scaleStepTo[3 * slot + j] = scale[j]
  }
  return slot
}

/** Called when `eid` loses its transform (see `Kinematics.generation`). */
export function transformLost(state: ClothWorldState, eid: number): void {
  const k = state.kinematics
  growGenerations(k, eid)
  k.generation[eid]++
}

function growGenerations(k: Kinematics, eid: number): void {
  if (eid < k.generation.length) return
  let n = k.generation.length
  while (n <= eid) n *= 2
  const grown = new Uint32Array(n)
  grown.set(k.generation)
  k.generation = grown
}

/** `Kinematics.generation` of an entity id (0 for an id never seen to lose its transform). */
export function transformGeneration(k: Kinematics, eid: number): number {
  return eid < k.generation.length ? k.generation[eid] : 0
}

/**
 * Whether the entity `eid` lost its transform since a snapshot that saved `saved` as its generation
 * (its id may name another entity now). Never while restoring another world's snapshot
 * (`Kinematics.foreign`): a twin world built by the same calls restores it, whatever ids lived
 * before in either world.
 */
export function generationChanged(k: Kinematics, saved: number, eid: number): boolean {
  return !k.foreign && saved !== transformGeneration(k, eid)
}

/**
 * Drops a reference to `eid`'s slot; the slot is freed when nothing uses it. Free slots at the end
 * are given up, so the per-step loops over the slots shrink back after a level unloads (20,000
 * colliders loaded and removed had left every later step 1.18× as long, walking dead slots).
 */
export function untrackEntity(state: ClothWorldState, eid: number): void {
  const k = state.kinematics
  const slot = eid < k.slotOf.length ? k.slotOf[eid] : -1
  if (slot < 0) return
  if (--k.refs[slot] > 0) return
  k.slotOf[eid] = -1
  k.eid[slot] = -1
  const at = k.liveAt[slot], last = k.live.pop()!
  if (last !== slot) {
    k.live[at] = last
    k.liveAt[last] = at
  }
  if (slot !== k.count - 1) {
    k.free.push(slot)
    return
  }
  let n = slot
  while (n > 0 && k.eid[n - 1] < 0) n--
  k.count = n
  // (configuration time: the free list keeps only slots below the new end)
  if (n < slot) k.free = k.free.filter((f) => f < n)
}

function growSlots(k: Kinematics, n: number): void {
  const grow = <T extends TypedArray>(a: T, stride: number, fill = 0): T => {
    const b = newArrayLike(a, n * stride) // shared memory stays shared
    if (fill !== 0) b.fill(fill)
    b.set(a)
    return b
  }
  k.eid = grow(k.eid, 1, -1)
  k.refs = grow(k.refs, 1)
  k.sampleFrom = grow(k.sampleFrom, 7)
  k.sampleTo = grow(k.sampleTo, 7)
  k.stepFrom = grow(k.stepFrom, 7)
  k.stepTo = grow(k.stepTo, 7)
  k.scaleSampleFrom = grow(k.scaleSampleFrom, 3)
  k.scaleSampleTo = grow(k.scaleSampleTo, 3)
  k.scaleStepFrom = grow(k.scaleStepFrom, 3)
  k.scaleStepTo = grow(k.scaleStepTo, 3)
  k.jumped = grow(k.jumped, 1)
  k.moved = grow(k.moved, 1)
  k.forceJump = grow(k.forceJump, 1)
  k.carry = grow(k.carry, 1)
  k.jump = grow(k.jump, 10)
}

/**
 * Reads an entity's pose from the transform source, normalising the rotation. A non-finite value
 * would poison every cloth it touches, so it is rejected here, where transforms enter the solver:
 * any component NaN or ±∞, or the position beyond ±MAX_COORDINATE. A rotation is any other
 * quaternion, normalised without overflow however large its components (all zero: identity).
 */
export function readPoseInto(state: ClothWorldState, eid: number, out: Float64Array): void {
  const t = state.transforms
  const px = t.px[eid], py = t.py[eid], pz = t.pz[eid]
  const qx = t.qx[eid], qy = t.qy[eid], qz = t.qz[eid], qw = t.qw[eid]
  // x − x is 0 for a finite x and NaN otherwise (a plain sum could overflow to ∞ for huge finite ones)
  const finite = px - px + (py - py) + (pz - pz) + (qx - qx) + (qy - qy) + (qz - qz) + (qw - qw) === 0
  if (!finite || !(Math.abs(px) <= MAX_COORDINATE && Math.abs(py) <= MAX_COORDINATE && Math.abs(pz) <= MAX_COORDINATE)) {
    throw new ClothError(
      `transform of entity ${eid}`,
      [px, py, pz, qx, qy, qz, qw],
      `must be finite, the position within ±${MAX_COORDINATE} m`,
    )
  }
  out[0] = px
  out[1] = py
  out[2] = pz
  out[3] = qx
  out[4] = qy
  out[5] = qz
  out[6] = qw
  normalizeQuatAt(out, 3)
}

/**
 * Reads an entity's scale into out[o..o+2]. Per axis: 1 where the source has no scale; a negative
 * scale (a mirrored character) counts as its size |s|; a scale of 0 (a hidden object) keeps the
 * axis's last value with `keep` (the entity's last sample: a cape on a character of scale 1.3
 * hidden at 0 kept its size, where taking 0 as 1 popped it at 31 m/s) and counts as 1 without.
 * NaN or ±∞ (a bug in the game's code) is refused with a ClothError naming the entity, as such a
 * position is; so is a scale above MAX_SCALE (it would carry offsets out of the range where
 * squared lengths stay finite).
 */
export function readScaleInto(state: ClothWorldState, eid: number, out: Float64Array, o: number, keep = false): void {
  const t = state.transforms
  if (!t.sx) {
    out[o] = out[o + 1] = out[o + 2] = 1
    return
  }
  const sx = t.sx[eid], sy = t.sy![eid], sz = t.sz![eid]
  const ax = Math.abs(sx), ay = Math.abs(sy), az = Math.abs(sz)
  if (!(ax <= MAX_SCALE && ay <= MAX_SCALE && az <= MAX_SCALE)) {
    throw new ClothError(
      `transform of entity ${eid}`,
      [sx, sy, sz],
      `must have a finite scale of at most ${MAX_SCALE} in size (a negative one counts as its size, 0 as the last one)`,
    )
  }
  if (ax > 0) out[o] = ax
  else if (!keep) out[o] = 1
  if (ay > 0) out[o + 1] = ay
  else if (!keep) out[o + 1] = 1
  if (az > 0) out[o + 2] = az
  else if (!keep) out[o + 2] = 1
}

/**
 * New frame sample for every tracked entity: the previous sample moves back, the current
 * Transform is read. A sample farther than the teleport distance from where the entity's last
 * step velocity would have taken it (or any sample after `forceJump`) is a jump: its rigid
 * transform is recorded (for the cloths to follow) and the entity's earlier poses are moved by it,
 * so the interpolation continues from the new place instead of sweeping across the gap.
 *
 * The span since the previous sample is `time[K_SINCE_SAMPLE]` plus the dropped `time[K_DROPPED]`
 * inside `stepCloth`, and one fixed step when an engine runs `clothFixedStep` itself. When frame
 * time was dropped (a hitch longer than `maxStepsPerFrame` steps), that share of every entity's
 * motion since its last sample is carried rather than simulated, for every entity but those a cloth
 * follows only in part (`carry`, CARRY_PART; see `markCarriedSlots`): a jump (jumped = 2,
 * `K_CARRIED`) to the pose that share of the way along (position lerp, rotation slerp), which the
 * cloths following it as a whole are carried by too, so the steps simulate only the motion of the
 * time they cover (a 0.5 s hitch squeezed 2 m of a running character's motion into 4 steps: 114 %
 * stretch). Colliders jump with their bodies (a leg on its own entity stays where it was relative
 * to the carried cape; swept, it ran through it: 347 %); an entity a cloth follows in part sweeps.
 */
export function sampleFrame(state: ClothWorldState): void {
  const k = state.kinematics
  const dropped = k.framed ? k.time[K_DROPPED] : 0
  const simulated = k.framed ? k.time[K_SINCE_SAMPLE] : state.fixedTimeStep
  // the last step's velocity over the frame's whole span (the teleport test), and over the part
  // the steps simulate (what a teleport leaves to them)
  const ratio = (simulated + dropped) / state.fixedTimeStep, simRatio = simulated / state.fixedTimeStep
  jumpTest[0] = ratio
  jumpTest[1] = state.teleportDistance * state.teleportDistance
  const reach = state.maxSpeed * state.fixedTimeStep * ratio
  jumpTest[2] = reach * reach // (not `** 2`: that call boxed its result)
  jumpTest[4] = ratio / k.time[K_LAST_SPAN]
  k.time[K_LAST_SPAN] = ratio
  const carry = dropped / (simulated + dropped) // (0 when nothing was dropped)
  // every transform is checked before any is taken: a rejected one leaves the sample untouched
  const live = k.live
  for (let q = 0; q < live.length; q++) {
    const eid = k.eid[live[q]]
    readPoseInto(state, eid, pose)
    readScaleInto(state, eid, scale, 0)
  }
  k.time[K_DROPPED] = 0
  for (let q = 0; q < live.length; q++) {
    const slot = live[q], eid = k.eid[slot]
    jumpTest[3] = k.jumped[slot] // (its last frame's, for `landsBeyond`)
    k.jumped[slot] = 0
    readPoseInto(state, eid, pose)
    const so = 3 * slot
    k.scaleSampleFrom[so] = k.scaleSampleTo[so]
    k.scaleSampleFrom[so + 1] = k.scaleSampleTo[so + 1]
    k.scaleSampleFrom[so + 2] = k.scaleSampleTo[so + 2]
    readScaleInto(state, eid, k.scaleSampleTo, so, true)
    const o = 7 * slot
    if (k.forceJump[slot] === 1 || landsBeyond(k, o, pose, jumpTest)) {
      k.forceJump[slot] = 0
      k.jumped[slot] = 1
      turned[3] = simRatio // (a double passed to a call is boxed)
      recordJump(k, slot)
      const j = 10 * slot
      applyJump(k.jump, j, k.sampleTo, o)
      applyJump(k.jump, j, k.stepTo, o)
      applyJump(k.jump, j, k.stepFrom, o)
    } else if (carry > 0 && k.carry[slot] < CARRY_PART) {
      // the dropped time's share of the motion, carried: a jump to `carry` of the way to the pose
      const j = 10 * slot
      k.jump[j] = k.sampleTo[o]
      k.jump[j + 1] = k.sampleTo[o + 1]
      k.jump[j + 2] = k.sampleTo[o + 2]
      for (let c = 0; c < 7; c++) carried[c] = k.sampleTo[o + c]
      carried[14] = carry
      interpolatePose(carried, pose, 0, carried, 14, carried, 7) // (pose lies at offset 0 too)
      relativeRotationAt(carried, 10, k.sampleTo, o + 3, k.jump, j + 3)
      k.jump[j + 7] = carried[7] - k.sampleTo[o]
      k.jump[j + 8] = carried[8] - k.sampleTo[o + 1]
      k.jump[j + 9] = carried[9] - k.sampleTo[o + 2]
      let moved = false
      for (let c = 0; c < 7 && !moved; c++) moved = pose[c] !== k.sampleTo[o + c]
      if (moved) {
        k.jumped[slot] = K_CARRIED
        applyJump(k.jump, j, k.sampleTo, o)
        applyJump(k.jump, j, k.stepTo, o)
        applyJump(k.jump, j, k.stepFrom, o)
      }
    }
    for (let c = 0; c < 7; c++) {
      k.sampleFrom[o + c] = k.sampleTo[o + c]
      k.sampleTo[o + c] = pose[c]
    }
  }
}

/**
 * The jump of tracked slot `slot` to the pose just read (`pose`), into k.jump: rotation
 * R = q_new · q_old⁻¹ about the old position, then the translation: the motion beyond the last
 * step's velocity, turned by R, over the simulated span (turned[3] steps; the dropped time's share
 * is jumped too). The history is turned by R, so the entity goes on at R·v: measured against v
 * unturned, a cart through a portal turning it 90° at 50 m/s went on along its old heading for a
 * frame, and dragged its banner's pinned row (106 %). (Taken from the pose directly:
 * x − x₀ − v·span with a huge span lost the jump to rounding.)
 */
function recordJump(k: Kinematics, slot: number): void {
  const o = 7 * slot, j = 10 * slot, simRatio = turned[3]
  k.jump[j] = k.sampleTo[o]
  k.jump[j + 1] = k.sampleTo[o + 1]
  k.jump[j + 2] = k.sampleTo[o + 2]
  relativeRotationAt(pose, 3, k.sampleTo, o + 3, k.jump, j + 3)
  for (let a = 0; a < 3; a++) turned[a] = k.stepTo[o + a] - k.stepFrom[o + a]
  rotateVecAt(k.jump, j + 3, turned, 0, turned, 0)
  k.jump[j + 7] = pose[0] - k.sampleTo[o] - turned[0] * simRatio
  k.jump[j + 8] = pose[1] - k.sampleTo[o + 1] - turned[1] * simRatio
  k.jump[j + 9] = pose[2] - k.sampleTo[o + 2] - turned[2] * simRatio
}

/**
 * Whether the position p[0..2] of the entity tracked at 7 × slot = o is a jump: farther than
 * √t[1] both from where its last step's velocity would have carried it from its last sample over
 * t[0] steps, and from that sample itself. (Without the second, an entity stopping dead from a
 * speed above the limit per frame was taken to jump back at every frame after, its velocity kept
 * for good: a cape behind a character stopped from 130 m/s streamed out at 200 m/s, 397 %
 * stretch.) Used by `sampleFrame` (the world's distance) and per cloth (its own distance).
 */
export function landsBeyond(k: Kinematics, o: number, p: Float64Array, t: Float64Array): boolean {
  const ratio = t[0], limit2 = t[1]
  const jx = p[0] - k.sampleTo[o] - (k.stepTo[o] - k.stepFrom[o]) * ratio
  const jy = p[1] - k.sampleTo[o + 1] - (k.stepTo[o + 1] - k.stepFrom[o + 1]) * ratio
  const jz = p[2] - k.sampleTo[o + 2] - (k.stepTo[o + 2] - k.stepFrom[o + 2]) * ratio
  if (!(jx * jx + jy * jy + jz * jz > limit2)) return false
  const dx = p[0] - k.sampleTo[o], dy = p[1] - k.sampleTo[o + 1], dz = p[2] - k.sampleTo[o + 2]
  if (!(dx * dx + dy * dy + dz * dz > limit2)) return false
  if (t[3] !== 1) return true
  // the last frame was a jump: its leap again (sampleTo − sampleFrom is the velocity it kept, plus
  // the jump's translation), no faster than the world's speed limit, is motion at that speed. A
  // start at full speed is a jump once (a standing cape was carried rigidly at every frame of a
  // 150 m/s dash, and a ball thrown at 150 m/s passed through a sheet unswept)
  const j = 10 * ((o / 7) | 0)
  // (scaled to this frame's span: frames alternating 1/60 and 1/30 s made every leap differ from
  // the last by more than the distance, and a dash a jump at every frame)
  const span = t[4]
  const lx = (k.sampleTo[o] - k.sampleFrom[o] + k.jump[j + 7]) * span
  const ly = (k.sampleTo[o + 1] - k.sampleFrom[o + 1] + k.jump[j + 8]) * span
  const lz = (k.sampleTo[o + 2] - k.sampleFrom[o + 2] + k.jump[j + 9]) * span
  const ex = dx - lx, ey = dy - ly, ez = dz - lz
  return ex * ex + ey * ey + ez * ez > limit2 || lx * lx + ly * ly + lz * lz > t[2]
}

/**
 * `landsBeyond`'s span (steps), squared distance, squared speed limit over the span (the world's
 * `maxSpeed`), whether the entity's last frame sample was a jump (1), and this span over the last
 * sample's, in an array: doubles passed to a call are boxed.
 */
export const jumpTest = new Float64Array(5)

/** A jump that carries the dropped time's share of the motion (`Kinematics.jumped`); 1 is a teleport. */
export const K_CARRIED = 2

/** `Kinematics.carry`: some cloth follows the slot as a whole, and no cloth follows it only in part. */
export const CARRY_WHOLE = 1
/** `Kinematics.carry`: a cloth follows the slot and something else (other pins, the world, bones): not carried. */
export const CARRY_PART = 2

/** Scratch of the carried share: the last sample's pose (0..6), the pose that share along (7..13), the share (14). */
const carried = new Float64Array(15)

/**
 * Moves a pose (at `po` in `poses`) by the jump transform at `j` (a rigid-motion record, see
 * `moveClothBy` in rigid.ts): p' = pivot + t + R(p − pivot), q' = R·q.
 */
export function applyJump(jump: Float64Array, j: number, poses: Float64Array, po: number): void {
  const cx = jump[j], cy = jump[j + 1], cz = jump[j + 2]
  const rx = jump[j + 3], ry = jump[j + 4], rz = jump[j + 5], rw = jump[j + 6]
  const vx = poses[po] - cx, vy = poses[po + 1] - cy, vz = poses[po + 2] - cz
  const tx = 2 * (ry * vz - rz * vy), ty = 2 * (rz * vx - rx * vz), tz = 2 * (rx * vy - ry * vx)
  poses[po] = cx + jump[j + 7] + vx + rw * tx + (ry * tz - rz * ty)
  poses[po + 1] = cy + jump[j + 8] + vy + rw * ty + (rz * tx - rx * tz)
  poses[po + 2] = cz + jump[j + 9] + vz + rw * tz + (rx * ty - ry * tx)
  multiplyQuatAt(jump, j + 3, poses, po + 3, poses, po + 3)
}

/**
 * Start of a fixed step: every tracked entity's step pose moves on to its pose at the step's end
 * (`time[K_STEP_FRACTION]` of the way from the previous frame sample to the current one; the
 * current sample itself when an engine runs steps directly), and records whether it moved.
 */
export function beginKinematicStep(k: Kinematics): void {
  if (!k.framed) k.time[K_STEP_FRACTION] = 1
  const f = k.time[K_STEP_FRACTION]
  const live = k.live
  for (let q = 0; q < live.length; q++) {
    const slot = live[q]
    const o = 7 * slot
    for (let c = 0; c < 7; c++) k.stepFrom[o + c] = k.stepTo[o + c]
    interpolatePose(k.sampleFrom, k.sampleTo, o, k.time, K_STEP_FRACTION, k.stepTo, o)
    let moved = k.jumped[slot] !== 0 ? 1 : 0
    for (let c = 0; c < 7 && moved === 0; c++) if (k.stepFrom[o + c] !== k.stepTo[o + c]) moved = 1
    const so = 3 * slot, snap = k.jumped[slot] === K_SCALED // (taken at once, unswept)
    for (let c = 0; c < 3; c++) {
      const a = k.scaleSampleFrom[so + c], b = k.scaleSampleTo[so + c]
      k.scaleStepFrom[so + c] = snap ? b : k.scaleStepTo[so + c]
      k.scaleStepTo[so + c] = snap || f >= 1 ? b : a + (b - a) * f
      if (k.scaleStepFrom[so + c] !== k.scaleStepTo[so + c]) moved = 1
    }
    k.moved[slot] = moved
  }
}

/**
 * Scale at fraction t[ti] of the current fixed step of the slot at `so` (3 × slot) into
 * out[oo..oo+2]: linear between its scale at the step's start and end; f ≥ 1 gives the end exactly.
 */
export function interpolateScale(k: Kinematics, so: number, t: Float64Array, ti: number, out: Float64Array, oo: number): void {
  const f = t[ti]
  const a = k.scaleStepFrom, b = k.scaleStepTo
  if (f >= 1) {
    out[oo] = b[so]
    out[oo + 1] = b[so + 1]
    out[oo + 2] = b[so + 2]
    return
  }
  out[oo] = a[so] + (b[so] - a[so]) * f
  out[oo + 1] = a[so + 1] + (b[so + 1] - a[so + 1]) * f
  out[oo + 2] = a[so + 2] + (b[so + 2] - a[so + 2]) * f
}

/**
 * Pose at fraction f = t[ti] between poses `a` and `b` (both at offset `o`) into out[oo..oo+6]:
 * position lerp, rotation slerp along the shortest arc (nlerp when nearly equal); f ≥ 1 gives b
 * exactly, and so does a rotation equal in a and b. (The fraction is read from an array: a double argument would be boxed per call.)
 */
export function interpolatePose(
  a: Float64Array,
  b: Float64Array,
  o: number,
  t: Float64Array,
  ti: number,
  out: Float64Array,
  oo: number,
): void {
  const f = t[ti]
  if (f >= 1) {
    for (let c = 0; c < 7; c++) out[oo + c] = b[o + c]
    return
  }
  out[oo] = a[o] + (b[o] - a[o]) * f
  out[oo + 1] = a[o + 1] + (b[o + 1] - a[o + 1]) * f
  out[oo + 2] = a[o + 2] + (b[o + 2] - a[o + 2]) * f
  const ax = a[o + 3], ay = a[o + 4], az = a[o + 5], aw = a[o + 6]
  let bx = b[o + 3], by = b[o + 4], bz = b[o + 5], bw = b[o + 6]
  if (ax === bx && ay === by && az === bz && aw === bw) {
    // not turning: the rotation itself (normalised, a still entity turned 0.3 rad came out an ulp
    // off, moved at every step that ended between frames and woke the cloth on it)
    for (let c = 3; c < 7; c++) out[oo + c] = b[o + c]
    return
  }
  let cos = ax * bx + ay * by + az * bz + aw * bw
  if (cos < 0) {
    cos = -cos
    bx = -bx
    by = -by
    bz = -bz
    bw = -bw
  }
  let s0 = 1 - f, s1 = f
  if (cos < 0.9995) {
    const omega = Math.acos(cos)
    const sin = Math.sin(omega)
    s0 = Math.sin((1 - f) * omega) / sin
    s1 = Math.sin(f * omega) / sin
  }
  const qx = s0 * ax + s1 * bx, qy = s0 * ay + s1 * by, qz = s0 * az + s1 * bz, qw = s0 * aw + s1 * bw
  const inv = 1 / Math.sqrt(qx * qx + qy * qy + qz * qz + qw * qw)
  out[oo + 3] = qx * inv
  out[oo + 4] = qy * inv
  out[oo + 5] = qz * inv
  out[oo + 6] = qw * inv
}

/** Values saved per tracked entity by `saveSlot`: sampleFrom, sampleTo, stepFrom, stepTo (7 each), jump (10), jumped, forceJump. */
export const SLOT_DATA = 7 * 4 + 10 + 2

/** Copies a slot's motion history into out[e..e + SLOT_DATA) (snapshots). */
export function saveSlot(k: Kinematics, slot: number, out: Float64Array, e: number): void {
  const o = 7 * slot
  for (let j = 0; j < 7; j++) {
    out[e + j] = k.sampleFrom[o + j]
    out[e + 7 + j] = k.sampleTo[o + j]
    out[e + 14 + j] = k.stepFrom[o + j]
    out[e + 21 + j] = k.stepTo[o + j]
  }
  for (let j = 0; j < 10; j++) out[e + 28 + j] = k.jump[10 * slot + j]
  out[e + 38] = k.jumped[slot]
  out[e + 39] = k.forceJump[slot]
}

/** Values saved per tracked entity by `saveSlotScale`: its scale at the two frame samples and the step's ends (3 each). */
export const SLOT_SCALE_DATA = 12

/**
 * Whether a[from..from + count) are scales a Transform can hold (`setTransform`: in (0, MAX_SCALE]),
 * for restores: a snapshot's scale history of 0, −1 (mirrored) or 1e300 restored without an error
 * and swept its pins through mirrored positions (16–31 % stretch) or overflowed to a guard reset.
 */
export function scalesInRange(a: Float64Array, from = 0, count = a.length - from): boolean {
  for (let q = from; q < from + count; q++) if (!(a[q] > 0 && a[q] <= MAX_SCALE)) return false
  return true
}

/** Copies a slot's scale history into out[e..e + SLOT_SCALE_DATA) (snapshots). */
export function saveSlotScale(k: Kinematics, slot: number, out: Float64Array, e: number): void {
  const o = 3 * slot
  for (let j = 0; j < 3; j++) {
    out[e + j] = k.scaleSampleFrom[o + j]
    out[e + 3 + j] = k.scaleSampleTo[o + j]
    out[e + 6 + j] = k.scaleStepFrom[o + j]
    out[e + 9 + j] = k.scaleStepTo[o + j]
  }
}

/**
 * Puts a slot's scale history back from from[e..e + SLOT_SCALE_DATA), or, with `from` null (a
 * snapshot saved without scales), sets all four to the entity's scale now.
 */
export function restoreSlotScale(state: ClothWorldState, slot: number, from: Float64Array | null, e: number): void {
  const k = state.kinematics
  const o = 3 * slot
  if (from === null) {
    readScaleInto(state, k.eid[slot], scale, 0)
    for (let j = 0; j < 3; j++)
      k.scaleSampleFrom[o + j] =
        k.scaleSampleTo[o + j] =
        k.scaleStepFrom[o + j] =
        k.scaleStepTo[o + j] =
          scale[j]
    return
  }
  for (let j = 0; j < 3; j++) {
    k.scaleSampleFrom[o + j] = from[e + j]
    k.scaleSampleTo[o + j] = from[e + 3 + j]
    k.scaleStepFrom[o + j] = from[e + 6 + j]
    k.scaleStepTo[o + j] = from[e + 9 + j]
  }
}

/** Puts a slot's motion history back from from[e..e + SLOT_DATA) (snapshots). */
export function restoreSlot(k: Kinematics, slot: number, from: Float64Array, e: number): void {
  const o = 7 * slot
  for (let j = 0; j < 7; j++) {
    k.sampleFrom[o + j] = from[e + j]
    k.sampleTo[o + j] = from[e + 7 + j]
    k.stepFrom[o + j] = from[e + 14 + j]
    k.stepTo[o + j] = from[e + 21 + j]
  }
  for (let j = 0; j < 10; j++) k.jump[10 * slot + j] = from[e + 28 + j]
  k.jumped[slot] = from[e + 38]
  k.forceJump[slot] = from[e + 39]
}
