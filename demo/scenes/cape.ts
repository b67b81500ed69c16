import { createCloth, pinRow } from '../../src/index'
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
  defaults: { substeps: 8, iterations: 1, material: 'cotton' },
  camera: { target: [0, 1.1, 0], distance: 4.3, yaw: Math.PI + 0.7, pitch: 0.22 },
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
      followYaw: () => hero.heading + Math.PI + 0.7, // behind the character and to its right
    }
  },
}
