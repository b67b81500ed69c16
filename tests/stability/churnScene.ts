// Shared scene of tests/stability/churn.test.ts (long sessions and entity churn).
import { addEntity, createWorld, entityExists, removeComponent, removeEntity } from 'bitecs'
import {
  addBoxCollider,
  addCapsuleCollider,
  addConvexHullCollider,
  addPlaneCollider,
  addSphereCollider,
  createCloth,
  createWindZone,
  enableSelfCollision,
  getClothComponents,
  getClothState,
  grabParticle,
  installClothPlugin,
  makeTearable,
  moveGrab,
  pinRow,
  removeCloth,
  removeCollider,
  removeWindZone,
  setClothBudget,
  setClothInertia,
  setClothMotionConstraints,
  setClothSkinning,
  setTransform,
  type ClothPluginOptions,
} from '../../src/index'
import { CALIBRATION } from '../helpers'

export type W = ReturnType<typeof createWorld>

export function mkWorld(o: ClothPluginOptions = {}): W {
  return installClothPlugin(createWorld(), o)
}

/** FNV-1a over the bytes of typed arrays. */
export function hashArrays(arrays: ArrayBufferView[]): string {
  let h = 0x811c9dc5
  for (const a of arrays) {
    const b = new Uint8Array(a.buffer, a.byteOffset, a.byteLength)
    for (let i = 0; i < b.length; i++) {
      h ^= b[i]
      h = Math.imul(h, 0x01000193)
    }
  }
  return (h >>> 0).toString(16)
}

export function clothBytes(world: W, cloth: number): string {
  const c = getClothState(world, cloth)
  return hashArrays([c.pos.subarray(0, 3 * c.count), c.vel.subarray(0, 3 * c.count), c.invMass.subarray(0, c.count)])
}

export interface Scene {
  hero: number
  bone: number
  bodies: number[]
  colliders: number[]
  zones: number[]
  cape: number
  skinned: number
  viewer: number
  grab: number
}

export interface SceneOpts {
  colliders?: boolean
  wind?: boolean
  character?: boolean
  skin?: boolean
  tear?: boolean
  self?: boolean
  grab?: boolean
  budget?: boolean
}

export const ALL: SceneOpts = { colliders: true, wind: true, character: true, skin: true, tear: true, self: true, grab: true, budget: true }

/** A scene with every feature: hero + bone, five colliders, two zones, a cape and a skinned strip. */
export function buildScene(w: W, opts: SceneOpts = ALL): Scene {
  const hero = addEntity(w)
  setTransform(w, hero, [0, 0, 0])
  const bone = addEntity(w)
  setTransform(w, bone, [2, 1, 0])
  const colliders: number[] = []
  const bodies: number[] = []
  if (opts.colliders) {
    const s = addEntity(w)
    addSphereCollider(w, s, { body: hero, offset: [0, 1.68, 0.02], radius: 0.13 })
    const cap = addEntity(w)
    addCapsuleCollider(w, cap, { body: hero, offset: [0, 1.15, 0], radius: 0.19, halfHeight: 0.22 })
    const box = addEntity(w)
    setTransform(w, box, [0.3, 0.6, -0.4])
    addBoxCollider(w, box, { halfExtents: [0.2, 0.1, 0.2] })
    const hull = addEntity(w)
    setTransform(w, hull, [-0.3, 0.5, -0.4])
    addConvexHullCollider(w, hull, { points: [0, 0.2, 0, 0.2, 0, 0, -0.2, 0, 0, 0, 0, 0.2, 0, 0, -0.2, 0, -0.2, 0] })
    const ground = addEntity(w)
    setTransform(w, ground, [0, 0, 0])
    addPlaneCollider(w, ground)
    colliders.push(s, cap, box, hull, ground)
    bodies.push(box, hull, ground)
  }
  const zones: number[] = []
  if (opts.wind) {
    zones.push(createWindZone(w, { direction: [1, 0, 0.2], strength: 3, turbulence: 0.3, seed: 5 }))
    zones.push(createWindZone(w, { shape: 'box', position: [0, 1, -1], size: [3, 3, 3], direction: [0, 0, -1], strength: 2 }))
  }
  const cape = createCloth(w, { width: 0.55, height: 1.0, resolution: [6, 10], position: [0, 1.47, -0.25], material: 'wool', substeps: 4 })
  pinRow(w, cape, 0, hero)
  if (opts.character) {
    setClothInertia(w, cape, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5, teleport: { mode: 'reset', angle: Math.PI / 2 } })
    const md = Array.from({ length: 60 }, (_, i) => {
      const u = Math.floor(i / 6) / 9
      return u === 1 ? Infinity : 0.9 * u * u
    })
    setClothMotionConstraints(w, cape, { maxDistance: md, backstop: { distance: 0.02, radius: 0.5 }, every: 2 })
  }
  if (opts.tear) makeTearable(w, cape, { strain: 0.3 })
  if (opts.self) enableSelfCollision(w, cape)
  let grab = 0
  if (opts.grab) grab = grabParticle(w, cape, 57, [0, 0.5, -0.6])
  let skinned = 0
  if (opts.skin) {
    skinned = createCloth(w, { width: 0.2, height: 0.6, resolution: [3, 6], position: [2, 1, 0], substeps: 2 })
    const n = 18
    const joints = new Array(4 * n).fill(0)
    const weights = Array.from({ length: 4 * n }, (_, k) => (k % 4 === 0 ? 1 : 0))
    setClothSkinning(w, skinned, { bones: [bone], joints, weights })
    setClothMotionConstraints(w, skinned, { maxDistance: Array.from({ length: n }, (_, i) => (i < 3 ? 0 : 0.2)) })
  }
  let viewer = 0
  if (opts.budget) {
    viewer = addEntity(w)
    setTransform(w, viewer, [0, 2, 5])
    setClothBudget(w, { viewer, near: 3, far: 20, calibration: CALIBRATION, adapt: false })
  }
  return { hero, bone, bodies, colliders, zones, cape, skinned, viewer, grab }
}

/** Drives the scene for frame f: hero walks and turns, bone swings, grab moves. */
export function drive(w: W, s: Scene, f: number): void {
  const t = f / 60
  const yaw = 0.5 * Math.sin(t)
  setTransform(w, s.hero, [Math.sin(t * 0.7) * 1.5, 0, t * 0.8], [0, Math.sin(yaw / 2), 0, Math.cos(yaw / 2)])
  const a = 0.6 * Math.sin(t * 2)
  setTransform(w, s.bone, [2 + 0.1 * Math.sin(t), 1, 0], [Math.sin(a / 2), 0, 0, Math.cos(a / 2)])
  if (s.grab) moveGrab(w, s.grab, [Math.sin(t * 0.7) * 1.5, 0.4, t * 0.8 - 0.7])
}

export function sceneBytes(w: W, s: Scene): string {
  return [s.cape, s.skinned].filter((c) => c !== 0).map((c) => clothBytes(w, c)).join('|')
}

/** Removes the scene in one of several ways. */
export function teardown(w: W, s: Scene, way: number): void {
  const { Transform } = getClothComponents(w)
  switch (way % 6) {
    case 0: // API removals
      if (s.cape) removeCloth(w, s.cape)
      if (s.skinned) removeCloth(w, s.skinned)
      for (const c of s.colliders) removeCollider(w, c)
      for (const z of s.zones) removeWindZone(w, z)
      for (const e of [s.hero, s.bone, s.viewer, ...s.colliders]) if (e && entityExists(w, e)) removeEntity(w, e)
      break
    case 1: // removeEntity on cloths first
      for (const e of [s.cape, s.skinned, ...s.zones, ...s.colliders, s.hero, s.bone, s.viewer])
        if (e && entityExists(w, e)) removeEntity(w, e)
      break
    case 2: // pin target / frame / bone / bodies first, then the rest
      for (const e of [s.hero, s.bone, ...s.bodies, s.viewer, ...s.zones, s.cape, s.skinned, ...s.colliders])
        if (e && entityExists(w, e)) removeEntity(w, e)
      break
    case 3: // transforms taken away first (component removal), then the entities
      for (const e of [s.hero, s.bone, ...s.bodies, ...s.zones]) if (entityExists(w, e)) removeComponent(w, e, Transform)
      for (const e of [...s.colliders, ...s.zones, s.hero, s.bone, s.viewer, s.cape, s.skinned])
        if (e && entityExists(w, e)) removeEntity(w, e)
      break
    case 4: // zones and colliders first, then cloths, then the rest
      for (const e of [...s.zones, ...s.colliders, s.cape, s.skinned, s.hero, s.bone, s.viewer])
        if (e && entityExists(w, e)) removeEntity(w, e)
      break
    case 5: // viewer and bone first
      for (const e of [s.viewer, s.bone, s.cape, s.hero, s.skinned, ...s.zones, ...s.colliders, ...s.bodies])
        if (e && entityExists(w, e)) removeEntity(w, e)
      break
  }
  if (s.viewer) setClothBudget(w, null)
}
