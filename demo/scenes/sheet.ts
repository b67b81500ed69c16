import { addEntity } from 'bitecs'
import { createCloth, pinParticle, pinRow, setTransform, unpin } from '../../src/index'
import { addButton, type DemoScene } from '../scene'

/**
 * A 1 m sheet hanging from a rail that sways gently: by its whole top row, or (button) by its two
 * top corners. The pins follow the rail entity's Transform.
 */
export const sheetScene: DemoScene = {
  id: 'sheet',
  title: 'Hanging sheet',
  defaults: { substeps: 4, iterations: 1, material: 'cotton' },
  camera: { target: [0, 1.3, 0], distance: 2.6, yaw: 0.5, pitch: 0.15 },
  create({ world, settings, ui }) {
    const n = 32
    const rail = addEntity(world as never)
    setTransform(world, rail, [0, 1.9, 0])
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
    const corners = () => [pinParticle(world, cloth, 0, rail), pinParticle(world, cloth, n - 1, rail)]
    let row = true
    let pins = pinRow(world, cloth, 0, rail)
    addButton(ui, 'Pin corners / top row', () => {
      for (const p of pins) unpin(world, p)
      row = !row
      pins = row ? pinRow(world, cloth, 0, rail) : corners()
    }, 'pin-mode')
    let railX = 0
    return {
      cloths: [cloth],
      update(time) {
        railX = 0.08 * Math.sin(time * 1.7)
        setTransform(world, rail, [railX, 1.9, 0.05 * Math.sin(time * 1.1)])
      },
      draw(r) {
        r.ground(0)
        r.capsule([railX, 1.9, 0], [0, 0, Math.SQRT1_2, Math.SQRT1_2], 0.012, 0.6, [0.75, 0.75, 0.78])
      },
    }
  },
}
