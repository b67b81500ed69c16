import { addEntity } from 'bitecs'
import * as THREE from 'three'
import { addCapsuleCollider, addSphereCollider, setTransform } from '../src/index'
import { shadows } from './fabrics'

/** Gaits and their speeds, m/s. */
export const GAITS = { stand: 0, walk: 1.4, run: 4, sprint: 6.5 } as const
export type Gait = keyof typeof GAITS
/** What the character can be told to do: hold a gait, or a one-off move. */
export type Move = Gait | 'turn' | 'jump' | 'teleport'

/** The auto-pilot's programme: gaits held for a while, and one-off moves between them. */
const PROGRAMME: [Move, number][] = [
  ['stand', 2.5],
  ['walk', 4],
  ['run', 4],
  ['sprint', 3],
  ['run', 1.5],
  ['walk', 2.5],
  ['stand', 2],
  ['turn', 0],
  ['stand', 1.2],
  ['walk', 2],
  ['jump', 0],
  ['walk', 1.5],
  ['run', 2.5],
  ['jump', 0],
  ['run', 1.5],
  ['walk', 2],
]

/** The track characters follow: two straights along z joined by half circles (a stadium). */
export class Track {
  readonly length: number
  constructor(readonly half = 7, readonly radius = 5, readonly origin = new THREE.Vector3()) {
    this.length = 4 * half + 2 * Math.PI * radius
  }

  /** Point at arc length `s` (any real), and the heading there (0 = facing +z). */
  at(s: number, out: THREE.Vector3): number {
    const { half: h, radius: r } = this
    s = ((s % this.length) + this.length) % this.length
    let heading: number
    if (s < 2 * h) {
      out.set(r, 0, -h + s)
      heading = 0
    } else if ((s -= 2 * h) < Math.PI * r) {
      const a = s / r
      out.set(r * Math.cos(a), 0, h + r * Math.sin(a))
      heading = -a
    } else if ((s -= Math.PI * r) < 2 * h) {
      out.set(-r, 0, h - s)
      heading = Math.PI
    } else {
      const a = Math.PI + (s - 2 * h) / r
      out.set(r * Math.cos(a), 0, -h + r * Math.sin(a))
      heading = -a
    }
    out.add(this.origin)
    return heading
  }
}

/** Body parts, in drawing order; their shapes are in PART_SHAPES. */
export const PARTS = [
  'torso',
  'shoulders',
  'pelvis',
  'neck',
  'head',
  'hair',
  'eyeL',
  'eyeR',
  'thighL',
  'thighR',
  'shinL',
  'shinR',
  'footL',
  'footR',
  'upperArmL',
  'upperArmR',
  'forearmL',
  'forearmR',
  'handL',
  'handR',
] as const
export type PartName = (typeof PARTS)[number]

/** Where a part is this frame (world space). */
export interface PartPose {
  position: THREE.Vector3
  quaternion: THREE.Quaternion
}

const L_THIGH = 0.44, L_SHIN = 0.43, ANKLE = 0.085
const _v = new THREE.Vector3(), _w = new THREE.Vector3(), _q = new THREE.Quaternion(), _e = new THREE.Euler()
// joints and directions of the pose being built (one character at a time)
const hipP = new THREE.Vector3(),
  kneeP = new THREE.Vector3(),
  ankleP = new THREE.Vector3(),
  thighD = new THREE.Vector3(),
  shinD = new THREE.Vector3()
const shoulderP = new THREE.Vector3(),
  elbowP = new THREE.Vector3(),
  wristP = new THREE.Vector3(),
  upperD = new THREE.Vector3(),
  foreD = new THREE.Vector3()
const hairQ = new THREE.Quaternion(), pelvisQ = new THREE.Quaternion(), footQ = new THREE.Quaternion(), bendOut = new THREE.Quaternion()
const UP = new THREE.Vector3(0, 1, 0)
const tmp3 = [0, 0, 0], tmp4 = [0, 0, 0, 1]

/** Direction of a limb hanging from a joint, swung forward by `a` (rad) about the joint's x axis. */
function limbDir(a: number, out: THREE.Vector3): THREE.Vector3 {
  return out.set(0, -Math.cos(a), Math.sin(a))
}

export interface CharacterOptions {
  /** Body colliders: 'full' (torso, head, thighs, shins, arms), 'crowd' (torso and two legs), 'none'. */
  colliders?: 'full' | 'crowd' | 'none'
  track?: Track
  /** Where on the track it starts, m. */
  start?: number
  /** Walking direction along the track: 1 or −1. */
  direction?: 1 | -1
  /** Runs `PROGRAMME` by itself (default); otherwise holds its gait until told. */
  auto?: boolean
  /** Initial gait. */
  gait?: Gait
  /** Cadence scale (crowds look better when not everyone steps in time). */
  cadence?: number
  /** Speed scale of every gait (default 1). */
  pace?: number
}

/**
 * A character that stands, walks, runs, sprints, turns on the spot, jumps and teleports along a
 * track, animated procedurally (legs with knees, arms with elbows, a torso that leans into its
 * speed, feet kept on the ground). It writes Transforms as an animation system would:
 *
 * - `eid`, the root at the feet (facing +z at heading 0);
 * - `chest`, the upper body's frame at the pelvis, leaning and twisting with the gait: capes pin
 *   to it (shoulders at `chestPoint(±0.235, 0.47, 0)`);
 * - one bone entity per collider limb.
 *
 * Its colliders are the shapes it is drawn with, a centimetre larger, so the flat triangles of a
 * cloth resting on them do not cut into what is drawn.
 */
export class Character {
  readonly eid: number
  readonly chest: number
  readonly track: Track
  /** Root position (feet), heading (rad) and speed (m/s) this frame. */
  readonly position = new THREE.Vector3()
  heading = 0
  speed = 0
  /** Vertical speed from jumping, for the camera (m/s). */
  lift = 0
  gait: Gait
  /** What it is doing now, for the overlay. */
  doing = 'stand'
  auto: boolean
  readonly parts = new Map<PartName, PartPose>()
  readonly colliders: number[] = []
  private s: number
  private dir: 1 | -1
  private phase = 0
  private turnLeft = 0
  private turnOffset = 0
  private jumpT = -1
  private teleported = 0
  private programme = 0
  private programmeT = 0
  private readonly cadence: number
  private readonly pace: number
  private readonly chestQ = new THREE.Quaternion()
  private readonly chestP = new THREE.Vector3()
  private readonly rootQ = new THREE.Quaternion()
  private readonly bones = new Map<PartName, number>()
  /** Two leg bones of a 'crowd' body (hip to ankle). */
  private readonly legBones: number[] = []
  private lean = 0

  constructor(readonly world: object, options: CharacterOptions = {}) {
    this.track = options.track ?? new Track()
    this.s = options.start ?? 0
    this.dir = options.direction ?? 1
    this.auto = options.auto ?? true
    this.gait = options.gait ?? 'stand'
    this.cadence = options.cadence ?? 1
    this.pace = options.pace ?? 1
    this.speed = GAITS[this.gait] * this.pace
    if (this.auto) this.doing = this.gait = PROGRAMME[0][0] as Gait
    for (const p of PARTS) this.parts.set(p, { position: new THREE.Vector3(), quaternion: new THREE.Quaternion() })
    this.eid = addEntity(world as never)
    this.chest = addEntity(world as never)
    this.place(0)
    this.pose()
    const kind = options.colliders ?? 'full'
    if (kind !== 'none') this.addColliders(kind)
  }

  /** Tells it what to do; turning it to anything but 'auto' stops the auto-pilot. */
  command(move: Move | 'auto'): void {
    if (move === 'auto') {
      this.auto = true
      this.programme = 0
      this.programmeT = 0
      this.start(PROGRAMME[0][0])
      return
    }
    this.auto = false
    this.start(move)
  }

  private start(move: Move): void {
    if (move === 'turn') this.turnLeft = Math.PI
    else if (move === 'jump') {
      if (this.jumpT < 0) this.jumpT = 0
    } else if (move === 'teleport') this.teleport()
    else this.gait = move
  }

  /** Jumps 8 m sideways in one frame (and back the next time). */
  teleport(): void {
    const d = this.teleported === 0 ? 8 : -8
    this.teleported += d
    this.track.origin.x += d
  }

  /** One frame of animation. */
  update(dt: number): void {
    if (this.auto) {
      this.programmeT += dt
      const [move, hold] = PROGRAMME[this.programme]
      const oneOff = move === 'turn' || move === 'jump' || move === 'teleport'
      const busy = this.turnLeft > 0 || this.jumpT >= 0
      if ((!oneOff && this.programmeT >= hold) || (oneOff && !busy && this.programmeT > 0.05)) {
        this.programme = (this.programme + 1) % PROGRAMME.length
        this.programmeT = 0
        this.start(PROGRAMME[this.programme][0])
      }
    }
    // speed toward the gait's (a turn on the spot first stops), limited acceleration
    const want = this.turnLeft > 0 ? 0 : GAITS[this.gait] * this.pace
    const a = want > this.speed ? 4.5 : 7
    this.speed += Math.max(-a * dt, Math.min(a * dt, want - this.speed))
    if (this.turnLeft > 0 && this.speed < 0.3) {
      const d = Math.min(this.turnLeft, 3 * dt) // 3 rad/s
      this.turnLeft -= d
      this.turnOffset += d
      if (this.turnLeft <= 0) {
        this.dir = this.dir === 1 ? -1 : 1
        this.turnOffset = 0
      }
    }
    this.s += this.dir * this.speed * dt
    // cadence: cycles per second grows with speed; stepping in place while turning
    const hz = this.speed > 0.05 ? 0.62 + 0.17 * this.speed : this.turnLeft > 0 ? 1.1 : 0
    this.phase += 2 * Math.PI * hz * this.cadence * dt
    if (hz === 0) this.phase += (Math.round(this.phase / Math.PI) * Math.PI - this.phase) * Math.min(1, 6 * dt) // settle feet together
    this.lift = 0
    if (this.jumpT >= 0) this.jumpT += dt
    this.place(dt)
    this.pose()
    this.doing = this.jumpT >= 0 ? 'jump'
      : this.turnLeft > 0 ? 'turn on the spot' : this.speed < 0.05 ? 'stand' : this.speed < 2.4 ? 'walk' : this.speed < 5 ? 'run' : 'sprint'
  }

  /** Root position and heading from the track. */
  private place(_dt: number): void {
    let h = this.track.at(this.s, this.position)
    if (this.dir < 0) h += Math.PI
    this.heading = h + this.turnOffset
    this.rootQ.setFromAxisAngle(UP, this.heading)
  }

  /** Limb poses for this frame; writes the Transforms of the root, chest and bones. */
  private pose(): void {
    const v = this.speed
    const amp = Math.min(1, v / 0.9) // 0 standing → 1 walking
    const run = Math.min(1, Math.max(0, (v - GAITS.walk) / (GAITS.run - GAITS.walk)))
    const sprint = Math.min(1, Math.max(0, (v - GAITS.run) / (GAITS.sprint - GAITS.run)))
    const stepping = this.turnLeft > 0 ? 0.35 : 0
    const hipAmp = Math.max(stepping, amp * (0.42 + 0.3 * run + 0.15 * sprint))
    const kneeAmp = Math.max(stepping * 1.5, amp * (0.7 + 0.65 * run))
    // jump: crouch (0.16 s), push off (0.12 s: the legs straighten while the body speeds up to
    // 2.6 m/s, so position and speed stay continuous), fly until the feet are down again (about
    // 0.58 s, 0.5 m up at the top), land (0.2 s)
    let crouch = 0, air = 0, tuck = 0
    const t = this.jumpT
    if (t >= 0) {
      const T0 = 0.16, T1 = 0.12, V = 2.6, G = 9.81, T3 = 0.2
      const h0 = (V * T1) / 2
      const flight = (V + Math.sqrt(V * V + 2 * G * h0)) / G
      if (t < T0) crouch = Math.sin((t / T0) * (Math.PI / 2))
      else if (t < T0 + T1) {
        const u = t - T0
        crouch = Math.cos((u / T1) * (Math.PI / 2))
        air = (V * u * u) / (2 * T1)
        this.lift = (V * u) / T1
      } else if (t < T0 + T1 + flight) {
        const f = t - T0 - T1
        air = h0 + V * f - 0.5 * G * f * f
        this.lift = V - G * f
        tuck = Math.sin((f / flight) * Math.PI)
      } else if (t < T0 + T1 + flight + T3) crouch = 0.7 * Math.sin(((t - T0 - T1 - flight) / T3) * Math.PI)
      else this.jumpT = -1
    }
    const legs: [number, number][] = []
    let reach = 0
    for (const side of [1, -1]) {
      const ph = this.phase + (side > 0 ? 0 : Math.PI)
      let hip = hipAmp * Math.sin(ph) + 0.45 * crouch + 0.7 * tuck
      // the knee bends most while the leg swings forward, and kicks higher running
      let knee = 0.06 + kneeAmp * Math.max(0, Math.cos(ph)) ** 1.5 + 0.25 * run * Math.max(0, Math.sin(ph)) + 0.9 * crouch + 1.2 * tuck
      hip -= 0.08 * run // running legs trail a little behind the leaning body
      knee = Math.min(2.3, knee)
      legs.push([hip, knee])
      reach = Math.max(reach, L_THIGH * Math.cos(hip) + L_SHIN * Math.cos(hip - knee))
    }
    // the lowest foot stands on the ground; a little flight when running
    const bounce = run * 0.05 * Math.abs(Math.sin(2 * this.phase))
    const hipY = reach + ANKLE + bounce + Math.max(0, air)
    const breathe = 0.006 * Math.sin(this.phaseIdle())
    const targetLean = 0.045 * v + 0.04 * sprint + 0.15 * crouch
    this.lean += (targetLean - this.lean) * 0.15
    const twist = 0.12 * hipAmp * Math.sin(this.phase) * (1 - 0.5 * run)
    // chest frame: at the pelvis, heading × lean × twist
    this.chestQ.copy(this.rootQ).multiply(_q.setFromEuler(_e.set(this.lean, twist, 0, 'YXZ')))
    this.chestP.set(0, hipY + 0.03 + breathe, 0).applyQuaternion(this.rootQ).add(this.position)
    const W = (x: number, y: number, z: number, out: THREE.Vector3) => out.set(x, y, z).applyQuaternion(this.rootQ).add(this.position)
    const C = (x: number, y: number, z: number, out: THREE.Vector3) => this.chestPoint(x, y, z, out)

    const set = (name: PartName, p: THREE.Vector3, q: THREE.Quaternion) => {
      const part = this.parts.get(name)!
      part.position.copy(p)
      part.quaternion.copy(q)
    }
    // upper body, in the chest frame
    set('torso', C(0, 0.17, 0, _v), this.chestQ)
    set('shoulders', C(0, 0.43, -0.005, _v), this.chestQ)
    set('neck', C(0, 0.56, 0.0, _v), this.chestQ)
    set('head', C(0, 0.7, 0.01, _v), this.chestQ)
    hairQ.copy(this.chestQ).multiply(_q.setFromEuler(_e.set(-0.35, 0, 0)))
    set('hair', C(0, 0.712, -0.004, _v), hairQ)
    set('eyeL', C(0.045, 0.715, 0.118, _v), this.chestQ)
    set('eyeR', C(-0.045, 0.715, 0.118, _v), this.chestQ)
    // pelvis and belt turn with the legs, not the chest
    pelvisQ.copy(this.rootQ).multiply(_q.setFromEuler(_e.set(0.3 * this.lean, -0.5 * twist, 0)))
    set('pelvis', W(0, hipY + 0.03, 0, _v), pelvisQ)

    // legs, hip joints in the root frame
    for (const [k, side] of [[0, 1], [1, -1]] as const) {
      const [hip, knee] = legs[k]
      const s = side > 0 ? 'L' : 'R'
      W(side * 0.095, hipY, 0, hipP)
      limbDir(hip, thighD).applyQuaternion(this.rootQ)
      kneeP.copy(hipP).addScaledVector(thighD, L_THIGH)
      limbDir(hip - knee, shinD).applyQuaternion(this.rootQ)
      ankleP.copy(kneeP).addScaledVector(shinD, L_SHIN)
      this.segment(`thigh${s}`, hipP, kneeP)
      this.segment(`shin${s}`, kneeP, ankleP)
      // the foot: flat on the ground in stance, pointing down a little in the swing
      const footPitch = Math.min(0, (hip - knee) * 0.8) - 0.4 * tuck
      footQ.copy(this.rootQ).multiply(_q.setFromEuler(_e.set(-footPitch, 0, 0)))
      const footP = _w.set(0, -0.045, 0.05).applyQuaternion(footQ).add(ankleP)
      set(`foot${s}`, footP, footQ)
      if (this.legBones.length === 2) this.writeSegment(this.legBones[k], hipP, ankleP)
    }

    // arms: swing against the legs, elbows bent more when running; up and out in a jump
    for (const side of [1, -1]) {
      const s = side > 0 ? 'L' : 'R'
      const ph = this.phase + (side > 0 ? Math.PI : 0)
      const swing = Math.max(stepping * 0.5, amp * (0.35 + 0.5 * run)) * Math.sin(ph) + 0.2 * run + 0.6 * tuck - 0.3 * crouch
      const elbow = 0.2 + 1.25 * run + 0.15 * amp + 0.4 * crouch
      const out = 0.1 + 0.06 * run + 0.35 * tuck
      C(side * 0.235, 0.44, 0, shoulderP)
      bendOut.setFromAxisAngle(_w.set(0, 0, 1), side * out)
      limbDir(swing, upperD).applyQuaternion(bendOut).applyQuaternion(this.chestQ)
      elbowP.copy(shoulderP).addScaledVector(upperD, 0.29)
      limbDir(swing + elbow, foreD).applyQuaternion(bendOut).applyQuaternion(this.chestQ)
      wristP.copy(elbowP).addScaledVector(foreD, 0.26)
      this.segment(`upperArm${s}`, shoulderP, elbowP)
      this.segment(`forearm${s}`, elbowP, wristP)
      set(`hand${s}`, wristP.addScaledVector(foreD, 0.035), this.chestQ)
    }

    // Transforms: root, chest, bones
    setTransform(this.world, this.eid, this.position.toArray(tmp3), this.rootQ.toArray(tmp4))
    setTransform(this.world, this.chest, this.chestP.toArray(tmp3), this.chestQ.toArray(tmp4))
    for (const [name, eid] of this.bones) {
      const p = this.parts.get(name)!
      setTransform(this.world, eid, p.position.toArray(tmp3), p.quaternion.toArray(tmp4))
    }
  }

  private idle = 0
  private phaseIdle(): number {
    return (this.idle += 0.035)
  }

  /** A capsule part between two joints (its local y along the segment). */
  private segment(name: PartName, a: THREE.Vector3, b: THREE.Vector3): void {
    const part = this.parts.get(name)!
    part.position.copy(a).add(b).multiplyScalar(0.5)
    part.quaternion.setFromUnitVectors(UP, _w.copy(b).sub(a).normalize())
  }

  private writeSegment(eid: number, a: THREE.Vector3, b: THREE.Vector3): void {
    const c = _v.copy(a).add(b).multiplyScalar(0.5)
    const q = _q.setFromUnitVectors(UP, _w.copy(b).sub(a).normalize())
    setTransform(this.world, eid, c.toArray(tmp3), q.toArray(tmp4))
  }

  /** A point given in the chest frame (origin at the pelvis, y up the spine, z forward), in world space. */
  chestPoint(x: number, y: number, z: number, out = new THREE.Vector3()): THREE.Vector3 {
    return out.set(x, y, z).applyQuaternion(this.chestQ).add(this.chestP)
  }

  /** The chest frame's rotation now (x, y, z, w). */
  chestRotation(): number[] {
    return this.chestQ.toArray([0, 0, 0, 0])
  }

  private addColliders(kind: 'full' | 'crowd'): void {
    const w = this.world
    const torso = addEntity(w as never)
    addCapsuleCollider(w, torso, { body: this.chest, offset: [0, 0.17, 0], radius: 0.19, halfHeight: 0.2 })
    this.colliders.push(torso)
    if (kind === 'crowd') {
      for (let k = 0; k < 2; k++) {
        const bone = addEntity(w as never)
        setTransform(w, bone, this.position.toArray(tmp3))
        this.legBones.push(bone)
      }
      // posed before they become colliders: a collider whose body moves before the first step sweeps
      // across that motion, and legs swept up from the feet flung every cape's hem 0.5 m at its
      // first step (edges 440 % long on average, some capes left caught between the legs)
      this.pose()
      for (const bone of this.legBones) {
        addCapsuleCollider(w, bone, { radius: 0.085, halfHeight: 0.36 })
        this.colliders.push(bone)
      }
      return
    }
    const head = addEntity(w as never)
    addSphereCollider(w, head, { body: this.chest, offset: [0, 0.7, 0.01], radius: 0.13 })
    this.colliders.push(head)
    const limbs: [PartName, number, number][] = [
      ['thighL', 0.085, L_THIGH / 2 - 0.085],
      ['thighR', 0.085, L_THIGH / 2 - 0.085],
      ['shinL', 0.07, L_SHIN / 2 - 0.05],
      ['shinR', 0.07, L_SHIN / 2 - 0.05],
      ['upperArmL', 0.058, 0.1],
      ['upperArmR', 0.058, 0.1],
      ['forearmL', 0.048, 0.1],
      ['forearmR', 0.048, 0.1],
    ]
    for (const [name, radius, halfHeight] of limbs) {
      const bone = addEntity(w as never)
      this.bones.set(name, bone)
      const p = this.parts.get(name)!
      setTransform(w, bone, p.position.toArray(tmp3), p.quaternion.toArray(tmp4))
      addCapsuleCollider(w, bone, { radius, halfHeight })
      this.colliders.push(bone)
    }
  }
}

/** Colours of one character's clothes. */
export interface Palette {
  shirt: THREE.ColorRepresentation
  trousers: THREE.ColorRepresentation
  boots: THREE.ColorRepresentation
  skin: THREE.ColorRepresentation
  hair: THREE.ColorRepresentation
  belt: THREE.ColorRepresentation
}

export const HERO: Palette = { shirt: 0x3f5a78, trousers: 0x3a3430, boots: 0x2a211c, skin: 0xd9a78a, hair: 0x3b2a20, belt: 0x6b4a2a }

type Slot = keyof Palette | 'eye'

/** Polygon budget of the part shapes: 1 for a hero, lower for a crowd. */
let detail = 1

/** Shapes of the parts (drawn a centimetre inside the colliders). */
const PART_SHAPES: Record<PartName, { slot: Slot; geometry: () => THREE.BufferGeometry }> = (() => {
  const capsule = (r: number, hh: number, axis: 'x' | 'y' | 'z' = 'y', segments = 12) => () => {
    const g = new THREE.CapsuleGeometry(r, 2 * hh, Math.max(2, Math.round(5 * detail)), Math.max(6, Math.round(segments * detail)))
    if (axis === 'x') g.rotateZ(Math.PI / 2)
    if (axis === 'z') g.rotateX(Math.PI / 2)
    return g
  }
  const sphere = (r: number, w = 20, h = 14) => () =>
    new THREE.SphereGeometry(r, Math.max(8, Math.round(w * detail)), Math.max(6, Math.round(h * detail)))
  return {
    torso: { slot: 'shirt', geometry: () => capsule(0.18, 0.2, 'y', 16)().scale(1.04, 1, 0.92) },
    shoulders: { slot: 'shirt', geometry: capsule(0.088, 0.15, 'x') },
    pelvis: { slot: 'trousers', geometry: () => capsule(0.135, 0.06, 'x', 14)().scale(1, 1, 0.95) },
    neck: { slot: 'skin', geometry: () => new THREE.CylinderGeometry(0.05, 0.055, 0.12, 12) },
    head: { slot: 'skin', geometry: sphere(0.118, 24, 16) },
    hair: { slot: 'hair', geometry: () => new THREE.SphereGeometry(0.124, 24, 12, 0, 2 * Math.PI, 0, Math.PI * 0.55) },
    eyeL: { slot: 'eye', geometry: sphere(0.014, 8, 6) },
    eyeR: { slot: 'eye', geometry: sphere(0.014, 8, 6) },
    thighL: { slot: 'trousers', geometry: capsule(0.077, L_THIGH / 2 - 0.07) },
    thighR: { slot: 'trousers', geometry: capsule(0.077, L_THIGH / 2 - 0.07) },
    shinL: { slot: 'boots', geometry: capsule(0.062, L_SHIN / 2 - 0.04) },
    shinR: { slot: 'boots', geometry: capsule(0.062, L_SHIN / 2 - 0.04) },
    footL: { slot: 'boots', geometry: capsule(0.045, 0.055, 'z') },
    footR: { slot: 'boots', geometry: capsule(0.045, 0.055, 'z') },
    upperArmL: { slot: 'shirt', geometry: capsule(0.05, 0.11) },
    upperArmR: { slot: 'shirt', geometry: capsule(0.05, 0.11) },
    forearmL: { slot: 'skin', geometry: capsule(0.04, 0.1) },
    forearmR: { slot: 'skin', geometry: capsule(0.04, 0.1) },
    handL: { slot: 'skin', geometry: sphere(0.043, 12, 8) },
    handR: { slot: 'skin', geometry: sphere(0.043, 12, 8) },
  }
})()

function materialsFor(p: Palette): Record<Slot, THREE.Material> {
  return {
    shirt: new THREE.MeshStandardMaterial({ color: p.shirt, roughness: 0.8 }),
    trousers: new THREE.MeshStandardMaterial({ color: p.trousers, roughness: 0.85 }),
    boots: new THREE.MeshStandardMaterial({ color: p.boots, roughness: 0.5 }),
    skin: new THREE.MeshStandardMaterial({ color: p.skin, roughness: 0.6 }),
    hair: new THREE.MeshStandardMaterial({ color: p.hair, roughness: 0.75 }),
    belt: new THREE.MeshStandardMaterial({ color: p.belt, roughness: 0.45 }),
    eye: new THREE.MeshStandardMaterial({ color: 0x1a1a1f, roughness: 0.2 }),
  }
}

/** One character drawn with a mesh per part. */
export class CharacterFigure {
  readonly group = new THREE.Group()
  private readonly meshes = new Map<PartName, THREE.Mesh>()

  constructor(readonly character: Character, palette: Palette = HERO) {
    const mats = materialsFor(palette)
    for (const name of PARTS) {
      const shape = PART_SHAPES[name]
      const m = new THREE.Mesh(shape.geometry(), mats[shape.slot])
      this.meshes.set(name, m)
      this.group.add(m)
    }
    shadows(this.group)
    this.sync()
  }

  /** Moves the meshes to the character's pose. */
  sync(): void {
    for (const [name, m] of this.meshes) {
      const p = this.character.parts.get(name)!
      m.position.copy(p.position)
      m.quaternion.copy(p.quaternion)
    }
  }
}

/**
 * Many characters drawn with one instanced mesh per part (a crowd in a handful of draw calls).
 * Each character gets its own shirt colour through instance colours.
 */
export class CrowdFigures {
  readonly group = new THREE.Group()
  private readonly meshes = new Map<PartName, THREE.InstancedMesh>()
  private readonly m = new THREE.Matrix4()
  private readonly one = new THREE.Vector3(1, 1, 1)

  constructor(readonly characters: readonly Character[], shirts: THREE.ColorRepresentation[]) {
    const base: Palette = { ...HERO, shirt: 0xffffff }
    const mats = materialsFor(base)
    const c = new THREE.Color()
    detail = 0.5 // seen from afar: half the segments
    for (const name of PARTS) {
      if (name === 'eyeL' || name === 'eyeR' || name === 'neck') continue
      const shape = PART_SHAPES[name]
      const mesh = new THREE.InstancedMesh(shape.geometry(), mats[shape.slot], characters.length)
      mesh.frustumCulled = false
      if (shape.slot === 'shirt') { for (let i = 0; i < characters.length; i++) mesh.setColorAt(i, c.set(shirts[i % shirts.length])) }
      this.meshes.set(name, mesh)
      this.group.add(mesh)
    }
    detail = 1
    shadows(this.group)
    this.sync()
  }

  sync(): void {
    for (const [name, mesh] of this.meshes) {
      for (let i = 0; i < this.characters.length; i++) {
        const p = this.characters[i].parts.get(name)!
        mesh.setMatrixAt(i, this.m.compose(p.position, p.quaternion, this.one))
      }
      mesh.instanceMatrix.needsUpdate = true
    }
  }
}
