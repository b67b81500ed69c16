import { buildGridMesh, createCloth, createWindZone, pinRow, removeWindZone } from '../../src/index'
import { Character, CharacterFigure, type Move } from '../character'
import { capeFabric } from '../fabrics'
import { addButton, addSegmented, type DemoScene } from '../scene'

/**
 * A cape pinned along a character's shoulders (to its chest entity's Transform). The character
 * stands, walks, runs, sprints, turns on the spot, jumps and teleports, by itself or as told;
 * capsules on its torso, arms and legs and a sphere on its head keep the cape on its back.
 */
export const capeScene: DemoScene = {
  id: 'cape',
  title: 'Cape',
  defaults: { substeps: 8, iterations: 1, material: 'wool' },
  camera: { target: [0, 1.1, 0], distance: 3.3, yaw: Math.PI + 0.8, pitch: 0.16 },
  shadowRadius: 3,
  sun: [-0.75, 0.7, -0.3],
  moments: [
    { name: 'rest', seconds: 3, action: 'stand' },
    { name: 'motion', seconds: 3.2, action: 'run' },
    { name: 'walk', seconds: 3, action: 'walk', extra: true },
    { name: 'sprint', seconds: 3.5, action: 'sprint', extra: true },
    { name: 'turn', seconds: 2.9, action: 'turn', actionAt: 2, extra: true },
    { name: 'jump', seconds: 3.05, action: 'jump', actionAt: 2.5, extra: true },
  ],
  create({ world, settings, ui, root, showCloth }) {
    const hero = new Character(world)
    const figure = new CharacterFigure(hero)
    root.add(figure.group)
    const cape = createCloth(world, {
      width: 0.55,
      height: 1.05,
      resolution: [14, 24],
      position: hero.chestPoint(0, 0.49, -0.2).toArray(),
      rotation: hero.chestRotation(),
      material: settings.material,
      substeps: settings.substeps,
      iterations: settings.iterations,
      tethers: settings.tethers,
    })
    pinRow(world, cape, 0, hero.chest)
    // drawn through a render proxy four times finer (every simulated edge in four): smooth folds
    showCloth(cape, capeFabric(), buildGridMesh({ width: 0.55, height: 1.05, resolution: [53, 93] }))

    const moves: [Move | 'auto', string][] = [['auto', 'Auto'], ['stand', 'Stand'], ['walk', 'Walk'], ['run', 'Run'], ['sprint', 'Sprint']]
    const setMode = addSegmented(ui, '', moves, 'auto', (m) => hero.command(m), 'move')
    const oneOff = (m: Move) => () => {
      hero.command(m)
      setMode(hero.gait)
    }
    addButton(ui, 'Turn', oneOff('turn'), 'turn')
    addButton(ui, 'Jump', oneOff('jump'), 'jump')
    addButton(ui, 'Teleport 8 m', oneOff('teleport'), 'teleport')
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
    const command = (m: Move | 'auto') => () => {
      hero.command(m)
      setMode(m === 'auto' ? 'auto' : hero.gait)
    }
    return {
      cloths: [cape],
      update(_time, dt) {
        hero.update(dt)
      },
      sync: () => figure.sync(),
      stats: () => [`speed       ${hero.speed.toFixed(1)} m/s`, `doing       ${hero.doing}${hero.auto ? ' (auto)' : ''}`],
      follow: () => hero.chestPoint(0, 0.12, 0).toArray(),
      followYaw: () => hero.heading + Math.PI + 0.8, // behind the character and to its right: the cape in three-quarter view
      api: {
        auto: command('auto'),
        stand: command('stand'),
        walk: command('walk'),
        run: command('run'),
        sprint: command('sprint'),
        turn: command('turn'),
        jump: command('jump'),
        teleport: command('teleport'),
        speed: () => hero.speed,
        doing: () => hero.doing,
      },
    }
  },
}
