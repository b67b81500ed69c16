// Inertia against the rotating-frame equation of motion (physics nobody here wrote): a tiny free
// cloth drifting across a frame turning at 3 rad/s, integrated by RK4 in the frame with the shares
// of Coriolis and centrifugal force the cloth feels. Before the fix (found by a hunt) the relative
// velocity was turned by one substep's rotation where the discrete field needs two: a cloth felt
// (1 + share)/2 of the Coriolis force, and at share 0 it was 58 cm off its straight line after 1 s.
import { addEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import { createCloth, getClothState, setClothInertia, setTransform, stepCloth } from '../../src/index'
import { makeWorld } from '../helpers'
import { DT, yawQuat as yaw } from './scenes'

const T0 = 0.5 // the hero stands first (its motion history is known when the turn starts)
const W = 3 // rad/s about +y

/** Centroid of a tiny free 2×2 cloth (no gravity, no damping) given velocity w0 at rest in the frame, in the hero's frame. */
function drift(share: number, w0: [number, number, number], seconds: number) {
  const world = makeWorld({ sleep: false, gravity: [0, 0, 0] })
  const hero = addEntity(world)
  setTransform(world, hero, [0, 0, 0])
  const cloth = createCloth(world, { width: 0.01, height: 0.01, resolution: [2, 2], position: [1, 0, 0], damping: 0 })
  setClothInertia(world, cloth, { frame: hero, linear: share, angular: share, centrifugal: share })
  const c = getClothState(world, cloth)
  for (let i = 0; i < 4; i++) for (let a = 0; a < 3; a++) c.vel[3 * i + a] = w0[a]
  const out: { t: number; p: number[] }[] = []
  for (let f = 1; f <= Math.round(seconds / DT); f++) {
    const t = f * DT, yawNow = W * Math.max(0, t - T0)
    setTransform(world, hero, [0, 0, 0], yaw(yawNow))
    stepCloth(world, DT)
    let x = 0, y = 0, z = 0
    for (let i = 0; i < 4; i++) {
      x += c.pos[3 * i] / 4
      y += c.pos[3 * i + 1] / 4
      z += c.pos[3 * i + 2] / 4
    }
    const cs = Math.cos(yawNow), sn = Math.sin(yawNow) // world → frame: rotate by −yaw about y
    out.push({ t, p: [cs * x - sn * z, y, sn * x + cs * z] })
  }
  return out
}

/** In the frame (yaw about +y at rate W): a = −k·(2ω×v + ω×(ω×r)), RK4. Returns the position at each frame. */
function reference(k: number, w0: [number, number, number], seconds: number) {
  const om = [0, W, 0]
  const cross = (a: number[], b: number[]) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
  const acc = (r: number[], v: number[], t: number) => {
    if (t < T0 - 1e-12) return [0, 0, 0]
    const c1 = cross(om, v), c2 = cross(om, cross(om, r))
    return [0, 1, 2].map((i) => -(k * 2 * c1[i] + k * c2[i]))
  }
  let r = [1, -0.005, 0], v = [...w0]
  const out: number[][] = []
  const n = 200
  for (let f = 1; f <= Math.round(seconds / DT); f++) {
    if (Math.abs((f - 1) * DT - T0) < 1e-9) {
      // the turn starts: the Euler force's impulse, share k (the angular share)
      const c = cross(om, r)
      v = v.map((x, i) => x - k * c[i])
    }
    for (let s = 0; s < n; s++) {
      const h = DT / n, t = (f - 1) * DT + s * h
      const a1 = acc(r, v, t)
      const r2 = r.map((x, i) => x + 0.5 * h * v[i]), v2 = v.map((x, i) => x + 0.5 * h * a1[i])
      const a2 = acc(r2, v2, t + h / 2)
      const r3 = r.map((x, i) => x + 0.5 * h * v2[i]), v3 = v.map((x, i) => x + 0.5 * h * a2[i])
      const a3 = acc(r3, v3, t + h / 2)
      const r4 = r.map((x, i) => x + h * v3[i]), v4 = v.map((x, i) => x + h * a3[i])
      const a4 = acc(r4, v4, t + h)
      r = r.map((x, i) => x + (h / 6) * (v[i] + 2 * v2[i] + 2 * v3[i] + v4[i]))
      v = v.map((x, i) => x + (h / 6) * (a1[i] + 2 * a2[i] + 2 * a3[i] + a4[i]))
    }
    out.push([...r])
  }
  return out
}

describe('inertia in a turning frame: the rotating-frame equation', () => {
  for (const share of [0, 0.5, 1]) {
    it(`shares ${share}: a particle drifting at 0.5 m/s radially in a frame turning at 3 rad/s follows the rotating-frame equation with ${share} of Coriolis and centrifugal`, () => {
      const got = drift(share, [0.5, 0, 0], 1.5)
      const ref = reference(share, [0.5, 0, 0], 1.5)
      let worst = 0
      for (let f = 0; f < got.length; f++) {
        const e = Math.hypot(got[f].p[0] - ref[f][0], got[f].p[1] - ref[f][1], got[f].p[2] - ref[f][2])
        worst = Math.max(worst, e)
      }
      expect(worst).toBeLessThan(share === 0 ? 0.01 : 0.03) // 1 cm (3 cm at share 0.5: the onset impulse is discretized) after a 1 s turn
    })
  }
})
