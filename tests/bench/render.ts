import { addEntity, createWorld } from 'bitecs'
import {
  buildGridMesh,
  createCloth,
  createRenderProxy,
  getClothMesh,
  installClothPlugin,
  pinRow,
  setTransform,
  stepCloth,
  updateRenderProxy,
} from '../../src/index'
import { fmt, saveJson, table } from './harness'

/**
 * What rendering costs per frame next to the cloth's own step: `getClothMesh` (the simulated
 * mesh's float32 positions and normals) and `updateRenderProxy` for a proxy four times finer
 * (every simulated edge in four: 16× the triangles). Two cloths: the demo's 14×24 cape on a
 * swaying, turning character, and a 64×64 sheet hanging from its top row, swaying. Each frame
 * steps once, then reads; the three are timed separately in the same frames (7 rounds of 60
 * frames after 120 warm-up frames, the median round each).
 */
export function proxyCost(): void {
  const rows: Record<string, string | number>[] = []
  const cases = [
    { name: 'cape 14×24 (0.55×1.05 m)', width: 0.55, height: 1.05, columns: 14, rows: 24 },
    { name: 'sheet 64×64 (1×1 m)', width: 1, height: 1, columns: 64, rows: 64 },
  ]
  for (const k of cases) {
    const world = installClothPlugin(createWorld(), { sleep: false })
    const hero = addEntity(world)
    setTransform(world, hero, [0, 2, 0])
    const cloth = createCloth(world, { width: k.width, height: k.height, resolution: [k.columns, k.rows], position: [0, 2, 0] })
    pinRow(world, cloth, 0, hero)
    const t0 = performance.now()
    const fine = buildGridMesh({ width: k.width, height: k.height, resolution: [4 * k.columns - 3, 4 * k.rows - 3] })
    const proxy = createRenderProxy(world, cloth, fine)
    const bindMs = performance.now() - t0
    let frame = 0
    const times = [[], [], []] as number[][]
    const round = (count: number, keep: boolean) => {
      const sum = [0, 0, 0]
      for (let i = 0; i < count; i++) {
        frame++
        const yaw = 0.6 * Math.sin(frame * 0.04)
        setTransform(world, hero, [0.4 * Math.sin(frame * 0.05), 2, 0], [0, Math.sin(yaw / 2), 0, Math.cos(yaw / 2)])
        const a = performance.now()
        stepCloth(world, 1 / 60)
        const b = performance.now()
        getClothMesh(world, cloth)
        const c = performance.now()
        updateRenderProxy(world, proxy)
        const d = performance.now()
        sum[0] += b - a
        sum[1] += c - b
        sum[2] += d - c
      }
      if (keep) { for (let j = 0; j < 3; j++) times[j].push(sum[j] / count) }
    }
    round(120, false)
    for (let r = 0; r < 7; r++) round(60, true)
    const [step, mesh, prox] = times.map((t) => t.sort((x, y) => x - y)[3])
    rows.push({
      cloth: k.name,
      'render vertices': fine.positions.length / 3,
      'step ms': fmt(step, 3),
      'getClothMesh ms': fmt(mesh, 3),
      'proxy ms': fmt(prox, 3),
      'proxy / step': fmt(prox / step, 2),
      'ns per render vertex': fmt((prox * 1e6) / (fine.positions.length / 3), 1),
      'proxy creation ms': fmt(bindMs, 0),
    })
  }
  table("Render proxies 4× finer than the cloth: cost per frame against the cloth's own step (8 substeps)", rows)
  saveJson('render-proxy', rows)
}
