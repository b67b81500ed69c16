import { addEntity, removeEntity } from 'bitecs'
import { createCloth, getClothTearCount, makeTearable, onClothTear, pinParticle, setTransform, unpin } from '../../src/index'
import { addButton, type DemoScene } from '../scene'

/**
 * A tearable curtain hanging from hooks on a rail. Drag it with the mouse (or press Yank) to tear
 * it; torn pieces keep hanging from their hooks or fall away. (A thrown ball arrives with
 * colliders.)
 */
export const curtainScene: DemoScene = {
  id: 'curtain',
  title: 'Tearing curtain',
  defaults: { substeps: 8, iterations: 1, material: 'cotton' },
  camera: { target: [0, 1.3, 0], distance: 3.6, yaw: 0.35, pitch: 0.12 },
  create({ world, settings, ui }) {
    const cols = 36, rows = 30
    const width = 2, height = 1.8, top = 2.3
    const curtain = createCloth(world, {
      width,
      height,
      resolution: [cols, rows],
      position: [0, top, 0],
      material: settings.material,
      substeps: settings.substeps,
      iterations: settings.iterations,
      tethers: settings.tethers,
    })
    // a hook every third particle along the rail
    for (let c = 0; c < cols; c += 3) pinParticle(world, curtain, c)
    pinParticle(world, curtain, cols - 1)
    makeTearable(world, curtain, { strain: 0.35, maxTearsPerStep: 4 })
    let flashes = 0
    onClothTear(world, () => flashes++)

    // Yank: grab the bottom edge at a point and pull it toward the camera and down
    let yank: { pin: number; hand: number; t: number; from: number[] } | null = null
    const startYank = () => {
      if (yank) return
      const index = (rows - 1) * cols + Math.floor(cols * (0.3 + 0.4 * ((flashes * 7919) % 10) / 10))
      const hand = addEntity(world as never)
      const from = [-width / 2 + (index % cols) * (width / (cols - 1)), top - height, 0]
      setTransform(world, hand, from)
      yank = { pin: pinParticle(world, curtain, index, hand), hand, t: 0, from }
    }
    addButton(ui, 'Yank', startYank, 'yank')
    let auto = false
    return {
      cloths: [curtain],
      colors: new Map([[curtain, [0.55, 0.1, 0.16]]]),
      update(time, dt) {
        if (!auto && time > 1.2) {
          auto = true
          startYank()
        }
        if (!yank) return
        yank.t += dt
        const u = Math.min(1, yank.t / 0.9)
        setTransform(world, yank.hand, [yank.from[0] + 0.3 * u, yank.from[1] - 0.6 * u, yank.from[2] + 1.6 * u])
        if (yank.t > 1.1) {
          unpin(world, yank.pin)
          removeEntity(world as never, yank.hand)
          yank = null
        }
      },
      draw(r) {
        r.ground(0)
        r.capsule([0, top + 0.03, 0], [0, 0, Math.SQRT1_2, Math.SQRT1_2], 0.025, width / 2 + 0.1, [0.6, 0.6, 0.62])
      },
      stats: () => [`tears      ${getClothTearCount(world, curtain)}`],
    }
  },
}
