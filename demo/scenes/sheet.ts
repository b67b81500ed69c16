import { addEntity } from 'bitecs'
import * as THREE from 'three'
import { createCloth, pinParticle, pinRow, setTransform, unpin } from '../../src/index'
import { ginghamFabric, shadows, steel } from '../fabrics'
import { addButton, type DemoScene } from '../scene'

/**
 * A 1 m sheet hanging from a rail that sways gently: by its whole top row, or (button) by its two
 * top corners. The pins follow the rail entity's Transform.
 */
export const sheetScene: DemoScene = {
  id: 'sheet',
  title: 'Hanging sheet',
  defaults: { substeps: 4, iterations: 1, material: 'cotton' },
  camera: { target: [0, 1.3, 0], distance: 3, yaw: 0.5, pitch: 0.15, fit: 0.6 },
  shadowRadius: 2.5,
  moments: [
    { name: 'rest', seconds: 3 },
    { name: 'motion', seconds: 1.1 },
  ],
  create({ world, settings, ui, root, showCloth }) {
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
    const togglePins = () => {
      for (const p of pins) unpin(world, p)
      row = !row
      pins = row ? pinRow(world, cloth, 0, rail) : corners()
    }
    addButton(ui, 'Pin corners / top row', togglePins, 'pin-mode')
    showCloth(cloth, ginghamFabric('#4f7a4a', 10))
    const bar = new THREE.Mesh(new THREE.CylinderGeometry(0.012, 0.012, 1.2, 12).rotateZ(Math.PI / 2), steel())
    root.add(shadows(bar))
    const railAt = [0, 1.9, 0]
    return {
      cloths: [cloth],
      update(time) {
        railAt[0] = 0.08 * Math.sin(time * 1.7)
        railAt[2] = 0.05 * Math.sin(time * 1.1)
        setTransform(world, rail, railAt)
      },
      sync: () => bar.position.set(railAt[0], railAt[1] + 0.014, railAt[2]),
      api: { corners: () => row && togglePins() },
    }
  },
}
