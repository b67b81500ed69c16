import { createCloth, createWindZone, gustWind, pinParticle, setWindZone } from '../../src/index'
import { addButton, addSlider, type DemoScene } from '../scene'

/** A flag on a pole in a turbulent wind zone: strength and turbulence sliders, and a gust button. */
export const flagScene: DemoScene = {
  id: 'flag',
  title: 'Flag in the wind',
  // a light flag carries ~100 g of wind load: a few iterations keep its edges from stretching
  defaults: { substeps: 8, iterations: 3, material: 'nylon' },
  camera: { target: [0.9, 2.6, 0.6], distance: 4.2, yaw: 0.9, pitch: 0.12 },
  create({ world, settings, ui }) {
    const cols = 30, rows = 20
    const top = 3.4, height = 1.0, width = 1.5
    const flag = createCloth(world, {
      width,
      height,
      resolution: [cols, rows],
      position: [width / 2, top, 0],
      material: settings.material,
      substeps: settings.substeps,
      iterations: settings.iterations,
      tethers: settings.tethers,
    })
    // the hoist (left edge) laced to the pole
    for (let r = 0; r < rows; r++) pinParticle(world, flag, r * cols)
    let strength = 9
    let turbulence = 0.35
    const wind = createWindZone(world, { direction: [0.4, 0, -1], strength, turbulence, turbulenceScale: 1.5, seed: 7 })
    addSlider(ui, 'Wind m/s', 0, 30, 0.5, strength, (v) => {
      strength = v
      setWindZone(world, wind, { strength })
    }, 'wind-strength')
    addSlider(ui, 'Turbulence', 0, 1, 0.05, turbulence, (v) => {
      turbulence = v
      setWindZone(world, wind, { turbulence })
    }, 'wind-turbulence')
    addButton(ui, 'Gust', () => gustWind(world, wind, { strength: Math.max(6, strength), duration: 1.6 }), 'gust')
    return {
      cloths: [flag],
      colors: new Map([[flag, [0.16, 0.36, 0.78]]]),
      draw(r) {
        r.ground(0)
        r.capsule([0, top / 2 + 0.1, 0], [0, 0, 0, 1], 0.03, top / 2 + 0.1, [0.75, 0.75, 0.78])
        r.sphere([0, top + 0.25, 0], 0.05, [0.85, 0.7, 0.2])
      },
      stats: () => [`wind       ${strength.toFixed(1)} m/s, turbulence ${turbulence.toFixed(2)}`],
    }
  },
}
