import type * as THREE from 'three'
import type { ClothPluginOptions, RenderProxyOptions } from '../src/index'

/** Settings shared by every scene, driven by the panel. */
export interface DemoSettings {
  material: string
  substeps: number
  iterations: number
  tethers: boolean
  /** Solve each row and column of edges at once (`lineSolve`). */
  lineSolve: boolean
}

/** What a scene gets when it is built: a fresh world with the plugin installed. */
export interface SceneContext {
  world: object
  settings: DemoSettings
  /** Container for the scene's own controls (buttons, sliders). */
  ui: HTMLElement
  /** Re-applies `settings` (after the scene changed them) and shows them in the panel. */
  refresh(): void
  /** three.js group the scene adds its objects to; emptied and disposed when the scene goes. */
  root: THREE.Group
  /**
   * Draws a cloth: makes its mesh through `bitecs-cloth/three` with this material (two-sided,
   * casting and receiving shadows), adds it to `root`, and keeps its geometry up to date after
   * every step. With `fine`, a render mesh finer than the cloth (`createRenderProxy`, in the cloth's
   * rest frame) is drawn instead, except in the stretch tint. Returns the mesh drawn.
   */
  showCloth(cloth: number, material: THREE.Material, fine?: RenderProxyOptions): THREE.Mesh
  /** The view: camera, renderer, sun (e.g. for the crowd's frustum test). */
  camera: THREE.PerspectiveCamera
  /** Builds the scene again in a fresh world (e.g. after a change of `worldOptions`). */
  reload(): void
}

/** A text label drawn over the canvas at a world point (an HTML overlay). */
export interface SceneLabel {
  text: string
  at: ArrayLike<number>
  /** Extra CSS class (e.g. 'title' for a larger heading). */
  className?: string
}

/** A live scene. */
export interface SceneInstance {
  /** Cloth entities of the scene (drag, stats, tests). */
  cloths: number[]
  /** Called every frame before stepping: move characters, colliders, wind. */
  update?(time: number, dt: number): void
  /**
   * Steps the world's cloths by `dt` (default `stepCloth(world, dt)`); returns the fixed steps
   * taken. A scene that steps differently (the crowd) does it here, in one place.
   */
  step?(dt: number): number
  /**
   * The live loop's step, when the scene has one that does not block (the crowd on workers:
   * `beginClothStep`, then `await endClothStepAsync`): the frame is drawn once it resolves.
   * `step` still serves `simulate`, which runs steps back to back.
   */
  stepAsync?(dt: number): Promise<number>
  /** Called before drawing: move three.js objects to the entities' poses. */
  sync?(): void
  /** Applies a change of the panel's substeps/iterations/tethers (default: to every cloth). */
  applySettings?(settings: DemoSettings): void
  /** Extra stats lines. */
  stats?(): string[]
  /** A point the camera keeps looking at (e.g. a moving character). */
  follow?(): ArrayLike<number>
  /**
   * The camera yaw to view the followed point from (e.g. behind a character, so its cape shows):
   * the camera swings toward it slowly, and leaves it to the user for a while after they orbit.
   */
  followYaw?(): number
  /**
   * A left click on the canvas (press and release without dragging), with the world-space ray
   * through the clicked point. Pressing and moving still drags cloth or orbits.
   */
  click?(origin: ArrayLike<number>, direction: ArrayLike<number>): void
  /** Labels to draw over the canvas this frame (the same array each call is fine). */
  labels?(): readonly SceneLabel[]
  /** Panel settings the scene does not take from the panel (shown disabled). */
  locked?(): readonly (keyof DemoSettings)[]
  /**
   * Materials the scene may switch its meshes to later (e.g. the crowd's LOD tint): their shaders
   * are compiled when the scene loads and kept drawn (a triangle under the floor each), so the
   * first switch does not stall a frame.
   */
  warmup?: readonly THREE.Material[]
  /** Actions and readouts for scripts and browser tests, exposed as `window.__demo.api`. */
  api?: Record<string, (...args: never[]) => unknown>
}

/** A moment of a scene worth a picture: `seconds` of simulation after loading, after `action`. */
export interface SceneMoment {
  name: string
  seconds: number
  /** Name of an `api` action to call, `actionAt` seconds after loading (default 0). */
  action?: string
  actionAt?: number
  /** Not one of the README's pictures: taken only with `npm run screenshots -- --all`. */
  extra?: boolean
}

/** A scene in the menu. Scenes use only the public API of bitecs-cloth. */
export interface DemoScene {
  id: string
  title: string
  /** Settings this scene starts with (the panel shows them). */
  defaults?: Partial<DemoSettings>
  /**
   * Where the camera starts. `fit`: the narrowest aspect ratio (width / height) of the free part of
   * the canvas at which everything the scene shows across still fits at the camera's field of
   * view; a narrower one (a window upright, the panel beside the picture) zooms out to keep it in
   * (default 1; 0 never zooms out).
   */
  camera?: { target: [number, number, number]; distance: number; yaw?: number; pitch?: number; fov?: number; fit?: number }
  /** Half-size of the sun's shadow box around the camera target, m (default 4). */
  shadowRadius?: number
  /** Shadow map size, texels (default 2048). */
  shadowMapSize?: number
  /** Direction toward the sun (default from the front left: [−0.45, 0.8, 0.4]). */
  sun?: [number, number, number]
  /**
   * Longest simulated time per drawn frame, s (default 0.05): when frames take longer, the scene
   * runs slower than real time rather than taking ever more fixed steps per frame.
   */
  maxFrameTime?: number
  /** What the mouse does in this scene (shown at the bottom of the page). */
  hint?: string
  /** Pictures for the README (`npm run screenshots`). */
  moments?: SceneMoment[]
  /**
   * Puts back what the scene keeps across its reloads (e.g. which counts the accuracy scene
   * compares): the panel's Reset calls it before loading the scene with its defaults.
   */
  resetState?(): void
  /** Plugin options of the scene's world (e.g. `threads`); read each time the scene loads. */
  worldOptions?(): ClothPluginOptions
  create(ctx: SceneContext): SceneInstance
}

/** Runs an input's change now, or later while workers step the world (set by main.ts). */
let defer: (change: () => void) => void = (change) => change()

/** Sets how the controls' changes run (main.ts holds them back while workers step the world). */
export function setInputDeferral(d: (change: () => void) => void): void {
  defer = d
}

/** Adds a button to a scene's control area. */
export function addButton(ui: HTMLElement, label: string, onClick: () => void, id?: string): HTMLButtonElement {
  const b = document.createElement('button')
  b.textContent = label
  if (id) b.id = id
  b.addEventListener('click', () => defer(onClick))
  ui.appendChild(b)
  return b
}

/** Adds a row of buttons of which one is active (a segmented switch); returns a setter. */
export function addSegmented<T extends string>(
  ui: HTMLElement,
  label: string,
  options: readonly [T, string][],
  value: T,
  onPick: (v: T) => void,
  idPrefix: string,
): (v: T) => void {
  const row = document.createElement('div')
  row.className = 'segmented'
  if (label) row.append(label + ' ')
  ui.appendChild(row)
  const buttons = options.map(([v, text]) => addButton(row, text, () => pick(v, true), `${idPrefix}-${v}`))
  const pick = (v: T, notify: boolean) => {
    options.forEach(([o], k) => buttons[k].classList.toggle('active', o === v))
    if (notify) onPick(v)
  }
  pick(value, false)
  return (v: T) => pick(v, false)
}

/** Adds a labelled slider to a scene's control area; returns the input. */
export function addSlider(
  ui: HTMLElement,
  label: string,
  min: number,
  max: number,
  step: number,
  value: number,
  onInput: (v: number) => void,
  id?: string,
): HTMLInputElement {
  const row = document.createElement('label')
  const input = document.createElement('input')
  input.type = 'range'
  input.min = String(min)
  input.max = String(max)
  input.step = String(step)
  input.value = String(value)
  if (id) input.id = id
  const out = document.createElement('span')
  out.textContent = String(value)
  input.addEventListener('input', () => {
    out.textContent = input.value
    const v = Number(input.value)
    defer(() => onInput(v))
  })
  row.append(label, input, out)
  ui.appendChild(row)
  return input
}

/** Adds a labelled checkbox to a scene's control area; returns the input. */
export function addToggle(ui: HTMLElement, label: string, value: boolean, onChange: (v: boolean) => void, id?: string): HTMLInputElement {
  const row = document.createElement('label')
  const input = document.createElement('input')
  input.type = 'checkbox'
  input.checked = value
  if (id) input.id = id
  input.addEventListener('change', () => {
    const v = input.checked
    defer(() => onChange(v))
  })
  row.append(label, input)
  ui.appendChild(row)
  return input
}
