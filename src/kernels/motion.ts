import { P_H, P_INV_H, P_MAX_SPEED, P_MAX_V2, P_STEP_FRACTION, P_STEP_START } from './params'

/**
 * Character cloth kernels: prediction in a moving frame, and the motion constraints that hold
 * particles near a reference pose.
 *
 * Frame parameters of `predictInFrame` (a Float64Array of FRAME_PARAMS, filled per substep by
 * `frameSubstep` in features/character):
 */
/** The frame's origin at the start of the substep, m. */
export const F_ORIGIN = 0
/** A (row-major 3×3): the new velocity's part linear in the old one. */
export const F_A = 3
/** Q (row-major 3×3, 1/s): its part linear in the offset from the origin. */
export const F_Q = 12
/** c (m/s): its constant part, gravity included. */
export const F_C = 21
export const FRAME_PARAMS = 24

/**
 * Predict step of a cloth simulated in a moving frame (symplectic Euler like `predictPositions`):
 *
 *   v ← A·v + Q·(x − origin) + c + a·h,   prev ← x,   x ← x + v·h
 *
 * With w = v − u₀(x) the velocity relative to the frame's motion in the previous substep, this is
 * v + ΔV + M·r + N·w + g·h (`frameSubstep` folds it into A, Q, c): ΔV, M and N carry the share of
 * the frame's acceleration and rotation the cloth does not feel, and damp w (not v), so damping
 * acts relative to the frame. With every share 0 this moves each particle exactly as if rigidly
 * attached to the frame (plus its own relative motion, turned with the frame); with every share 1
 * only the damping differs from the world-space predict. Inverse mass 0: only prev is recorded.
 * With `start`, x is recorded there too (where the motion constraints' velocity bound finds it:
 * one store here saves a pass copying the positions).
 */
export function predictInFrame(
  pos: Float64Array,
  prev: Float64Array,
  start: Float64Array | null,
  vel: Float64Array,
  invMass: Float64Array,
  accel: Float64Array | null,
  params: Float64Array,
  f: Float64Array,
  count: number,
): void {
  const h = params[P_H]
  const ox = f[F_ORIGIN], oy = f[F_ORIGIN + 1], oz = f[F_ORIGIN + 2]
  const a00 = f[F_A],
    a01 = f[F_A + 1],
    a02 = f[F_A + 2],
    a10 = f[F_A + 3],
    a11 = f[F_A + 4],
    a12 = f[F_A + 5],
    a20 = f[F_A + 6],
    a21 = f[F_A + 7],
    a22 = f[F_A + 8]
  const q00 = f[F_Q],
    q01 = f[F_Q + 1],
    q02 = f[F_Q + 2],
    q10 = f[F_Q + 3],
    q11 = f[F_Q + 4],
    q12 = f[F_Q + 5],
    q20 = f[F_Q + 6],
    q21 = f[F_Q + 7],
    q22 = f[F_Q + 8]
  const cx = f[F_C], cy = f[F_C + 1], cz = f[F_C + 2]
  for (let i = 0; i < count; i++) {
    const j = 3 * i
    const x = pos[j], y = pos[j + 1], z = pos[j + 2]
    prev[j] = x
    prev[j + 1] = y
    prev[j + 2] = z
    if (start !== null) {
      start[j] = x
      start[j + 1] = y
      start[j + 2] = z
    }
    if (invMass[i] === 0) continue
    const rx = x - ox, ry = y - oy, rz = z - oz
    const vx = vel[j], vy = vel[j + 1], vz = vel[j + 2]
    let nx = a00 * vx + a01 * vy + a02 * vz + q00 * rx + q01 * ry + q02 * rz + cx
    let ny = a10 * vx + a11 * vy + a12 * vz + q10 * rx + q11 * ry + q12 * rz + cy
    let nz = a20 * vx + a21 * vy + a22 * vz + q20 * rx + q21 * ry + q22 * rz + cz
    if (accel !== null) {
      nx += accel[j] * h
      ny += accel[j + 1] * h
      nz += accel[j + 2] * h
    }
    vel[j] = nx
    vel[j + 1] = ny
    vel[j + 2] = nz
    pos[j] = x + nx * h
    pos[j + 1] = y + ny * h
    pos[j + 2] = z + nz * h
  }
}

/** The mean position of the first `count` particles into out[o..o+2], their mean velocity into out[o+3..o+5]. */
export function meanMotion(pos: Float64Array, vel: Float64Array, count: number, out: Float64Array, o: number): void {
  let px = 0, py = 0, pz = 0, vx = 0, vy = 0, vz = 0
  for (let j = 0; j < 3 * count; j += 3) {
    px += pos[j]
    py += pos[j + 1]
    pz += pos[j + 2]
    vx += vel[j]
    vy += vel[j + 1]
    vz += vel[j + 2]
  }
  const n = Math.max(count, 1)
  out[o] = px / n
  out[o + 1] = py / n
  out[o + 2] = pz / n
  out[o + 3] = vx / n
  out[o + 4] = vy / n
  out[o + 5] = vz / n
}

/**
 * Where the motion kernels find each particle's reference (float32, BLEND values per particle):
 * its position at the start and at the end of the step, each as an offset from an anchor (the
 * frame's origin then: float32 keeps ~0.1 µm at a metre from it), and its normal at the end. A
 * rigid reference is written there once a step from its bind coordinates (RIGID values per
 * particle: position and normal in the frame's bind coordinates), a skinned one by blending.
 * Within the step the reference moves linearly from start to end, as the frame's transform does.
 * Limits are a second float32 stream, LIMITS per particle: max distance (m, Infinity = free),
 * backstop distance and radius (radius 0 = none).
 */
export const RIGID = 6
export const BLEND = 9
export const LIMITS = 3
export const L_MAX = 0
export const L_BACK = 1
export const L_RADIUS = 2

/**
 * The frame's part of the reference for the current substep (REF_PARAMS doubles, filled per
 * substep by `referenceSubstep` in features/character): the anchors at the end (t) and at the
 * start (t0) of the substep, with params[P_STEP_FRACTION] and params[P_STEP_START] the fractions
 * of the step.
 */
export const W_T = 0
export const W_T0 = 3
export const REF_PARAMS = 6

/**
 * Places the listed particles (`list` null: particles 0 to listCount − 1) on their reference
 * positions at the end of the substep (particles held with max distance 0; a teleport's reset).
 * With `holds` (each particle's pins, plus 1 when held: `ClothState.pinCount`), a listed held
 * particle that a pin holds too (holds > 1) is left where its pin put it: a pin wins.
 */
export function placeOnReference(
  pos: Float64Array,
  list: Int32Array | null,
  listCount: number,
  ref: Float32Array,
  w: Float64Array,
  params: Float64Array,
  holds: Uint16Array | null,
): void {
  const f = params[P_STEP_FRACTION]
  const tx = w[W_T], ty = w[W_T + 1], tz = w[W_T + 2]
  for (let q = 0; q < listCount; q++) {
    const i = list === null ? q : list[q]
    if (holds !== null && holds[i] > 1) continue
    const j = 3 * i, o = BLEND * i
    pos[j] = tx + ref[o] + (ref[o + 3] - ref[o]) * f
    pos[j + 1] = ty + ref[o + 1] + (ref[o + 4] - ref[o + 1]) * f
    pos[j + 2] = tz + ref[o + 2] + (ref[o + 5] - ref[o + 2]) * f
  }
}

/**
 * The drive of a cloth with motion constraints, before `constrainAndUpdateVelocities` (its first
 * constraint; a cloth without a drive skips this pass). For each free particle (inverse mass > 0)
 * with ω = drive[i] > 0 (a frequency, rad/s) and r its reference position at the end of the
 * substep: a critically damped spring (stiffness m·ω², damping 2m·ω) pulls the offset e = x − r
 * toward 0, its damping acting on the offset's change over the substep (e_prev from `prev` and the
 * reference at the substep's start); integrated implicitly, Δx = −(a²·e + 2a·(e − e_prev))/(1 + a)²,
 * a = ω·h: independent of the mass, stable for any ω; ω = Infinity puts x on r.
 */
export function driveTowardReference(
  pos: Float64Array,
  prev: Float64Array,
  invMass: Float64Array,
  ref: Float32Array,
  w: Float64Array,
  drive: Float64Array,
  params: Float64Array,
  count: number,
): void {
  const f = params[P_STEP_FRACTION], f0 = params[P_STEP_START], h = params[P_H]
  const tx = w[W_T], ty = w[W_T + 1], tz = w[W_T + 2]
  const sx = w[W_T0], sy = w[W_T0 + 1], sz = w[W_T0 + 2]
  for (let i = 0; i < count; i++) {
    const om = drive[i]
    if (!(om > 0) || invMass[i] === 0) continue
    const j = 3 * i, o = BLEND * i
    const rx = tx + ref[o] + (ref[o + 3] - ref[o]) * f
    const ry = ty + ref[o + 1] + (ref[o + 4] - ref[o + 1]) * f
    const rz = tz + ref[o + 2] + (ref[o + 5] - ref[o + 2]) * f
    if (om === Infinity) {
      pos[j] = rx
      pos[j + 1] = ry
      pos[j + 2] = rz
      continue
    }
    const a = om * h
    const inv = 1 / ((1 + a) * (1 + a))
    const ex = pos[j] - rx, ey = pos[j + 1] - ry, ez = pos[j + 2] - rz
    // the offset at the substep's start
    const qx = prev[j] - sx - ref[o] - (ref[o + 3] - ref[o]) * f0
    const qy = prev[j + 1] - sy - ref[o + 1] - (ref[o + 4] - ref[o + 1]) * f0
    const qz = prev[j + 2] - sz - ref[o + 2] - (ref[o + 5] - ref[o + 2]) * f0
    pos[j] -= (a * a * ex + 2 * a * (ex - qx)) * inv
    pos[j + 1] -= (a * a * ey + 2 * a * (ey - qy)) * inv
    pos[j + 2] -= (a * a * ez + 2 * a * (ez - qz)) * inv
  }
}

/**
 * A particle a limit moved weighs this share of its inverse mass in the next substep's distance
 * solve (see `constrainAndUpdateVelocities`): heavy against free neighbours, as its own weight
 * against a neighbour held too (the split of a correction depends only on the weights' ratio).
 */
export const HELD_WEIGHT = 1 / 16

/**
 * The writeback of a cloth with motion constraints (after its drive, `driveTowardReference`):
 * first the limits around its reference pose, then the velocities from the substep's motion, in
 * one pass (the positions are read once for both).
 *
 * Limits, for each free particle (inverse mass > 0), with r its reference position at the end of
 * the substep and n its reference normal (`ref` and `w`, see above):
 * 1. max distance: x is brought back onto the sphere of that radius around r when outside it;
 * 2. backstop: x is pushed out of the sphere of radius ρ centred at r − n·(distance + ρ), then
 *    step 1 once more; the two regions are not convex together, so when that straight way back
 *    cuts into the sphere again, x goes to the nearest point of the circle where the two spheres
 *    meet (r itself satisfies both).
 * Positions are written only where something moved them. A particle a limit moved is made heavy
 * for the next substep's distance solve: its entries in `invMass3` (the distance loops' inverse
 * masses) become HELD_WEIGHT of its inverse mass and it is listed in `held` ([0] = count, then
 * particles), for `releaseLimitHolds` to give back (the solve's refresh of `invMass3` at a step's
 * first substep gives them back too). A particle at its limit is held there by the body, so the
 * edges it shares with free particles pulled away (a hand, a collision) correct mostly the free
 * ones, instead of stretching by what the limit takes back each substep.
 *
 * Velocities, for every particle: v = (x − prev)/h, so a particle stopped at its limit loses its
 * outward speed. When the limits last ran `since` substeps ago (`every`), a correction undoes
 * that many substeps of drift, and a particle a limit moved from x₀ gets v = (x₀ + (x − x₀)/since
 * − prev)/h: the correction enters its velocity spread over them (taken as one substep's motion,
 * seven substeps of drift stretched a running cape's edges by up to 866 %). Where a collider
 * moved `prev` this substep (its push-out is no motion), a particle a limit moved leaves no faster,
 * relative to its reference, than it moved since the substep's start (`start`): the two would
 * otherwise each take back the other's correction while its velocity stayed. A speed above
 * params[P_MAX_SPEED] is scaled down to it, the largest squared speed before that goes to
 * params[P_MAX_V2] (as `updateVelocities` in integrate.ts, whose loop this repeats rather than
 * calls: a second pass over the positions is what this kernel saves).
 * One long function on purpose: the limits written out in full run per particle and substep,
 * where a call per particle would box its doubles.
 */
export function constrainAndUpdateVelocities(
  pos: Float64Array,
  prev: Float64Array,
  start: Float64Array,
  vel: Float64Array,
  invMass: Float64Array,
  invMass3: Float64Array,
  held: Int32Array,
  ref: Float32Array,
  lim: Float32Array,
  w: Float64Array,
  params: Float64Array,
  since: number,
  count: number,
): void {
  const share = 1 / since // (an integer argument: a fraction passed to a call would be boxed)
  const f = params[P_STEP_FRACTION], f0 = params[P_STEP_START], invH = params[P_INV_H]
  let heldCount = 0
  const maxSpeed = params[P_MAX_SPEED]
  const max2 = maxSpeed * maxSpeed
  let top = 0
  const tx = w[W_T], ty = w[W_T + 1], tz = w[W_T + 2]
  const sx = w[W_T0], sy = w[W_T0 + 1], sz = w[W_T0 + 2]
  for (let i = 0; i < count; i++) {
    const j = 3 * i
    let x = pos[j], y = pos[j + 1], z = pos[j + 2]
    if (invMass[i] !== 0) {
      const o = BLEND * i
      const rx = tx + ref[o] + (ref[o + 3] - ref[o]) * f
      const ry = ty + ref[o + 1] + (ref[o + 4] - ref[o + 1]) * f
      const rz = tz + ref[o + 2] + (ref[o + 5] - ref[o + 2]) * f
      let moved = false
      const l = LIMITS * i
      const r = lim[l]
      const r2 = r * r // Infinity when free
      let ex = x - rx, ey = y - ry, ez = z - rz
      let d2 = ex * ex + ey * ey + ez * ez
      if (d2 > r2) {
        const s = r / Math.sqrt(d2)
        ex *= s
        ey *= s
        ez *= s
        x = rx + ex
        y = ry + ey
        z = rz + ez
        moved = true
      }
      const rho = lim[l + L_RADIUS]
      if (rho > 0) {
        const nx = ref[o + 6], ny = ref[o + 7], nz = ref[o + 8]
        const dist = lim[l + L_BACK]
        // the sphere lies wholly `distance` or more behind the reference: a particle less deep is clear
        if (ex * nx + ey * ny + ez * nz < -dist) {
          const back = dist + rho
          const cx = rx - nx * back, cy = ry - ny * back, cz = rz - nz * back
          const bx = x - cx, by = y - cy, bz = z - cz
          const b2 = bx * bx + by * by + bz * bz
          if (b2 < rho * rho) {
            if (b2 > 1e-24) {
              const s = rho / Math.sqrt(b2)
              x = cx + bx * s
              y = cy + by * s
              z = cz + bz * s
            } else {
              x = cx + nx * rho
              y = cy + ny * rho
              z = cz + nz * rho
            }
            ex = x - rx
            ey = y - ry
            ez = z - rz
            d2 = ex * ex + ey * ey + ez * ez
            if (d2 > r2) {
              const s = r / Math.sqrt(d2)
              x = rx + ex * s
              y = ry + ey * s
              z = rz + ez * s
              const qx = x - cx, qy = y - cy, qz = z - cz
              if (qx * qx + qy * qy + qz * qz < rho * rho) {
                // the straight way back cut into the sphere again: the nearest point of the circle
                // where the two spheres meet, a·n behind the reference (a > distance: allowed)
                const a = (r2 - rho * rho + back * back) / (2 * back)
                const mx = rx - nx * a, my = ry - ny * a, mz = rz - nz * a
                let px = x - mx, py = y - my, pz = z - mz
                const along = px * nx + py * ny + pz * nz
                px -= along * nx
                py -= along * ny
                pz -= along * nz
                let p2 = px * px + py * py + pz * pz
                if (!(p2 > 1e-24)) {
                  // on the axis: any way across it (n × x̂, or n × ŷ when n lies along x)
                  const useY = Math.abs(nx) > 0.9
                  px = useY ? -nz : 0
                  py = useY ? 0 : nz
                  pz = useY ? nx : -ny
                  p2 = px * px + py * py + pz * pz
                }
                const k = Math.sqrt(Math.max(0, r2 - a * a) / p2)
                x = mx + px * k
                y = my + py * k
                z = mz + pz * k
              }
            }
            moved = true
          }
        }
      }
      if (moved) {
        const x0 = pos[j], y0 = pos[j + 1], z0 = pos[j + 2]
        pos[j] = x
        pos[j + 1] = y
        pos[j + 2] = z
        const heavy = invMass[i] * HELD_WEIGHT
        invMass3[j] = heavy
        invMass3[j + 1] = heavy
        invMass3[j + 2] = heavy
        held[++heldCount] = i
        if (since !== 1) {
          // the correction undoes the drift of the `since` substeps since the last check: it
          // enters the velocity spread over them, not as one substep's motion
          x = x0 + (x - x0) * share
          y = y0 + (y - y0) * share
          z = z0 + (z - z0) * share
        }
        // it leaves no faster, relative to its reference, than it moved since the substep's start:
        // where a collider and a limit disagree, each takes back the other's correction (the
        // collider as no motion, moving prev along), and a particle wedged between them kept the
        // velocity it came in with (8 m/s on a still cape whose capsule reached 2 cm behind it)
        // (only where a collider moved prev: elsewhere prev is the start)
        if (prev[j] !== start[j] || prev[j + 1] !== start[j + 1] || prev[j + 2] !== start[j + 2]) {
          const qx = rx - sx - ref[o] - (ref[o + 3] - ref[o]) * f0
          const qy = ry - sy - ref[o + 1] - (ref[o + 4] - ref[o + 1]) * f0
          const qz = rz - sz - ref[o + 2] - (ref[o + 5] - ref[o + 2]) * f0
          const ux = x - prev[j] - qx, uy = y - prev[j + 1] - qy, uz = z - prev[j + 2] - qz
          const ax = pos[j] - start[j] - qx, ay = pos[j + 1] - start[j + 1] - qy, az = pos[j + 2] - start[j + 2] - qz
          const u2 = ux * ux + uy * uy + uz * uz, a2 = ax * ax + ay * ay + az * az
          if (u2 > a2) {
            const k = Math.sqrt(a2 / u2)
            x = prev[j] + qx + ux * k
            y = prev[j + 1] + qy + uy * k
            z = prev[j + 2] + qz + uz * k
          }
        }
      }
    }
    let vx = (x - prev[j]) * invH
    let vy = (y - prev[j + 1]) * invH
    let vz = (z - prev[j + 2]) * invH
    const s2 = vx * vx + vy * vy + vz * vz
    if (!(s2 <= top)) top = s2 // NaN sticks: a broken cloth never counts as still
    if (s2 > max2) {
      const k = maxSpeed / Math.sqrt(s2)
      vx *= k
      vy *= k
      vz *= k
    }
    vel[j] = vx
    vel[j + 1] = vy
    vel[j + 2] = vz
  }
  params[P_MAX_V2] = top
  held[0] = heldCount
}

/** Whether any of the first `count` particles has a max distance (finite) or a backstop (radius > 0). */
export function anyLimit(lim: Float32Array, count: number): boolean {
  for (let l = 0; l < LIMITS * count; l += LIMITS) if (lim[l + L_MAX] < Infinity || lim[l + L_RADIUS] > 0) return true
  return false
}

/** Gives the particles `constrainAndUpdateVelocities` held (`held`) their inverse masses back in `invMass3`, and empties the list. */
export function releaseLimitHolds(invMass: Float64Array, invMass3: Float64Array, held: Int32Array): void {
  for (let q = 1; q <= held[0]; q++) {
    const i = held[q]
    const m = invMass[i]
    invMass3[3 * i] = m
    invMass3[3 * i + 1] = m
    invMass3[3 * i + 2] = m
  }
  held[0] = 0
}
