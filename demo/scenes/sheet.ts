import { createCloth, pinParticle, pinRow, unpin } from '../../src/index'
import { addButton, type DemoScene } from '../scene'

/** A 1 m sheet hanging from its two top corners; toggle to the whole top row. */
export const sheetScene: DemoScene = {
  id: 'sheet',
  title: 'Hanging sheet',
  defaults: { substeps: 4, iterations: 1, material: 'cotton' },
  camera: { target: [0, 1.3, 0], distance: 2.6, yaw: 0.5, pitch: 0.15 },
  create({ world, settings, ui }) {
    const n = 32
    const cloth = createCloth(world, {
      width: 1,
      height: 1,
      resolution: n,
      position: [0, 1.9, 0],
      material: settings.material,
      substeps: settings.substeps,
      iterations: settings.iterations,
      tethers: settings.tethers,
    })
    let pins = [pinParticle(world, cloth, 0), pinParticle(world, cloth, n - 1)]
    let row = false
    addButton(ui, 'Pin top row / corners', () => {
      for (const p of pins) unpin(world, p)
      row = !row
      pins = row ? pinRow(world, cloth, 0) : [pinParticle(world, cloth, 0), pinParticle(world, cloth, n - 1)]
    })
    return {
      cloths: [cloth],
      draw(r) {
        r.ground(0)
        r.sphere([-0.5, 1.9, 0], 0.02, [0.9, 0.9, 0.9])
        r.sphere([0.5, 1.9, 0], 0.02, [0.9, 0.9, 0.9])
      },
    }
  },
}
