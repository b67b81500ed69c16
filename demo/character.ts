import { addEntity } from 'bitecs'
import { quat, vec3 } from 'gl-matrix'
import { addCapsuleCollider, addSphereCollider, setTransform } from '../src/index'
import type { Renderer } from './renderer'

/** A limb drawn as a capsule: its pose this frame, and its bone entity once it has a collider. */
interface Limb {
  center: vec3
  rotation: quat
  radius: number
  halfHeight: number
  color: [number, number, number]
  bone: number
}

/**
 * A simple character: an entity with a Transform (root at the feet, facing +z) that walks, runs,
 * turns and jumps along a loop. Shoulders are at local (±0.2, 1.45, −0.12).
 *
 * With `addColliders()` its body gets the colliders it is drawn with: torso and head on small
 * entities that follow the character's Transform at an offset, legs and arms on bone entities
 * whose Transforms the character writes every frame (as an animation system would).
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
  private readonly limbs: Limb[] = []
  /** Collider entities (empty until `addColliders`). */
  readonly colliders: number[] = []

  constructor(readonly world: object, readonly color: [number, number, number] = [0.35, 0.45, 0.7]) {
    this.eid = addEntity(world as never)
    setTransform(world, this.eid, this.position, this.rotation)
    for (let k = 0; k < 2; k++) this.limbs.push({ center: vec3.create(), rotation: quat.create(), radius: 0.08, halfHeight: 0.3, color: [0.25, 0.27, 0.32], bone: 0 })
    for (let k = 0; k < 2; k++) this.limbs.push({ center: vec3.create(), rotation: quat.create(), radius: 0.055, halfHeight: 0.22, color, bone: 0 })
    this.pose()
  }

  /**
   * Gives the body colliders matching what is drawn: a torso capsule and a head sphere following
   * the character's Transform, a capsule on each leg and arm bone. Returns the collider entities.
   */
  addColliders(options: { layer?: number; mask?: number; friction?: number } = {}): number[] {
    const w = this.world
    const torso = addEntity(w as never)
    addCapsuleCollider(w, torso, { ...options, body: this.eid, offset: [0, 1.15, 0], radius: 0.19, halfHeight: 0.22 })
    const head = addEntity(w as never)
    addSphereCollider(w, head, { ...options, body: this.eid, offset: [0, 1.68, 0.02], radius: 0.13 })
    this.colliders.push(torso, head)
    for (const limb of this.limbs) {
      limb.bone = addEntity(w as never)
      setTransform(w, limb.bone, limb.center, limb.rotation)
      addCapsuleCollider(w, limb.bone, { ...options, radius: limb.radius, halfHeight: limb.halfHeight })
      this.colliders.push(limb.bone)
    }
    return this.colliders
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
    this.pose()
  }

  /** Limb poses for this frame (legs and arms swing about the hips and shoulders); moves the bones. */
  private pose(): void {
    const swing = Math.sin(this.phase) * Math.min(0.6, 0.15 * this.speed)
    for (let k = 0; k < 4; k++) {
      const limb = this.limbs[k]
      const side = k % 2 === 0 ? -1 : 1
      const leg = k < 2
      quat.rotateX(limb.rotation, this.rotation, leg ? side * swing : -side * swing * 0.8)
      // hinge at the top end, the limb hanging half its length plus the cap below it
      const top = leg ? this.local(side * 0.1, 0.8, 0) : this.local(side * 0.27, 1.42, 0)
      const down = vec3.transformQuat(vec3.create(), [0, -(leg ? 0.33 : 0.25), 0], limb.rotation)
      vec3.add(limb.center, top, down)
      if (limb.bone !== 0) setTransform(this.world, limb.bone, limb.center, limb.rotation)
    }
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
    r.capsule(this.local(0, 1.15, 0), this.rotation, 0.19, 0.22, this.color) // torso
    r.sphere(this.local(0, 1.68, 0.02), 0.13, [0.85, 0.7, 0.6]) // head
    for (const limb of this.limbs) r.capsule(limb.center, limb.rotation, limb.radius, limb.halfHeight, limb.color)
  }
}
