import { createWindZone, removeWindZone, setClothCollision } from '../../src/index'
import {
  applyCapeSettings,
  CAPE_SETTINGS,
  capeHemAngle,
  capeShape,
  capeTorsoDepth,
  createCape,
  placeCape,
  type CapeSettings,
} from '../capeShape'
import { Character, CharacterFigure, type Move } from '../character'
import { capeFabric } from '../fabrics'
import { addButton, addSegmented, addSlider, addToggle, type DemoScene } from '../scene'

/** Rows (collar to hem) and columns of the simulated cape. */
const ROWS = 24, COLS = 15

/**
 * A cape pinned along its collar to the character's chest frame (its Transform), simulated in that
 * frame: it feels half the character's accelerations and turning (the Inertia slider), its collar
 * rows may move only a little from where the body carries them and its hem is free (max distance
 * painted from 0 at the collar), and a backstop keeps it off the back where no collider is. The
 * character stands, walks, runs, sprints, turns on the spot, jumps and teleports, by itself or as
 * told; capsules on its torso, arms and legs and a sphere on its head keep the cape on its back.
 */
export const capeScene: DemoScene = {
  id: 'cape',
  title: 'Cape',
  defaults: { substeps: 8, iterations: 1, material: 'wool' },
  camera: { target: [0, 1.1, 0], distance: 3.3, yaw: Math.PI + 0.8, pitch: 0.16, fit: 0.55 },
  shadowRadius: 3,
  sun: [-0.75, 0.7, -0.3],
  moments: [
    { name: 'rest', seconds: 3, action: 'stand' },
    { name: 'run', seconds: 3.2, action: 'run' },
    { name: 'turn', seconds: 2.9, action: 'turn', actionAt: 2 },
    { name: 'walk', seconds: 3, action: 'walk', extra: true },
    { name: 'sprint', seconds: 3.5, action: 'sprint', extra: true },
    { name: 'jump', seconds: 3.05, action: 'jump', actionAt: 2.5, extra: true },
  ],
  create({ world, settings, ui, root, showCloth }) {
    const hero = new Character(world)
    const figure = new CharacterFigure(hero)
    root.add(figure.group)
    const { cape, mesh } = createCape(world, hero, { rows: ROWS, cols: COLS, ...settings })
    // drawn through a render proxy four times finer (every simulated edge in four): smooth folds
    const fine = capeShape(4 * (ROWS - 1) + 1, 4 * (COLS - 1) + 1)
    showCloth(cape, capeFabric(), { positions: placeCape(fine, hero), indices: fine.indices, uvs: fine.uvs })

    // character cloth: inertia in the chest's frame, motion constraints around the cape as the
    // body carries it (its rest shape), a snap round of more than 90° in one frame resets it
    const cape0: CapeSettings = { ...CAPE_SETTINGS }
    let limits = true, reach = cape0.reach === false ? 1 : cape0.reach
    const apply = () => applyCapeSettings(world, cape, hero, mesh, { ...cape0, reach: limits ? reach : false })

    const moves: [Move | 'auto', string][] = [['auto', 'Auto'], ['stand', 'Stand'], ['walk', 'Walk'], ['run', 'Run'], ['sprint', 'Sprint']]
    const setMode = addSegmented(ui, '', moves, 'auto', (m) => hero.command(m), 'move')
    const oneOff = (m: Move) => () => {
      hero.command(m)
      setMode(hero.gait)
    }
    addButton(ui, 'Turn', oneOff('turn'), 'turn')
    addButton(ui, 'Jump', oneOff('jump'), 'jump')
    addButton(ui, 'Teleport 8 m', oneOff('teleport'), 'teleport')
    const inertiaSlider = addSlider(ui, 'Inertia', 0, 1, 0.05, cape0.inertia, (v) => {
      cape0.inertia = v
      apply()
    }, 'inertia')
    // running steadily there is no acceleration to share: air drag sets the hem's angle (the
    // motion limits cap it), so the slider shows as the body starts, stops and turns
    inertiaSlider.parentElement!.title = "share of the chest's acceleration, angular acceleration and rotation the cape feels " +
      '(0: carried rigidly, 1: world space). Running steadily there is none: air drag sets the hem angle and the motion ' +
      'limits cap it; inertia shows as the body starts, stops and turns, most with Air drag off'
    const note = document.createElement('div')
    note.className = 'note'
    note.textContent = 'felt as it starts, stops, turns; try Air drag off'
    inertiaSlider.parentElement!.after(note)
    const reachSlider = addSlider(ui, 'Reach', 0.25, 2, 0.25, reach, (v) => {
      reach = v
      apply()
    }, 'reach')
    const limitsBox = addToggle(ui, 'Motion limits', limits, (v) => {
      limits = v
      apply()
    }, 'limits')
    const backstopBox = addToggle(ui, 'Backstop', cape0.backstop, (v) => {
      cape0.backstop = v
      apply()
    }, 'backstop')
    // the body's colliders on or off for the cape: with them off, the backstop alone keeps it out of the body
    const collide = (on: boolean) => setClothCollision(world, cape, { mask: on ? 0xffffffff : 0 })
    const collidersBox = addToggle(ui, 'Body colliders', true, collide, 'colliders')
    // still air: a calm global wind zone, so the cape meets the air as the character runs and
    // streams behind it (per-triangle drag and lift)
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
      stats: () => [
        `speed       ${hero.speed.toFixed(1)} m/s`,
        `doing       ${hero.doing}${hero.auto ? ', auto' : ''}`,
        `hem angle   ${capeHemAngle(world, cape, hero, mesh).toFixed(0)}°`,
      ],
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
        /** The hem's angle from the vertical, degrees (positive: trailing behind). */
        hemAngle: () => capeHemAngle(world, cape, hero, mesh),
        /** How deep the deepest cape particle is inside the torso collider, m (≤ 0: none). */
        torsoDepth: () => capeTorsoDepth(world, cape, hero),
        heading: () => hero.heading,
        /** Inertia share, motion limits, reach, backstop and body colliders at once (the panel follows). */
        setCape: (o: { inertia?: number; limits?: boolean; backstop?: boolean; reach?: number; colliders?: boolean }) => {
          if (o.colliders !== undefined) collide(collidersBox.checked = o.colliders)
          if (o.reach !== undefined) reach = reachSlider.valueAsNumber = o.reach
          if (o.inertia !== undefined) cape0.inertia = inertiaSlider.valueAsNumber = o.inertia
          if (o.limits !== undefined) limits = limitsBox.checked = o.limits
          if (o.backstop !== undefined) cape0.backstop = backstopBox.checked = o.backstop
          apply()
        },
      },
    }
  },
}
