import * as THREE from 'three'
import { createCloth, createWindZone, gustWind, pinParticle, setWindZone } from '../../src/index'
import { brass, flagFabric, paint, shadows, steel } from '../fabrics'
import { addButton, addSlider, addToggle, type DemoScene } from '../scene'

/**
 * A flag laced to a pole in a turbulent wind zone: sliders for wind speed and turbulence, gusts
 * now and then (and a Gust button).
 */
export const flagScene: DemoScene = {
  id: 'flag',
  title: 'Flag in the wind',
  // a light flag carries ~100 g of wind load: a few iterations keep its edges from stretching
  defaults: { substeps: 8, iterations: 3, material: 'nylon' },
  camera: { target: [0.85, 2.75, 0], distance: 4.3, yaw: 0.35, pitch: 0.0, fit: 0.7 },
  shadowRadius: 4,
  moments: [
    { name: 'rest', seconds: 5, action: 'calm' },
    { name: 'motion', seconds: 4.2, action: 'gust', actionAt: 3.4 },
  ],
  create({ world, settings, ui, root, showCloth }) {
    const cols = 30, rows = 20
    const top = 3.4, height = 1.0, width = 1.5
    const flag = createCloth(world, {
      width,
      height,
      resolution: [cols, rows],
      position: [width / 2 + 0.04, top, 0],
      material: settings.material,
      substeps: settings.substeps,
      iterations: settings.iterations,
      tethers: settings.tethers,
    })
    // the hoist (left edge) laced to the pole
    for (let r = 0; r < rows; r++) pinParticle(world, flag, r * cols)
    showCloth(flag, flagFabric())

    // pole on a stone plinth, a brass finial
    const poleH = top + 0.22
    const pole = new THREE.Mesh(new THREE.CylinderGeometry(0.03, 0.04, poleH, 20), steel())
    pole.position.set(0, poleH / 2, 0)
    const finial = new THREE.Mesh(new THREE.SphereGeometry(0.06, 20, 14), brass())
    finial.position.set(0, poleH + 0.05, 0)
    const plinth = new THREE.Mesh(new THREE.BoxGeometry(0.6, 0.3, 0.6), paint(0x9a958c, 0.9))
    plinth.position.set(0, 0.15, 0)
    const ring = (y: number) => {
      const m = new THREE.Mesh(new THREE.TorusGeometry(0.045, 0.008, 8, 20), brass())
      m.rotation.x = Math.PI / 2
      m.position.set(0, y, 0)
      return m
    }
    root.add(shadows(pole), shadows(finial), shadows(plinth), shadows(ring(top + 0.01)), shadows(ring(top - height + 0.01)))

    let strength = 9
    let turbulence = 0.35
    let autoGusts = true
    let nextGust = 4
    const wind = createWindZone(world, { direction: [1, 0, -0.3], strength, turbulence, turbulenceScale: 1.5, seed: 7 })
    const strengthInput = addSlider(ui, 'Wind m/s', 0, 30, 0.5, strength, (v) => {
      strength = v
      setWindZone(world, wind, { strength })
    }, 'wind-strength')
    addSlider(ui, 'Turbulence', 0, 1, 0.05, turbulence, (v) => {
      turbulence = v
      setWindZone(world, wind, { turbulence })
    }, 'wind-turbulence')
    addToggle(ui, 'Gusts now and then', autoGusts, (v) => (autoGusts = v), 'auto-gusts')
    const gust = () => gustWind(world, wind, { strength: Math.max(6, strength), duration: 1.6 })
    addButton(ui, 'Gust', gust, 'gust')
    return {
      cloths: [flag],
      update(time) {
        if (autoGusts && time >= nextGust) {
          gust()
          // the next one in 5 to 9 s (a fixed sequence: the same run every time)
          nextGust = time + 5 + 4 * ((Math.sin(time * 12.9898) * 43758.5453) % 1 + 1) % 1
        }
      },
      stats: () => [`wind        ${strength.toFixed(1)} m/s`, `turbulence  ${turbulence.toFixed(2)}`],
      api: {
        gust,
        /** A light breeze: the flag hangs and stirs. */
        calm: () => {
          strength = 1.5
          autoGusts = false
          strengthInput.value = String(strength)
          strengthInput.dispatchEvent(new Event('input'))
        },
      },
    }
  },
}
