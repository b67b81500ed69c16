import { addEntity, removeEntity } from 'bitecs'
import {
  addPlaneCollider,
  addSphereCollider,
  createCloth,
  getClothState,
  getClothTearCount,
  makeTearable,
  pinParticle,
  resolveMaterial,
  setTransform,
} from '../../src/index'
import { addButton, type DemoScene } from '../scene'

/** A thrown ball: a sphere collider on an entity the scene moves ballistically. */
interface Ball {
  eid: number
  p: [number, number, number]
  v: [number, number, number]
  age: number
}

const GRAVITY = 9.81

/**
 * A tearable curtain hanging from hooks on a rail. Click to throw a ball at it (or press Throw):
 * the ball is a sphere collider on an entity whose Transform the scene moves ballistically; it
 * rips through, and pieces that come free fall to the floor (a plane collider). Drag the cloth to
 * tear it by hand.
 */
export const curtainScene: DemoScene = {
  id: 'curtain',
  title: 'Tearing curtain',
  defaults: { substeps: 8, iterations: 1, material: 'cotton', tethers: false },
  camera: { target: [0, 1.25, 0], distance: 4.2, yaw: 0.35, pitch: 0.12 },
  hint: 'click to throw a ball · drag the cloth to pull it · right-drag or shift-drag to orbit · wheel to zoom',
  create({ world, settings, ui }) {
    const cols = 36, rows = 30
    const width = 2, height = 1.8, top = 2.3
    const radius = 0.22, speed = 9 // a 44 cm ball at 9 m/s (32 km/h)
    const ground = addEntity(world as never)
    setTransform(world, ground, [0, 0, 0])
    addPlaneCollider(world, ground)
    const curtain = createCloth(world, {
      width,
      height,
      resolution: [cols, rows],
      position: [0, top, 0],
      material: settings.material,
      substeps: settings.substeps,
      iterations: settings.iterations,
      tethers: settings.tethers,
    })
    // a hook every other particle along the rail
    for (let c = 0; c < cols; c += 2) pinParticle(world, curtain, c)
    pinParticle(world, curtain, cols - 1)
    // A weak, brittle cloth (40 % of the material's tear strain: 12 % for cotton) that breaks at
    // once (hysteresis 1) and as much as the ball demands (up to 32 edges per step): otherwise the
    // ball drags it out to several times its size before it lets go, and it snaps back. Tethers
    // are off by default here: they would carry the impact straight to the hooks.
    makeTearable(world, curtain, { strain: 0.4 * resolveMaterial(settings.material).tearStrain, maxTearsPerStep: 32, hysteresis: 1 })

    const balls: Ball[] = []
    let thrown = 0
    /** Throws a ball from beside the viewer so that it reaches `target` after flying at `speed`. */
    const throwAt = (target: ArrayLike<number>, from: ArrayLike<number>) => {
      const p: [number, number, number] = [from[0], from[1], from[2]]
      const d = Math.hypot(target[0] - p[0], target[1] - p[1], target[2] - p[2])
      const t = d / speed
      const v: [number, number, number] = [
        (target[0] - p[0]) / t,
        (target[1] - p[1]) / t + 0.5 * GRAVITY * t, // aim above to fall onto the target
        (target[2] - p[2]) / t,
      ]
      const eid = addEntity(world as never)
      setTransform(world, eid, p)
      // frictionless: the cloth slides round the ball and tears at its front instead of being
      // dragged along
      addSphereCollider(world, eid, { radius, friction: 0 })
      balls.push({ eid, p, v, age: 0 })
      if (balls.length > 4) removeEntity(world as never, balls.shift()!.eid)
      thrown++
    }
    // the Throw button and the automatic first throw aim at these points of the curtain in turn
    const aims = [[-0.1, 1.05], [0.45, 1.35], [-0.5, 1.5], [0.2, 0.85]]
    const throwNext = () => {
      const [x, y] = aims[thrown % aims.length]
      throwAt([x, y, 0], [x + 0.6, 0.9, 3.2])
    }
    addButton(ui, 'Throw', throwNext, 'throw')
    return {
      cloths: [curtain],
      colors: new Map([[curtain, [0.55, 0.1, 0.16]]]),
      update(time, dt) {
        if (thrown === 0 && time > 0.8) throwNext() // show what the scene is about
        for (const b of balls) {
          b.age += dt
          b.v[1] -= GRAVITY * dt
          for (let k = 0; k < 3; k++) b.p[k] += b.v[k] * dt
          if (b.p[1] < radius) {
            // bounce and roll on the floor
            b.p[1] = radius
            b.v[1] = Math.abs(b.v[1]) > 1 ? -0.4 * b.v[1] : 0
            const f = Math.exp(-1.5 * dt)
            b.v[0] *= f
            b.v[2] *= f
          }
          setTransform(world, b.eid, b.p)
        }
      },
      click(origin, dir) {
        // aim where the ray meets the curtain's plane (z = 0), or 4 m ahead when it does not
        const t = Math.abs(dir[2]) > 1e-3 && -origin[2] / dir[2] > 0 ? Math.min(12, -origin[2] / dir[2]) : 4
        const target = [origin[0] + t * dir[0], Math.max(radius, origin[1] + t * dir[1]), origin[2] + t * dir[2]]
        // from a little below and to the right of the eye, so the ball's arc is visible
        throwAt(target, [origin[0] + 0.35, origin[1] - 0.45, origin[2]])
      },
      draw(r) {
        r.ground(0)
        r.capsule([0, top + 0.03, 0], [0, 0, Math.SQRT1_2, Math.SQRT1_2], 0.025, width / 2 + 0.1, [0.6, 0.6, 0.62])
        for (const b of balls) r.sphere(b.p, radius, [0.85, 0.78, 0.3])
      },
      stats: () => [`tears      ${getClothTearCount(world, curtain)}`, `balls      ${thrown}`],
      api: {
        /** Throws the next ball (as the Throw button does). */
        throw: () => throwNext(),
        tears: () => getClothTearCount(world, curtain),
        thrown: () => thrown,
        /** Particles lying on the floor: only torn-off cloth gets there (the hem hangs at 0.5 m). */
        onFloor: () => {
          const c = getClothState(world, curtain)
          let n = 0
          for (let i = 0; i < c.count; i++) if (c.pos[3 * i + 1] < 0.05) n++
          return n
        },
      },
    }
  },
}
