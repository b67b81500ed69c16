import { addEntity, removeEntity } from 'bitecs'
import * as THREE from 'three'
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
import { brass, curtainFabric, shadows, steel, wood } from '../fabrics'
import { addButton, type DemoScene } from '../scene'

/** A thrown ball: a sphere collider on an entity the scene moves ballistically. */
interface Ball {
  eid: number
  mesh: THREE.Mesh
  p: [number, number, number]
  v: [number, number, number]
}

const GRAVITY = 9.81

/**
 * A tearable curtain hanging from rings on a rail. Click to throw a ball at it (or press Throw):
 * the ball is a sphere collider on an entity whose Transform the scene moves ballistically; it
 * rips through, and pieces that come free fall to the floor (a plane collider). Drag the cloth to
 * pull it.
 */
export const curtainScene: DemoScene = {
  id: 'curtain',
  title: 'Tearing curtain',
  defaults: { substeps: 8, iterations: 1, material: 'cotton', tethers: false },
  camera: { target: [0, 1.3, 0], distance: 4.6, yaw: 0.45, pitch: 0.12, fit: 0.8 },
  shadowRadius: 3.5,
  hint: 'click to throw a ball · drag the cloth to pull it · right-drag or shift-drag to orbit · wheel to zoom',
  moments: [
    { name: 'rest', seconds: 2.5, action: 'hold' },
    { name: 'motion', seconds: 1.3 },
  ],
  create({ world, settings, ui, root, showCloth }) {
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
    // a ring every other particle along the rail
    const hooks: number[] = []
    for (let c = 0; c < cols; c += 2) hooks.push(c)
    hooks.push(cols - 1)
    for (const c of hooks) pinParticle(world, curtain, c)
    // A weak, brittle cloth (40 % of the material's tear strain: 12 % for cotton) that breaks at
    // once (hysteresis 1) and as much as the ball demands (up to 32 edges per step): otherwise the
    // ball drags it out to several times its size before it lets go, and it snaps back. Tethers
    // are off by default here: they would carry the impact straight to the hooks.
    makeTearable(world, curtain, { strain: 0.4 * resolveMaterial(settings.material).tearStrain, maxTearsPerStep: 32, hysteresis: 1 })
    showCloth(curtain, curtainFabric())

    // the frame: two wooden posts, a steel rail, a brass ring at each hook
    const railY = top + 0.045
    const rail = new THREE.Mesh(new THREE.CylinderGeometry(0.02, 0.02, width + 0.5, 16).rotateZ(Math.PI / 2), steel())
    rail.position.set(0, railY, 0)
    root.add(shadows(rail))
    for (const x of [-(width / 2 + 0.22), width / 2 + 0.22]) {
      const post = new THREE.Mesh(new THREE.BoxGeometry(0.09, railY + 0.12, 0.09), wood())
      post.position.set(x, (railY + 0.12) / 2, 0)
      const foot = new THREE.Mesh(new THREE.BoxGeometry(0.16, 0.05, 0.5), wood())
      foot.position.set(x, 0.025, 0)
      root.add(shadows(post), shadows(foot))
    }
    const ringGeometry = new THREE.TorusGeometry(0.032, 0.006, 8, 18)
    const ringMaterial = brass()
    for (const c of hooks) {
      const ring = new THREE.Mesh(ringGeometry, ringMaterial)
      ring.position.set(-width / 2 + (c / (cols - 1)) * width, railY - 0.005, 0)
      ring.rotation.y = Math.PI / 2
      root.add(shadows(ring))
    }

    const ballGeometry = new THREE.SphereGeometry(radius * 0.97, 32, 20)
    const ballMaterial = new THREE.MeshPhysicalMaterial({ color: 0xe8a21a, roughness: 0.35, clearcoat: 0.6, clearcoatRoughness: 0.2 })
    // a ball parked under the floor: its shader is ready when the first ball flies, instead of
    // stalling that frame (0.25 to 1 s in software WebGL)
    const parked = shadows(new THREE.Mesh(ballGeometry, ballMaterial))
    parked.position.y = -10
    parked.frustumCulled = false // drawn (and hidden by the floor) every frame: software WebGL compiles a draw's code at its first draw
    root.add(parked)
    const balls: Ball[] = []
    let thrown = 0
    let autoThrow = true
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
      const mesh = shadows(new THREE.Mesh(ballGeometry, ballMaterial))
      mesh.position.set(...p)
      root.add(mesh)
      balls.push({ eid, mesh, p, v })
      if (balls.length > 4) {
        const old = balls.shift()!
        removeEntity(world as never, old.eid)
        root.remove(old.mesh)
      }
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
      update(time, dt) {
        if (autoThrow && thrown === 0 && time > 0.8) throwNext() // show what the scene is about
        for (const b of balls) {
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
      sync() {
        for (const b of balls) b.mesh.position.set(...b.p)
      },
      click(origin, dir) {
        // aim where the ray meets the curtain's plane (z = 0), or 4 m ahead when it does not
        const t = Math.abs(dir[2]) > 1e-3 && -origin[2] / dir[2] > 0 ? Math.min(12, -origin[2] / dir[2]) : 4
        const target = [origin[0] + t * dir[0], Math.max(radius, origin[1] + t * dir[1]), origin[2] + t * dir[2]]
        // from a little below and to the right of the eye, so the ball's arc is visible
        throwAt(target, [origin[0] + 0.35, origin[1] - 0.45, origin[2]])
      },
      stats: () => [`tears       ${getClothTearCount(world, curtain)}`, `balls       ${thrown}`],
      api: {
        /** Throws the next ball (as the Throw button does). */
        throw: () => throwNext(),
        /** No automatic first throw. */
        hold: () => (autoThrow = false),
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
