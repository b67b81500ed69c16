import { createCloth, createWindZone, pinRow, removeWindZone } from '../../src/index'
import { Character } from '../character'
import { addButton, type DemoScene } from '../scene'

/**
 * A cape pinned to a character's shoulders through its Transform; the character walks, runs,
 * turns and jumps. Capsules on its torso, arms and legs and a sphere on its head keep the cape on
 * its back.
 */
export const capeScene: DemoScene = {
  id: 'cape',
  title: 'Cape',
  defaults: { substeps: 8, iterations: 1, material: 'wool' },
  camera: { target: [0, 1.1, 0], distance: 4.3, yaw: Math.PI + 1.2, pitch: 0.22 },
  create({ world, settings, ui }) {
    const hero = new Character(world)
    hero.addColliders()
    const cape = createCloth(world, {
      width: 0.55,
      height: 1.05,
      resolution: [14, 24],
      position: hero.local(0, 1.47, -0.2),
      material: settings.material,
      substeps: settings.substeps,
      iterations: settings.iterations,
      tethers: settings.tethers,
    })
    pinRow(world, cape, 0, hero.eid)
    addButton(ui, 'Teleport 8 m', () => hero.teleport(8), 'teleport')
    // still air: a calm global wind zone, so the cape meets the air as the character runs and
    // streams behind it (per-triangle drag and lift; without it only the material's linear damping)
    let air: number | null = null
    const toggleAir = () => {
      if (air === null) air = createWindZone(world, { direction: [1, 0, 0], strength: 0 })
      else {
        removeWindZone(world, air)
        air = null
      }
      airButton.textContent = air === null ? 'Air drag: off' : 'Air drag: on'
    }
    const airButton = addButton(ui, '', toggleAir, 'air')
    toggleAir()
    return {
      cloths: [cape],
      colors: new Map([[cape, [0.72, 0.12, 0.14]]]),
      update(time, dt) {
        hero.update(time, dt)
      },
      draw(r) {
        r.ground(0)
        hero.draw(r)
      },
      stats: () => [`speed      ${hero.speed.toFixed(1)} m/s`],
      follow: () => hero.local(0, 1.1, 0),
      followYaw: () => hero.heading + Math.PI + 1.2, // behind the character and well to its right: the cape in profile
    }
  },
}
