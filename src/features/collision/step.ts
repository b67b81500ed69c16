import { SHAPE_BOX, SHAPE_CAPSULE, SHAPE_HULL, SHAPE_SPHERE } from '../../core/shapes'
import { collideBox, collideCapsule, collideHull, collidePlane, collideSphere, measureCloth } from '../../kernels/collide'
import { F_MU_K, F_MU_S, F_RADIUS } from '../../kernels/colliderFrame'
import type { ClothState, ClothWorldState } from '../../world/state'
import { pinTravel } from '../pins/step'
import { grabTravel } from '../grab/step'
import { fillColliderFrame, sweepColliderBounds, sweptAtRest } from './colliders'
import { colliderLayersMatch, colliderReaches } from './reach'
import { buildSelfCollisionPairs, solveSelfCollision } from './selfCollision'
import { B_MAX_DEV, B_MEAN_V, B_REFRESH } from './types'
import { liveColliders } from './list'

/**
 * Once per fixed step (the sync phase): each collider's bounds swept over the step, from its
 * body's pose at the step's start and end (read by the broadphase and by the sleep test). A
 * collider whose body is at rest keeps the bounds it had at rest there (a level's 1024 props cost
 * each step 1.34× a cape's step without them, most of it here and in the sample).
 */
export function sweepColliders(state: ClothWorldState): void {
  const C = state.collision.Collider
  const moved = state.kinematics.moved
  // the list compacted once a step, here in the sync phase (a call at each reader made V8 allocate)
  if (state.collision.released > 0) liveColliders(state.collision)
  const colliders = state.collision.entries
  for (let q = 0; q < colliders.length; q++) {
    const eid = colliders[q]
    if (moved[C.slot[eid]] === 0 && sweptAtRest(state, eid)) continue
    sweepColliderBounds(state, eid)
  }
}

/** Slot of `measure` after `measureCloth`'s: how far the cloth's pins and hands still go this step (`pinTravel`, `grabTravel`). */
const M_PIN_TRAVEL = 11

/**
 * Once per fixed step (the collide phase's first substep): for each running cloth that could
 * touch a collider (layers) or collides with itself, its particle bounds grown by how far
 * particles can travel in the step, and the list of colliders whose swept bounds (see
 * `sweepColliders`) reach them; then the self-collision hashes and pair lists. A cloth far from
 * every collider gets an empty list and costs nothing per particle in the substeps; an idle
 * cloth (asleep, frozen) keeps its last bounds.
 */
export function beginCollisionStep(state: ClothWorldState): void {
  const cloths = state.cloths
  for (let ci = 0; ci < cloths.length; ci++) beginClothCollision(state, cloths[ci])
  if (state.collision.selfCloths.length > 0) buildSelfCollisionPairs(state)
}

/** `beginCollisionStep`'s work for one cloth: its bounds and its colliders in range (not the self-collision pairs). */
export function beginClothCollision(state: ClothWorldState, c: ClothState): void {
  const cw = state.collision
  const C = cw.Collider
  // (read as the sync phase left them: a collider removed since, between phases run by hand, is
  // skipped by its slot; compacting here, a call per cloth and step, made V8 allocate in the step)
  const colliders = cw.entries
  const cc = c.collision
  cc.activeCount = 0
  const b = cc.bounds
  if (c.idle && b[B_REFRESH] === 0) return
  if (cc.self === null) b[B_REFRESH] = 0 // (a self-colliding cloth's hash is built after: it clears it there)
  let candidates = false
  for (let k = 0; k < colliders.length; k++) {
    if (colliderLayersMatch(C, colliders[k], cc)) {
      candidates = true
      break
    }
  }
  if (!candidates && cc.self === null) return
  const m = cw.measure
  measureCloth(c.pos, c.vel, c.invMass, c.count, cc.self !== null ? 1 : 0, m, c.topology.unused)
  // how far a particle can get this step: its speed now, gravity, where its pins still go (they
  // drag the rest) and where hands still pull it, and room for acceleration
  const g = state.gravity
  const gravity = Math.sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2])
  const dt = c.h * c.substeps // the cloth's step (longer when it steps every n-th)
  m[M_PIN_TRAVEL] = 0
  if (c.pins.list.length > 0) pinTravel(state, c, m, M_PIN_TRAVEL)
  if (c.grab.count > 0) grabTravel(c, m, M_PIN_TRAVEL) // (the larger of the two)
  const travel = 1.5 * (Math.sqrt(m[6]) * dt + gravity * dt * dt + m[M_PIN_TRAVEL]) + 0.01
  for (let a = 0; a < 3; a++) {
    b[a] = m[a] - travel
    b[3 + a] = m[3 + a] + travel
    b[B_MEAN_V + a] = m[7 + a]
  }
  b[B_MAX_DEV] = m[10]
  if (!candidates) return
  for (let k = 0; k < colliders.length; k++) {
    const e = colliders[k]
    if (C.slot[e] >= 0 && colliderLayersMatch(C, e, cc) && colliderReaches(C, e, b, c)) cc.active[cc.activeCount++] = e
  }
}

/**
 * Every substep: particle–particle collisions first (self and cloth–cloth), then each running
 * cloth against the colliders in range, in creation order, so colliders have the last word.
 */
export function collideSubstep(state: ClothWorldState): void {
  const cw = state.collision
  if (cw.selfCloths.length > 0) solveSelfCollision(state)
  collideColliders(state)
}

function collideColliders(state: ClothWorldState): void {
  const cw = state.collision
  // with no collider a self-colliding cloth still forgets its collider contacts below
  if (cw.entries.length === 0 && cw.selfCloths.length === 0) return
  const cloths = state.cloths
  for (let ci = 0; ci < cloths.length; ci++) collideClothColliders(state, cloths[ci])
}

/** One running cloth against its colliders in range, at the world's substep (`collideSubstep`'s second part). */
export function collideClothColliders(state: ClothWorldState, c: ClothState): void {
  if (c.subIndex < 0) return
  const cw = state.collision
  const C = cw.Collider
  const f = cw.frame, s = cw.scratch
  const cc = c.collision
  // self-colliding cloths remember which particles rest on a collider (heavier in particle pairs);
  // forgotten every substep, also with no collider in range (a cloth lifted off the ground)
  const touched = cc.self !== null ? cc.self.touched : null
  if (touched !== null) touched.fill(0)
  if (cc.activeCount === 0) return
  const muK = cc.friction >= 0 ? cc.friction : c.material.friction
  const muS = cc.staticFriction >= 0 ? cc.staticFriction : muK
  const r = cc.thickness >= 0 ? cc.thickness : c.material.thickness
  for (let a = 0; a < cc.activeCount; a++) {
    const e = cc.active[a]
    f[F_RADIUS] = r
    fillColliderFrame(state, e, c.subIndex, c.substeps, f)
    // friction: the cloth's, or the geometric mean with the collider's when it sets one
    const ck = C.friction[e], cs = C.staticFriction[e]
    f[F_MU_K] = ck >= 0 ? Math.sqrt(muK * ck) : muK
    f[F_MU_S] = cs >= 0 ? Math.sqrt(muS * cs) : ck >= 0 ? Math.sqrt(muS * ck) : muS
    const shape = C.shape[e]
    if (shape === SHAPE_SPHERE) collideSphere(c.pos, c.prev, c.invMass, c.count, f, s, touched)
    else if (shape === SHAPE_CAPSULE) collideCapsule(c.pos, c.prev, c.invMass, c.count, f, s, touched)
    else if (shape === SHAPE_BOX) collideBox(c.pos, c.prev, c.invMass, c.count, f, s, touched)
    else if (shape === SHAPE_HULL) {
      const hull = C.hulls[e]!
      collideHull(c.pos, c.prev, c.invMass, c.count, f, hull.planes, hull.planeCount, s, touched)
    } else collidePlane(c.pos, c.prev, c.invMass, c.count, f, s, touched)
    state.stats.colliderTests += c.count
  }
}

/**
 * The collide phase of the cloths that collide with themselves or each other (`selfCloths`, in
 * creation order), at the world's substep: their bounds and colliders in range and their pairs at
 * the step's first substep, then their particle contacts, then each against its colliders. Their
 * contacts join them within a substep, so the pipeline runs them phase by phase together.
 */
export function collideSelfColliding(state: ClothWorldState): void {
  const group = state.collision.selfCloths
  if (state.substep === 0) {
    for (let q = 0; q < group.length; q++) beginClothCollision(state, group[q])
    buildSelfCollisionPairs(state)
  }
  solveSelfCollision(state)
  for (let q = 0; q < group.length; q++) collideClothColliders(state, group[q])
}
