// Skinned reference poses: linear blend skinning of a strip by two bones, checked against the
// same blend computed here with gl-matrix; held and free particles; bones that go away.
import { addComponent, addEntity, removeEntity } from 'bitecs'
import { glMatrix, mat4, quat, vec3 } from 'gl-matrix'
import { describe, expect, it } from 'vitest'
import {
  ClothError,
  createCloth,
  createClothFromMesh,
  getClothComponents,
  getClothReference,
  getClothState,
  setClothMotionConstraints,
  setClothSkinning,
  setTransform,
  stepCloth,
} from '../../src/index'
import { allFinite, makeWorld } from '../helpers'
import { DT, expectClothErrors, positionsNow } from './scenes'

glMatrix.setMatrixArrayType(Array)

const N = 11 // particles along the strip

/** A 1 m strip along +x at height 1 m, two rows; bone 0 at x = 0, bone 1 (the elbow) at x = 0.5. */
function strip() {
  const world = makeWorld({ sleep: false })
  const bones = [addEntity(world), addEntity(world)]
  setTransform(world, bones[0], [0, 1, 0])
  setTransform(world, bones[1], [0.5, 1, 0])
  const cloth = createCloth(world, { width: 1, height: 0.1, resolution: [N, 2], position: [0.5, 1, 0] })
  const rest = positionsNow(world, cloth)
  const n = rest.length / 3
  const joints: number[] = [], weights: number[] = []
  for (let i = 0; i < n; i++) {
    const x = rest[3 * i]
    const u = Math.min(1, Math.max(0, (x - 0.3) / 0.4))
    const w1 = u * u * (3 - 2 * u) // smooth hand-over from bone 0 to bone 1 between x = 0.3 and 0.7
    joints.push(0, 1, 0, 0)
    weights.push(1 - w1, w1, 0, 0)
  }
  return { world, bones, cloth, rest, joints, weights }
}

/** Linear blend skinning with gl-matrix: Σ w_b · M_b(now) · M_b(bind)⁻¹ · rest. */
function lbs(rest: Float64Array, joints: number[], weights: number[], bind: mat4[], now: mat4[]): Float64Array {
  const skin = now.map((m, b) => mat4.multiply(mat4.create(), m, mat4.invert(mat4.create(), bind[b])!))
  const out = new Float64Array(rest.length)
  const p = vec3.create()
  for (let i = 0; i < rest.length / 3; i++) {
    for (let k = 0; k < 4; k++) {
      const w = weights[4 * i + k]
      if (w === 0) continue
      vec3.transformMat4(p, [rest[3 * i], rest[3 * i + 1], rest[3 * i + 2]], skin[joints[4 * i + k]])
      for (let d = 0; d < 3; d++) out[3 * i + d] += w * p[d]
    }
  }
  return out
}

const pose = (p: vec3 | number[], q: quat) => mat4.fromRotationTranslation(mat4.create(), q, p as vec3)

describe('skinned reference', () => {
  it('a strip bound to two bones with max distance 0 follows the linear-blend-skinned pose within 1 µm while one bone turns 90°', () => {
    const { world, bones, cloth, rest, joints, weights } = strip()
    setClothSkinning(world, cloth, { bones, joints, weights })
    setClothMotionConstraints(world, cloth, { maxDistance: 0 })
    const bind = [pose([0, 1, 0], quat.create()), pose([0.5, 1, 0], quat.create())]
    const c = getClothState(world, cloth)
    let worst = 0, moved = 0
    for (let f = 1; f <= 60; f++) {
      const q = quat.setAxisAngle(quat.create(), [0, 0, 1], (Math.PI / 2) * Math.min(1, f / 45)) // elbow turns 90° up
      setTransform(world, bones[1], [0.5, 1, 0], q)
      stepCloth(world, DT)
      const expected = lbs(rest, joints, weights, bind, [bind[0], pose([0.5, 1, 0], q)])
      for (let j = 0; j < expected.length; j++) worst = Math.max(worst, Math.abs(c.pos[j] - expected[j]))
      moved = Math.max(moved, Math.hypot(c.pos[3 * (N - 1)] - rest[3 * (N - 1)], c.pos[3 * (N - 1) + 1] - rest[3 * (N - 1) + 1]))
    }
    console.log(
      `skinning: worst difference from gl-matrix linear blend skinning ${(1000 * worst).toExponential(2)} mm; the tip moved ${
        moved.toFixed(3)
      } m`,
    )
    expect(worst).toBeLessThan(1e-6) // measured 4.7e-5 mm: float32 rounding of the reference
    expect(moved).toBeGreaterThan(0.6) // the tip swung up (0.5 m arm turned 90°: 0.71 m)
    expect(allFinite(world, cloth)).toBe(true)
  })

  it('free particles swing under gravity but stay within their max distance of the skinned pose while the root bone moves and turns', () => {
    const { world, bones, cloth, rest, joints, weights } = strip()
    setClothSkinning(world, cloth, { bones, joints, weights })
    const md = Array.from({ length: rest.length / 3 }, (_, i) => (i % N === 0 ? 0 : 0.05))
    setClothMotionConstraints(world, cloth, { maxDistance: md })
    const bind = [pose([0, 1, 0], quat.create()), pose([0.5, 1, 0], quat.create())]
    const c = getClothState(world, cloth)
    let worst = -Infinity, sag = 0
    for (let f = 1; f <= 120; f++) {
      const t = f * DT
      const q0 = quat.setAxisAngle(quat.create(), [0, 1, 0], 2 * t) // the root turns at 2 rad/s and walks
      const p0 = vec3.fromValues(t, 1, 0)
      const q1 = quat.multiply(quat.create(), q0, quat.setAxisAngle(quat.create(), [0, 0, 1], Math.min(1, t) * 1.2))
      const p1 = vec3.add(vec3.create(), p0, vec3.transformQuat(vec3.create(), [0.5, 0, 0], q0))
      setTransform(world, bones[0], p0, q0)
      setTransform(world, bones[1], p1, q1)
      stepCloth(world, DT)
      const expected = lbs(rest, joints, weights, bind, [pose(p0, q0), pose(p1, q1)])
      for (let i = 0; i < md.length; i++) {
        const d = Math.hypot(c.pos[3 * i] - expected[3 * i], c.pos[3 * i + 1] - expected[3 * i + 1], c.pos[3 * i + 2] - expected[3 * i + 2])
        worst = Math.max(worst, d - md[i])
        sag = Math.max(sag, d)
      }
    }
    expect(worst).toBeLessThan(0.002)
    expect(sag).toBeGreaterThan(0.04) // gravity does pull them off the pose, up to the limit
    expect(allFinite(world, cloth)).toBe(true)
  })

  it('a bone removed mid-turn keeps its part of the pose where it was in the (still) frame; its recycled id is never followed', () => {
    const { world, bones, cloth, joints, weights } = strip()
    setClothSkinning(world, cloth, { bones, joints, weights })
    setClothMotionConstraints(world, cloth, { maxDistance: 0 })
    const c = getClothState(world, cloth)
    const turn = (a: number) => quat.setAxisAngle(quat.create(), [0, 0, 1], a)
    for (let f = 1; f <= 20; f++) {
      setTransform(world, bones[1], [0.5, 1, 0], turn(0.02 * f))
      stepCloth(world, DT)
    }
    const removed = bones[1]
    removeEntity(world, removed)
    stepCloth(world, DT)
    const frozen = c.pos.slice(0, 3 * c.count)
    const recycled = addEntity(world)
    expect(recycled).toBe(removed) // bitECS hands the id out again
    addComponent(world, recycled, getClothComponents(world).Transform)
    for (let f = 1; f <= 30; f++) {
      setTransform(world, recycled, [3, 2, 1], turn(-f))
      stepCloth(world, DT)
    }
    for (let j = 0; j < frozen.length; j++) expect(Math.abs(c.pos[j] - frozen[j])).toBeLessThan(1e-12)
    expect(c.character!.skin!.bones[1]).toBe(0)
    expect(allFinite(world, cloth)).toBe(true)
  })

  it('null returns to the rigid reference from where the skin left it', () => {
    const { world, bones, cloth, joints, weights } = strip()
    setClothSkinning(world, cloth, { bones, joints, weights })
    setClothMotionConstraints(world, cloth, { maxDistance: 0 })
    const c = getClothState(world, cloth)
    for (let f = 1; f <= 20; f++) {
      setTransform(world, bones[1], [0.5, 1, 0], quat.setAxisAngle(quat.create(), [0, 0, 1], 0.05 * f))
      stepCloth(world, DT)
    }
    const bent = c.pos.slice(0, 3 * c.count)
    setClothSkinning(world, cloth, null)
    expect(c.character!.skin).toBeNull()
    for (let f = 1; f <= 10; f++) {
      setTransform(world, bones[1], [0.5, 1, 0], quat.create()) // the elbow straightens: no longer followed
      stepCloth(world, DT)
    }
    // its frame is bone 0 (a skinned cloth without pins defaults to its first bone), which stood still
    for (let j = 0; j < bent.length; j++) expect(Math.abs(c.pos[j] - bent[j])).toBeLessThan(1e-9)
  })

  it('rejects bones without a Transform, wrong-length arrays, joints out of range and weights that do not sum to 1, naming the argument', () => {
    const { world, bones, cloth, joints, weights } = strip()
    const bare = addEntity(world)
    const n = weights.length / 4
    const badWeights = weights.slice()
    badWeights[4 * 5] += 0.1
    const bad: [object, string][] = [
      [{ bones: [bones[0], bare], joints, weights }, 'skinning.bones[1]'],
      [{ bones: [bones[0], 9999], joints, weights }, 'skinning.bones[1]'],
      [{ bones: [], joints, weights }, 'skinning.bones'],
      [{ bones, joints: joints.slice(1), weights }, 'skinning.joints'],
      [{ bones, joints: joints.map((j, k) => (k === 9 ? 2 : j)), weights }, 'skinning.joints[9]'],
      [{ bones, joints: joints.map((j, k) => (k === 9 ? 0.5 : j)), weights }, 'skinning.joints[9]'],
      [{ bones, joints, weights: weights.slice(0, 4 * n - 4) }, 'skinning.weights'],
      [{ bones, joints, weights: badWeights }, 'skinning.weights'],
      [{ bones, joints, weights: weights.map((w, k) => (k === 2 ? -0.1 : w)) }, 'skinning.weights[2]'],
      [{ bones, joints, weights: weights.map((w, k) => (k === 2 ? NaN : w)) }, 'skinning.weights[2]'],
    ]
    expectClothErrors(bad, (skinning) => setClothSkinning(world, cloth, skinning as never))
    expect(() => setClothSkinning(world, cloth, undefined as never)).toThrow(ClothError)
    expect(getClothState(world, cloth).character).toBeNull()
    // a float32 exporter's weight a rounding above 1 is a weight of 1 (the sum's tolerance, 1e-3)
    const rounded = weights.map((w) => (w === 1 ? 1.0005 : w))
    expect(rounded).toContain(1.0005)
    expect(() => setClothSkinning(world, cloth, { bones, joints, weights: rounded })).not.toThrow()
    // and one a rounding below 0, as 1 − 0.75 − 0.25000000000000006 gives, is a weight of 0 (it was refused)
    const below = weights.map((w) => (w === 0 ? 1 - 0.75 - 0.25000000000000006 : w))
    expect(below).toContain(-5.551115123125783e-17)
    expect(() => setClothSkinning(world, cloth, { bones, joints, weights: below })).not.toThrow()
  })

  it('a vertex no triangle uses may have no weights (as exports leave it); a used one may not', () => {
    // (it is no part of the cloth; it was refused: "of particle 4 sum to 0")
    const world = makeWorld()
    const bone = addEntity(world)
    setTransform(world, bone, [0, 1, 0])
    const positions = [0, 1, 0, 1, 1, 0, 0, 0, 0, 1, 0, 0, 5, 5, 5]
    const cloth = createClothFromMesh(world, { positions, indices: [0, 2, 1, 1, 2, 3] })
    const joints = new Array(20).fill(0)
    const weights = [1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0]
    setClothMotionConstraints(world, cloth, { maxDistance: 0.1 })
    setClothSkinning(world, cloth, { bones: [bone], joints, weights })
    expect(getClothReference(world, cloth)!.every(Number.isFinite)).toBe(true)
    stepCloth(world, DT)
    expect(allFinite(world, cloth)).toBe(true)
    const unweighted = weights.slice()
    unweighted[12] = 0 // particle 3, used
    expect(() => setClothSkinning(world, cloth, { bones: [bone], joints, weights: unweighted })).toThrow(ClothError)
  })

  it('a vertex no triangle uses keeps its place under a max distance of 0 while the skeleton runs and turns', () => {
    // (held like the cloth's own, it was put on the reference its no weights give, and went on at
    // the speed cap: in a hunt, one made at (1000, 1000, 1000) was at (680.8, 1000, 1239.2) after 2 s)
    const world = makeWorld()
    const hero = addEntity(world), bone = addEntity(world)
    setTransform(world, hero, [0, 1, 0])
    setTransform(world, bone, [0, 0.5, 0])
    const positions = [0, 1, 0, 1, 1, 0, 0, 0, 0, 1, 0, 0, 5, 5, 5]
    const cloth = createClothFromMesh(world, { positions, indices: [0, 2, 1, 1, 2, 3] })
    const joints = new Array(20).fill(0)
    const weights = [1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0]
    setClothMotionConstraints(world, cloth, { maxDistance: [0, 0, 0.2, 0.2, 0] })
    setClothSkinning(world, cloth, { bones: [bone], joints, weights })
    const c = getClothState(world, cloth)
    for (let f = 1; f <= 120; f++) {
      const a = 3 * f * DT
      const q: [number, number, number, number] = [0, Math.sin(a / 2), 0, Math.cos(a / 2)]
      setTransform(world, hero, [1.5 - 1.5 * Math.cos(a), 1, 1.5 * Math.sin(a)], q)
      setTransform(world, bone, [1.5 - 1.5 * Math.cos(a), 0.5, 1.5 * Math.sin(a)], q)
      stepCloth(world, DT)
      expect(Array.from(c.pos.subarray(12, 15)), `frame ${f}`).toEqual([5, 5, 5])
      expect(Array.from(c.vel.subarray(12, 15))).toEqual([0, 0, 0])
    }
    // the used particles held at 0 follow the skeleton
    expect(Math.hypot(c.pos[0] - c.pos[3], c.pos[1] - c.pos[4], c.pos[2] - c.pos[5])).toBeCloseTo(1, 6)
    expect(allFinite(world, cloth)).toBe(true)
  })
})
