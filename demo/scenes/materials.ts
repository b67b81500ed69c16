import { addEntity } from 'bitecs'
import * as THREE from 'three'
import {
  addCapsuleCollider,
  addPlaneCollider,
  createCloth,
  createWindZone,
  gustWind,
  pinRow,
  resolveMaterial,
  setTransform,
  setWindZone,
} from '../../src/index'
import { ginghamFabric, leatherMaterial, paint, rubberMaterial, shadows, silkFabric, steel } from '../fabrics'
import { addButton, addSlider, type DemoScene, type SceneLabel } from '../scene'

const MATERIALS: { name: string; look: () => THREE.Material; note: string }[] = [
  { name: 'silk', look: silkFabric, note: 'light, catches the wind' },
  { name: 'cotton', look: () => ginghamFabric('#3b62a8', 8), note: 'the default' },
  { name: 'leather', look: leatherMaterial, note: 'heavy and stiff' },
  { name: 'rubber', look: rubberMaterial, note: 'heavy and stretchy' },
]
const SPACING = 1.1
const TOP = 2.3
const RAIL_RADIUS = 0.022

/**
 * Silk, cotton, leather and rubber side by side, the same size and resolution, hanging from one
 * rail in the same wind: their weight, bending stiffness, stretch and drag come from the material
 * presets alone. The rail is a capsule collider: cloth blown up against it drapes over it instead
 * of passing through.
 */
export const materialsScene: DemoScene = {
  id: 'materials',
  title: 'Materials',
  // tethers off: rubber's stretch is part of the comparison
  defaults: { substeps: 8, iterations: 1, tethers: false },
  camera: { target: [0, 1.45, 0], distance: 5.4, yaw: 0.3, pitch: 0.12, fit: 1.2 },
  shadowRadius: 4,
  moments: [
    { name: 'rest', seconds: 4 },
    { name: 'motion', seconds: 3.4, action: 'gust', actionAt: 2.2 },
  ],
  create({ world, settings, ui, root, showCloth }) {
    const ground = addEntity(world as never)
    setTransform(world, ground, [0, 0, 0])
    addPlaneCollider(world, ground)
    let strength = 1
    // eddies much larger than the row of sheets: every sheet feels the same air
    const wind = createWindZone(world, {
      direction: [0.35, 0, -1],
      strength,
      turbulence: 0.35,
      turbulenceScale: 15,
      turbulencePeriod: 1.2,
      seed: 11,
    })
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
      showCloth(cloth, m.look())
      return cloth
    })
    // the rail: a capsule collider just above the pinned top rows, drawn 2 mm thinner than it
    const span = (MATERIALS.length - 1) * SPACING + 1.0
    const railY = TOP + RAIL_RADIUS + 0.012
    const railEntity = addEntity(world as never)
    setTransform(world, railEntity, [0, railY, 0])
    addCapsuleCollider(world, railEntity, { radius: RAIL_RADIUS, halfHeight: span / 2, axis: [1, 0, 0] })
    const rail = new THREE.Mesh(
      new THREE.CylinderGeometry(RAIL_RADIUS - 0.002, RAIL_RADIUS - 0.002, span, 16).rotateZ(Math.PI / 2),
      steel(),
    )
    rail.position.set(0, railY, 0)
    root.add(shadows(rail))
    for (const px of [-span / 2, span / 2]) {
      const post = new THREE.Mesh(new THREE.CylinderGeometry(0.03, 0.035, railY + 0.05, 16), paint(0x3f444d, 0.45))
      post.position.set(px, (railY + 0.05) / 2, 0)
      root.add(shadows(post))
    }

    addSlider(ui, 'Wind m/s', 0, 20, 0.5, strength, (v) => {
      strength = v
      setWindZone(world, wind, { strength })
    }, 'wind-strength')
    const gust = () => gustWind(world, wind, { strength: Math.max(5, strength), duration: 1.6 })
    addButton(ui, 'Gust', gust, 'gust')

    const labels: SceneLabel[] = MATERIALS.flatMap((m, k) => {
      const spec = resolveMaterial(m.name)
      const density = spec.density >= 1 ? `${spec.density} kg/m²` : `${Math.round(spec.density * 1000)} g/m²`
      return [{
        text: `${m.name[0].toUpperCase() + m.name.slice(1)}\n${density}\n${m.note}`,
        at: [x0 + k * SPACING, 0.62, 0.2],
        className: 'card',
      }]
    })
    // in a narrow window the cards stand close together: name and weight only
    const narrow = window.matchMedia('(max-width: 639px)')
    const short = labels.map((l) => ({ ...l, text: l.text.split('\n').slice(0, 2).join('\n') }))
    return {
      cloths,
      labels: () => (narrow.matches ? short : labels),
      locked: () => ['material'],
      stats: () => [`wind        ${strength.toFixed(1)} m/s`],
      api: { gust, railY: () => railY, railRadius: () => RAIL_RADIUS },
    }
  },
}
