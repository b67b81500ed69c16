import { addEntity } from 'bitecs'
import * as THREE from 'three'
import {
  beginClothStep,
  endClothStepAsync,
  getClothBudgetStats,
  getClothLod,
  getClothStretch,
  setClothBudget,
  setClothVisible,
  setTransform,
  stepCloth,
  type ClothPluginOptions,
} from '../../src/index'
import { createCape } from '../capeShape'
import { Character, CrowdFigures, Track, type Gait } from '../character'
import { simpleCotton } from '../fabrics'
import { addSegmented, addToggle, type DemoScene } from '../scene'

/** Level-of-detail classes the tint shows, with their colours. */
const LOD_CLASSES: { label: string; color: number }[] = [
  { label: '8+ substeps', color: 0x3fbf4a },
  { label: '4–6', color: 0xc9d13a },
  { label: '2–3', color: 0xf08a24 },
  { label: '1', color: 0xe0352b },
  { label: 'every n-th step', color: 0x9b4fd1 },
  { label: 'frozen', color: 0x7d8590 },
]

function lodClass(lod: { substeps: number; stepEvery: number; frozen: boolean }): number {
  if (lod.frozen) return 5
  if (lod.stepEvery > 1) return 4
  return lod.substeps >= 8 ? 0 : lod.substeps >= 4 ? 1 : lod.substeps >= 2 ? 2 : 3
}

/**
 * Workers that step the crowd's cloths (0: the page's main thread). Kept across reloads of the
 * scene; `?threads=2` starts with them.
 */
let threads = Number(new URLSearchParams(location.search).get('threads') ?? 0) === 2 ? 2 : 0

/** The crowd's world: on `threads` workers (the worker script is built beside the demo's main.js). */
function crowdWorld(): ClothPluginOptions {
  return threads > 0 ? { threads, workerUrl: new URL('./worker.js', import.meta.url).href } : {}
}

/** Rows (collar to hem) and columns of each cape: the cape scene's shaped cape. */
const CAPE_ROWS = 24, CAPE_COLS = 15

/** The budget's distances from the camera: full quality within NEAR, one substep beyond FAR, m. */
const NEAR = 6, FAR = 25

const CAPE_COLOURS = ['#8c1620', '#1f4e8c', '#2f6b3a', '#6b3a8c', '#8c6a1f', '#1f7a7a', '#4a4a52', '#a0522d']
const SHIRTS = [0x3f5a78, 0x7a4a3a, 0x5a6a3a, 0x6a5a7a, 0x8a7a5a, 0x3a6a6a, 0x7a3a4a, 0x5a5a5a]

/** Tracks of the crowd: stadiums round the square, each with its gait, pace and direction. */
const LANES: { radius: number; count: number; gait: Gait; pace: number; direction: 1 | -1 }[] = [
  { radius: 2, count: 8, gait: 'walk', pace: 0.9, direction: 1 },
  { radius: 3.3, count: 10, gait: 'run', pace: 0.75, direction: -1 },
  { radius: 4.6, count: 13, gait: 'walk', pace: 1.1, direction: 1 },
  { radius: 5.9, count: 15, gait: 'walk', pace: 1, direction: -1 },
  { radius: 7.2, count: 18, gait: 'walk', pace: 0.95, direction: 1 },
]

/**
 * A crowd: 64 characters walking and running round a square, each with the cape scene's shaped
 * cape (24 × 15 particles, pinned along its collar, half the chest's motion, painted max distance
 * and a backstop: `createCape`) on a torso capsule and two leg capsules. The world budget (`setClothBudget`) measures distance from the
 * camera (an entity whose Transform follows it): capes within 6 m keep 8 substeps, farther ones
 * get fewer, down to one at 25 m, and a time budget per fixed step (4, 8 or 16 ms, or none) lowers
 * levels further until the predicted cost fits; capes outside the view are marked invisible
 * (`setClothVisible`) and freeze. "Tint by LOD" colours each cape by the level it runs.
 * "Workers 2" steps the capes on two Web Workers (the page is cross-origin isolated: the demo
 * server sends COOP and COEP): `beginClothStep` after the characters move, `endClothStepAsync`
 * before drawing, so the main thread only syncs and hands over; the capes move bit for bit as
 * without workers.
 */
export const crowdScene: DemoScene = {
  id: 'crowd',
  title: 'Crowd: budget and LOD',
  defaults: { substeps: 8, iterations: 1, material: 'cotton', tethers: true },
  camera: { target: [3, 0.8, 5.5], distance: 9, yaw: 0.65, pitch: 0.3, fit: 0 },
  shadowRadius: 13,
  shadowMapSize: 1024,
  // at most two fixed steps per drawn frame: on a slow machine the crowd runs in slow motion
  // rather than spending ever more time per frame
  maxFrameTime: 1 / 30,
  worldOptions: crowdWorld,
  moments: [
    { name: 'rest', seconds: 3 },
    { name: 'motion', seconds: 3, action: 'lodByDistance' },
  ],
  create({ world, settings, ui, root, showCloth, camera, reload }) {
    const characters: Character[] = []
    const capes: number[] = []
    const meshes: THREE.Mesh[] = []
    const fabrics = CAPE_COLOURS.map((c) => simpleCotton(c))
    let n = 0
    for (const lane of LANES) {
      const track = new Track(4, lane.radius)
      for (let k = 0; k < lane.count; k++, n++) {
        const hero = new Character(world, {
          colliders: 'crowd',
          track,
          start: (k / lane.count) * track.length,
          direction: lane.direction,
          auto: false,
          gait: lane.gait,
          pace: lane.pace,
          cadence: 0.93 + 0.14 * ((n * 0.618) % 1),
        })
        // the hero's cape and character-cloth settings (demo/capeShape.ts)
        const { cape } = createCape(world, hero, { rows: CAPE_ROWS, cols: CAPE_COLS, ...settings })
        characters.push(hero)
        capes.push(cape)
        meshes.push(showCloth(cape, fabrics[n % fabrics.length]))
      }
    }
    const figures = new CrowdFigures(characters, SHIRTS)
    root.add(figures.group)

    // the budget measures distances from the camera, an entity the scene moves with the view
    const viewer = addEntity(world as never)
    setTransform(world, viewer, camera.position.toArray())
    type Budget = '4' | '8' | '16' | 'distance'
    let budget: Budget = '8'
    const setBudget = (b: Budget) => {
      budget = b
      setClothBudget(world, { msPerFrame: b === 'distance' ? undefined : Number(b), viewer, near: NEAR, far: FAR })
    }
    setBudget(budget)
    const showBudget = addSegmented<Budget>(
      ui,
      'Budget ms',
      [['4', '4'], ['8', '8'], ['16', '16'], ['distance', 'none']],
      budget,
      setBudget,
      'budget',
    )

    // workers: the scene is built again in a world with (or without) them
    const setThreads = (n: number) => {
      threads = n
      reload()
    }
    addSegmented<'0' | '2'>(ui, 'Workers', [['0', 'none'], ['2', '2']], threads === 2 ? '2' : '0', (v) => setThreads(Number(v)), 'workers')

    const lodMaterials = LOD_CLASSES.map((c) => new THREE.MeshStandardMaterial({ color: c.color, roughness: 0.8, side: THREE.DoubleSide }))
    let tintLod = false
    const tintBox = addToggle(ui, 'Tint by LOD', tintLod, (v) => (tintLod = v), 'tint-lod')
    const legend = document.createElement('div')
    legend.className = 'legend'
    legend.innerHTML = LOD_CLASSES.map((c) => `<span><i style="background:#${c.color.toString(16).padStart(6, '0')}"></i>${c.label}</span>`)
      .join('')
    ui.appendChild(legend)

    const frustum = new THREE.Frustum()
    const m = new THREE.Matrix4()
    const sphere = new THREE.Sphere(new THREE.Vector3(), 1.3)
    const histogram = new Array<number>(LOD_CLASSES.length).fill(0)
    let visibleCount = 0

    /** Marks capes outside the camera's view invisible (the budget freezes them). */
    const cull = () => {
      camera.updateMatrixWorld()
      frustum.setFromProjectionMatrix(m.multiplyMatrices(camera.projectionMatrix, camera.matrixWorldInverse))
      visibleCount = 0
      for (let i = 0; i < capes.length; i++) {
        characters[i].chestPoint(0, 0.1, -0.2, sphere.center)
        const visible = frustum.intersectsSphere(sphere)
        setClothVisible(world, capes[i], visible)
        meshes[i].visible = visible
        if (visible) visibleCount++
      }
    }

    return {
      cloths: capes,
      warmup: lodMaterials, // the first switch to the LOD tint does not stall
      update(_time, dt) {
        for (const c of characters) c.update(dt)
        setTransform(world, viewer, camera.position.toArray())
        cull()
      },
      /** All of the crowd's cloth stepping happens here (`simulate` runs steps back to back). */
      step: (dt) => stepCloth(world, dt),
      // with workers, the live loop draws once the frame is done, and the main thread does not wait
      stepAsync: threads > 0
        ? (dt) => {
          beginClothStep(world, dt)
          return endClothStepAsync(world)
        }
        : undefined,
      sync() {
        figures.sync()
        histogram.fill(0)
        for (let i = 0; i < capes.length; i++) {
          const k = lodClass(getClothLod(world, capes[i]))
          histogram[k]++
          // (a material that is neither, the stretch tint's, stays until the panel takes it off)
          const now = meshes[i].material
          if (
            tintLod || (lodMaterials as THREE.Material[]).includes(now as THREE.Material) ||
            (fabrics as THREE.Material[]).includes(now as THREE.Material)
          ) {
            meshes[i].material = tintLod ? lodMaterials[k] : fabrics[i % fabrics.length]
          }
        }
      },
      // the budget picks each cape's substeps; the panel's count is what near capes want
      stats() {
        const b = getClothBudgetStats(world)
        const ms = (v: number) => v.toFixed(2).padStart(6)
        return [
          `workers     ${threads > 0 ? `${threads}${crossOriginIsolated ? '' : ' (not isolated!)'}` : 'none (main thread)'}`,
          ...(budget === 'distance'
            ? [`budget      none: by distance`, `  full ≤ ${NEAR} m, 1 substep ≥ ${FAR} m`]
            : [
              `budget      ${budget} ms per step`,
              `  predicted ${ms(b.predictedMs)}`,
              // the budget times one step before each allocation; until the first, nothing is measured
              `  measured  ${b.measuredMs > 0 ? ms(b.measuredMs) : '     –'}`,
              // over the budget with no cape left to lower: this machine needs fewer capes in view
              ...(b.predictedMs > Number(budget) && histogram[0] + histogram[1] + histogram[2] === 0
                ? ['  over it at the lowest levels']
                : []),
            ]),
          `visible     ${visibleCount} of ${capes.length} capes`,
          ...LOD_CLASSES.map((c, k) => `  ${c.label.padEnd(16)}${histogram[k]}`),
        ]
      },
      api: {
        tintLod: () => {
          tintLod = true
          tintBox.checked = true
        },
        /** The LOD tint with levels by distance only (what the screenshot of the levels shows). */
        lodByDistance: () => {
          setBudget('distance')
          showBudget('distance')
          tintLod = true
          tintBox.checked = true
        },
        /** Level of detail by distance only (no time budget). */
        byDistance: () => {
          setBudget('distance')
          showBudget('distance')
        },
        lods: () => capes.map((c) => getClothLod(world, c)),
        histogram: () => Object.fromEntries(LOD_CLASSES.map((c, k) => [c.label, histogram[k]])),
        budget: () => getClothBudgetStats(world),
        visible: () => visibleCount,
        /** Builds the crowd again on `n` workers (0 or 2). */
        threads: (n: number) => setThreads(n),
        maxStretch: () => Math.max(...capes.map((c) => getClothStretch(world, c).max)),
      },
    }
  },
}
