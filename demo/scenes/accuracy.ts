import { addEntity } from 'bitecs'
import * as THREE from 'three'
import {
  addPlaneCollider,
  createCloth,
  createWindZone,
  getClothStretch,
  gustWind,
  pinParticle,
  setClothQuality,
  setClothTethers,
  setTransform,
  setWindZone,
} from '../../src/index'
import { chainMaterial, gridFabric, paint, shadows, steel } from '../fabrics'
import { addButton, addSlider, type DemoSettings, type SceneLabel, type DemoScene } from '../scene'

/** What the two sides compare; kept across resets of the scene, like the counts. */
let mode: 'iterations' | 'substeps' = 'iterations'
let rightIterations = 12
let rightSubsteps = 12

const PATCH_N = 20 // particles per side of the patch
const CHAIN_LINKS = 30
const TOP = 2.55
const SIDE_X = 1.25 // each side's centre is this far left or right of the middle

/**
 * The two classic test objects of position-based dynamics (Müller et al. 2007), each run twice
 * side by side: a cloth patch hanging from a rail of pins (warp and weft distance constraints,
 * compression-only diagonals) in a breeze, and a hanging chain (a strip two particles wide). The
 * left side runs 1 substep × 1 iteration; the right side 12 iterations (or 12 substeps) of the
 * same solver. The patches carry a measuring grid, so stretch shows as squares drawn out into
 * rectangles (the panel's stretch tint colours it). The panel's iterations (or substeps) slider sets
 * the right side; the other count is 1 on both sides.
 */
export const accuracyScene: DemoScene = {
  id: 'accuracy',
  title: 'Accuracy side by side',
  defaults: { substeps: 1, iterations: 12, tethers: false, material: 'cotton' },
  camera: { target: [0, 1.45, 0], distance: 4.8, yaw: 0, pitch: 0.08, fit: 1.25 },
  shadowRadius: 3.5,
  moments: [
    { name: 'rest', seconds: 4 },
    { name: 'motion', seconds: 2.6, action: 'gust', actionAt: 1.2 },
  ],
  resetState() {
    mode = 'iterations'
    rightIterations = 12
    rightSubsteps = 12
  },
  create({ world, settings, ui, refresh, root, showCloth }) {
    // the panel shows the compared count (the right side's); the other count is 1
    if (mode === 'iterations') Object.assign(settings, { substeps: 1, iterations: rightIterations })
    else Object.assign(settings, { substeps: rightSubsteps, iterations: 1 })

    const ground = addEntity(world as never)
    setTransform(world, ground, [0, 0, 0])
    addPlaneCollider(world, ground)
    // A breeze whose eddies (20 m) are much larger than the scene, so both sides feel the same
    // air at the same time: the comparison is of the solver, not of the weather.
    let breeze = 0.8
    const wind = createWindZone(world, {
      direction: [0.3, 0, -1],
      strength: breeze,
      turbulence: 0.35,
      turbulenceScale: 20,
      turbulencePeriod: 1.5,
      seed: 3,
    })

    const make = (side: -1 | 1) => {
      const x = side * SIDE_X
      const common = { material: settings.material, tethers: settings.tethers, substeps: 1, iterations: 1 }
      // the patch: rows and columns (warp and weft) as distance constraints, diagonals resist
      // only compression (they keep it from folding up, never from shearing)
      const patch = createCloth(world, {
        ...common,
        width: 1,
        height: 1,
        resolution: PATCH_N,
        position: [x + 0.25, TOP, 0],
        shear: 'compression',
      })
      for (let c = 0; c < PATCH_N; c++) pinParticle(world, patch, c)
      // the chain: a strip two particles wide, held by its top two particles; chain mail is
      // heavy (6 kg/m²), so the breeze hardly moves it
      const chain = createCloth(world, {
        ...common,
        material: 'chainmail',
        width: 0.06,
        height: 1.2,
        resolution: [2, CHAIN_LINKS],
        position: [x - 0.6, TOP, 0],
      })
      pinParticle(world, chain, 0)
      pinParticle(world, chain, 1)
      showCloth(patch, gridFabric(side < 0 ? '#e9e2d2' : '#d6e0ea'))
      showCloth(chain, chainMaterial())
      // the rig: a rail over each object, a post at each end
      const railMat = steel()
      const rail = (cx: number, half: number) => {
        const m = new THREE.Mesh(new THREE.CylinderGeometry(0.016, 0.016, 2 * half, 12).rotateZ(Math.PI / 2), railMat)
        m.position.set(cx, TOP + 0.02, 0)
        root.add(shadows(m))
      }
      rail(x + 0.25, 0.6)
      rail(x - 0.6, 0.1)
      for (const px of [x - 0.72, x + 0.87]) {
        const post = new THREE.Mesh(new THREE.BoxGeometry(0.05, TOP + 0.06, 0.05), paint(0x4a4f58, 0.5))
        post.position.set(px, (TOP + 0.06) / 2, 0)
        root.add(shadows(post))
      }
      return [patch, chain]
    }
    const left = make(-1), right = make(1)

    const apply = (s: DemoSettings) => {
      if (mode === 'iterations') {
        rightIterations = s.iterations
        s.substeps = 1
      } else {
        rightSubsteps = s.substeps
        s.iterations = 1
      }
      for (const c of left) setClothQuality(world, c, { substeps: 1, iterations: 1 })
      for (const c of left) setClothQuality(world, c, { lineSolve: false })
      for (const c of right) setClothQuality(world, c, { substeps: s.substeps, iterations: s.iterations, lineSolve: s.lineSolve })
      for (const c of [...left, ...right]) setClothTethers(world, c, s.tethers)
    }
    apply(settings)

    // compare iterations or substeps: a two-button switch
    const row = document.createElement('div')
    row.className = 'segmented'
    row.append('Compare ')
    ui.appendChild(row)
    const setMode = (m: typeof mode) => {
      mode = m
      if (mode === 'iterations') Object.assign(settings, { substeps: 1, iterations: rightIterations })
      else Object.assign(settings, { substeps: rightSubsteps, iterations: 1 })
      refresh()
      byIterations.classList.toggle('active', mode === 'iterations')
      bySubsteps.classList.toggle('active', mode === 'substeps')
    }
    const byIterations = addButton(row, 'Iterations', () => setMode('iterations'), 'compare-iterations')
    const bySubsteps = addButton(row, 'Substeps', () => setMode('substeps'), 'compare-substeps')
    byIterations.classList.toggle('active', mode === 'iterations')
    bySubsteps.classList.toggle('active', mode === 'substeps')
    addSlider(ui, 'Breeze m/s', 0, 8, 0.1, breeze, (v) => {
      breeze = v
      setWindZone(world, wind, { strength: breeze })
    }, 'breeze')
    const gust = () => gustWind(world, wind, { strength: 3, duration: 2 })
    addButton(ui, 'Gust', gust, 'gust')

    const stretch = (cloths: number[]) => {
      let mean = 0, max = 0
      for (const c of cloths) {
        const s = getClothStretch(world, c)
        mean += s.mean / cloths.length
        max = Math.max(max, s.max)
      }
      return { mean, max }
    }
    const pct = (v: number) => `${(100 * v).toFixed(v < 0.1 ? 1 : 0)} %`
    const plural = (n: number, word: string) => `${n} ${word}${n === 1 ? '' : 's'}`
    const labels: SceneLabel[] = [
      { text: '', at: [-SIDE_X, 0.2, 0.5], className: 'title' },
      { text: '', at: [SIDE_X, 0.2, 0.5], className: 'title' },
      { text: '', at: [-SIDE_X, 0.02, 0.5], className: 'dim' },
      { text: '', at: [SIDE_X, 0.02, 0.5], className: 'dim' },
    ]
    let shownAt = -1
    let time = 0
    return {
      cloths: [...left, ...right],
      update(t) {
        time = t
      },
      labels() {
        // the text changes at most four times a second (readable numbers)
        if (time - shownAt < 0.25 && shownAt >= 0) return labels
        shownAt = time
        const sub = mode === 'iterations' ? 1 : settings.substeps
        const it = mode === 'iterations' ? settings.iterations : 1
        labels[0].text = `${plural(1, 'substep')} × ${plural(1, 'iteration')}`
        labels[1].text = `${plural(sub, 'substep')} × ${plural(it, 'iteration')}`
        const l = stretch(left), rt = stretch(right)
        labels[2].text = `stretch: mean ${pct(l.mean)}, max ${pct(l.max)}`
        labels[3].text = `stretch: mean ${pct(rt.mean)}, max ${pct(rt.max)}`
        return labels
      },
      applySettings: apply,
      locked: () => (mode === 'iterations' ? ['substeps'] : ['iterations']),
      stats: () => [`compare    ${mode}`, `breeze     ${breeze.toFixed(1)} m/s`],
      api: {
        /** Stretch of each side now: { left: { mean, max }, right: { mean, max } }. */
        stretch: () => ({ left: stretch(left), right: stretch(right) }),
        mode: () => mode,
        gust,
        setMode: (m: 'iterations' | 'substeps') => setMode(m),
      },
    }
  },
}
