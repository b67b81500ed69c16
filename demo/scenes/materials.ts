import { addEntity } from 'bitecs'
import {
  addPlaneCollider,
  createCloth,
  createWindZone,
  gustWind,
  pinRow,
  resolveMaterial,
  setTransform,
  setWindZone,
} from '../../src/index'
import { addButton, addSlider, type DemoScene, type SceneLabel } from '../scene'

const MATERIALS: { name: string; color: [number, number, number]; note: string }[] = [
  { name: 'silk', color: [0.86, 0.74, 0.42], note: 'light, floppy, catches the wind' },
  { name: 'cotton', color: [0.74, 0.77, 0.82], note: 'the default' },
  { name: 'leather', color: [0.5, 0.3, 0.17], note: 'heavy and stiff' },
  { name: 'rubber', color: [0.16, 0.5, 0.46], note: 'heavy and stretchy' },
]
const SPACING = 1.1
const TOP = 2.3

/**
 * Silk, cotton, leather and rubber side by side, the same size and resolution, hanging from one
 * rail in the same wind: their weight, bending stiffness, stretch and drag come from the material
 * presets alone.
 */
export const materialsScene: DemoScene = {
  id: 'materials',
  title: 'Materials',
  // tethers off: rubber's stretch is part of the comparison
  defaults: { substeps: 8, iterations: 1, tethers: false },
  camera: { target: [0.3, 1.5, -0.2], distance: 4.9, yaw: 0.25, pitch: 0.16 },
  create({ world, settings, ui }) {
    const ground = addEntity(world as never)
    setTransform(world, ground, [0, 0, 0])
    addPlaneCollider(world, ground)
    let strength = 1
    // eddies much larger than the row of sheets: every sheet feels the same air
    const wind = createWindZone(world, { direction: [0.35, 0, -1], strength, turbulence: 0.35, turbulenceScale: 15, turbulencePeriod: 1.2, seed: 11 })
    const x0 = (-(MATERIALS.length - 1) / 2) * SPACING
    const cloths = MATERIALS.map((m, k) => {
      const cloth = createCloth(world, {
        width: 0.8,
        height: 1.1,
        resolution: [14, 19],
        position: [x0 + k * SPACING, TOP, 0],
        material: m.name,
        substeps: settings.substeps,
        iterations: settings.iterations,
        tethers: settings.tethers,
      })
      pinRow(world, cloth, 0)
      return cloth
    })
    addSlider(ui, 'Wind m/s', 0, 20, 0.5, strength, (v) => {
      strength = v
      setWindZone(world, wind, { strength })
    }, 'wind-strength')
    addButton(ui, 'Gust', () => gustWind(world, wind, { strength: Math.max(5, strength), duration: 1.6 }), 'gust')

    const labels: SceneLabel[] = MATERIALS.flatMap((m, k) => {
      const spec = resolveMaterial(m.name)
      const density = spec.density >= 1 ? `${spec.density} kg/m²` : `${Math.round(spec.density * 1000)} g/m²`
      return [
        { text: m.name[0].toUpperCase() + m.name.slice(1), at: [x0 + k * SPACING, 0.78, 0.2], className: 'title' },
        { text: `${density}\n${m.note}`, at: [x0 + k * SPACING, 0.58, 0.2], className: 'dim' },
      ]
    })
    return {
      cloths,
      colors: new Map(cloths.map((c, k) => [c, MATERIALS[k].color])),
      draw(r) {
        r.ground(0)
        const span = (MATERIALS.length - 1) * SPACING + 1.0
        r.capsule([0, TOP + 0.02, 0], [0, 0, Math.SQRT1_2, Math.SQRT1_2], 0.02, span / 2, [0.62, 0.63, 0.66])
        for (const px of [-span / 2, span / 2]) r.capsule([px, TOP / 2, 0], [0, 0, 0, 1], 0.03, TOP / 2, [0.4, 0.42, 0.46])
      },
      labels: () => labels,
      locked: () => ['material'],
      stats: () => [`wind       ${strength.toFixed(1)} m/s`],
    }
  },
}
