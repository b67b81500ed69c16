import { addEntity } from 'bitecs'
import { quat, vec3 } from 'gl-matrix'
import { setTransform } from '../src/index'
import type { Renderer } from './renderer'

/**
 * A simple character: an entity with a Transform (root at the feet, facing +z) that walks, runs,
 * turns and jumps along a loop. Shoulders are at local (±0.2, 1.45, −0.12).
 */
export class Character {
  readonly eid: number
  readonly position = vec3.fromValues(0, 0, 0)
  readonly rotation = quat.create()
  heading = 0
  speed = 0
  private phase = 0
  private jumpTime = -1
  private teleportOffset = vec3.create()

  constructor(readonly world: object, readonly color: [number, number, number] = [0.35, 0.45, 0.7]) {
    this.eid = addEntity(world as never)
    setTransform(world, this.eid, this.position, this.rotation)
  }

  /** Advances the walk cycle: accelerates between walking and running, turns, jumps now and then. */
  update(time: number, dt: number): void {
    const target = 1.4 + 2.6 * Math.max(0, Math.sin(time * 0.35)) // 1.4 m/s walk ↔ 4 m/s run
    this.speed += Math.max(-6 * dt, Math.min(6 * dt, target - this.speed))
    this.heading += dt * (0.45 + 0.35 * Math.sin(time * 0.21)) // a wandering loop
    this.phase += dt * (4 + 2.2 * this.speed)
    if (this.jumpTime < 0 && Math.sin(time * 0.5) > 0.995) this.jumpTime = 0
    let lift = 0.04 * Math.abs(Math.sin(this.phase)) * Math.min(1, this.speed / 2)
    if (this.jumpTime >= 0) {
      this.jumpTime += dt
      const T = 0.7
      if (this.jumpTime > T) this.jumpTime = -1
      else lift += 4 * 0.55 * (this.jumpTime / T) * (1 - this.jumpTime / T)
    }
    this.position[0] += Math.sin(this.heading) * this.speed * dt
    this.position[2] += Math.cos(this.heading) * this.speed * dt
    this.position[1] = lift
    quat.setAxisAngle(this.rotation, [0, 1, 0], this.heading)
    const p = vec3.add(vec3.create(), this.position, this.teleportOffset)
    setTransform(this.world, this.eid, p, this.rotation)
  }

  /** Jumps the character `distance` metres sideways in one frame. */
  teleport(distance: number): void {
    this.teleportOffset[0] += distance * Math.cos(this.heading)
    this.teleportOffset[2] -= distance * Math.sin(this.heading)
  }

  /** World position of the root (feet), including teleports. */
  root(out = vec3.create()): vec3 {
    return vec3.add(out, this.position, this.teleportOffset)
  }

  /** A point given in the character's local frame, in world space. */
  local(x: number, y: number, z: number, out = vec3.create()): vec3 {
    vec3.transformQuat(out, [x, y, z], this.rotation)
    return vec3.add(out, out, this.root())
  }

  draw(r: Renderer): void {
    const swing = Math.sin(this.phase) * Math.min(0.6, 0.15 * this.speed)
    r.capsule(this.local(0, 1.15, 0), this.rotation, 0.19, 0.22, this.color) // torso
    r.sphere(this.local(0, 1.68, 0.02), 0.13, [0.85, 0.7, 0.6]) // head
    for (const side of [-1, 1]) {
      const q = quat.rotateX(quat.create(), this.rotation, side * swing)
      r.capsule(this.local(side * 0.1, 0.47, 0), q, 0.08, 0.3, [0.25, 0.27, 0.32]) // legs
      const a = quat.rotateX(quat.create(), this.rotation, -side * swing * 0.8)
      r.capsule(this.local(side * 0.27, 1.17, 0), a, 0.055, 0.22, this.color) // arms
    }
  }
}
