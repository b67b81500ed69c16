/**
 * Character cloth: state shapes. A cloth worn by a character can be simulated in the character's
 * frame (inertia shares), held near a reference pose (max distance, backstop, drive), have that
 * reference skinned by bones, and reset to it on teleports. `ClothState.character` is null until
 * one of `setClothInertia`, `setClothMotionConstraints` or `setClothSkinning` is called, so a
 * cloth without any of them pays one null check per phase.
 */

/** What a cloth does when its frame teleports (see `ClothTeleportOptions`). */
export type ClothTeleportMode = 'keep' | 'reset'

/** Options of the `teleport` field of `setClothInertia`. */
export interface ClothTeleportOptions {
  /**
   * 'keep' (default): carry the cloth rigidly along with the frame's jump, keeping its shape and
   * (rotated) velocities. 'reset': put it on its reference pose, at rest in the frame.
   */
  mode?: ClothTeleportMode
  /**
   * A frame sample farther than this from where the frame's velocity would have taken it counts
   * as a teleport, m. Default: the world's `teleportDistance` (2 m).
   */
  distance?: number
  /**
   * A frame sample turned by more than this from where the frame's turn (its last step's, over the
   * frame's span) would have taken it counts as a teleport, rad, in (0, π]. Default: off
   * (Infinity); π/2 catches a character snapped around in one frame while a steady turn stays a
   * turn, even through a long frame.
   */
  angle?: number
}

/** Options of `setClothInertia`. */
export interface ClothInertiaOptions {
  /**
   * The entity whose motion is the cloth's frame (it must have a Transform), or null for the
   * world. Default: the target of the cloth's first pin that has one; for a skinned cloth without
   * such a pin, its first bone; else the world.
   */
  frame?: number | null
  /** Share of the frame's linear acceleration the cloth feels, 0..1. Default 1 (world space). */
  linear?: number
  /** Share of the frame's angular acceleration (Euler force) the cloth feels, 0..1. Default 1. */
  angular?: number
  /** Share of the centrifugal and Coriolis effects of the frame's rotation, 0..1. Default 1. */
  centrifugal?: number
  /** The frame's speed the cloth can feel, m/s; faster motion is carried rigidly. Default Infinity. */
  maxLinearSpeed?: number
  /** The frame's turn rate the cloth can feel, rad/s; faster turning is carried rigidly. Default Infinity. */
  maxAngularSpeed?: number
  /** Teleport detection and response for this cloth's frame. */
  teleport?: ClothTeleportOptions
}

/** A number for every particle, or one per particle (`count` values). */
export type PerParticle = number | ArrayLike<number>

/** Options of `setClothMotionConstraints`. */
export interface ClothMotionConstraints {
  /**
   * How far each particle may move from its reference position, m (0 = kinematic: it follows
   * the reference exactly; Infinity = free). Default Infinity.
   */
  maxDistance?: PerParticle
  /**
   * A sphere of `radius` m whose surface lies `distance` m behind each particle's reference
   * position, along the reference normal reversed: the particle stays outside it. Default: none.
   */
  backstop?: { distance?: PerParticle; radius: PerParticle } | null
  /**
   * Pull toward the reference position by a critically damped spring (mass-independent; its
   * damping acts on the motion relative to the reference), as the fraction of an offset it closes
   * in 1/60 s from rest, 0..1: 0 = none (default), 1 = the particle follows the reference.
   * Independent of the substep length.
   */
  drive?: PerParticle
  /**
   * Run max distance and backstop at every n-th substep only, and always at the step's last (an
   * integer ≥ 1; default 1: every substep). Each step still ends within the limits; between two
   * runs a particle may drift past them by what it travels meanwhile, and what a run takes back
   * enters its velocity spread over the substeps since the last. Cheaper: the 64-cape benchmark
   * (inertia 0.5 as well) costs 1.22–1.28× the crowd without character cloth at every substep,
   * 1.13–1.16× at 4 and 1.10–1.12× at 8 (its step's last substep only; README, Capes and
   * character cloth, Cost). A cloth with a drive runs its constraints at every substep whatever
   * this says.
   */
  every?: number
}

/** Options of `setClothSkinning`: linear blend skinning with up to 4 bones per particle. */
export interface ClothSkinningOptions {
  /** Bone entities (each with a Transform). Their poses when this is called are the bind pose. */
  bones: ArrayLike<number>
  /** 4 bone indices (into `bones`) per particle. */
  joints: ArrayLike<number>
  /** 4 weights per particle, each ≥ 0, summing to 1 (within 1e-3). */
  weights: ArrayLike<number>
}

/** Skinned reference pose of a cloth (`ClothCharacter.skin`). */
export interface ClothSkin {
  /** Bone entities (0 once removed) and their kinematic slots (−1 once removed). */
  bones: Int32Array
  slots: Int32Array
  /** Per bone: bind pose px py pz qx qy qz qw sx sy sz (stride 10). */
  bind: Float64Array
  /** Per bone: pose at the cloth's last step end (stride 10); a removed bone keeps its last one. */
  pose: Float64Array
  /**
   * Per bone: skinning matrix (pose · bind⁻¹) as a row-major 3×4 (stride 12) at the end of the
   * current step, and at its start when the reference is blended anew; scratch of a step, set by
   * the sync phase for the blend in the predict phase (`work[W_BLEND]`).
   */
  matrices: Float64Array
  matricesFrom: Float64Array
  /** 4 bone indices and 4 weights per particle (room for the cloth's capacity). */
  joints: Int32Array
  weights: Float64Array
}

/** Character-cloth state of one cloth (`ClothState.character`). */
export interface ClothCharacter {
  /** The frame entity (0: the world) and its kinematic slot (−1: none or removed). */
  frame: number
  frameSlot: number
  /** Simulated in the frame (`setClothInertia`): inertia shares and frame-relative damping. */
  inertia: boolean
  /** Settings, slots S_*. */
  settings: Float64Array
  /** Motion history saved in snapshots, slots M_*. */
  motion: Float64Array
  /** Scratch of a step: the frame's pose at its start and end, and its velocities (slots W_*). */
  work: Float64Array
  /** Per-substep parameters of the frame kernel (see `kernels/motion.ts`). */
  frameParams: Float64Array
  /** Rest positions, world, m: where the particles are when the frame (or every bone) stands at its bind pose. */
  rest: Float64Array
  /** Rest vertex normals, at the same pose. */
  restNormal: Float64Array
  /**
   * Per particle, float32 (BLEND values, see `kernels/motion.ts`): the reference at the start and
   * the end of the cloth's current step as offsets from the frame's origin then (`work[W_FROM..]`,
   * `work[W_TO..]`; between steps `motion[M_POSE..]`) and the normal at its end: skinned, or the
   * rigid reference carried from `bind`.
   */
  ref: Float32Array
  /** Per particle, float32 (RIGID values): the rest position and normal in the frame's bind coordinates (without a skin). */
  bind: Float32Array
  /** Particles a limit moved in the last substep, held for the next distance solve ([0] = count; see `constrainAndUpdateVelocities`). */
  limitHeld: Int32Array
  /** Positions at the current substep's start, for a cloth with motion constraints (written by its predict, read by its writeback). */
  start: Float64Array
  /** Per particle, float32 (LIMITS values): max distance (m, Infinity = free), backstop distance and radius (0 = none). */
  lim: Float32Array
  /** The frame's part of the reference for the current substep (see `kernels/motion.ts`, REF_PARAMS). */
  refParams: Float64Array
  /** Motion constraints are set (`setClothMotionConstraints`): the reference is kept every step. */
  constrained: boolean
  /** Drive frequency ω per particle (rad/s, Infinity = follows the reference), or null when no particle has a drive. */
  drive: Float64Array | null
  /** 1 for particles held on the reference (max distance 0; counted in `pinCount`), and their list. */
  held: Uint8Array
  heldList: Int32Array
  heldCount: number
  skin: ClothSkin | null
}

/** Slots of `ClothCharacter.settings`. */
export const S_LINEAR = 0
export const S_ANGULAR = 1
export const S_CENTRIFUGAL = 2
export const S_MAX_LINEAR = 3
export const S_MAX_ANGULAR = 4
/** 0 keep, 1 reset. */
export const S_TELEPORT_MODE = 5
export const S_TELEPORT_DISTANCE = 6
export const S_TELEPORT_ANGLE = 7
/** 1 when the frame was chosen explicitly (`frame` given), 0 when it was defaulted. */
export const S_FRAME_EXPLICIT = 8
/** Max distance and backstop run at every n-th substep (and the step's last). */
export const S_EVERY = 9
export const SETTINGS = 10

/** Slots of `ClothCharacter.motion`. */
/** The frame's pose (px py pz qx qy qz qw sx sy sz) at the end of the cloth's last step (kept when the frame goes away). */
export const M_POSE = 0
/** The frame's pose when the reference was bound (its rest positions are world positions at this pose). */
export const M_BIND = 10
/** The frame's linear and angular velocity over the last substep (m/s, rad/s), and their felt (clamped) parts. */
export const M_V = 20
export const M_W = 23
export const M_VC = 26
export const M_WC = 29
/**
 * 1 once the velocities above are known; 0: the next step feels no acceleration at its start; 2
 * (`FROM_CLOTH`, a new frame entity): the cloth's motion decides (see `frameFromCloth`).
 */
export const M_PRIMED = 32
export const FROM_CLOTH = 2
/** 1 while a skinned cloth's `ref` holds its reference at the end of its last step. */
export const M_REF_VALID = 33
/** 1 when the cloth sat steps out (asleep, frozen): its next step starts from the frame's pose then. */
export const M_GAP = 34
export const MOTION = 35

/** Slots of `ClothCharacter.work` (a step's scratch). */
export const W_FROM = 0
export const W_TO = 10
/** This step's velocities (actual and felt), and the previous substep's. */
export const W_V = 20
export const W_W = 23
export const W_VC = 26
export const W_WC = 29
export const W_PV = 32
export const W_PW = 35
export const W_PVC = 38
export const W_PWC = 41
/** Scratch for matrices: 4 rotations (9 each) and a quaternion; then M, N and P of `frameSubstep`. */
export const W_R = 44
export const W_M = W_R + 40
export const W_N = W_M + 9
export const W_P = W_N + 9
/** The frame's transform [R·diag(s) | p] (12) at the step's start and end, and its rotation at the end (9). */
export const W_TF = W_P + 9
export const W_TT = W_TF + 12
export const W_RT = W_TT + 12
/**
 * The per-particle blend of a skinned reference the sync phase left to the step's first substep
 * (BLEND_*), so that it runs where the cloth steps (a worker, in a threaded world). 0 between steps.
 */
export const W_BLEND = W_RT + 9
/**
 * 1 through the step after a gap (the cloth sat steps out asleep or frozen, and was carried
 * rigidly while its reference moved on): the limits then place particles without a velocity kick
 * (see `writebackCharacter`). Set by the sync phase, cleared at the step's last substep.
 */
export const W_RESUME = W_BLEND + 1
/**
 * 1 when a particle has a max distance or a backstop (set by the sync phase of a cloth with motion
 * constraints): with neither and no drive, the writeback is the plain velocity update.
 */
export const W_LIMITED = W_RESUME + 1
/**
 * 1 through a step in which a skinned cloth's bones jumped against its frame (see `skinJumped` in
 * step.ts): its motion constraints, drive and held particles rest for the step. Set by the sync phase.
 */
export const W_SKIN_JUMPED = W_LIMITED + 1
/**
 * 1 when a bone of a skinned cloth landed beyond the cloth's own teleport distance or angle at this
 * frame's sample (`markBoneLeaps`): a leap for this cloth's `skinJumped` only. (Marked as the
 * bone's jump for the whole world, it reset another cloth framed on that bone, and a hand collider
 * on it stopped sweeping.)
 */
export const W_BONE_LEAPT = W_SKIN_JUMPED + 1
/** The cloth's mean position and velocity (`meanMotion`), scratch of `beginFrameStep` for a new frame entity. */
export const W_MEAN = W_BONE_LEAPT + 1
export const WORK = W_MEAN + 6
/** `work[W_BLEND]`: the end of last step becomes the start, then the end is blended. */
export const BLEND_END = 1
/** `work[W_BLEND]`: start and end are blended (the reference was not continuous). */
export const BLEND_BOTH = 2
