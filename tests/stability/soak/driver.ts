// A seeded random game session (soak.test.ts): capes on running, turning, jumping, teleporting
// heroes (some with inertia and motion limits), a flag in turbulent and gusty zones, a tearing
// sheet, grabs, colliders added and removed, cloths created and removed (ids recycled), budget and
// LOD changes, snapshots saved and restored, sleep, teleportCloth, frames of 0 to 1 s. The script is
// plain data made from the seed alone, then run, so a failing run can be shrunk by deleting actions
// or frames. SOAK_FSE=1 lets budget changes pick farStepEvery 2 or 4.
import { addEntity, createWorld, removeEntity } from 'bitecs'
import {
  ClothError,
  addBoxCollider,
  addCapsuleCollider,
  addPlaneCollider,
  addSphereCollider,
  createCloth,
  createWindZone,
  getClothState,
  getClothStats,
  getClothStretch,
  grabParticle,
  gustWind,
  installClothPlugin,
  isGrabActive,
  makeTearable,
  moveGrab,
  pinParticle,
  pinRow,
  releaseGrab,
  removeCloth,
  removeCollider,
  restoreClothState,
  saveClothState,
  setClothBudget,
  setClothInertia,
  setClothMotionConstraints,
  setClothCollision,
  setClothSleep,
  setClothVisible,
  setTransform,
  setWindZone,
  stepCloth,
  teleportCloth,
  wakeCloth,
  type ClothSnapshot,
} from '../../../src/index'
import { getClothWorld } from '../../../src/world/access'
import { rng } from '../../helpers'

export type Action =
  | { k: 'mode'; ch: number; mode: 'stand' | 'run' | 'turn' | 'jump' | 'teleport' | 'snap' }
  | { k: 'capeRespawn'; ch: number; character: boolean; tear: boolean }
  | { k: 'capeRemove'; ch: number }
  | { k: 'extraSpawn'; slot: number; x: number; z: number; res: number; pinned: boolean; material: string }
  | { k: 'extraRemove'; slot: number }
  | { k: 'colAdd'; slot: number; shape: 0 | 1 | 2; x: number; y: number; z: number; r: number; body: number }
  | { k: 'colMove'; slot: number; x: number; y: number; z: number }
  | { k: 'colRemove'; slot: number }
  | { k: 'grab'; slot: number; target: number; frac: number; dx: number; dy: number; dz: number }
  | { k: 'grabMove'; slot: number; dx: number; dy: number; dz: number }
  | { k: 'grabRelease'; slot: number }
  | { k: 'budget'; on: boolean; near: number; far: number; cull: number; ms: number; farStepEvery: 1 | 2 | 4 }
  | { k: 'viewer'; x: number; z: number }
  | { k: 'visible'; target: number; visible: boolean }
  | { k: 'save' }
  | { k: 'restore' }
  | { k: 'sleep'; target: number; on: boolean }
  | { k: 'wake'; target: number }
  | { k: 'gust'; strength: number; duration: number }
  | { k: 'wind'; strength: number; turbulence: number }
  | { k: 'teleportCloth'; target: number; dx: number; dz: number }
  | { k: 'tearSheetPull'; amount: number }

export interface Frame {
  dt: number
  actions: Action[]
}

export const NCH = 3
export const NEXTRA = 4
export const NCOL = 4
export const NGRAB = 3
// cloth targets: 0..2 capes, 3 flag, 4 sheet, 5..8 extras
export const NTARGET = 5 + NEXTRA

export function generateScript(seed: number, frames: number, intensity = 1): Frame[] {
  const r = rng(seed)
  const pick = <T>(a: readonly T[]): T => a[Math.floor(r() * a.length)]
  const out: Frame[] = []
  const p = (x: number) => r() < x * intensity
  for (let f = 0; f < frames; f++) {
    let dt: number
    const u = r()
    if (u < 0.01) dt = 0
    else if (u < 0.015) dt = 1
    else dt = 1 / 240 + r() * (1 / 10 - 1 / 240)
    if (r() < 0.6) dt = pick([1 / 60, 1 / 144, 1 / 30, 1 / 120])
    const actions: Action[] = []
    for (let ch = 0; ch < NCH; ch++)
      if (p(0.01)) actions.push({ k: 'mode', ch, mode: pick(['stand', 'run', 'turn', 'jump', 'teleport', 'snap'] as const) })
    if (p(0.002)) actions.push({ k: 'capeRespawn', ch: Math.floor(r() * NCH), character: r() < 0.6, tear: r() < 0.3 })
    if (p(0.001)) actions.push({ k: 'capeRemove', ch: Math.floor(r() * NCH) })
    if (p(0.006))
      actions.push({
        k: 'extraSpawn',
        slot: Math.floor(r() * NEXTRA),
        x: -6 + 12 * r(),
        z: -6 + 12 * r(),
        res: 3 + Math.floor(r() * 6),
        pinned: r() < 0.6,
        material: pick(['silk', 'cotton', 'leather', 'rubber', 'chainmail']),
      })
    if (p(0.005)) actions.push({ k: 'extraRemove', slot: Math.floor(r() * NEXTRA) })
    if (p(0.006))
      actions.push({
        k: 'colAdd',
        slot: Math.floor(r() * NCOL),
        shape: pick([0, 1, 2] as const),
        x: -4 + 8 * r(),
        y: 0.2 + 2 * r(),
        z: -4 + 8 * r(),
        r: 0.05 + 0.4 * r(),
        body: r() < 0.3 ? Math.floor(r() * NCH) : -1,
      })
    if (p(0.05)) actions.push({ k: 'colMove', slot: Math.floor(r() * NCOL), x: -4 + 8 * r(), y: 0.2 + 2 * r(), z: -4 + 8 * r() })
    if (p(0.004)) actions.push({ k: 'colRemove', slot: Math.floor(r() * NCOL) })
    if (p(0.01))
      actions.push({
        k: 'grab',
        slot: Math.floor(r() * NGRAB),
        target: Math.floor(r() * NTARGET),
        frac: r(),
        dx: r() - 0.5,
        dy: r() - 0.5,
        dz: r() - 0.5,
      })
    if (p(0.3))
      actions.push({ k: 'grabMove', slot: Math.floor(r() * NGRAB), dx: 0.4 * (r() - 0.5), dy: 0.4 * (r() - 0.5), dz: 0.4 * (r() - 0.5) })
    if (p(0.008)) actions.push({ k: 'grabRelease', slot: Math.floor(r() * NGRAB) })
    if (p(0.003))
      actions.push({
        k: 'budget',
        on: r() < 0.7,
        near: 1 + 8 * r(),
        far: 10 + 30 * r(),
        cull: r() < 0.5 ? 1e6 : 15 + 30 * r(),
        ms: r() < 0.5 ? 0 : 0.05 + 2 * r(),
        farStepEvery: (process.env.SOAK_FSE ? pick([1, 2, 4] as const) : 1) as 1 | 2 | 4,
      })
    if (p(0.02)) actions.push({ k: 'viewer', x: -30 + 60 * r(), z: -30 + 60 * r() })
    if (p(0.003)) actions.push({ k: 'visible', target: Math.floor(r() * NTARGET), visible: r() < 0.6 })
    if (p(0.004)) actions.push({ k: 'save' })
    if (p(0.003)) actions.push({ k: 'restore' })
    if (p(0.003)) actions.push({ k: 'sleep', target: Math.floor(r() * NTARGET), on: r() < 0.7 })
    if (p(0.003)) actions.push({ k: 'wake', target: Math.floor(r() * NTARGET) })
    if (p(0.003)) actions.push({ k: 'gust', strength: 2 + 10 * r(), duration: 0.2 + 2 * r() })
    if (p(0.002)) actions.push({ k: 'wind', strength: 12 * r(), turbulence: r() })
    if (p(0.002)) actions.push({ k: 'teleportCloth', target: Math.floor(r() * NTARGET), dx: 20 * (r() - 0.5), dz: 20 * (r() - 0.5) })
    if (p(0.01)) actions.push({ k: 'tearSheetPull', amount: 0.6 * r() })
    out.push({ dt, actions })
  }
  return out
}

export interface FrameRecord {
  frame: number
  dt: number
  ms: number
  steps: number
  actions: string
}

export interface Violation {
  frame: number
  what: string
  detail: string
}

export interface SoakResult {
  hashes: string[]
  violations: Violation[]
  records: FrameRecord[]
  worstStretch: { value: number; frame: number; target: number; torn: boolean }
  stretchByTarget: number[]
  resets: number
  errors: string[]
  tears: number
}

function fnv(h: number, a: ArrayBufferView): number {
  const b = new Uint8Array(a.buffer, a.byteOffset, a.byteLength)
  for (let i = 0; i < b.length; i++) {
    h ^= b[i]
    h = Math.imul(h, 0x01000193)
  }
  return h
}

export interface RunOptions {
  checkPins?: boolean
  hash?: boolean
  stretchBound?: number
  timing?: boolean
  onFrame?: (f: number, world: object) => void
  sleep?: boolean
  threads?: number
  /** replaces the stepCloth call (to measure around it) */
  step?: (world: object, dt: number, f: number) => void
  /** keep no per-frame records or hashes (memory runs) */
  lean?: boolean
}

export function runScript(script: Frame[], o: RunOptions = {}): SoakResult {
  const world = installClothPlugin(createWorld(), {
    sleep: o.sleep === false ? false : { speed: 0.01, delay: 1 },
    ...(o.threads ? { threads: o.threads } : {}),
  })
  const stretchBound = o.stretchBound ?? 1.5
  const res: SoakResult = {
    hashes: [],
    violations: [],
    records: [],
    worstStretch: { value: 0, frame: -1, target: -1, torn: false },
    stretchByTarget: new Array(NTARGET).fill(0),
    resets: 0,
    errors: [],
    tears: 0,
  }
  const ground = addEntity(world)
  setTransform(world, ground, [0, 0, 0])
  addPlaneCollider(world, ground)
  const heroes: number[] = []
  const mode: string[] = []
  const hp: number[][] = [] // x y z yaw vy
  for (let ch = 0; ch < NCH; ch++) {
    const h = addEntity(world)
    setTransform(world, h, [3 * ch, 0, 0])
    heroes.push(h)
    mode.push('stand')
    hp.push([3 * ch, 0, 0, 0, 0])
    const torso = addEntity(world)
    addCapsuleCollider(world, torso, { body: h, offset: [0, 1.15, 0], radius: 0.19, halfHeight: 0.22, layer: 2 << ch })
  }
  const viewer = addEntity(world)
  setTransform(world, viewer, [0, 2, 8])
  // targets: cloth ids per slot, 0 = none; gen counts instances
  const target: number[] = new Array(NTARGET).fill(0)
  const gen: number[] = new Array(NTARGET).fill(0)
  const tearable: boolean[] = new Array(NTARGET).fill(false)
  const makeCape = (ch: number, character: boolean, tear: boolean) => {
    const h = heroes[ch]
    const [x, y, z] = hp[ch]
    const cape = createCloth(world, {
      width: 0.55,
      height: 1.0,
      resolution: [7, 11],
      position: [x, y + 1.47, z - 0.25],
      material: 'wool',
      substeps: 4,
    })
    pinRow(world, cape, 0, h)
    setClothCollision(world, cape, { mask: 1 | (2 << ch) }) // its own body, the ground and the free colliders
    if (character) {
      setClothInertia(world, cape, {
        frame: h,
        linear: 0.5,
        angular: 0.5,
        centrifugal: 0.5,
        teleport: { mode: ch % 2 ? 'reset' : 'keep', angle: Math.PI / 2 },
      })
      const md = Array.from({ length: 77 }, (_, i) => {
        const u = Math.floor(i / 7) / 10
        return u === 1 ? Infinity : 0.9 * u * u
      })
      setClothMotionConstraints(world, cape, { maxDistance: md, backstop: { distance: 0.02, radius: 0.5 } })
    }
    if (tear) makeTearable(world, cape, { strain: 0.5 })
    target[ch] = cape
    gen[ch]++
    tearable[ch] = tear
  }
  for (let ch = 0; ch < NCH; ch++) makeCape(ch, ch !== 2, false)
  // flag on a pole in wind zones
  const pole = addEntity(world)
  setTransform(world, pole, [-5, 2, 0])
  const flag = createCloth(world, {
    width: 1.2,
    height: 0.8,
    resolution: [12, 8],
    position: [-4.4, 2.4, 0],
    material: 'nylon',
    substeps: 8,
  })
  for (let row = 0; row < 8; row++) pinParticle(world, flag, row * 12, pole)
  setClothCollision(world, flag, { mask: 1 })
  target[3] = flag
  gen[3]++
  const globalWind = createWindZone(world, { direction: [1, 0, 0.3], strength: 2, turbulence: 0.3, seed: 7 })
  const box = createWindZone(world, {
    shape: 'box',
    position: [-4.5, 2, 0],
    size: [3, 3, 3],
    falloff: 1,
    direction: [1, 0, 0],
    strength: 6,
    turbulence: 0.4,
  })
  // tearable sheet on two bars
  const barL = addEntity(world), barR = addEntity(world)
  setTransform(world, barL, [5, 2, 3])
  setTransform(world, barR, [5, 2, 3])
  const sheet = createCloth(world, { width: 1, height: 1, resolution: 10, position: [5, 2.5, 3], material: 'cotton', substeps: 4 })
  for (let row = 0; row < 10; row++) {
    pinParticle(world, sheet, row * 10, barL)
    pinParticle(world, sheet, row * 10 + 9, barR)
  }
  makeTearable(world, sheet, { strain: 0.3, maxTearsPerStep: 4 })
  setClothCollision(world, sheet, { mask: 1 })
  target[4] = sheet
  gen[4]++
  tearable[4] = true
  let pull = 0
  const colliders: number[] = new Array(NCOL).fill(0)
  const colGoal: (number[] | null)[] = new Array(NCOL).fill(null)
  const colPos: number[][] = Array.from({ length: NCOL }, () => [0, 0, 0])
  const colFree: boolean[] = new Array(NCOL).fill(false)
  const grabs: number[] = new Array(NGRAB).fill(0)
  const grabPt: number[][] = Array.from({ length: NGRAB }, () => [0, 0, 0])
  let saved: { slot: number; cloth: number; gen: number; snap: ClothSnapshot }[] | null = null
  let savedFrame = -1
  let savedGame: string | null = null
  const tearsAt: number[] = new Array(NTARGET).fill(0)

  const guarded = (what: string, f: number, fn: () => void) => {
    try {
      fn()
    } catch (e) {
      if (e instanceof ClothError) {
        res.errors.push(`frame ${f} ${what}: ClothError(${e.argument}) ${e.message.slice(0, 160)}`)
      } else {
        res.violations.push({ frame: f, what: 'non-ClothError', detail: `${what}: ${(e as Error)?.stack?.slice(0, 600)}` })
      }
    }
  }
  let resetsSeen = 0
  const tmpStretch = { mean: 0, max: 0 }
  let lastSteps = 0
  for (let f = 0; f < script.length; f++) {
    const fr = script[f]
    const names: string[] = []
    for (const a of fr.actions) {
      if (a.k !== 'grabMove' && a.k !== 'colMove' && a.k !== 'viewer') names.push(JSON.stringify(a))
      guarded(a.k, f, () => {
        switch (a.k) {
          case 'mode': {
            mode[a.ch] = a.mode
            if (a.mode === 'jump' && hp[a.ch][1] <= 0) hp[a.ch][4] = 4
            if (a.mode === 'teleport') {
              hp[a.ch][0] += 15
              hp[a.ch][2] -= 7
              mode[a.ch] = 'stand'
            }
            if (a.mode === 'snap') {
              hp[a.ch][3] += Math.PI
              mode[a.ch] = 'stand'
            }
            break
          }
          case 'capeRespawn':
            if (target[a.ch]) removeCloth(world, target[a.ch])
            target[a.ch] = 0
            makeCape(a.ch, a.character, a.tear)
            break
          case 'capeRemove':
            if (target[a.ch]) removeCloth(world, target[a.ch])
            target[a.ch] = 0
            break
          case 'extraSpawn': {
            const s = 5 + a.slot
            if (target[s]) removeCloth(world, target[s])
            target[s] = 0
            const c = createCloth(world, {
              width: 0.8,
              height: 0.8,
              resolution: a.res,
              position: [a.x, 2.5, a.z],
              material: a.material,
              substeps: 2 + (a.res % 3) * 2,
            })
            if (a.pinned) pinRow(world, c, 0)
            setClothCollision(world, c, { mask: 1 })
            target[s] = c
            gen[s]++
            tearable[s] = false
            break
          }
          case 'extraRemove': {
            const s = 5 + a.slot
            if (target[s]) removeCloth(world, target[s])
            target[s] = 0
            break
          }
          case 'colAdd': {
            if (colliders[a.slot]) removeEntity(world, colliders[a.slot])
            colliders[a.slot] = 0
            const e = addEntity(world)
            colliders[a.slot] = e
            colFree[a.slot] = false
            if (a.body >= 0) {
              addSphereCollider(world, e, { body: heroes[a.body], offset: [0, 0.6, 0.3], radius: a.r, layer: 2 << a.body })
            } else {
              setTransform(world, e, [a.x, a.y, a.z])
              colPos[a.slot] = [a.x, a.y, a.z]
              colGoal[a.slot] = null
              colFree[a.slot] = true
              if (a.shape === 0) addSphereCollider(world, e, { radius: a.r })
              else if (a.shape === 1) addCapsuleCollider(world, e, { radius: a.r * 0.5, halfHeight: a.r })
              else addBoxCollider(world, e, { halfExtents: [a.r, a.r * 0.5, a.r] })
            }
            break
          }
          case 'colMove':
            if (colliders[a.slot] && hp.length) {
              // bodies on heroes move with them; free ones are moved
              colGoal[a.slot] = [a.x, a.y, a.z]
            }
            break
          case 'colRemove':
            if (colliders[a.slot]) removeCollider(world, colliders[a.slot])
            if (colliders[a.slot]) removeEntity(world, colliders[a.slot])
            colliders[a.slot] = 0
            break
          case 'grab': {
            const c = target[a.target]
            if (!c) break
            if (grabs[a.slot] && isGrabActive(world, grabs[a.slot])) releaseGrab(world, grabs[a.slot])
            const st = getClothState(world, c)
            const i = Math.min(st.count - 1, Math.floor(a.frac * st.count))
            const pt = [st.pos[3 * i] + a.dx, st.pos[3 * i + 1] + a.dy, st.pos[3 * i + 2] + a.dz]
            grabs[a.slot] = grabParticle(world, c, i, pt)
            grabPt[a.slot] = pt
            break
          }
          case 'grabMove':
            if (grabs[a.slot] && isGrabActive(world, grabs[a.slot])) {
              const pt = grabPt[a.slot]
              pt[0] += a.dx
              pt[1] = Math.max(-1, Math.min(5, pt[1] + a.dy))
              pt[2] += a.dz
              moveGrab(world, grabs[a.slot], pt)
            }
            break
          case 'grabRelease':
            if (grabs[a.slot] && isGrabActive(world, grabs[a.slot])) releaseGrab(world, grabs[a.slot])
            grabs[a.slot] = 0
            break
          case 'budget':
            if (!a.on) setClothBudget(world, null)
            else
              setClothBudget(world, {
                viewer,
                near: a.near,
                far: a.far,
                cull: a.cull,
                farStepEvery: a.farStepEvery,
                ...(a.ms > 0 ? { msPerFrame: a.ms } : {}),
                calibration: { nsPerParticle: 20, nsPerProjection: 12, nsPerColliderTest: 5, nsPerClothSubstep: 500 },
                adapt: false,
              })
            break
          case 'viewer':
            setTransform(world, viewer, [a.x, 2, a.z])
            break
          case 'visible':
            if (target[a.target]) setClothVisible(world, target[a.target], a.visible)
            break
          case 'save':
            saved = []
            for (let s = 0; s < NTARGET; s++)
              if (target[s]) saved.push({ slot: s, cloth: target[s], gen: gen[s], snap: saveClothState(world, target[s]) })
            savedFrame = f
            // the game's own state, rewound with the cloths (README: restore your own Transforms too)
            savedGame = JSON.stringify({ hp, mode, colPos, colGoal, pull, grabPt })
            break
          case 'restore':
            if (!saved) break
            {
              const g = JSON.parse(savedGame!)
              for (let ch = 0; ch < NCH; ch++) {
                hp[ch] = g.hp[ch]
                mode[ch] = g.mode[ch]
              }
              for (let k = 0; k < NCOL; k++) {
                colPos[k] = g.colPos[k]
                colGoal[k] = g.colGoal[k]
              }
              for (let k = 0; k < NGRAB; k++) grabPt[k] = g.grabPt[k]
              pull = g.pull
              for (let ch = 0; ch < NCH; ch++)
                setTransform(world, heroes[ch], [hp[ch][0], hp[ch][1], hp[ch][2]], [0, Math.sin(hp[ch][3] / 2), 0, Math.cos(hp[ch][3] / 2)])
            }
            for (const s of saved) {
              if (target[s.slot] === s.cloth && gen[s.slot] === s.gen) {
                try {
                  restoreClothState(world, s.cloth, s.snap)
                } catch (e) {
                  if (e instanceof ClothError) {
                    res.errors.push(
                      `frame ${f} restore slot ${s.slot} (saved ${savedFrame}): ClothError(${e.argument}) ${e.message.slice(0, 120)}`,
                    )
                  } else throw e
                }
              }
            }
            break
          case 'sleep':
            if (target[a.target]) setClothSleep(world, target[a.target], a.on)
            break
          case 'wake':
            if (target[a.target]) wakeCloth(world, target[a.target])
            break
          case 'gust':
            gustWind(world, box, { strength: a.strength, duration: a.duration })
            break
          case 'wind':
            setWindZone(world, globalWind, { strength: a.strength, turbulence: a.turbulence })
            break
          case 'teleportCloth':
            // used as a game would: a cape with its character moved by the same vector; a sheet on world pins alone
            if (a.target < NCH) {
              hp[a.target][0] += a.dx
              hp[a.target][2] += a.dz
              if (target[a.target]) teleportCloth(world, target[a.target], [a.dx, 0, a.dz])
            } else if (a.target >= 5 && target[a.target]) teleportCloth(world, target[a.target], [a.dx, 0, a.dz])
            break
          case 'tearSheetPull':
            pull = a.amount
            break
        }
      })
    }
    // character motion
    const dt = fr.dt
    for (let ch = 0; ch < NCH; ch++) {
      const s = hp[ch]
      const m = mode[ch]
      const speed = m === 'run' ? 4 : m === 'turn' ? 2 : m === 'jump' ? 3 : 0
      if (m === 'turn') s[3] += 3 * dt
      s[0] += Math.sin(s[3]) * speed * dt
      s[2] += Math.cos(s[3]) * speed * dt
      if (s[1] > 0 || s[4] > 0) {
        s[4] -= 9.81 * dt
        s[1] += s[4] * dt
        if (s[1] <= 0) {
          s[1] = 0
          s[4] = 0
        }
      }
      // keep them in a 30 m box
      if (Math.abs(s[0]) > 30) s[0] = -Math.sign(s[0]) * 29
      if (Math.abs(s[2]) > 30) s[2] = -Math.sign(s[2]) * 29
      setTransform(world, heroes[ch], [s[0], s[1], s[2]], [0, Math.sin(s[3] / 2), 0, Math.cos(s[3] / 2)])
    }
    // free colliders glide toward their goals at 2 m/s
    for (let k = 0; k < NCOL; k++) {
      const g = colGoal[k]
      if (!colliders[k] || !colFree[k] || !g) continue
      const p = colPos[k]
      const d = Math.hypot(g[0] - p[0], g[1] - p[1], g[2] - p[2])
      const step = Math.min(d, 2 * dt)
      if (d > 0) { for (let j = 0; j < 3; j++) p[j] += ((g[j] - p[j]) * step) / d }
      setTransform(world, colliders[k], [p[0], p[1], p[2]])
    }
    setTransform(world, barL, [5 - pull, 2, 3])
    setTransform(world, barR, [5 + pull, 2, 3])
    // step
    const t0 = o.timing ? performance.now() : 0
    guarded('stepCloth', f, () => (o.step ? o.step(world, dt, f) : stepCloth(world, dt)))
    const ms = o.timing ? performance.now() - t0 : 0
    const stats = getClothStats(world)
    const lastStepsBefore = lastSteps
    if (!o.lean) res.records.push({ frame: f, dt, ms, steps: stats.steps - lastSteps, actions: names.join(' ') })
    lastSteps = stats.steps
    if (stats.guardResets > resetsSeen) {
      res.violations.push({ frame: f, what: 'guardReset', detail: `${stats.guardResets - resetsSeen} resets; actions ${names.join(' ')}` })
      resetsSeen = stats.guardResets
    }
    // checks
    let h = 0x811c9dc5
    const state = getClothWorld(world)
    for (let s = 0; s < NTARGET; s++) {
      const c = target[s]
      if (!c) continue
      const st = getClothState(world, c)
      if (o.hash !== false) {
        h = fnv(h, st.pos.subarray(0, 3 * st.count))
        h = fnv(h, st.vel.subarray(0, 3 * st.count))
      }
      for (let i = 0; i < 3 * st.count; i++) {
        if (!Number.isFinite(st.pos[i]) || !Number.isFinite(st.vel[i])) {
          res.violations.push({ frame: f, what: 'nonFinite', detail: `slot ${s} cloth ${c} index ${i}` })
          break
        }
      }
      getClothStretch(world, c, tmpStretch)
      const torn = getClothState(world, c).pieceCount > 1 || false
      if (tmpStretch.max > res.stretchByTarget[s]) res.stretchByTarget[s] = tmpStretch.max
      if (tmpStretch.max > res.worstStretch.value) res.worstStretch = { value: tmpStretch.max, frame: f, target: s, torn }
      if (tmpStretch.max > (tearable[s] ? 4 : stretchBound))
        res.violations.push({
          frame: f,
          what: 'stretch',
          detail: `slot ${s} cloth ${c} max ${(100 * tmpStretch.max).toFixed(1)}% tearable ${tearable[s]}`,
        })
      if (tearable[s]) {
        const tc = stats.tears
        res.tears = tc
      }
      // pins hold: particle at the target's pose at the end of the last step (+ offset)
      if (o.checkPins !== false && !st.idle && stats.steps > lastStepsBefore) {
        const P = state.components.Pin
        const k = state.kinematics
        for (const pin of st.pins.list) {
          if (P.blendLeft[pin] > 0) continue
          const i = P.particle[pin]
          const slot = P.slot[pin]
          let wx: number, wy: number, wz: number
          if (slot < 0) {
            wx = P.ox[pin]
            wy = P.oy[pin]
            wz = P.oz[pin]
          } else {
            const b = 7 * slot
            const [px, py, pz, qx, qy, qz, qw] = [
              k.stepTo[b],
              k.stepTo[b + 1],
              k.stepTo[b + 2],
              k.stepTo[b + 3],
              k.stepTo[b + 4],
              k.stepTo[b + 5],
              k.stepTo[b + 6],
            ]
            const sc = k.scaleStepTo
            const ox = P.ox[pin] * sc[3 * slot], oy = P.oy[pin] * sc[3 * slot + 1], oz = P.oz[pin] * sc[3 * slot + 2]
            // rotate (ox,oy,oz) by q
            const tx = 2 * (qy * oz - qz * oy), ty = 2 * (qz * ox - qx * oz), tz = 2 * (qx * oy - qy * ox)
            wx = px + ox + qw * tx + (qy * tz - qz * ty)
            wy = py + oy + qw * ty + (qz * tx - qx * tz)
            wz = pz + oz + qw * tz + (qx * ty - qy * tx)
          }
          const d = Math.hypot(st.pos[3 * i] - wx, st.pos[3 * i + 1] - wy, st.pos[3 * i + 2] - wz)
          if (!(d < 1e-6)) {
            res.violations.push({
              frame: f,
              what: 'pin',
              detail: `slot ${s} cloth ${c} pin ${pin} particle ${i} off by ${d.toExponential(3)} m`,
            })
            break
          }
        }
      }
      void tearsAt
    }
    if (!o.lean) res.hashes.push((h >>> 0).toString(16))
    if (o.lean) {
      if (res.violations.length > 200) res.violations.length = 200
      if (res.errors.length > 200) res.errors.length = 200
    }
    o.onFrame?.(f, world)
  }
  res.resets = resetsSeen
  return res
}
