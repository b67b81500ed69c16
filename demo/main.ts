import { createWorld } from 'bitecs'
import * as THREE from 'three'
import {
  ClothMaterial,
  type ClothRenderProxy,
  createRenderProxy,
  type RenderProxyOptions,
  getClothState,
  getClothStretch,
  getClothTearCount,
  disposeClothWorld,
  installClothPlugin,
  isClothSleeping,
  grabParticle,
  moveGrab,
  releaseGrab,
  setClothQuality,
  setClothTethers,
  stepCloth,
} from '../src/index'
import {
  createClothGeometry,
  createProxyGeometry,
  updateClothDrawMatrix,
  updateClothGeometry,
  updateProxyGeometry,
} from '../src/three/index'
import { setInputDeferral, type DemoScene, type DemoSettings, type SceneInstance, type SceneLabel } from './scene'
import { scenes } from './scenes/index'
import { View } from './view'

const $ = <T extends HTMLElement>(id: string) => document.getElementById(id) as T
const canvas = $<HTMLCanvasElement>('view')
const params = new URLSearchParams(location.search)
const view = new View(canvas, { antialias: params.get('aa') !== '0' })
/**
 * Dynamic resolution: the canvas renders at `resolution` × the device's pixel ratio, lowered
 * while fewer than 24 frames a second are drawn (software WebGL, a weak GPU) and raised again
 * above 50. `?pr=<ratio>` fixes the pixel ratio instead (the screenshot script uses `?pr=1`).
 */
const fixedRatio = params.has('pr') ? Number(params.get('pr')) : null
const RESOLUTIONS = [1, 0.75, 0.5, 0.35]
let resolution = 0
function applyResolution(): void {
  view.renderer.setPixelRatio(fixedRatio ?? Math.min(2, window.devicePixelRatio) * RESOLUTIONS[resolution])
}
applyResolution()

const settings: DemoSettings = { material: 'cotton', substeps: 8, iterations: 1, tethers: true, lineSolve: false }
let world: object
/** Whether `world` exists yet (a scene's world is disposed when the next scene loads: its workers exit). */
let haveWorld = false
let scene: DemoScene
let instance: SceneInstance
let paused = false
let simTime = 0
let frame = 0
let stepOnce = 0
/** Stretch tint on the cloths (off by default). */
let tint = false

// ------------------------------------------------------------------------------------------
// Panel

const panel = $('panel')
const statsBox = $('stats-box')
const statsEl = $('stats')
const statsHead = $('stats-head')
let statsShownAt = 0
const hint = $('hint')

const sceneSelect = $<HTMLSelectElement>('scene')
for (const s of scenes) sceneSelect.add(new Option(s.title, s.id))
const materialSelect = $<HTMLSelectElement>('material')
for (const m of Object.values(ClothMaterial)) materialSelect.add(new Option(m.name, m.name))
const substeps = $<HTMLInputElement>('substeps')
const iterations = $<HTMLInputElement>('iterations')
const tethers = $<HTMLInputElement>('tethers')
const lineSolve = $<HTMLInputElement>('line-solve')
const tintBox = $<HTMLInputElement>('tint')

function showSettings(): void {
  materialSelect.value = settings.material
  substeps.value = String(settings.substeps)
  iterations.value = String(settings.iterations)
  tethers.checked = settings.tethers
  lineSolve.checked = settings.lineSolve
  $('substeps-value').textContent = String(settings.substeps)
  $('iterations-value').textContent = String(settings.iterations)
  const locked = instance?.locked?.() ?? []
  materialSelect.disabled = locked.includes('material')
  substeps.disabled = locked.includes('substeps')
  iterations.disabled = locked.includes('iterations')
  tethers.disabled = locked.includes('tethers')
  lineSolve.disabled = locked.includes('lineSolve')
}

function applySettings(): void {
  if (instance.applySettings) instance.applySettings(settings)
  else {
    for (const cloth of instance.cloths) {
      setClothQuality(world, cloth, { substeps: settings.substeps, iterations: settings.iterations, lineSolve: settings.lineSolve })
      setClothTethers(world, cloth, settings.tethers)
    }
  }
  showSettings()
}

/**
 * Input that changes the world waits while workers step it (the crowd on workers: between
 * `beginClothStep` and `endClothStepAsync` changes throw), and runs at the start of the next frame.
 */
const deferred: (() => void)[] = []
let stepping = false
function change(f: () => void): void {
  if (stepping) deferred.push(f)
  else f()
}

setInputDeferral(change) // the scenes' own controls too
sceneSelect.addEventListener('change', () => change(() => loadScene(sceneSelect.value)))
materialSelect.addEventListener('change', () =>
  change(() => {
    settings.material = materialSelect.value
    loadScene(scene.id, false)
  }))
substeps.addEventListener('input', () =>
  change(() => {
    settings.substeps = Number(substeps.value)
    applySettings()
  }))
iterations.addEventListener('input', () =>
  change(() => {
    settings.iterations = Number(iterations.value)
    applySettings()
  }))
tethers.addEventListener('change', () =>
  change(() => {
    settings.tethers = tethers.checked
    applySettings()
  }))
lineSolve.addEventListener('change', () =>
  change(() => {
    settings.lineSolve = lineSolve.checked
    applySettings()
  }))
tintBox.addEventListener('change', () => setTint(tintBox.checked))
$('pause').addEventListener('click', () => setPaused(!paused))
$('step').addEventListener('click', () => stepOnce++)
// Reset starts the scene again as it opens: its default settings (the panel shows them) and its
// own controls' defaults, also those it keeps across reloads (e.g. what the accuracy scene compares).
// The stretch tint and pause are ways of looking and stay; so do the crowd's workers, which step
// the same capes bit for bit.
$('reset').addEventListener('click', () =>
  change(() => {
    scene.resetState?.()
    loadScene(scene.id)
  }))

// folding: the panel down to its scene menu, the stats to a summary line (both start folded in
// a narrow window, where they would cover most of the picture)
const panelToggle = $<HTMLButtonElement>('panel-toggle')
function foldPanel(folded: boolean): void {
  panel.classList.toggle('collapsed', folded)
  panelToggle.textContent = folded ? 'Show' : 'Hide'
}
function foldStats(folded: boolean): void {
  statsBox.classList.toggle('collapsed', folded)
  statsShownAt = 0
}
const narrow = window.matchMedia('(max-width: 639px)')
// in a narrow window one of them opens at a time, so the picture keeps a place below them
panelToggle.addEventListener('click', () => {
  const open = panel.classList.contains('collapsed')
  foldPanel(!open)
  if (open && narrow.matches) foldStats(true)
})
$('stats-head').addEventListener('click', () => {
  const open = statsBox.classList.contains('collapsed')
  foldStats(!open)
  if (open && narrow.matches) foldPanel(true)
})
if (narrow.matches) {
  foldPanel(true)
  foldStats(true)
}

function setPaused(p: boolean): void {
  paused = p
  $('pause').textContent = paused ? 'Play' : 'Pause'
}

// ------------------------------------------------------------------------------------------
// Cloth meshes, through the three.js adapter

interface ClothView {
  cloth: number
  /** The simulated mesh (drawn unless a render proxy stands in for it outside the stretch tint). */
  mesh: THREE.Mesh
  geometry: THREE.BufferGeometry
  material: THREE.Material
  /** Vertex colours for the stretch tint, sized like the position attribute. */
  colors: THREE.BufferAttribute | null
  strain: Float32Array
  /** A finer render mesh driven by the cloth (`createRenderProxy`), and its three.js mesh. */
  proxy: { handle: ClothRenderProxy; mesh: THREE.Mesh } | null
}
const clothViews: ClothView[] = []
/** The stretch tint: the cloth's lighting with a plain light-grey fabric turning orange as it stretches. */
const tintMaterial = new THREE.MeshStandardMaterial({ vertexColors: true, roughness: 0.8, side: THREE.DoubleSide })

function showCloth(cloth: number, material: THREE.Material, fine?: RenderProxyOptions): THREE.Mesh {
  const geometry = createClothGeometry(world, cloth)
  const mesh = new THREE.Mesh(geometry, material)
  mesh.castShadow = mesh.receiveShadow = true
  view.root.add(mesh)
  let proxy: ClothView['proxy'] = null
  if (fine) {
    const handle = createRenderProxy(world, cloth, fine)
    const proxyMesh = new THREE.Mesh(createProxyGeometry(world, handle), material)
    proxyMesh.castShadow = proxyMesh.receiveShadow = true
    view.root.add(proxyMesh)
    proxy = { handle, mesh: proxyMesh }
  }
  const v: ClothView = { cloth, mesh, geometry, material, colors: null, strain: new Float32Array(0), proxy }
  clothViews.push(v)
  showProxy(v)
  return proxy?.mesh ?? mesh
}

/** A cloth with a render proxy draws the proxy, except in the stretch tint (which colours particles). */
function showProxy(v: ClothView): void {
  if (!v.proxy) return
  v.proxy.mesh.visible = !tint
  v.mesh.visible = tint
}

const BASE = [0.78, 0.78, 0.76], ORANGE = [1.0, 0.35, 0.02]

/** Each vertex coloured by the largest strain of its structural edges (fully orange at 10 %). */
function paintStretch(v: ClothView): void {
  const position = v.geometry.getAttribute('position') as THREE.BufferAttribute
  if (!v.colors || v.colors.count !== position.count) {
    v.colors = new THREE.BufferAttribute(new Float32Array(3 * position.count), 3)
    v.geometry.setAttribute('color', v.colors)
  }
  const c = getClothState(world, v.cloth)
  if (v.strain.length < c.count) v.strain = new Float32Array(position.count)
  const s = v.strain
  s.fill(0, 0, c.count)
  const t = c.topology
  for (let e = 0; e < t.stretchCount; e++) {
    const a = t.stretchIds[2 * e], b = t.stretchIds[2 * e + 1]
    const d = Math.hypot(c.pos[3 * b] - c.pos[3 * a], c.pos[3 * b + 1] - c.pos[3 * a + 1], c.pos[3 * b + 2] - c.pos[3 * a + 2])
    const st = d / t.stretchRest[e] - 1
    if (st > s[a]) s[a] = st
    if (st > s[b]) s[b] = st
  }
  const out = v.colors.array as Float32Array
  for (let i = 0; i < c.count; i++) {
    const k = Math.min(1, Math.max(0, s[i] / 0.1))
    for (let j = 0; j < 3; j++) out[3 * i + j] = BASE[j] + (ORANGE[j] - BASE[j]) * k
  }
  v.colors.needsUpdate = true
}

function updateCloths(): void {
  for (const v of clothViews) {
    // drawn moved with their characters since the last fixed step (displays faster than 60 Hz)
    if (v.proxy?.mesh.visible) {
      updateProxyGeometry(world, v.proxy.handle, v.proxy.mesh.geometry)
      updateClothDrawMatrix(world, v.cloth, v.proxy.mesh)
    }
    if (!v.mesh.visible) continue
    updateClothGeometry(world, v.cloth, v.geometry)
    updateClothDrawMatrix(world, v.cloth, v.mesh)
    if (tint) paintStretch(v)
  }
}

/**
 * Meshes that draw the materials a scene's cloths may switch to later (the stretch tint's, the
 * scene's `warmup`) every frame, under the floor (hidden by it), like the curtain's parked ball:
 * three.js compiles their shaders with the rest when the scene loads (`renderer.compile`), and
 * drawing them keeps the GPU driver's code for them ready, so the first switch does not stall a
 * frame (in software WebGL, turning the crowd's LOD tint on took 262 ms more than a frame, the
 * stretch tint 451 ms; warmed, 93 and 56 ms when drawn only once, about 0 drawn every frame;
 * drawing them costs no measurable time). One small triangle with a cloth's attributes per
 * material, casting and receiving shadows as cloths do.
 */
const warm = new THREE.Group()
view.scene.add(warm)
const warmGeometry = new THREE.BufferGeometry()
warmGeometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array([0, 0, 0, 0.01, 0, 0, 0, 0.01, 0]), 3))
warmGeometry.setAttribute('normal', new THREE.BufferAttribute(new Float32Array([0, 0, 1, 0, 0, 1, 0, 0, 1]), 3))
warmGeometry.setAttribute('uv', new THREE.BufferAttribute(new Float32Array([0, 0, 1, 0, 0, 1]), 2))
warmGeometry.setAttribute('color', new THREE.BufferAttribute(new Float32Array(9).fill(0.5), 3))
warmGeometry.setIndex(new THREE.BufferAttribute(new Uint32Array([0, 1, 2]), 1)) // 32-bit, as cloth geometries'
function warmUp(materials: readonly THREE.Material[]): void {
  warm.clear()
  for (const material of materials) {
    const m = new THREE.Mesh(warmGeometry, material)
    m.position.set(0, -5, 0)
    m.frustumCulled = false
    m.castShadow = m.receiveShadow = true
    warm.add(m)
  }
}

function setTint(on: boolean): void {
  tint = on
  tintBox.checked = on
  for (const v of clothViews) {
    v.mesh.material = on ? tintMaterial : v.material
    showProxy(v)
    if (on) {
      updateClothGeometry(world, v.cloth, v.geometry)
      paintStretch(v)
    }
  }
}

// ------------------------------------------------------------------------------------------
// Scenes

function loadScene(id: string, useDefaults = true): void {
  scene = scenes.find((s) => s.id === id) ?? scenes[0]
  sceneSelect.value = scene.id
  if (useDefaults)
    Object.assign(settings, { material: 'cotton', substeps: 8, iterations: 1, tethers: true, lineSolve: false }, scene.defaults)
  for (const m of instance?.warmup ?? []) m.dispose() // the last scene's (its meshes' are disposed by clear)
  view.clear()
  clothViews.length = 0
  if (haveWorld) disposeClothWorld(world)
  world = installClothPlugin(createWorld(), scene.worldOptions?.() ?? {})
  haveWorld = true
  const ui = $('extra')
  ui.replaceChildren()
  labelLayer.replaceChildren()
  drag = null
  const cam = scene.camera ?? { target: [0, 1, 0], distance: 4 }
  view.orbit.target.set(...cam.target)
  view.orbit.distance = cam.distance
  view.orbit.yaw = cam.yaw ?? 0.6
  view.orbit.pitch = cam.pitch ?? 0.3
  view.camera.fov = cam.fov ?? 45
  view.shadowRadius = scene.shadowRadius ?? 4
  view.setSun(scene.sun ?? [-0.45, 0.8, 0.4], scene.shadowMapSize ?? 2048)
  lastOrbit = -Infinity
  instance = scene.create({
    world,
    settings,
    ui,
    refresh: applySettings,
    root: view.root,
    showCloth,
    camera: view.camera,
    reload: () => loadScene(scene.id, false),
  })
  // (the scenes make their cloths with the panel's substeps, iterations and tethers; the line solve is switched on after)
  if (settings.lineSolve && !instance.applySettings) { for (const c of instance.cloths) setClothQuality(world, c, { lineSolve: true }) }
  simTime = 0
  setTint(tint)
  warmUp([tintMaterial, ...(instance.warmup ?? [])])
  view.update()
  view.renderer.compile(view.scene, view.camera) // every shader now, not at the first frame that shows its object
  $('hint').textContent = scene.hint ?? DEFAULT_HINT
  showSettings()
  const url = new URL(location.href)
  url.searchParams.set('scene', scene.id)
  history.replaceState(null, '', url)
}

const DEFAULT_HINT = 'drag cloth with the mouse · right-drag or shift-drag to orbit · wheel to zoom'

// ------------------------------------------------------------------------------------------
// Mouse: grab a particle (`grabParticle`: a soft grip with a force limit, so a moving cloth
// stretches as under a hand) and move the grip with the cursor; orbit with right button or shift

let drag: { grab: number; depth: number } | null = null
let orbit: { x: number; y: number } | null = null
let lastOrbit = -Infinity // simTime of the last manual orbit
/** Where and when the left button went down: a release close by is a click. */
let press: { x: number; y: number; time: number } | null = null
const rayO = new THREE.Vector3(), rayD = new THREE.Vector3()

function ndc(e: PointerEvent): [number, number] {
  const r = canvas.getBoundingClientRect()
  return [((e.clientX - r.left) / r.width) * 2 - 1, 1 - ((e.clientY - r.top) / r.height) * 2]
}

canvas.addEventListener('contextmenu', (e) => e.preventDefault())
canvas.addEventListener('pointerdown', (e) => {
  canvas.setPointerCapture(e.pointerId)
  press = null
  if (e.button !== 0 || e.shiftKey) {
    orbit = { x: e.clientX, y: e.clientY }
    return
  }
  press = { x: e.clientX, y: e.clientY, time: performance.now() }
  const [x, y] = ndc(e)
  view.ray(x, y, rayO, rayD)
  let best = { d: 0.08, cloth: -1, index: -1, t: 0 }
  for (const cloth of instance.cloths) {
    const c = getClothState(world, cloth)
    for (let i = 0; i < c.count; i++) {
      const px = c.pos[3 * i] - rayO.x, py = c.pos[3 * i + 1] - rayO.y, pz = c.pos[3 * i + 2] - rayO.z
      const t = px * rayD.x + py * rayD.y + pz * rayD.z
      if (t <= 0) continue
      const d = Math.hypot(px - t * rayD.x, py - t * rayD.y, pz - t * rayD.z)
      if (d < best.d) best = { d, cloth, index: i, t }
    }
  }
  if (best.cloth < 0) {
    orbit = { x: e.clientX, y: e.clientY }
    return
  }
  const c = getClothState(world, best.cloth)
  const at = [c.pos[3 * best.index], c.pos[3 * best.index + 1], c.pos[3 * best.index + 2]]
  // a hand's grip: up to the cloth's weight (the library's default, twice that, pulls the free
  // hem of a cape held by its motion limits to 32-64 % stretch; this grip to 19-38 %)
  let mass = 0
  for (let i = 0; i < c.count; i++) mass += c.topology.masses[i]
  const maxForce = 9.81 * mass
  change(() => {
    drag = { grab: grabParticle(world, best.cloth, best.index, at, { maxForce }), depth: best.t }
  })
})
canvas.addEventListener('pointermove', (e) => {
  if (orbit) {
    view.orbit.yaw -= (e.clientX - orbit.x) * 0.008
    lastOrbit = simTime
    view.orbit.pitch = Math.max(-0.2, Math.min(1.4, view.orbit.pitch + (e.clientY - orbit.y) * 0.008))
    orbit = { x: e.clientX, y: e.clientY }
  } else if (drag) {
    const [x, y] = ndc(e)
    view.ray(x, y, rayO, rayD)
    const grab = drag.grab, to = rayO.clone().addScaledVector(rayD, drag.depth).toArray()
    change(() => moveGrab(world, grab, to))
  }
})
const endDrag = () => {
  orbit = null
  change(() => {
    if (!drag) return
    releaseGrab(world, drag.grab)
    drag = null
  })
}
canvas.addEventListener('pointerup', (e) => {
  endDrag()
  const p = press
  press = null
  if (!p || !instance.click) return
  if (Math.hypot(e.clientX - p.x, e.clientY - p.y) > 5 || performance.now() - p.time > 400) return
  const [x, y] = ndc(e)
  view.ray(x, y, rayO, rayD)
  instance.click(rayO.toArray(), rayD.toArray())
})
canvas.addEventListener('pointercancel', () => {
  press = null
  endDrag()
})
canvas.addEventListener('wheel', (e) => {
  e.preventDefault()
  view.orbit.distance = Math.max(0.8, Math.min(60, view.orbit.distance * Math.exp(e.deltaY * 0.001)))
}, { passive: false })

// ------------------------------------------------------------------------------------------
// Frame: update, step, geometry, render; costs measured per frame and averaged over a second

/** Main-thread ms per frame, averaged over the last second: the scene's own work, the cloth step, geometry updates, rendering. */
const costs = { sceneMs: 0, stepMs: 0, waitMs: 0, geometryMs: 0, renderMs: 0, frameMs: 0 }
const acc = { sceneMs: 0, stepMs: 0, waitMs: 0, geometryMs: 0, renderMs: 0, frameMs: 0, frames: 0, start: 0 }
/** Time stamps of the frames drawn in the last second (the fps is their count). */
const drawn: number[] = []
let fps = 0
/** ms per fixed step of the cloth work (averaged like the other costs). */
let msPerStep = 0
let stepsInWindow = 0
/** ms of the last frame's geometry updates. */
let lastGeometryMs = 0

/** Advances the simulation by `h` seconds: the scene's update, then the cloth step. */
function advance(h: number): number {
  simTime += h
  const t0 = performance.now()
  instance.update?.(simTime, h)
  const t1 = performance.now()
  const steps = instance.step ? instance.step(h) : stepCloth(world, h)
  const t2 = performance.now()
  acc.sceneMs += t1 - t0
  acc.stepMs += t2 - t1
  stepsInWindow += steps
  followCamera(h)
  return steps
}

/**
 * `advance` for a scene whose step does not block (`stepAsync`): the step's main-thread time is
 * what its begin and end take, the wait for the workers is not counted (`waitMs` shows it).
 */
async function advanceAsync(h: number, step: (dt: number) => Promise<number>): Promise<number> {
  simTime += h
  const t0 = performance.now()
  instance.update?.(simTime, h)
  const t1 = performance.now()
  const pending = step(h)
  const t2 = performance.now()
  const steps = await pending
  const t3 = performance.now()
  acc.sceneMs += t1 - t0
  acc.stepMs += t2 - t1 + (performance.now() - t3)
  acc.waitMs += t3 - t2
  stepsInWindow += steps
  followCamera(h)
  return steps
}

/** The camera eases toward a followed point (0.12 s) and yaw (1.5 s), unless the user orbited lately. */
function followCamera(h: number): void {
  const follow = instance.follow?.()
  if (follow) {
    const t = view.orbit.target
    const a = 1 - Math.exp(-h / 0.12)
    t.x += (follow[0] - t.x) * a
    t.y += (follow[1] - t.y) * a
    t.z += (follow[2] - t.z) * a
  }
  const yaw = instance.followYaw?.()
  if (yaw !== undefined && simTime - lastOrbit > 5) {
    const d = yaw - view.orbit.yaw - 2 * Math.PI * Math.round((yaw - view.orbit.yaw) / (2 * Math.PI))
    view.orbit.yaw += d * (1 - Math.exp(-h / 1.5))
  }
}

let last = performance.now()
let running = true
async function tick(now: number): Promise<void> {
  if (!running) return
  const dt = Math.min(scene.maxFrameTime ?? 0.05, Math.max(0, (now - last) / 1000)) // rAF stamps can precede the last read
  last = now
  const f0 = performance.now()
  for (const f of deferred.splice(0)) f()
  if (!paused || stepOnce > 0) {
    const h = paused ? 1 / 60 : dt
    if (paused) stepOnce--
    const stepAsync = instance.stepAsync
    if (h > 0) {
      if (stepAsync) {
        stepping = true
        try {
          await advanceAsync(h, stepAsync)
        } finally {
          stepping = false
        }
      } else advance(h)
    }
  }
  draw()
  acc.frameMs += performance.now() - f0
  countFrame(performance.now())
  requestAnimationFrame(tick)
}

function countFrame(now: number): void {
  frame++
  drawn.push(now)
  while (drawn.length > 0 && drawn[0] <= now - 1000) drawn.shift()
  fps = drawn.length
  acc.frames++
  if (now - acc.start >= 1000) {
    const n = Math.max(1, acc.frames)
    costs.sceneMs = acc.sceneMs / n
    costs.stepMs = acc.stepMs / n
    costs.waitMs = acc.waitMs / n
    costs.geometryMs = acc.geometryMs / n
    costs.renderMs = acc.renderMs / n
    costs.frameMs = acc.frameMs / n
    msPerStep = stepsInWindow > 0 ? acc.stepMs / stepsInWindow : msPerStep
    acc.sceneMs =
      acc.stepMs =
      acc.waitMs =
      acc.geometryMs =
      acc.renderMs =
      acc.frameMs =
        0
    acc.frames = 0
    acc.start = now
    stepsInWindow = 0
    if (fixedRatio === null && !paused) {
      if (fps < 24 && resolution < RESOLUTIONS.length - 1) resolution++
      else if (fps > 50 && resolution > 0) resolution--
      else return
      applyResolution()
    }
  }
}

/** Geometry, labels, render, overlay. */
function draw(): void {
  const t0 = performance.now()
  instance.sync?.()
  const t1 = performance.now()
  updateCloths()
  const t2 = performance.now()
  view.fit = scene.camera?.fit ?? 1
  view.frame = freeFrame(view.fit)
  view.update()
  view.render()
  const t3 = performance.now()
  acc.sceneMs += t1 - t0
  acc.geometryMs += t2 - t1
  lastGeometryMs = t2 - t1
  acc.renderMs += t3 - t2
  drawLabels(instance.labels?.() ?? [])
  showStats()
}

/** The stats' widest (`#stats-box` in index.html) plus the margin right of them, px. */
const STATS_WIDTH = 270 + 10

/**
 * The part of the canvas the overlays leave free, where the picture is framed: beside the panel
 * (between it and the stats when they are unfolded) or below both (a narrow window), whichever
 * shows the scene larger once it is fitted (`View.fit`); null when neither leaves room.
 */
function freeFrame(fit: number): View['frame'] {
  const W = canvas.clientWidth, H = canvas.clientHeight
  const p = panel.getBoundingClientRect()
  const s = statsBox.getBoundingClientRect()
  const statsOpen = s.height > 60 // folded, it is one line in a corner
  const hintTop = hint.textContent ? hint.getBoundingClientRect().top : H
  // beside: from the panel's right edge to where the stats may reach (or the canvas's): not
  // their width now, which changes with their lines and would move the picture (and the crowd's
  // view, so which capes are culled)
  const right = statsOpen && s.left > p.right ? W - STATS_WIDTH : W
  const beside = { x: p.right, y: 0, width: right - p.right, height: H }
  // below: under the panel and the stats, above the hint
  const top = Math.max(p.bottom, statsOpen || s.left < p.right ? s.bottom : 0)
  const below = { x: 0, y: top, width: W, height: Math.max(0, Math.min(H, hintTop) - top) }
  const scale = (r: { width: number; height: number }) => Math.min(r.height, fit > 0 ? r.width / fit : Infinity)
  const roomy = (r: { width: number; height: number }) => r.width >= Math.min(360, 0.4 * W) && r.height >= Math.min(200, 0.3 * H)
  const clear = [beside, below].filter(roomy).sort((a, b) => scale(b) - scale(a))
  if (clear.length > 0) return clear[0]
  // no room clear of both: beside the panel, under the stats (they cover the top corner only)
  const besidePanel = { x: p.right, y: 0, width: W - p.right, height: H }
  return roomy(besidePanel) ? besidePanel : null
}

// ------------------------------------------------------------------------------------------
// Labels: HTML text over the canvas at projected world points

const labelLayer = $('labels')
const projected = { x: 0, y: 0, visible: false }
function drawLabels(labels: readonly SceneLabel[]): void {
  while (labelLayer.children.length > labels.length) labelLayer.lastElementChild!.remove()
  while (labelLayer.children.length < labels.length) labelLayer.appendChild(document.createElement('div'))
  for (let i = 0; i < labels.length; i++) {
    const { text, at, className } = labels[i]
    const el = labelLayer.children[i] as HTMLDivElement
    if (el.textContent !== text) el.textContent = text
    const cls = `label ${className ?? ''}`
    if (el.className !== cls) el.className = cls
    view.project(at, projected)
    el.style.display = projected.visible ? '' : 'none'
    if (projected.visible) el.style.transform = `translate(${projected.x}px, ${projected.y}px) translate(-50%, -100%)`
  }
}

// ------------------------------------------------------------------------------------------
// Overlay

let lastStats = { particles: 0, constraints: 0, maxStretch: 0 }
function showStats(): void {
  const now = performance.now()
  if (now - statsShownAt < 250) return // four times a second: readable, and cheap
  statsShownAt = now
  let particles = 0, constraints = 0, maxStretch = 0, asleep = 0
  for (const cloth of instance.cloths) {
    if (isClothSleeping(world, cloth)) asleep++
    const c = getClothState(world, cloth)
    particles += c.count
    constraints += c.topology.distCount + c.topology.compCount + c.topology.hingeCount + c.tethers.set.count
    maxStretch = Math.max(maxStretch, getClothStretch(world, cloth).max)
  }
  lastStats = { particles, constraints, maxStretch }
  const f = (v: number) => v.toFixed(2).padStart(6)
  statsHead.textContent = statsBox.classList.contains('collapsed')
    ? `▸ ${fps} fps · ${costs.frameMs.toFixed(1)} ms/frame · stretch ${(maxStretch * 100).toFixed(1)} %`
    : '▾ stats'
  statsEl.textContent = [
    `fps         ${fps}${fixedRatio === null && resolution > 0 ? ` (${RESOLUTIONS[resolution] * 100} % resolution)` : ''}`,
    `ms/frame    ${f(costs.frameMs)}`,
    `  step      ${f(costs.stepMs)}`,
    ...(costs.waitMs > 0 ? [`  awaited   ${f(costs.waitMs)} (workers)`] : []), // the main thread was free meanwhile
    `  geometry  ${f(costs.geometryMs)}`,
    `  render    ${f(costs.renderMs)}`,
    `  scene     ${f(costs.sceneMs)}`,
    `ms/step     ${f(msPerStep)}`,
    `particles   ${particles}`,
    `constraints ${constraints}`,
    `max stretch ${(maxStretch * 100).toFixed(2)} %`,
    ...(asleep > 0 ? [`asleep      ${asleep} of ${instance.cloths.length}`] : []),
    ...(instance.stats?.() ?? []),
  ].join('\n')
}

// ------------------------------------------------------------------------------------------
// Hooks for browser tests and the screenshot script

/** Renders now and reads the canvas back (RGBA rows, bottom first). */
function readPixels(): { w: number; h: number; px: Uint8Array } {
  instance.sync?.()
  updateCloths()
  view.update()
  view.render()
  const gl = view.renderer.getContext()
  const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight
  const px = new Uint8Array(4 * w * h)
  gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px)
  return { w, h, px }
}

function differing(a: Uint8Array, b: Uint8Array): number {
  let n = 0
  for (let i = 0; i < a.length; i += 4) if (Math.abs(a[i] - b[i]) + Math.abs(a[i + 1] - b[i + 1]) + Math.abs(a[i + 2] - b[i + 2]) > 12) n++
  return n / (a.length / 4)
}

/**
 * What the cloths add to the picture: the share of pixels that change when the cloth meshes are
 * hidden, and how many distinct colours (5 bits per channel) the picture has.
 */
function snapshot(): { clothCoverage: number; colors: number } {
  const shown = readPixels().px
  const meshes = clothViews.flatMap((v) => (v.proxy ? [v.mesh, v.proxy.mesh] : [v.mesh]))
  const visible = meshes.map((m) => m.visible)
  for (const m of meshes) m.visible = false
  const hidden = readPixels().px
  meshes.forEach((m, k) => (m.visible = visible[k]))
  const seen = new Set<number>()
  for (let i = 0; i < shown.length; i += 4 * 7) seen.add((shown[i] >> 3) | ((shown[i + 1] >> 3) << 5) | ((shown[i + 2] >> 3) << 10))
  return { clothCoverage: differing(shown, hidden), colors: seen.size }
}

/** Share of pixels that change when the stretch tint is turned on (the simulation paused meanwhile). */
function tintDifference(): number {
  const wasPaused = paused, wasTint = tint
  paused = true
  setTint(false)
  const off = readPixels().px
  setTint(true)
  const on = readPixels().px
  setTint(wasTint)
  paused = wasPaused
  return differing(off, on)
}

/** A cloth's particle positions now (a copy), for tests that compare frames. */
function positions(index = 0): number[] {
  const cloth = instance.cloths[index]
  const c = getClothState(world, cloth)
  return Array.from(c.pos.subarray(0, 3 * c.count))
}

/** Where a world point appears on the page, in CSS pixels (for tests that click on things). */
function screenPoint(p: ArrayLike<number>): [number, number] {
  const r = canvas.getBoundingClientRect()
  view.project(p, projected)
  return [r.left + projected.x, r.top + projected.y]
}

/**
 * Simulates `seconds` at a fixed 60 Hz without drawing (the loop stays paused), then draws one
 * frame (unless `show` is false: tests that sample every frame): the same picture whatever the
 * machine's speed (the screenshot script uses it).
 */
function simulate(seconds: number, show = true): void {
  setPaused(true)
  const n = Math.round(seconds * 60)
  for (let i = 0; i < n; i++) advance(1 / 60)
  if (show) draw()
}

;(window as unknown as { __demo: unknown }).__demo = {
  snapshot,
  tintDifference,
  readPixels,
  differing,
  /** ms per call of the geometry updates of every shown cloth (no step between: copies only). */
  timeGeometry(n = 20): number {
    const t0 = performance.now()
    for (let i = 0; i < n; i++) updateCloths()
    return (performance.now() - t0) / n
  },
  positions,
  screenPoint,
  simulate,
  setTint,
  setPaused,
  get ready() {
    return frame > 2
  },
  get frame() {
    return frame
  },
  get scene() {
    return scene.id
  },
  /** Frame rate (frames drawn in the last second) and main-thread ms per frame, averaged over a second. */
  get stats() {
    return {
      ...lastStats,
      ...costs,
      lastGeometryMs,
      fps,
      msPerStep,
      outsideStepMs: costs.geometryMs + costs.renderMs,
      tint,
      pixelRatio: view.renderer.getPixelRatio(),
    }
  },
  get world() {
    return world
  },
  /** The three.js view (renderer, scene, camera). */
  view,
  get cloths() {
    return instance.cloths
  },
  /** The current scene's own actions and readouts (e.g. `throw()` in the curtain scene). */
  get api() {
    return instance.api ?? {}
  },
  /** Whether the mouse holds a particle. */
  get grabbing() {
    return drag !== null
  },
  /** Largest edge stretch over the scene's cloths now. */
  maxStretch() {
    let m = 0
    for (const cloth of instance.cloths) m = Math.max(m, getClothStretch(world, cloth).max)
    return m
  },
  /** Tears so far, summed over the scene's cloths. */
  tearCount() {
    let n = 0
    for (const cloth of instance.cloths) n += getClothTearCount(world, cloth)
    return n
  },
  scenes: scenes.map((s) => s.id),
  moments: Object.fromEntries(scenes.map((s) => [s.id, s.moments ?? []])),
  loadScene,
  settings,
  applySettings,
}

loadScene(params.get('scene') ?? scenes[0].id)
if (params.has('tint')) setTint(true)
acc.start = performance.now()
requestAnimationFrame(tick)
window.addEventListener('pagehide', () => (running = false))
