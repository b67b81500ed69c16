import type { Renderer } from './renderer'

/** Settings shared by every scene, driven by the panel. */
export interface DemoSettings {
  material: string
  substeps: number
  iterations: number
  tethers: boolean
}

/** What a scene gets when it is built: a fresh world with the plugin installed. */
export interface SceneContext {
  world: object
  settings: DemoSettings
  /** Container for the scene's own controls (buttons, sliders). */
  ui: HTMLElement
  /** Re-applies `settings` (after the scene changed them) and shows them in the panel. */
  refresh(): void
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
  /** Cloth entities to draw (with stretch tint) and count in the stats. */
  cloths: number[]
  /** Base colour per cloth (defaults to a neutral cloth colour). */
  colors?: Map<number, [number, number, number]>
  /** Called every frame before stepping: move characters, colliders, wind. */
  update?(time: number, dt: number): void
  /** Draws everything that is not cloth. */
  draw?(renderer: Renderer): void
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
  /** Actions and readouts for scripts and browser tests, exposed as `window.__demo.api`. */
  api?: Record<string, (...args: never[]) => unknown>
}

/** A scene in the menu. Scenes use only the public API of bitecs-cloth. */
export interface DemoScene {
  id: string
  title: string
  /** Settings this scene starts with (the panel shows them). */
  defaults?: Partial<DemoSettings>
  camera?: { target: [number, number, number]; distance: number; yaw?: number; pitch?: number }
  /** What the mouse does in this scene (shown at the bottom of the page). */
  hint?: string
  create(ctx: SceneContext): SceneInstance
}

/** Adds a button to a scene's control area. */
export function addButton(ui: HTMLElement, label: string, onClick: () => void, id?: string): HTMLButtonElement {
  const b = document.createElement('button')
  b.textContent = label
  if (id) b.id = id
  b.addEventListener('click', onClick)
  ui.appendChild(b)
  return b
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
    onInput(Number(input.value))
  })
  row.append(label, input, out)
  ui.appendChild(row)
  return input
}
