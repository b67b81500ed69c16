import { addEntity, createWorld } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  ClothError, createCloth, getClothState, getClothStats, getClothStretch, installClothPlugin, pinRow, setClothInertia,
  setClothMotionConstraints, setClothSkinning, setTransform, stepCloth, getClothReference, getClothDrawTransform,
  saveClothState, restoreClothState, getClothComponents,
} from '../src/index'

const dt = 1 / 60
function finite(a: ArrayLike<number>, n: number) { for (let i = 0; i < n; i++) if (!Number.isFinite(a[i])) return false; return true }

function cape(s: number, frameScaleAtConfig: number, opts: { constraints?: boolean; inertia?: boolean } = {}) {
  const world = installClothPlugin(createWorld())
  const hero = addEntity(world)
  setTransform(world, hero, [0, 0, 0], [0, 0, 0, 1], [s, s, s])
  const cloth = createCloth(world, { width: 0.55, height: 1.05, resolution: [8, 12], position: [0, 1.47, -0.2], material: 'wool' })
  pinRow(world, cloth, 0, hero)
  setTransform(world, hero, [0, 0, 0], [0, 0, 0, 1], [frameScaleAtConfig, frameScaleAtConfig, frameScaleAtConfig])
  let err: unknown = null
  try {
    if (opts.inertia) setClothInertia(world, cloth, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5 })
    if (opts.constraints) setClothMotionConstraints(world, cloth, { maxDistance: 0.3, backstop: { distance: 0.02, radius: 0.5 } })
  } catch (e) { err = e }
  return { world, hero, cloth, err }
}

describe('scale near zero on a character frame', () => {
  for (const s of [1e-3, 1e-20, 1e-39, 1e-45]) {
    it(`frame scaled ${s} when motion constraints are set`, () => {
      const world = installClothPlugin(createWorld())
      const hero = addEntity(world)
      setTransform(world, hero, [0, 0, 0], [0, 0, 0, 1], [s, s, s])
      const cloth = createCloth(world, { width: 0.55, height: 1.05, resolution: [8, 12], position: [0, 1.47, -0.2], material: 'wool' })
      let err: unknown = null
      try {
        setClothInertia(world, cloth, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5 })
        setClothMotionConstraints(world, cloth, { maxDistance: 0.3, backstop: { distance: 0.02, radius: 0.5 } })
      } catch (e) { err = e }
      let info = 'no error'
      if (err) info = err instanceof ClothError ? `ClothError(${err.argument})` : `OTHER ${String(err)}`
      let nan = false
      if (!err) {
        for (let f = 0; f < 30; f++) stepCloth(world, dt)
        const c = getClothState(world, cloth)
        nan = !finite(c.pos, 3 * c.count)
        const ref = getClothReference(world, cloth)
        console.log(`s=${s} ${info} finite=${!nan} refFinite=${ref ? finite(ref, ref.length) : 'null'} resets=${getClothStats(world).guardResets} stretch=${JSON.stringify(getClothStretch(world, cloth))}`)
      } else console.log(`s=${s} ${info}`)
    })
  }
})

describe('skinning with bones at near-zero scale', () => {
  for (const s of [1, 1e-20, 1e-39]) {
    it(`bone scaled ${s} at bind`, () => {
      const world = installClothPlugin(createWorld())
      const bone = addEntity(world)
      setTransform(world, bone, [0, 1.5, 0], [0, 0, 0, 1], [s, s, s])
      const cloth = createCloth(world, { width: 0.5, height: 0.5, resolution: [6, 6], position: [0, 1.3, 0] })
      const n = 36
      const joints = new Array(4 * n).fill(0), weights = new Array(4 * n).fill(0)
      for (let i = 0; i < n; i++) weights[4 * i] = 1
      let err: unknown = null
      try {
        setClothSkinning(world, cloth, { bones: [bone], joints, weights })
        setClothMotionConstraints(world, cloth, { maxDistance: 0 })
      } catch (e) { err = e }
      if (err) { console.log(`bone s=${s}`, err instanceof ClothError ? `ClothError(${err.argument})` : String(err)); return }
      setTransform(world, bone, [0, 1.5, 0], [0, 0, 0, 1], [1, 1, 1])
      for (let f = 0; f < 10; f++) stepCloth(world, dt)
      const c = getClothState(world, cloth)
      console.log(`bone s=${s} finite=${finite(c.pos, 3 * c.count)} resets=${getClothStats(world).guardResets} p0=${Array.from(c.pos.slice(0, 3))}`)
    })
  }
})
