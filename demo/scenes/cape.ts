import {
  createClothFromMesh, createWindZone, getClothState, pinParticle, removeWindZone, setClothInertia, setClothMotionConstraints, type ClothInertiaOptions,
} from '../../src/index'
import * as THREE from 'three'
import { Character, CharacterFigure, type Move } from '../character'
import { capeFabric } from '../fabrics'
import { addButton, addSegmented, addSlider, addToggle, type DemoScene } from '../scene'

/** Rows (collar to hem) and columns of the simulated cape. */
const ROWS = 24, COLS = 15

/**
 * A cape cut like a cape, in the chest frame (x right, y up the spine, z forward, origin at the
 * pelvis): its top edge is a collar that follows the shoulders around the back of the neck, it runs
 * back over the shoulders and hangs down the back, narrow at the collar (40 cm along it) and wide
 * at the hem (96 cm, at the calves). Each row is an arc around a centre in front of it, tight
 * around the neck and flatter lower down. Triangles face away from the body (the side the backstop
 * is not on). `rows` × `cols` vertices; uvs u across, v down.
 */
function capeShape(rows: number, cols: number): { positions: number[]; indices: number[]; uvs: number[] } {
  // the middle of each row, down the back: over the shoulders from behind the neck, then down
  const profile: [number, number][] = [[0.54, -0.12], [0.52, -0.17], [0.48, -0.21], [0.42, -0.235], [0.3, -0.245], [-0.52, -0.27]]
  const lengths = [0]
  for (let k = 1; k < profile.length; k++) {
    lengths.push(lengths[k - 1] + Math.hypot(profile[k][0] - profile[k - 1][0], profile[k][1] - profile[k - 1][1]))
  }
  const total = lengths[lengths.length - 1]
  const along = (s: number): [number, number] => {
    let k = 1
    while (k < profile.length - 1 && lengths[k] < s) k++
    const t = (s - lengths[k - 1]) / (lengths[k] - lengths[k - 1])
    return [profile[k - 1][0] + (profile[k][0] - profile[k - 1][0]) * t, profile[k - 1][1] + (profile[k][1] - profile[k - 1][1]) * t]
  }
  const positions: number[] = [], uvs: number[] = [], indices: number[] = []
  for (let r = 0; r < rows; r++) {
    const v = r / (rows - 1)
    const [y, zBack] = along(v * total)
    const halfWidth = 0.2 + 0.28 * v ** 0.7 // half the row's length along its arc
    const tight = Math.min(1, v / 0.2)
    const radius = 0.15 + 0.5 * tight * tight * (3 - 2 * tight) // around the neck, then flatter
    for (let c = 0; c < cols; c++) {
      const u = (2 * c) / (cols - 1) - 1
      const a = (u * halfWidth) / radius
      positions.push(radius * Math.sin(a), y, zBack + radius * (1 - Math.cos(a)))
      uvs.push(c / (cols - 1), 1 - v)
    }
  }
  for (let r = 0; r + 1 < rows; r++) {
    for (let c = 0; c + 1 < cols; c++) {
      const a = r * cols + c, b = a + cols
      indices.push(a, a + 1, b, a + 1, b + 1, b) // counter-clockwise seen from behind (−z)
    }
  }
  return { positions, indices, uvs }
}

/** The shape in world space, for a character standing as it does now (chest frame → world). */
function placed(shape: { positions: number[] }, hero: Character): number[] {
  const out: number[] = []
  const p = new THREE.Vector3()
  for (let i = 0; i < shape.positions.length; i += 3) {
    hero.chestPoint(shape.positions[i], shape.positions[i + 1], shape.positions[i + 2], p)
    out.push(p.x, p.y, p.z)
  }
  return out
}

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
    const shape = capeShape(ROWS, COLS)
    const cape = createClothFromMesh(world, {
      positions: placed(shape, hero),
      indices: shape.indices,
      uvs: shape.uvs,
      material: settings.material,
      substeps: settings.substeps,
      iterations: settings.iterations,
      tethers: settings.tethers,
    })
    for (let c = 0; c < COLS; c++) pinParticle(world, cape, c, hero.chest) // the collar, where it is now
    // drawn through a render proxy four times finer (every simulated edge in four): smooth folds
    const fine = capeShape(4 * (ROWS - 1) + 1, 4 * (COLS - 1) + 1)
    showCloth(cape, capeFabric(), { positions: placed(fine, hero), indices: fine.indices, uvs: fine.uvs })

    // character cloth: inertia in the chest's frame, motion constraints around the cape as the
    // body carries it (its rest shape), a snap round of more than 90° in one frame resets it
    let share = 0.5, limits = true, backstop = true, reach = 1
    const applyInertia = () => {
      const o: ClothInertiaOptions = { frame: hero.chest, linear: share, angular: share, centrifugal: share, teleport: { angle: Math.PI / 2 } }
      setClothInertia(world, cape, o)
    }
    const applyLimits = () => {
      if (!limits) return setClothMotionConstraints(world, cape, null)
      // 0 at the collar, growing down the back (× the Reach slider), free at the hem
      const maxDistance = Array.from({ length: ROWS * COLS }, (_, i) => {
        const v = Math.floor(i / COLS) / (ROWS - 1)
        return v === 1 ? Infinity : reach * 0.9 * v * v
      })
      setClothMotionConstraints(world, cape, { maxDistance, backstop: backstop ? { distance: 0.03, radius: 0.4 } : null })
    }
    applyInertia()
    applyLimits()

    const moves: [Move | 'auto', string][] = [['auto', 'Auto'], ['stand', 'Stand'], ['walk', 'Walk'], ['run', 'Run'], ['sprint', 'Sprint']]
    const setMode = addSegmented(ui, '', moves, 'auto', (m) => hero.command(m), 'move')
    const oneOff = (m: Move) => () => {
      hero.command(m)
      setMode(hero.gait)
    }
    addButton(ui, 'Turn', oneOff('turn'), 'turn')
    addButton(ui, 'Jump', oneOff('jump'), 'jump')
    addButton(ui, 'Teleport 8 m', oneOff('teleport'), 'teleport')
    addSlider(ui, 'Inertia', 0, 1, 0.05, share, (v) => {
      share = v
      applyInertia()
    }, 'inertia')
    addSlider(ui, 'Reach', 0.25, 2, 0.25, reach, (v) => {
      reach = v
      applyLimits()
    }, 'reach')
    addToggle(ui, 'Motion limits', limits, (v) => {
      limits = v
      applyLimits()
    }, 'limits')
    addToggle(ui, 'Backstop', backstop, (v) => {
      backstop = v
      applyLimits()
    }, 'backstop')
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
    /** The hem's angle from the vertical, degrees: collar middle to hem middle, seen from the side of the character. */
    const hemAngle = (): number => {
      const c = getClothState(world, cape)
      const mid = (row: number, out: THREE.Vector3) => {
        out.set(0, 0, 0)
        for (let k = 0; k < COLS; k++) out.add(new THREE.Vector3().fromArray(c.pos, 3 * (row * COLS + k)))
        return out.multiplyScalar(1 / COLS)
      }
      const top = mid(0, new THREE.Vector3()), hem = mid(ROWS - 1, new THREE.Vector3())
      const d = hem.sub(top)
      const forward = new THREE.Vector3(Math.sin(hero.heading), 0, Math.cos(hero.heading))
      return (Math.atan2(-d.dot(forward), -d.y) * 180) / Math.PI // positive: the hem trails behind
    }
    return {
      cloths: [cape],
      update(_time, dt) {
        hero.update(dt)
      },
      sync: () => figure.sync(),
      stats: () => [`speed       ${hero.speed.toFixed(1)} m/s`, `doing       ${hero.doing}${hero.auto ? ' (auto)' : ''}`, `hem angle   ${hemAngle().toFixed(0)}°`],
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
        hemAngle,
        setInertia: (v: number) => {
          share = v
          applyInertia()
        },
      },
    }
  },
}
