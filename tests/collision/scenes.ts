// Reference distances for the collision tests, written independently of the kernels, and small
// scene builders shared by the collision test files.
import { addEntity } from 'bitecs'
import { quat, vec3 } from 'gl-matrix'
import { addPlaneCollider, createCloth, getClothState, getColliderPose, setTransform, type CreateClothOptions } from '../../src/index'

/** Shapes as the tests know them (dimensions as given to the add*Collider calls). */
export type Shape =
  | { kind: 'sphere'; radius: number }
  | { kind: 'capsule'; radius: number; halfHeight: number }
  | { kind: 'box'; halfExtents: [number, number, number] }
  | { kind: 'prism'; radius: number; halfHeight: number; sides: number }
  | { kind: 'plane' }

/** The points of a regular prism around local y (vertices at `radius`), for addConvexHullCollider. */
export function prismPoints(radius: number, halfHeight: number, sides: number): number[] {
  const pts: number[] = []
  for (let k = 0; k < sides; k++) {
    const a = (2 * Math.PI * k) / sides
    pts.push(radius * Math.cos(a), -halfHeight, radius * Math.sin(a), radius * Math.cos(a), halfHeight, radius * Math.sin(a))
  }
  return pts
}

const tmpP = vec3.create(), tmpQ = quat.create(), tmpL = vec3.create(), inv = quat.create()

/**
 * Signed distance (m) from world point (x, y, z) to collider `eid` of the given shape at its pose
 * now. For the prism it is the largest face-plane distance: exact inside, never more than the
 * true distance outside, so "≥ d" checks stay sound.
 */
export function signedDistance(world: object, eid: number, shape: Shape, x: number, y: number, z: number): number {
  getColliderPose(world, eid, tmpP, tmpQ)
  quat.invert(inv, tmpQ)
  vec3.transformQuat(tmpL, vec3.sub(tmpL, [x, y, z], tmpP), inv)
  const [lx, ly, lz] = tmpL
  switch (shape.kind) {
    case 'sphere':
      return Math.hypot(lx, ly, lz) - shape.radius
    case 'capsule': {
      const t = Math.max(-shape.halfHeight, Math.min(shape.halfHeight, ly))
      return Math.hypot(lx, ly - t, lz) - shape.radius
    }
    case 'box': {
      const [hx, hy, hz] = shape.halfExtents
      const qx = Math.abs(lx) - hx, qy = Math.abs(ly) - hy, qz = Math.abs(lz) - hz
      const outside = Math.hypot(Math.max(qx, 0), Math.max(qy, 0), Math.max(qz, 0))
      return outside + Math.min(Math.max(qx, qy, qz), 0)
    }
    case 'prism': {
      let d = Math.abs(ly) - shape.halfHeight
      const apothem = shape.radius * Math.cos(Math.PI / shape.sides)
      for (let k = 0; k < shape.sides; k++) {
        const a = (2 * Math.PI * (k + 0.5)) / shape.sides
        d = Math.max(d, lx * Math.cos(a) + lz * Math.sin(a) - apothem)
      }
      return d
    }
    case 'plane':
      return ly
  }
}

/** Smallest signed distance of a cloth's free particles to a collider. */
export function clearance(world: object, cloth: number, eid: number, shape: Shape): number {
  const c = getClothState(world, cloth)
  let min = Infinity
  for (let i = 0; i < c.count; i++) {
    if (c.invMass[i] === 0) continue
    min = Math.min(min, signedDistance(world, eid, shape, c.pos[3 * i], c.pos[3 * i + 1], c.pos[3 * i + 2]))
  }
  return min
}

/** Largest particle speed of a cloth, m/s. */
export function maxSpeed(world: object, cloth: number): number {
  const c = getClothState(world, cloth)
  let v = 0
  for (let i = 0; i < c.count; i++) v = Math.max(v, Math.hypot(c.vel[3 * i], c.vel[3 * i + 1], c.vel[3 * i + 2]))
  return v
}

/** A horizontal sheet (its front facing up) centred at (x, y, z). */
export function flatSheet(
  world: object,
  x: number,
  y: number,
  z: number,
  size: number,
  n: number,
  extra: Partial<CreateClothOptions> = {},
): number {
  return createCloth(world, {
    width: size,
    height: size,
    resolution: n,
    position: [x, y, z - size / 2],
    rotation: [-Math.SQRT1_2, 0, 0, Math.SQRT1_2],
    ...extra,
  })
}

/** A new entity. */
export function entity(world: object): number {
  return addEntity(world as never)
}

/**
 * A cols × rows sheet folded like an accordion into `layers` layers (rows split evenly) `d` apart,
 * particles `d` apart in each layer, the lowest layer at height `y0`, columns from `x0` along x;
 * previous positions equal the positions (at rest). Self-collision is left to the caller.
 */
export function accordionSheet(
  world: object,
  o: { cols: number; rows: number; layers: number; d: number; y0: number; x0?: number; material?: CreateClothOptions['material'] },
): number {
  const { cols, rows, layers, d, y0 } = o
  const x0 = o.x0 ?? 0
  const cloth = createCloth(world, { width: d * (cols - 1), height: d * (rows - 1), resolution: [cols, rows], material: o.material })
  const c = getClothState(world, cloth)
  const per = rows / layers
  for (let r = 0; r < rows; r++) {
    const layer = Math.floor(r / per), k = r % per
    for (let col = 0; col < cols; col++) {
      const i = r * cols + col
      c.pos[3 * i] = x0 + col * d
      c.pos[3 * i + 1] = y0 + layer * d
      c.pos[3 * i + 2] = (layer % 2 === 0 ? k : per - 1 - k) * d
    }
  }
  c.prev.set(c.pos)
  return cloth
}

/** A ground plane at y = 0 on its own entity; returns the entity. */
export function ground(world: object): number {
  const e = addEntity(world as never)
  setTransform(world, e, [0, 0, 0])
  addPlaneCollider(world, e)
  return e
}

/**
 * Smallest distance, over `d`, between two particles that are not mesh neighbours: at least 1.5 × d
 * apart at rest (d is the particle spacing here, so direct and diagonal neighbours are excluded,
 * as the solver excludes them).
 */
export function closestNonNeighbours(world: object, cloth: number, d: number): number {
  const c = getClothState(world, cloth)
  const rest = c.topology.restPositions
  let min = Infinity
  for (let i = 0; i < c.count; i++) {
    for (let j = i + 1; j < c.count; j++) {
      const r = Math.hypot(rest[3 * i] - rest[3 * j], rest[3 * i + 1] - rest[3 * j + 1], rest[3 * i + 2] - rest[3 * j + 2])
      if (r < 1.5 * d) continue
      min = Math.min(min, Math.hypot(c.pos[3 * i] - c.pos[3 * j], c.pos[3 * i + 1] - c.pos[3 * j + 1], c.pos[3 * i + 2] - c.pos[3 * j + 2]))
    }
  }
  return min / d
}
