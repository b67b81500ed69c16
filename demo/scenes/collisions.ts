import { addEntity } from 'bitecs'
import { quat, vec3 } from 'gl-matrix'
import * as THREE from 'three'
import { RoundedBoxGeometry } from 'three/examples/jsm/geometries/RoundedBoxGeometry.js'
import {
  addBoxCollider,
  addCapsuleCollider,
  addConvexHullCollider,
  addPlaneCollider,
  addSphereCollider,
  createCloth,
  disableSelfCollision,
  enableSelfCollision,
  getClothStats,
  getColliderHull,
  getColliderPose,
  setClothCollision,
  setTransform,
} from '../../src/index'
import { cottonFabric, ginghamFabric, paint, shadows, towelFabric, wood } from '../fabrics'
import { grainNormal } from '../textures'
import { addButton, type DemoScene } from '../scene'

/** Self-collision on or off, kept across resets of the scene. */
let selfCollision = true

/** A lumpy rock: an icosahedron with jittered radii (its convex hull has 20 faces). */
function rockPoints(size: number): number[] {
  const t = (1 + Math.sqrt(5)) / 2
  const ico = [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t], [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [
    -t,
    0,
    -1,
  ], [-t, 0, 1]]
  const out: number[] = []
  ico.forEach((v, k) => {
    const r = (size * (0.85 + 0.3 * ((k * 0.618) % 1))) / Math.hypot(v[0], v[1], v[2])
    out.push(v[0] * r, v[1] * r * 0.8, v[2] * r)
  })
  return out
}

/**
 * Sheets dropped onto a sphere, a capsule, a box and a convex hull standing on a ground plane,
 * and a tall sheet that crumples onto the ground; self-collision keeps their folds apart (toggle
 * it to see them pass through themselves).
 */
export const collisionsScene: DemoScene = {
  id: 'collisions',
  title: 'Colliders and self-collision',
  defaults: { substeps: 8, iterations: 1, material: 'cotton' },
  camera: { target: [0, 0.35, 0.45], distance: 6.2, yaw: 0.3, pitch: 0.36, fit: 1.25 },
  shadowRadius: 4.5,
  moments: [
    { name: 'rest', seconds: 5 },
    { name: 'motion', seconds: 0.42 },
  ],
  resetState() {
    selfCollision = true
  },
  create({ world, settings, ui, root, showCloth }) {
    const ground = addEntity(world as never)
    setTransform(world, ground, [0, 0, 0])
    addPlaneCollider(world, ground)
    const shape = (x: number, y: number, rotation?: ArrayLike<number>) => {
      const e = addEntity(world as never)
      setTransform(world, e, [x, y, 0], rotation)
      return e
    }
    const ball = addSphereCollider(world, shape(-2.4, 0.45), { radius: 0.45 })
    const log = addCapsuleCollider(world, shape(-0.8, 0.3), { radius: 0.3, halfHeight: 0.35, axis: [0, 0, 1] })
    const crate = addBoxCollider(world, shape(0.8, 0.35, quat.setAxisAngle(quat.create(), [0, 1, 0], 0.5)), {
      halfExtents: [0.4, 0.35, 0.4],
    })
    const rock = addConvexHullCollider(world, shape(2.4, 0.3), { points: rockPoints(0.5) })

    const flat = quat.setAxisAngle(quat.create(), [1, 0, 0], -Math.PI / 2)
    const sheet = (x: number, y: number, z: number, turn: number, size: number, n: number) => {
      const q = quat.multiply(quat.create(), quat.setAxisAngle(quat.create(), [0, 1, 0], turn), flat)
      const start = vec3.transformQuat(vec3.create(), [0, size / 2, 0], q) // position = middle of the top edge
      return createCloth(world, {
        width: size,
        height: size,
        resolution: n,
        position: [x + start[0], y + start[1], z + start[2]],
        rotation: q,
        material: settings.material,
        substeps: settings.substeps,
        iterations: settings.iterations,
        tethers: settings.tethers,
      })
    }
    const cloths = [
      sheet(-2.35, 1.3, 0.05, 0.2, 1.3, 26),
      sheet(-0.8, 1.2, 0.1, 0.6, 1.3, 26),
      sheet(0.85, 1.25, 0, -0.3, 1.3, 26),
      sheet(2.4, 1.35, 0.05, 0.9, 1.3, 26),
    ]
    // a long sheet let go just above the ground, like a towel dropped by its top edge, piles up
    // in folds
    const tall = createCloth(world, {
      width: 0.9,
      height: 2.4,
      resolution: [18, 48],
      position: [0, 2.47, 1.7],
      rotation: quat.setAxisAngle(quat.create(), [1, 0, 0], 0.04),
      material: settings.material,
      substeps: settings.substeps,
      iterations: settings.iterations,
      tethers: settings.tethers,
    })
    cloths.push(tall)
    // a thicker collision shell than the material's 5 mm: the flat triangles between particles
    // 5 cm apart then stay clear of the box's and the rock's edges
    for (const c of cloths) setClothCollision(world, c, { thickness: 0.015 })
    const apply = () => {
      for (const c of cloths) {
        if (selfCollision) enableSelfCollision(world, c)
        else disableSelfCollision(world, c)
      }
    }
    apply()
    const button = addButton(ui, '', () => {
      selfCollision = !selfCollision
      apply()
      label()
    }, 'self-collision')
    const label = () => (button.textContent = `Self-collision: ${selfCollision ? 'on' : 'off'}`)
    label()

    const looks = [
      ginghamFabric('#d9822b', 6),
      cottonFabric('#2f7f95', '#e9e4d8'),
      ginghamFabric('#b8324f', 10),
      cottonFabric('#5d8f3c'),
      towelFabric('#3a6fb0'),
    ]
    cloths.forEach((c, k) => showCloth(c, looks[k]))

    // The solids are drawn 1 to 1.5 cm inside their colliders, and the crate with rounded edges:
    // cloth particles rest on the collider (plus the cloth's thickness), but the flat triangles
    // between them cut across a convex edge, and would show the edge of a shape drawn at the
    // collider's exact size through the cloth.
    const p = vec3.create(), q = quat.create()
    const at = (e: number, m: THREE.Mesh) => {
      getColliderPose(world, e, p, q)
      m.position.set(p[0], p[1], p[2])
      m.quaternion.set(q[0], q[1], q[2], q[3])
      root.add(shadows(m))
    }
    const stone = new THREE.MeshStandardMaterial({
      color: 0x8d8a84,
      roughness: 0.85,
      normalMap: grainNormal(3),
      normalScale: new THREE.Vector2(0.8, 0.8),
      flatShading: true,
    })
    at(ball, new THREE.Mesh(new THREE.SphereGeometry(0.44, 40, 24), paint(0x6c7a89, 0.45)))
    at(log, new THREE.Mesh(new THREE.CapsuleGeometry(0.29, 0.7, 8, 24).rotateX(Math.PI / 2), wood()))
    at(crate, new THREE.Mesh(new RoundedBoxGeometry(0.78, 0.68, 0.78, 4, 0.035), paint(0x7d6a55, 0.7)))
    const hull = getColliderHull(world, rock)!
    const hullGeometry = new THREE.BufferGeometry()
    hullGeometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(hull.vertices).map((v) => v * 0.97), 3))
    hullGeometry.setIndex(Array.from(hull.indices))
    const rockGeometry = hullGeometry.toNonIndexed()
    rockGeometry.computeVertexNormals()
    at(rock, new THREE.Mesh(rockGeometry, stone))
    let lastTests = 0, lastPairs = 0, lastSteps = 0, testsPerStep = 0, pairsPerStep = 0
    return {
      cloths,
      stats() {
        const s = getClothStats(world)
        if (s.steps > lastSteps) {
          testsPerStep = (s.colliderTests - lastTests) / (s.steps - lastSteps)
          pairsPerStep = (s.selfCollisionTests - lastPairs) / (s.steps - lastSteps)
          lastTests = s.colliderTests
          lastPairs = s.selfCollisionTests
          lastSteps = s.steps
        }
        return [`collider tests/step ${testsPerStep.toFixed(0)}`, `self pairs/step ${pairsPerStep.toFixed(0)}`]
      },
    }
  },
}
