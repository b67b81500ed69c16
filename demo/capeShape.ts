import * as THREE from 'three'
import {
  createClothFromMesh,
  getClothState,
  pinParticle,
  setClothInertia,
  setClothMotionConstraints,
  type ClothInertiaOptions,
  type ClothMotionConstraints,
} from '../src/index'
import type { Character } from './character'

/** A cape's mesh in the chest frame: `rows` × `cols` vertices, row 0 the collar. */
export interface CapeMesh {
  rows: number
  cols: number
  positions: number[]
  indices: number[]
  uvs: number[]
}

/**
 * The middle of each row down the back, chest frame (y up the spine, z forward, origin at the
 * pelvis): from behind the neck back over the shoulders, then down the back to the calves.
 */
const PROFILE: [number, number][] = [[0.54, -0.12], [0.52, -0.17], [0.48, -0.21], [0.42, -0.235], [0.3, -0.245], [-0.64, -0.275]]

/**
 * A cape cut like a cape, in the chest frame: its top edge is a collar that follows the shoulders
 * around the back of the neck, it runs back over the shoulders and hangs down the back to the
 * calves, narrow at the collar (40 cm along it) and wide at the hem (1 m). Each row is an arc
 * around a centre in front of it, tight around the neck and flatter lower down; below the
 * shoulder blades the cloth is laid in soft vertical folds (its rest shape, so the bending
 * constraints keep them). Triangles face away from the body (the side the backstop is not on).
 * uvs: u across, v down.
 */
export function capeShape(rows: number, cols: number): CapeMesh {
  const lengths = [0]
  for (let k = 1; k < PROFILE.length; k++) {
    lengths.push(lengths[k - 1] + Math.hypot(PROFILE[k][0] - PROFILE[k - 1][0], PROFILE[k][1] - PROFILE[k - 1][1]))
  }
  const total = lengths[lengths.length - 1]
  const along = (s: number): [number, number] => {
    let k = 1
    while (k < PROFILE.length - 1 && lengths[k] < s) k++
    const t = (s - lengths[k - 1]) / (lengths[k] - lengths[k - 1])
    return [PROFILE[k - 1][0] + (PROFILE[k][0] - PROFILE[k - 1][0]) * t, PROFILE[k - 1][1] + (PROFILE[k][1] - PROFILE[k - 1][1]) * t]
  }
  const smooth = (a: number, b: number, x: number) => {
    const t = Math.min(1, Math.max(0, (x - a) / (b - a)))
    return t * t * (3 - 2 * t)
  }
  const positions: number[] = [], uvs: number[] = [], indices: number[] = []
  for (let r = 0; r < rows; r++) {
    const v = r / (rows - 1)
    const [y, zBack] = along(v * total)
    const halfWidth = 0.2 + 0.3 * v ** 0.7 // half the row's length along its arc
    const radius = 0.15 + 0.5 * smooth(0, 0.2, v) // around the neck, then flatter
    const fold = 0.035 * smooth(0.15, 0.7, v) // depth of the folds, growing down the back
    for (let c = 0; c < cols; c++) {
      const u = (2 * c) / (cols - 1) - 1
      const a = (u * halfWidth) / radius
      // three and a half folds across, outward (away from the body) at the middle and the edges
      const out = fold * (0.5 + 0.5 * Math.cos(3.5 * Math.PI * u))
      const rr = radius + out
      positions.push(rr * Math.sin(a), y, zBack + radius - rr * Math.cos(a))
      uvs.push(c / (cols - 1), 1 - v)
    }
  }
  for (let r = 0; r + 1 < rows; r++) {
    for (let c = 0; c + 1 < cols; c++) {
      const a = r * cols + c, b = a + cols
      indices.push(a, a + 1, b, a + 1, b + 1, b) // counter-clockwise seen from behind (−z)
    }
  }
  return { rows, cols, positions, indices, uvs }
}

/** The mesh in world space for a character standing as it does now (chest frame → world). */
export function placeCape(mesh: { positions: number[] }, hero: Character): number[] {
  const out: number[] = []
  const p = new THREE.Vector3()
  for (let i = 0; i < mesh.positions.length; i += 3) {
    hero.chestPoint(mesh.positions[i], mesh.positions[i + 1], mesh.positions[i + 2], p)
    out.push(p.x, p.y, p.z)
  }
  return out
}

/** Character-cloth settings of a cape (the cape scene's panel controls). */
export interface CapeSettings {
  /** Share of the chest's linear and angular acceleration and rotation the cape feels, 0..1 (1 = world space). */
  inertia: number
  /** Max distance painted from 0 at the collar, × this (the Reach slider); false: no motion limits. */
  reach: number | false
  /** A backstop behind the cape's reference pose. */
  backstop: boolean
}

/** What the demo ships: half the chest's motion, painted max distance, a backstop. */
export const CAPE_SETTINGS: CapeSettings = { inertia: 0.5, reach: 0.75, backstop: true }
/** The old behaviour, for comparison: world space, no limits. */
export const WORLD_SPACE_CAPE: CapeSettings = { inertia: 1, reach: false, backstop: false }

/**
 * Max distance of row `r` of `rows`, m: 0 at the collar, 0.9 v² × reach down the back (v: 0 at the
 * collar, 1 at the hem), free over the last tenth, so a hand grabbing the hem pulls on several
 * free rows rather than on one row of edges against a held one.
 */
function paintedMaxDistance(r: number, rows: number, reach: number): number {
  const v = r / (rows - 1)
  return v > 0.9 ? Infinity : reach * 0.9 * v * v
}

/** Applies `settings` to a cape made by `createCape` (inertia in the chest frame, motion constraints). */
export function applyCapeSettings(world: object, cape: number, hero: Character, mesh: CapeMesh, settings: CapeSettings): void {
  const share = settings.inertia
  // a snap round of more than 90° in one frame resets the cape onto the body
  const inertia: ClothInertiaOptions = {
    frame: hero.chest,
    linear: share,
    angular: share,
    centrifugal: share,
    teleport: { angle: Math.PI / 2 },
  }
  setClothInertia(world, cape, inertia)
  if (settings.reach === false) {
    setClothMotionConstraints(world, cape, null)
    return
  }
  const reach = settings.reach
  const maxDistance = Array.from(
    { length: mesh.rows * mesh.cols },
    (_, i) => paintedMaxDistance(Math.floor(i / mesh.cols), mesh.rows, reach),
  )
  const limits: ClothMotionConstraints = { maxDistance, backstop: settings.backstop ? { distance: 0.03, radius: 0.4 } : null }
  setClothMotionConstraints(world, cape, limits)
}

export interface CreateCapeOptions {
  rows: number
  cols: number
  material: string
  substeps: number
  iterations: number
  tethers: boolean
  settings?: CapeSettings
}

/**
 * A shaped cape on `hero`: created where the chest carries it now, pinned along its collar (row
 * 0) to the chest entity, with `settings` (default `CAPE_SETTINGS`). Returns the cloth and its mesh.
 */
export function createCape(world: object, hero: Character, o: CreateCapeOptions): { cape: number; mesh: CapeMesh } {
  const mesh = capeShape(o.rows, o.cols)
  const cape = createClothFromMesh(world, {
    positions: placeCape(mesh, hero),
    indices: mesh.indices,
    uvs: mesh.uvs,
    material: o.material,
    substeps: o.substeps,
    iterations: o.iterations,
    tethers: o.tethers,
  })
  for (let c = 0; c < o.cols; c++) pinParticle(world, cape, c, hero.chest)
  applyCapeSettings(world, cape, hero, mesh, o.settings ?? CAPE_SETTINGS)
  return { cape, mesh }
}

const _a = new THREE.Vector3(), _b = new THREE.Vector3(), _p = new THREE.Vector3(), _q = new THREE.Quaternion()

/** Mean position of row `row` of a cape's particles. */
function rowMiddle(pos: Float64Array | Float32Array, row: number, cols: number, out: THREE.Vector3): THREE.Vector3 {
  out.set(0, 0, 0)
  for (let k = 0; k < cols; k++)
    out.x += pos[3 * (row * cols + k)], out.y += pos[3 * (row * cols + k) + 1], out.z += pos[3 * (row * cols + k) + 2]
  return out.multiplyScalar(1 / cols)
}

/**
 * The hem's angle from the vertical, degrees, seen from the side of the character: from the
 * collar's middle to the hem's middle, positive when the hem trails behind.
 */
export function capeHemAngle(world: object, cape: number, hero: Character, mesh: CapeMesh): number {
  const pos = getClothState(world, cape).pos
  const top = rowMiddle(pos, 0, mesh.cols, _a)
  const d = rowMiddle(pos, mesh.rows - 1, mesh.cols, _b).sub(top)
  const forward = _p.set(Math.sin(hero.heading), 0, Math.cos(hero.heading))
  return (Math.atan2(-d.dot(forward), -d.y) * 180) / Math.PI
}

/**
 * How deep the deepest cape particle lies inside the character's torso capsule (the collider:
 * radius 0.19 m around the chest frame's y axis from −0.03 to 0.37 m), m; ≤ 0 when none is inside.
 */
export function capeTorsoDepth(world: object, cape: number, hero: Character): number {
  const c = getClothState(world, cape)
  _q.fromArray(hero.chestRotation()).invert()
  const o = hero.chestPoint(0, 0, 0, _a)
  let worst = -Infinity
  for (let i = 0; i < c.count; i++) {
    _p.set(c.pos[3 * i], c.pos[3 * i + 1], c.pos[3 * i + 2]).sub(o).applyQuaternion(_q)
    const y = Math.max(-0.03, Math.min(0.37, _p.y))
    worst = Math.max(worst, 0.19 - Math.hypot(_p.x, _p.y - y, _p.z))
  }
  return worst
}
