/**
 * bitecs-cloth: real-time cloth for bitECS worlds (XPBD, Müller et al.).
 *
 * Install the plugin on a world, create cloths, pin them to entities with a Transform, and call
 * `stepCloth(world, dt)` each frame, or schedule the exported phase systems yourself.
 * @module bitecs-cloth
 */
export { installClothPlugin, getClothComponents, getClothStats, resetClothStats } from './plugin'
export { stepCloth, beginClothStep, endClothStep, endClothStepAsync, disposeClothWorld } from '../systems/step'
export { getClothMesh } from './mesh'
export {
  createRenderProxy,
  updateRenderProxy,
  removeRenderProxy,
  type ClothRenderProxy,
  type RenderProxyMesh,
  type RenderProxyOptions,
} from './proxy'
export type { ProxyBinding } from './model/proxy'
export { getClothDrawTransform } from './draw'
export {
  createCloth,
  createClothFromMesh,
  getClothState,
  getCloths,
  getClothStretch,
  removeCloth,
  setClothQuality,
  setClothTethers,
  type ClothQuality,
  type ClothOptions,
  type CreateClothOptions,
  type CreateClothFromMeshOptions,
  type TetherOptions,
} from './cloth'
export { pinParticle, pinRow, unpin, getPins, type PinOptions } from './features/pins/api'
export { teleportCloth } from './teleport'
export {
  grabParticle,
  moveGrab,
  releaseGrab,
  isGrabActive,
  getGrabs,
  getGrabParticle,
  getGrabForce,
  type GrabOptions,
} from './features/grab/api'
export { setTransform, getTransform } from './world/transform'
export { ClothMaterial, defineMaterial, resolveMaterial, type ClothMaterialSpec, type ClothMaterialName } from './model/materials'
export { ClothError } from './core/errors'
export { ClothSimulation, type ClothSimulationOptions } from './simulation'
export {
  createWindZone,
  setWindZone,
  gustWind,
  removeWindZone,
  getWindZones,
  sampleWind,
  type WindZoneOptions,
  type GustOptions,
} from './features/wind/api'
export type { WindShape } from './features/wind/types'
export { makeTearable, getClothTearCount, type TearableOptions } from './features/tearing/api'
export { onClothTear, drainClothTears } from './features/tearing/events'
export type { ClothTearEvent, ClothTearListener } from './features/tearing/types'
export type {
  ClothMesh,
  ClothPluginOptions,
  ClothSleepOptions,
  ClothState,
  ClothStats,
  ClothWorldState,
  TransformSource,
} from './world/state'
export type { ClothTopology, BendingModel, BendSide, ShearModel } from './model/topology'
export type { TetherMode } from './model/tethers'

// Components and systems, for engines that query or schedule them directly.
export type { TransformStore } from '../components/Transform'
export type { PinStore } from '../components/Pin'
export type { ClothStore } from '../components/Cloth'
export type { WindZoneStore } from '../components/WindZone'
export type { TearableStore } from '../components/Tearable'
export {
  clothSync,
  clothForces,
  clothPredict,
  clothSolve,
  clothCollide,
  clothTear,
  clothWriteback,
  clothGuard,
  clothEvents,
  clothPhases,
} from '../systems/scheduled'
export { clothFixedStep, clothSubstepCount, setClothSubstep } from '../systems/pipeline'

// Kernels: plain functions over typed arrays, usable without a world. The exported versions check
// their arguments (ClothError); the plugin's systems call the unchecked ones in src/kernels/.
export { predictPositions, updateVelocities } from './checked'
export { solveDistances, solveDistancesXpbd, spreadInverseMasses, solveCompression } from './checked'
export { dampPairs } from './checked'
export { solveDihedrals, solveLineBending } from './checked'
export { solveTethers } from './checked'
export { writeRenderMesh, measureStretch } from './checked'
export { buildGridTopology, buildMeshTopology, buildGridMesh, dihedralAngle } from './checked'
export { buildTethers } from './checked'

// Explosion guard and snapshots (hard cases stay numerically stable).
export { onClothReset, drainClothResets, setClothGuard, getClothGuard } from './features/guard/api'
export type { ClothGuardOptions, ClothResetEvent, ClothResetReason } from './features/guard/types'
export { checkClothHealth } from './checked'
export { saveClothState, restoreClothState, type ClothSnapshot } from './snapshot'

// Character cloth: inertia in the character's frame, motion constraints, skinned reference poses, teleports.
export { setClothInertia, setClothMotionConstraints, setClothSkinning, getClothReference } from './features/character/api'
export type {
  ClothInertiaOptions,
  ClothMotionConstraints,
  ClothSkinningOptions,
  ClothTeleportOptions,
  ClothTeleportMode,
  PerParticle,
} from './features/character/types'

// Sleeping: still cloths cost nothing until disturbed.
export { setClothSleep, wakeCloth, isClothSleeping } from './features/sleep/api'

// Quality targets, the world budget and level of detail.
export { setClothQualityTarget, setClothBudget, calibrateClothCost } from './calibrate'
export {
  setClothVisible,
  getClothLod,
  getClothBudgetStats,
  type ClothQualityTarget,
  type ClothBudgetOptions,
  type ClothLodInfo,
  type ClothBudgetStats,
  type ClothCostCalibration,
} from './features/budget/api'
export { SUBSTEP_LADDER } from './features/budget/levels'

// Collisions: colliders, layers, self-collision.
export {
  addSphereCollider,
  addCapsuleCollider,
  addBoxCollider,
  addConvexHullCollider,
  addPlaneCollider,
  removeCollider,
  getColliders,
  getColliderPose,
  getColliderHull,
  type ColliderOptions,
  type SphereColliderOptions,
  type CapsuleColliderOptions,
  type BoxColliderOptions,
  type ConvexHullColliderOptions,
  type PlaneColliderOptions,
} from './features/collision/colliders'
export { setClothCollision, getCollisionComponents, type ClothCollisionOptions } from './features/collision/api'
export { enableSelfCollision, disableSelfCollision, hasSelfCollision, type SelfCollisionOptions } from './features/collision/selfCollision'
export { buildConvexHull, MAX_HULL_PLANES } from './model/hull'
export {
  SHAPE_SPHERE,
  SHAPE_CAPSULE,
  SHAPE_BOX,
  SHAPE_HULL,
  SHAPE_PLANE,
  type ColliderStore,
  type ConvexHull,
} from '../components/Collider'
export type { SelfCollisionStore } from '../components/SelfCollision'
