import { addEntity, createWorld, removeEntity } from 'bitecs'
import { vec3 } from 'gl-matrix'
import {
  ClothMaterial,
  getClothMesh,
  getClothState,
  getClothStretch,
  getClothTearCount,
  installClothPlugin,
  isClothSleeping,
  pinParticle,
  setClothQuality,
  setClothTethers,
  setTransform,
  stepCloth,
  unpin,
} from '../src/index'
import { Renderer } from './renderer'
import type { DemoScene, DemoSettings, SceneInstance, SceneLabel } from './scene'
import { scenes } from './scenes/index'

const $ = <T extends HTMLElement>(id: string) => document.getElementById(id) as T
const canvas = $<HTMLCanvasElement>('view')
const renderer = new Renderer(canvas)
const params = new URLSearchParams(location.search)

const settings: DemoSettings = { material: 'cotton', substeps: 8, iterations: 1, tethers: true }
let world: object
let scene: DemoScene
let instance: SceneInstance
let paused = false
let simTime = 0
let frame = 0
let stepMs = 0
let fps = 60
const stepOnce = { pending: 0 }

// ------------------------------------------------------------------------------------------
// Panel

const sceneSelect = $<HTMLSelectElement>('scene')
for (const s of scenes) sceneSelect.add(new Option(s.title, s.id))
const materialSelect = $<HTMLSelectElement>('material')
for (const m of Object.values(ClothMaterial)) materialSelect.add(new Option(m.name, m.name))
const substeps = $<HTMLInputElement>('substeps')
const iterations = $<HTMLInputElement>('iterations')
const tethers = $<HTMLInputElement>('tethers')

function showSettings(): void {
  materialSelect.value = settings.material
  substeps.value = String(settings.substeps)
  iterations.value = String(settings.iterations)
  tethers.checked = settings.tethers
  $('substeps-value').textContent = String(settings.substeps)
  $('iterations-value').textContent = String(settings.iterations)
  const locked = instance?.locked?.() ?? []
  materialSelect.disabled = locked.includes('material')
  substeps.disabled = locked.includes('substeps')
  iterations.disabled = locked.includes('iterations')
  tethers.disabled = locked.includes('tethers')
}

function applySettings(): void {
  if (instance.applySettings) instance.applySettings(settings)
  else {
    for (const cloth of instance.cloths) {
      setClothQuality(world, cloth, { substeps: settings.substeps, iterations: settings.iterations })
      setClothTethers(world, cloth, settings.tethers)
    }
  }
  showSettings()
}

sceneSelect.addEventListener('change', () => loadScene(sceneSelect.value))
materialSelect.addEventListener('change', () => {
  settings.material = materialSelect.value
  loadScene(scene.id, false)
})
substeps.addEventListener('input', () => {
  settings.substeps = Number(substeps.value)
  applySettings()
})
iterations.addEventListener('input', () => {
  settings.iterations = Number(iterations.value)
  applySettings()
})
tethers.addEventListener('change', () => {
  settings.tethers = tethers.checked
  applySettings()
})
$('pause').addEventListener('click', () => {
  paused = !paused
  $('pause').textContent = paused ? 'Play' : 'Pause'
})
$('step').addEventListener('click', () => {
  stepOnce.pending++
})
$('reset').addEventListener('click', () => loadScene(scene.id, false))

// ------------------------------------------------------------------------------------------
// Scenes

function loadScene(id: string, useDefaults = true): void {
  scene = scenes.find((s) => s.id === id) ?? scenes[0]
  sceneSelect.value = scene.id
  if (useDefaults) Object.assign(settings, { material: 'cotton', substeps: 8, iterations: 1, tethers: true }, scene.defaults)
  if (instance) for (const c of instance.cloths) renderer.release(clothKey(c))
  keys.clear()
  world = installClothPlugin(createWorld())
  const ui = $('extra')
  ui.replaceChildren()
  labelLayer.replaceChildren()
  instance = scene.create({ world, settings, ui, refresh: applySettings })
  simTime = 0
  drag = null
  $('hint').textContent = scene.hint ?? DEFAULT_HINT
  const cam = scene.camera ?? { target: [0, 1, 0], distance: 4 }
  vec3.set(renderer.camera.target, ...cam.target)
  renderer.camera.distance = cam.distance
  renderer.camera.yaw = cam.yaw ?? 0.6
  renderer.camera.pitch = cam.pitch ?? 0.3
  showSettings()
  const url = new URL(location.href)
  url.searchParams.set('scene', scene.id)
  history.replaceState(null, '', url)
}

const DEFAULT_HINT = 'drag cloth with the mouse · right-drag or shift-drag to orbit · wheel to zoom'

const keys = new Map<number, object>()
/** Renderer buffers are keyed per cloth entity of the current world. */
function clothKey(cloth: number): object {
  let k = keys.get(cloth)
  if (!k) keys.set(cloth, (k = {}))
  return k
}

// ------------------------------------------------------------------------------------------
// Stretch tint: each vertex coloured by the largest strain of its structural edges

const ORANGE = [1.0, 0.45, 0.05]
const colorBuffers = new Map<number, Float32Array>()
const strain = new Map<number, Float32Array>()

function stretchColors(cloth: number, base: ArrayLike<number>): Float32Array {
  const c = getClothState(world, cloth)
  let colors = colorBuffers.get(cloth)
  if (!colors || colors.length !== 3 * c.count) {
    colors = new Float32Array(3 * c.count)
    colorBuffers.set(cloth, colors)
  }
  let s = strain.get(cloth)
  if (!s || s.length !== c.count) {
    s = new Float32Array(c.count)
    strain.set(cloth, s)
  }
  s.fill(0)
  const t = c.topology
  for (let e = 0; e < t.stretchCount; e++) {
    const a = t.stretchIds[2 * e], b = t.stretchIds[2 * e + 1]
    const d = Math.hypot(c.pos[3 * b] - c.pos[3 * a], c.pos[3 * b + 1] - c.pos[3 * a + 1], c.pos[3 * b + 2] - c.pos[3 * a + 2])
    const st = d / t.stretchRest[e] - 1
    if (st > s[a]) s[a] = st
    if (st > s[b]) s[b] = st
  }
  for (let i = 0; i < c.count; i++) {
    const k = Math.min(1, Math.max(0, s[i] / 0.1)) // fully orange at 10 % stretch
    for (let j = 0; j < 3; j++) colors[3 * i + j] = base[j] + (ORANGE[j] - base[j]) * k
  }
  return colors
}

// ------------------------------------------------------------------------------------------
// Mouse: drag a particle by pinning it to a hidden entity; orbit with right button or shift

let drag: { cloth: number; pin: number; target: number; depth: number } | null = null
let orbit: { x: number; y: number } | null = null
let lastOrbit = -Infinity // performance.now() of the last manual orbit
/** Where and when the left button went down: a release close by is a click. */
let press: { x: number; y: number; time: number } | null = null
const rayO = vec3.create(), rayD = vec3.create()

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
  renderer.camera.ray(x, y, rayO, rayD)
  let best = { d: 0.08, cloth: -1, index: -1, t: 0 }
  for (const cloth of instance.cloths) {
    const c = getClothState(world, cloth)
    for (let i = 0; i < c.count; i++) {
      const px = c.pos[3 * i] - rayO[0], py = c.pos[3 * i + 1] - rayO[1], pz = c.pos[3 * i + 2] - rayO[2]
      const t = px * rayD[0] + py * rayD[1] + pz * rayD[2]
      if (t <= 0) continue
      const d = Math.hypot(px - t * rayD[0], py - t * rayD[1], pz - t * rayD[2])
      if (d < best.d) best = { d, cloth, index: i, t }
    }
  }
  if (best.cloth < 0) {
    orbit = { x: e.clientX, y: e.clientY }
    return
  }
  const c = getClothState(world, best.cloth)
  const target = addEntity(world as never)
  setTransform(world, target, [c.pos[3 * best.index], c.pos[3 * best.index + 1], c.pos[3 * best.index + 2]])
  drag = { cloth: best.cloth, pin: pinParticle(world, best.cloth, best.index, target), target, depth: best.t }
})
canvas.addEventListener('pointermove', (e) => {
  if (orbit) {
    renderer.camera.yaw -= (e.clientX - orbit.x) * 0.008
    lastOrbit = performance.now()
    renderer.camera.pitch = Math.max(-1.2, Math.min(1.4, renderer.camera.pitch + (e.clientY - orbit.y) * 0.008))
    orbit = { x: e.clientX, y: e.clientY }
  } else if (drag) {
    const [x, y] = ndc(e)
    renderer.camera.ray(x, y, rayO, rayD)
    setTransform(world, drag.target, vec3.scaleAndAdd(vec3.create(), rayO, rayD, drag.depth))
  }
})
const endDrag = () => {
  orbit = null
  if (!drag) return
  unpin(world, drag.pin)
  removeEntity(world as never, drag.target)
  drag = null
}
canvas.addEventListener('pointerup', (e) => {
  endDrag()
  const p = press
  press = null
  if (!p || !instance.click) return
  if (Math.hypot(e.clientX - p.x, e.clientY - p.y) > 5 || performance.now() - p.time > 400) return
  const [x, y] = ndc(e)
  renderer.camera.ray(x, y, rayO, rayD)
  instance.click(rayO, rayD)
})
canvas.addEventListener('pointercancel', () => {
  press = null
  endDrag()
})
canvas.addEventListener('wheel', (e) => {
  e.preventDefault()
  renderer.camera.distance = Math.max(0.5, Math.min(40, renderer.camera.distance * Math.exp(e.deltaY * 0.001)))
}, { passive: false })

// ------------------------------------------------------------------------------------------
// Loop

let last = performance.now()
function tick(now: number): void {
  const dt = Math.min(0.1, Math.max(0, (now - last) / 1000)) // rAF stamps can precede the last read
  last = now
  fps += (1 / Math.max(dt, 1e-3) - fps) * 0.05
  const advance = !paused || stepOnce.pending > 0
  if (advance) {
    const h = paused ? 1 / 60 : dt
    if (paused) stepOnce.pending--
    simTime += h
    instance.update?.(simTime, h)
    const t0 = performance.now()
    const steps = stepCloth(world, h)
    if (steps > 0) stepMs += ((performance.now() - t0) / steps - stepMs) * 0.1
  }
  render()
  frame++
  requestAnimationFrame(tick)
}

// ------------------------------------------------------------------------------------------
// Labels: HTML text over the canvas at projected world points

const labelLayer = $('labels')
const clip = new Float32Array(4)
function drawLabels(labels: readonly SceneLabel[]): void {
  while (labelLayer.children.length > labels.length) labelLayer.lastElementChild!.remove()
  while (labelLayer.children.length < labels.length) labelLayer.appendChild(document.createElement('div'))
  const m = renderer.camera.viewProj
  const w = canvas.clientWidth, h = canvas.clientHeight
  for (let i = 0; i < labels.length; i++) {
    const { text, at, className } = labels[i]
    const el = labelLayer.children[i] as HTMLDivElement
    if (el.textContent !== text) el.textContent = text
    const cls = `label ${className ?? ''}`
    if (el.className !== cls) el.className = cls
    for (let r = 0; r < 4; r++) clip[r] = m[r] * at[0] + m[4 + r] * at[1] + m[8 + r] * at[2] + m[12 + r]
    const visible = clip[3] > 0.05
    el.style.display = visible ? '' : 'none'
    if (!visible) continue
    el.style.transform = `translate(${((clip[0] / clip[3] + 1) / 2) * w}px, ${((1 - clip[1] / clip[3]) / 2) * h}px) translate(-50%, -100%)`
  }
}

let lastStats = { particles: 0, constraints: 0, maxStretch: 0 }
const panel = $('panel')
let lastRender = performance.now()
function render(): void {
  // centre the scene in the canvas right of the panel (when the window is wide enough to have room)
  const free = canvas.clientWidth - panel.getBoundingClientRect().right
  renderer.camera.shiftX = free > 500 ? (canvas.clientWidth - free) / canvas.clientWidth : 0
  const now = performance.now()
  const follow = instance.follow?.()
  if (follow) {
    // ease toward the followed point with a 0.12 s time constant, whatever the frame rate
    const t = renderer.camera.target
    const a = 1 - Math.exp(-Math.min(0.1, (now - lastRender) / 1000) / 0.12)
    for (let k = 0; k < 3; k++) t[k] += (follow[k] - t[k]) * a
  }
  const yaw = instance.followYaw?.()
  if (yaw !== undefined && now - lastOrbit > 5000) {
    // swing the shorter way round, with a 1.5 s time constant
    const cam = renderer.camera
    const d = yaw - cam.yaw - 2 * Math.PI * Math.round((yaw - cam.yaw) / (2 * Math.PI))
    cam.yaw += d * (1 - Math.exp(-Math.min(0.1, (now - lastRender) / 1000) / 1.5))
  }
  lastRender = now
  renderer.begin()
  instance.draw?.(renderer)
  let particles = 0, constraints = 0, maxStretch = 0, asleep = 0
  for (const cloth of instance.cloths) {
    if (isClothSleeping(world, cloth)) asleep++
    const c = getClothState(world, cloth)
    const base = instance.colors?.get(cloth) ?? [0.78, 0.76, 0.7]
    renderer.drawDynamic(clothKey(cloth), getClothMesh(world, cloth), stretchColors(cloth, base))
    particles += c.count
    constraints += c.topology.distCount + c.topology.compCount + c.topology.hingeCount + c.tethers.set.count
    maxStretch = Math.max(maxStretch, getClothStretch(world, cloth).max)
  }
  lastStats = { particles, constraints, maxStretch }
  drawLabels(instance.labels?.() ?? [])
  $('stats').textContent = [
    `ms/step    ${stepMs.toFixed(3)}`,
    `particles  ${particles}`,
    `constraints ${constraints}`,
    `max stretch ${(maxStretch * 100).toFixed(2)} %`,
    `fps        ${fps.toFixed(0)}`,
    ...(asleep > 0 ? [`asleep     ${asleep} of ${instance.cloths.length}`] : []),
    ...(instance.stats?.() ?? []),
  ].join('\n')
}

/** Renders a frame now and reads the canvas back: how much of it differs from the clear colour. */
function snapshot(): { coverage: number; colors: number } {
  render()
  const gl = renderer.gl
  const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight
  const px = new Uint8Array(4 * w * h)
  gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px)
  let drawn = 0
  const seen = new Set<number>()
  for (let i = 0; i < px.length; i += 4 * 7) {
    const r = px[i], g = px[i + 1], b = px[i + 2]
    if (Math.abs(r - 27) + Math.abs(g - 29) + Math.abs(b - 34) > 6) drawn++
    seen.add((r >> 3) | ((g >> 3) << 5) | ((b >> 3) << 10))
  }
  return { coverage: drawn / (px.length / (4 * 7)), colors: seen.size }
}

/** A cloth's particle positions now (a copy), for tests that compare frames. */
function positions(index = 0): number[] {
  const cloth = instance.cloths[index]
  const c = getClothState(world, cloth)
  return Array.from(c.pos.subarray(0, 3 * c.count))
}

/** Where a world point appears on the page, in CSS pixels (for tests that click on things). */
function screenPoint(p: ArrayLike<number>): [number, number] {
  const m = renderer.camera.viewProj
  const r = canvas.getBoundingClientRect()
  const x = m[0] * p[0] + m[4] * p[1] + m[8] * p[2] + m[12]
  const y = m[1] * p[0] + m[5] * p[1] + m[9] * p[2] + m[13]
  const w = m[3] * p[0] + m[7] * p[1] + m[11] * p[2] + m[15]
  return [r.left + ((x / w + 1) / 2) * r.width, r.top + ((1 - y / w) / 2) * r.height]
}

/** Hook for browser tests. */
;(window as unknown as { __demo: unknown }).__demo = {
  snapshot,
  positions,
  screenPoint,
  get ready() {
    return frame > 2
  },
  get frame() {
    return frame
  },
  get scene() {
    return scene.id
  },
  get stats() {
    return { ...lastStats, stepMs, fps }
  },
  get world() {
    return world
  },
  get cloths() {
    return instance.cloths
  },
  /** The current scene's own actions and readouts (e.g. `throw()` in the curtain scene). */
  get api() {
    return instance.api ?? {}
  },
  /** Tears so far, summed over the scene's cloths. */
  tearCount() {
    let n = 0
    for (const cloth of instance.cloths) n += getClothTearCount(world, cloth)
    return n
  },
  scenes: scenes.map((s) => s.id),
  loadScene,
  settings,
  applySettings,
}

loadScene(params.get('scene') ?? scenes[0].id)
requestAnimationFrame(tick)
