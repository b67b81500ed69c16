// Drawing a cloth where its character is now (getClothDrawTransform; updateClothDrawMatrix in the
// three.js entry): between fixed steps (displays faster than 60 Hz, uneven frames, a pipelined
// frame) the mesh shows the last finished step; moved by its anchor's rigid motion since then, its
// pinned edge is where its pins hold it, with the anchor turning; a change of the anchor's scale is
// left out (it moves the pins by the scale change of less than a step; drawn scaled with it, a cape
// whose character grew from 0.01 to 1 in 0.5 s was 3.9 m long).
import { addEntity } from 'bitecs'
import { Mesh, type Object3D } from 'three'
import { describe, expect, it } from 'vitest'
import {
  ClothError,
  addSphereCollider,
  beginClothStep,
  createCloth,
  endClothStep,
  getClothComponents,
  getClothDrawTransform,
  getClothLod,
  getClothMesh,
  getClothState,
  getPins,
  getClothStretch,
  pinParticle,
  pinRow,
  restoreClothState,
  saveClothState,
  setClothBudget,
  setClothInertia,
  setClothMotionConstraints,
  setClothSkinning,
  setClothVisible,
  setTransform,
  stepCloth,
  teleportCloth,
  unpin,
} from '../../src/index'
import { getClothWorld } from '../../src/world/access'
import { createClothMesh, updateClothDrawMatrix, updateClothGeometry } from '../../src/three/index'
import { makeWorld } from '../helpers'

const yawQuat = (a: number): [number, number, number, number] => [0, Math.sin(a / 2), 0, Math.cos(a / 2)]

function scene() {
  const world = makeWorld({ sleep: false })
  const hero = addEntity(world)
  setTransform(world, hero, [0, 1.6, 0])
  const cloth = createCloth(world, { width: 0.5, height: 0.8, resolution: [6, 9], position: [0, 1.55, -0.15] })
  const pins = pinRow(world, cloth, 0, hero)
  return { world, hero, cloth, pins }
}

/** The hero at time t: walking a curve at 3 m/s, turning, growing 1 → 1.5× over 2 s (`growth`). */
function pose(t: number, growth = 0.25) {
  const s = 1 + growth * t
  return { p: [3 * t, 1.6, Math.sin(t)] as [number, number, number], q: yawQuat(0.8 * t), s: [s, s, s] as [number, number, number] }
}

/** Largest distance between the drawn pinned particles (moved by m) and where their pins hold them now. */
function offPins(world: object, cloth: number, pins: number[], m: ArrayLike<number>, now: ReturnType<typeof pose>): number {
  const P = getClothComponents(world).Pin
  const pos = getClothState(world, cloth).pos
  const [qx, qy, qz, qw] = now.q
  let worst = 0
  for (const pin of pins) {
    const i = 3 * P.particle[pin]
    const x = pos[i], y = pos[i + 1], z = pos[i + 2]
    const dx = m[0] * x + m[4] * y + m[8] * z + m[12],
      dy = m[1] * x + m[5] * y + m[9] * z + m[13],
      dz = m[2] * x + m[6] * y + m[10] * z + m[14]
    // where the pin holds it: p + q·(s ⊙ offset)
    const vx = now.s[0] * P.ox[pin], vy = now.s[1] * P.oy[pin], vz = now.s[2] * P.oz[pin]
    const tx = 2 * (qy * vz - qz * vy), ty = 2 * (qz * vx - qx * vz), tz = 2 * (qx * vy - qy * vx)
    const hx = now.p[0] + vx + qw * tx + (qy * tz - qz * ty)
    const hy = now.p[1] + vy + qw * ty + (qz * tx - qx * tz)
    const hz = now.p[2] + vz + qw * tz + (qx * ty - qy * tx)
    worst = Math.max(worst, Math.hypot(dx - hx, dy - hy, dz - hz))
  }
  return worst
}

describe('getClothDrawTransform', () => {
  for (const growth of [0, 0.25]) {
    it(`at 144 Hz, with the anchor turning${growth > 0 ? ' and growing' : ''}, the drawn pinned row is where the pins hold it now${growth > 0 ? ' but for the scale change within a step' : ''} (up to a step off undrawn)`, () => {
      for (const inertia of [false, true]) {
        const { world, hero, cloth, pins } = scene()
        if (inertia) setClothInertia(world, cloth, { linear: 0.5, angular: 0.5 }) // the anchor: the frame
        const m = new Float64Array(16), identity = Array.from({ length: 16 }, (_, j) => (j % 5 === 0 ? 1 : 0))
        let t = 0, drawn = 0, raw = 0
        for (let f = 0; f < 288; f++) {
          t += 1 / 144
          const now = pose(t, growth)
          setTransform(world, hero, now.p, now.q, now.s)
          stepCloth(world, 1 / 144)
          drawn = Math.max(drawn, offPins(world, cloth, pins, getClothDrawTransform(world, cloth, m), now))
          raw = Math.max(raw, offPins(world, cloth, pins, identity, now))
        }
        expect(raw).toBeGreaterThan(0.02) // (up to a step of 3 m/s: 5 cm)
        // growing: the pins (0.25 m from the anchor at most) move with a step's scale change, 0.25/60
        expect(drawn).toBeLessThan(growth === 0 ? 1e-6 : 0.3 * (growth / 60))
      }
    })
  }

  it('a character growing from 0.01 to 1 in 0.5 s: the drawn cloth keeps its size (drawn scaled with it, it was 3.9 m long)', () => {
    // the hero's origin at its feet, the cape pinned at the shoulders: shrunk to 0.01, settled, then grown
    const world = makeWorld({ sleep: false })
    const hero = addEntity(world)
    setTransform(world, hero, [0, 0, 0])
    const cloth = createCloth(world, { width: 0.55, height: 1.05, resolution: [8, 12], position: [0, 1.47, -0.2], material: 'wool' })
    pinRow(world, cloth, 0, hero)
    for (let f = 0; f < 120; f++) stepCloth(world, 1 / 60)
    setTransform(world, hero, [0, 0, 0], [0, 0, 0, 1], [0.01, 0.01, 0.01])
    for (let f = 0; f < 120; f++) stepCloth(world, 1 / 60)
    const m = new Float64Array(16)
    const c = getClothState(world, cloth)
    let t = 0, farthest = 0
    for (let f = 0; f < 144; f++) {
      t += 1 / 144
      const s = Math.min(1, 0.01 + 2 * t)
      setTransform(world, hero, [0, 0, 0], [0, 0, 0, 1], [s, s, s])
      stepCloth(world, 1 / 144)
      getClothDrawTransform(world, cloth, m)
      // the drawn particles' distance from the collar's middle (where the pins hold it now)
      for (let i = 0; i < c.count; i++) {
        const x = c.pos[3 * i], y = c.pos[3 * i + 1], z = c.pos[3 * i + 2]
        const d = [0, 1, 2].map((r) => m[r] * x + m[4 + r] * y + m[8 + r] * z + m[12 + r])
        farthest = Math.max(farthest, Math.hypot(d[0], d[1] - 1.47 * s, d[2] + 0.2 * s))
      }
    }
    expect(farthest).toBeLessThan(1.3) // the cape: 1.05 m long, 0.55 m wide
  })

  it('teleportCloth with its character on a frame that runs no step (144 Hz): the drawn pinned row stays on the pins, turned too', () => {
    // (the draw transform measured from the anchor's pose at the last step, which the mesh no
    // longer showed: the cape was drawn moved twice, 10 m off its pins, until the next step; found
    // by a hunt)
    for (const turn of [0, 1]) {
      const { world, hero, cloth, pins } = scene()
      const m = new Float64Array(16)
      let t = 0, worst = 0, teleported = false
      for (let f = 0; f < 144; f++) {
        t += 1 / 144
        const now = pose(t, 0)
        // from 0.5 s the hero is 10 m along x and turned by `turn` rad about its own position
        const jumped = t >= 0.5
        if (jumped) {
          now.p[0] += 10
          now.q = yawQuat(0.8 * t + turn)
        }
        setTransform(world, hero, now.p, now.q)
        // the jump on a frame that runs no step (one frame in 2.4 runs one at 144 Hz)
        if (jumped && !teleported && getClothWorld(world).accumulator + 1 / 144 < 1 / 60 - 1e-9) {
          teleported = true
          teleportCloth(world, cloth, [10, 0, 0], yawQuat(turn), pose(t, 0).p)
        }
        if (jumped && !teleported) setTransform(world, hero, pose(t, 0).p, yawQuat(0.8 * t)) // (wait for such a frame)
        stepCloth(world, 1 / 144)
        if (teleported) worst = Math.max(worst, offPins(world, cloth, pins, getClothDrawTransform(world, cloth, m), now))
      }
      expect(teleported).toBe(true)
      expect(worst).toBeLessThan(1e-6)
    }
  })

  it('saved, teleported with its character on a frame that runs no step, then rolled back (Transform and snapshot): drawn on its pins', () => {
    // (the pose the teleport carried outlived the restore: drawn 10 m off its pins; found by a hunt)
    const { world, hero, cloth, pins } = scene()
    const m = new Float64Array(16)
    let t = 0
    for (let f = 0; f < 40; f++) {
      t += 1 / 144
      setTransform(world, hero, pose(t, 0).p, pose(t, 0).q)
      stepCloth(world, 1 / 144)
    }
    while (getClothWorld(world).accumulator + 1 / 144 >= 1 / 60 - 1e-9) {
      t += 1 / 144
      setTransform(world, hero, pose(t, 0).p, pose(t, 0).q)
      stepCloth(world, 1 / 144)
    }
    const saved = saveClothState(world, cloth), at = pose(t, 0)
    const jumped = { ...at, p: [at.p[0] + 10, at.p[1], at.p[2]] as [number, number, number] }
    setTransform(world, hero, jumped.p, jumped.q)
    teleportCloth(world, cloth, [10, 0, 0])
    expect(offPins(world, cloth, pins, getClothDrawTransform(world, cloth, m), jumped)).toBeLessThan(1e-6)
    setTransform(world, hero, at.p, at.q)
    restoreClothState(world, cloth, saved)
    expect(offPins(world, cloth, pins, getClothDrawTransform(world, cloth, m), at)).toBeLessThan(1e-6)
  })

  it('pipelined by a frame (animate → beginClothStep → draw → endClothStep), the drawn pinned row is on the pins too', () => {
    const { world, hero, cloth, pins } = scene()
    const m = new Float64Array(16)
    stepCloth(world, 1 / 60)
    getClothState(world, cloth) // (read once outside a frame)
    let t = 0, drawn = 0
    for (let f = 0; f < 60; f++) {
      t += 1 / 60
      const now = pose(t, 0)
      setTransform(world, hero, now.p, now.q, now.s)
      beginClothStep(world, 1 / 60)
      drawn = Math.max(drawn, offPins(world, cloth, pins, getClothDrawTransform(world, cloth, m), now))
      endClothStep(world)
    }
    expect(drawn).toBeLessThan(1e-6)
  })

  it('pipelined, a far cloth the budget steps every 4th step, and one hidden near and shown far (thawed into that level): on the pins every frame', () => {
    // (with a frame open, a far cloth running the step in flight was drawn from the world's last
    // step, not its own: 150 mm behind its pins every 4th frame at 3 m/s; a cape thawed into a far
    // level sat out 3 more steps, drawn 3 m off its character; found by a hunt)
    for (const pipelined of [false, true]) {
      const { world, hero, cloth, pins } = scene()
      const camera = addEntity(world)
      setTransform(world, camera, [0, 2, 0])
      setClothBudget(world, {
        viewer: camera,
        near: 5,
        far: 20,
        farStepEvery: 4,
        calibration: { nsPerParticle: 10, nsPerProjection: 10, nsPerColliderTest: 10, nsPerClothSubstep: 100, nsPerWindTriangle: 10 },
        adapt: false,
      })
      const m = new Float64Array(16)
      stepCloth(world, 1 / 60)
      let t = 0, drawn = 0, sat = 0
      for (let f = 0; f < 120; f++) {
        t += 1 / 60
        const now = pose(t, 0)
        setTransform(world, hero, now.p, now.q, now.s)
        setTransform(world, camera, [now.p[0], 2, f >= 60 ? 40 : 0]) // near for the hidden second, far when shown
        if (f === 30) setClothVisible(world, cloth, false)
        if (f === 60) setClothVisible(world, cloth, true)
        if (pipelined) beginClothStep(world, 1 / 60)
        else stepCloth(world, 1 / 60)
        if (f >= 60 && getClothLod(world, cloth).stepEvery === 4) sat++
        drawn = Math.max(drawn, offPins(world, cloth, pins, getClothDrawTransform(world, cloth, m), now))
        if (pipelined) endClothStep(world)
      }
      expect(sat).toBeGreaterThan(50) // (it did run at the far level)
      expect(drawn).toBeLessThan(1e-6)
    }
  })

  it('is the identity for a cloth without an anchor, and for one whose anchor lost its Transform; checks its out array', () => {
    const { world, hero, cloth } = scene()
    const free = createCloth(world, { width: 0.5, height: 0.5, resolution: 4, position: [5, 2, 0] })
    const m = new Float64Array(16).fill(7)
    const identity = Array.from({ length: 16 }, (_, j) => (j % 5 === 0 ? 1 : 0))
    expect(Array.from(getClothDrawTransform(world, free, m))).toEqual(identity)
    setTransform(world, hero, [1, 1.6, 0])
    stepCloth(world, 1 / 144) // no step: the hero moved 1 m since the last
    expect(getClothDrawTransform(world, cloth, m)[12]).toBeCloseTo(1, 12)
    expect(() => getClothDrawTransform(world, cloth, new Float64Array(15))).toThrow(ClothError)
    expect(() => getClothDrawTransform(world, cloth, null as never)).toThrow(ClothError)
  })
})

describe('updateClothDrawMatrix (three.js)', () => {
  it("sets the object's matrix to the draw transform and stops three from overwriting it", () => {
    const { world, hero, cloth } = scene()
    const mesh = createClothMesh(world, cloth)
    setTransform(world, hero, [0.5, 1.6, 0])
    stepCloth(world, 1 / 144)
    updateClothGeometry(world, cloth, mesh.geometry)
    expect(updateClothDrawMatrix(world, cloth, mesh)).toBe(mesh)
    expect(mesh.matrixAutoUpdate).toBe(false)
    expect(Array.from(mesh.matrix.elements)).toEqual(Array.from(getClothDrawTransform(world, cloth, new Float64Array(16))))
    expect(mesh.matrix.elements[12]).toBeCloseTo(0.5, 12)
    expect(() => updateClothDrawMatrix(world, cloth, {} as Object3D)).toThrow(ClothError)
    expect(() => updateClothDrawMatrix(world, cloth, new Mesh())).not.toThrow()
  })
})

describe('a cape spawned on a running character', () => {
  /**
   * The hero runs along x at 5 m/s; at frame `spawn` the game animates it, then creates a cape
   * where the hero is now and pins its top row to it, then steps. Per frame after: the pinned row
   * drawn (mesh × draw transform) against where it was placed, carried with the hero (mm), and
   * the row's mesh against the hero's Transform at its last step (mm): where the pins hold it.
   */
  function spawnRun(hz: number, tracked: boolean, far: boolean) {
    const w = makeWorld({ sleep: false })
    const hero = addEntity(w), cam = addEntity(w)
    setTransform(w, hero, [0, 0, 0])
    setTransform(w, cam, [0, 1.6, far ? 60 : 0])
    if (far) setClothBudget(w, { viewer: cam, near: 5, far: 20, farStepEvery: 4 })
    // (a collider on the hero tracks it from the start, as the README's character recipe does)
    if (tracked) addSphereCollider(w, addEntity(w), { body: hero, radius: 0.1, offset: [0, 3, 0] })
    const m = new Float64Array(16)
    let t = 0, cape = -1, drawn = 0
    for (let f = 0; f < 50; f++) {
      t += 1 / hz
      const x = 5 * t
      setTransform(w, hero, [x, 0, 0])
      if (f === 30) {
        cape = createCloth(w, { width: 0.5, height: 1, resolution: [6, 10], position: [x, 1.47, -0.2] })
        pinRow(w, cape, 0, hero)
      }
      stepCloth(w, 1 / hz)
      if (cape < 0) continue
      getClothDrawTransform(w, cape, m)
      const p = getClothMesh(w, cape).positions
      for (let i = 0; i < 6; i++) {
        const at = m[0] * p[3 * i] + m[4] * p[3 * i + 1] + m[8] * p[3 * i + 2] + m[12]
        drawn = Math.max(drawn, Math.abs(at - (x - 0.25 + 0.1 * i)))
      }
    }
    return 1000 * drawn
  }
  it('is pinned where it was placed and drawn there from its spawn frame, tracked or not, at 60 and 144 Hz, near and far (it sat 83 mm ahead for good, 111 mm at 144 Hz; far, 167 mm off before its first step)', () => {
    for (const hz of [60, 144]) {
      for (const tracked of [false, true]) {
        for (const far of [false, true]) expect(spawnRun(hz, tracked, far), `${hz} Hz, tracked ${tracked}, far ${far}`).toBeLessThan(1e-3)
      }
    }
  })
})

describe('a cloth spawned on a running character, set up in other orders', () => {
  /**
   * A hero (tracked: a collider on it) and a hip bone run at 5 m/s; at frame 30 a cape is created
   * where they are now and set up in `order`; the worst stretch 0.5–1 s after, and where a particle
   * pinned in place (world) ends against where it was placed.
   */
  function spawn(order: 'skinFirst' | 'pinsThenSkin' | 'worldPinAfter' | 'repinned' | 'hipAfterSettings' | 'frameHeld') {
    const COLS = 8, ROWS = 12, n = COLS * ROWS
    const w = makeWorld({ sleep: false })
    const hero = addEntity(w), hip = addEntity(w)
    setTransform(w, hero, [0, 1.5, 0])
    setTransform(w, hip, [0, 1.0, 0])
    addSphereCollider(w, addEntity(w), { body: hero, radius: 0.05, offset: [0, 3, 0] })
    const u = (i: number) => Math.floor(i / COLS) / (ROWS - 1)
    let cape = -1, stretch = 0, placed = 0
    const character = () => {
      setClothInertia(w, cape, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5 })
      setClothSkinning(w, cape, {
        bones: [hero, hip],
        joints: Array.from({ length: 4 * n }, (_, k) => (k % 4 === 1 ? 1 : 0)),
        weights: Array.from({ length: 4 * n }, (_, k) => (k % 4 === 0 ? 1 - u(k >> 2) : k % 4 === 1 ? u(k >> 2) : 0)),
      })
      setClothMotionConstraints(w, cape, {
        maxDistance: Array.from({ length: n }, (_, i) => (Math.floor(i / COLS) === 1 ? 0 : 0.9 * u(i) ** 2)),
      })
    }
    for (let f = 0; f < 90; f++) {
      const x = (5 * f) / 60
      setTransform(w, hero, [x, 1.5, 0])
      setTransform(w, hip, [x, 1.0, 0])
      if (f === 30) {
        cape = createCloth(w, { width: 0.5, height: 0.9, resolution: [COLS, ROWS], position: [x, 1.05, -0.15], material: 'wool' })
        placed = getClothState(w, cape).pos[3 * (n - 1)]
        if (order === 'skinFirst' || order === 'frameHeld') character()
        if (order !== 'frameHeld') pinRow(w, cape, 0, hero) // (held by its settings alone: max distance 0 at the top rows)
        if (order === 'repinned') {
          for (let k = 0; k < 3; k++) {
            for (const pin of getPins(w, cape)) unpin(w, pin)
            pinRow(w, cape, 0, hero)
          }
        }
        if (order === 'pinsThenSkin' || order === 'repinned' || order === 'hipAfterSettings') character()
        if (order === 'hipAfterSettings') pinParticle(w, cape, n - 1, hip)
        if (order === 'worldPinAfter') {
          pinParticle(w, cape, n - 1) // the hem's corner held in place as well
        }
      }
      stepCloth(w, 1 / 60)
      if (f >= 60 && order !== 'worldPinAfter') stretch = Math.max(stretch, getClothStretch(w, cape).max)
    }
    // the collar's first particle against where it was placed, carried with the hero (−0.25 m from it)
    const collarOff = Math.abs(getClothState(w, cape).pos[0] - ((5 * 89) / 60 - 0.25))
    return { stretch, collarOff, worldPinOff: order === 'worldPinAfter' ? Math.abs(getClothState(w, cape).pos[3 * (n - 1)] - placed) : 0 }
  }
  it('skinned before its pins, or after: whole (a first cut moved the cloth but not its skinned rest shape: 42.7 % for good); a world pin after an entity pin holds where placed (83 mm off)', () => {
    expect(spawn('skinFirst').stretch).toBeLessThan(0.05) // measured 2.1 %
    expect(spawn('pinsThenSkin').stretch).toBeLessThan(0.05)
    expect(spawn('worldPinAfter').worldPinOff).toBeLessThan(1e-3)
  })
  it('unpinned and pinned again three times, given a pin on the hip after its settings, or held by its settings alone: its collar where placed (moved back at every pin: 250 mm; the hip pin undid the move under the settings: 83 mm off its reference; settings alone bound it at the last step: 83 mm)', () => {
    for (const order of ['pinsThenSkin', 'repinned', 'hipAfterSettings', 'frameHeld'] as const) {
      const r = spawn(order)
      expect(r.collarOff, order).toBeLessThan(1e-3)
    }
  })
})
