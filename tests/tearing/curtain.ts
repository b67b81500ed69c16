import { addEntity, createWorld, removeEntity } from 'bitecs'
import {
  addPlaneCollider,
  addSphereCollider,
  createCloth,
  getClothMesh,
  getClothState,
  getClothTearCount,
  installClothPlugin,
  makeTearable,
  pinParticle,
  setTransform,
  stepCloth,
  type TearableOptions,
} from '../../src/index'
import { meshPieces } from './util'

/**
 * The demo's tearing curtain without a browser (demo/scenes/curtain.ts): a 2 × 1.8 m cotton
 * curtain, 36 × 30 particles, on hooks at every other particle of its top row, 8 substeps × 1
 * iteration, no tethers, above a floor; 44 cm balls thrown at 9 m/s from 3.2 m in front, one every
 * 1.5 s. Each throw aims at the next of `AIMS` or, where the cloth there is gone or torn, at the
 * intact hanging cloth nearest to it (at least 20 cm from any tear), as a player aims at what is
 * left. Deterministic: same options, same throws, same bytes.
 */

/** Where the throws aim in turn (x, y on the curtain's plane z = 0). */
export const AIMS: readonly (readonly [number, number])[] = [
  [-0.1, 1.05],
  [0.45, 1.35],
  [-0.5, 1.5],
  [0.2, 0.85],
  [-0.6, 0.9],
  [0.6, 1.8],
  [0, 1.6],
  [-0.5, 2.0],
  [0.6, 0.9],
  [0.1, 2.0],
  [-0.8, 1.3],
  [0.8, 1.3],
]

/** The tearing settings the demo's curtain should use with crack tearing (strain 25 %, tears at once). */
export const CURTAIN_TEARING: TearableOptions = { strain: 0.25, maxTearsPerStep: 32, hysteresis: 1 }

export interface ThrowResult {
  /** Tears the throw made (in the 1.5 s after it). */
  tears: number
  /** Triangles still connected to a hook. */
  hanging: number
  /** Triangles of every piece that hangs on no hook (on the floor or falling). */
  fallen: number[]
  /** Triangles of the smallest piece of the whole mesh (hanging or not). */
  smallest: number
  /**
   * The throw's new torn edges, grouped into openings (connected through torn edges old and new,
   * by rest position): their sizes, largest first.
   */
  openings: number[]
  /** Slowest fixed step of the throw, ms (wall clock: for benchmarks, not for assertions). */
  slowest: number
}

export function curtainScene(tearing: TearableOptions = CURTAIN_TEARING) {
  const world = installClothPlugin(createWorld(), { sleep: false })
  const ground = addEntity(world)
  setTransform(world, ground, [0, 0, 0])
  addPlaneCollider(world, ground)
  const cols = 36, rows = 30
  const curtain = createCloth(world, {
    width: 2,
    height: 1.8,
    resolution: [cols, rows],
    position: [0, 2.3, 0],
    substeps: 8,
    iterations: 1,
    tethers: false,
    material: 'cotton',
  })
  const hooks: number[] = []
  for (let col = 0; col < cols; col += 2) hooks.push(col)
  hooks.push(cols - 1)
  for (const h of hooks) pinParticle(world, curtain, h)
  makeTearable(world, curtain, tearing)
  for (let f = 0; f < 48; f++) stepCloth(world, 1 / 60)
  const balls: number[] = []
  let thrown = 0
  const radius = 0.22, speed = 9, g = 9.81

  /** Throws the next ball, steps 1.5 s and measures. */
  const throwBall = (): ThrowResult => {
    const [x, y] = aimAt(world, curtain, hooks, AIMS[thrown % AIMS.length])
    thrown++
    const p = [x + 0.6, 0.9, 3.2]
    const t = Math.hypot(x - p[0], y - p[1], -p[2]) / speed
    const v = [(x - p[0]) / t, (y - p[1]) / t + 0.5 * g * t, -p[2] / t]
    const ball = addEntity(world)
    setTransform(world, ball, p)
    addSphereCollider(world, ball, { radius, friction: 0 })
    balls.push(ball)
    if (balls.length > 4) removeEntity(world, balls.shift()!)
    const before = getClothTearCount(world, curtain)
    const tornBefore = tornEdges(world, curtain)
    let slowest = 0
    for (let f = 0; f < 90; f++) {
      v[1] -= g / 60
      for (let j = 0; j < 3; j++) p[j] += v[j] / 60
      if (p[1] < radius) {
        p[1] = radius
        v[1] = Math.abs(v[1]) > 1 ? -0.4 * v[1] : 0
      }
      setTransform(world, ball, p)
      const t0 = performance.now()
      stepCloth(world, 1 / 60)
      slowest = Math.max(slowest, performance.now() - t0)
    }
    return {
      tears: getClothTearCount(world, curtain) - before,
      ...pieces(world, curtain, hooks),
      openings: openings(tornBefore, tornEdges(world, curtain)),
      slowest,
    }
  }
  return { world, curtain, hooks, throwBall }
}

/** Triangles per piece: hanging (holding a hook) and fallen, and the smallest of all. */
function pieces(world: object, curtain: number, hooks: number[]): Pick<ThrowResult, 'hanging' | 'fallen' | 'smallest'> {
  const m = getClothMesh(world, curtain)
  const label = meshPieces(m.indices, m.vertexCount)
  const size = new Map<number, number>()
  for (let t = 0; t < m.triangleCount; t++) size.set(label[m.indices[3 * t]], (size.get(label[m.indices[3 * t]]) ?? 0) + 1)
  const hooked = new Set(hooks.map((h) => label[h]))
  let hanging = 0
  const fallen: number[] = []
  for (const [l, n] of size) {
    if (hooked.has(l)) hanging += n
    else fallen.push(n)
  }
  return { hanging, fallen: fallen.sort((a, b) => b - a), smallest: Math.min(...size.values()) }
}

/** Particles on a torn edge (an edge two triangles shared at rest and no longer share). */
function tornParticles(world: object, curtain: number): Uint8Array {
  const c = getClothState(world, curtain)
  const out = new Uint8Array(c.count)
  for (const e of tornEdgeList(world, curtain)) {
    out[e[0]] = 1
    out[e[1]] = 1
  }
  return out
}

/** Torn edges as [particle, particle, rest key]. */
function tornEdgeList(world: object, curtain: number): [number, number, string][] {
  const c = getClothState(world, curtain)
  const t = c.topology, tris = t.triangles, rest = t.restPositions
  const key = (i: number) => `${rest[3 * i]},${rest[3 * i + 1]},${rest[3 * i + 2]}`
  const byRest = new Map<string, number>(), byIndex = new Map<string, [number, number, string]>(), uses = new Map<string, number>()
  for (let k = 0; k < t.triangleCount; k++) {
    for (let j = 0; j < 3; j++) {
      const a = tris[3 * k + j], b = tris[3 * k + ((j + 1) % 3)]
      const rk = [key(a), key(b)].sort().join('|')
      byRest.set(rk, (byRest.get(rk) ?? 0) + 1)
      const ik = a < b ? `${a},${b}` : `${b},${a}`
      uses.set(ik, (uses.get(ik) ?? 0) + 1)
      byIndex.set(ik, [a, b, rk])
    }
  }
  // used once by index but twice by rest position: the two sides of a tear
  return [...byIndex].filter(([ik, e]) => uses.get(ik) === 1 && byRest.get(e[2]) === 2).map(([, e]) => e)
}

function tornEdges(world: object, curtain: number): Set<string> {
  return new Set(tornEdgeList(world, curtain).map((e) => e[2]))
}

/** Sizes of the groups of new torn edges, connected through all torn edges (by rest position). */
function openings(before: Set<string>, after: Set<string>): number[] {
  const parent = new Map<string, string>()
  const find = (x: string): string => {
    while (parent.get(x) !== x) x = parent.get(x)!
    return x
  }
  for (const e of after) {
    const [a, b] = e.split('|')
    for (const v of [a, b]) if (!parent.has(v)) parent.set(v, v)
    parent.set(find(a), find(b))
  }
  const groups = new Map<string, number>()
  for (const e of after) {
    if (before.has(e)) continue
    const r = find(e.split('|')[0])
    groups.set(r, (groups.get(r) ?? 0) + 1)
  }
  return [...groups.values()].sort((a, b) => b - a)
}

/** The aim, or the intact hanging cloth nearest to it (20 cm from any tear, above 0.6 m). */
function aimAt(world: object, curtain: number, hooks: number[], aim: readonly [number, number]): [number, number] {
  const c = getClothState(world, curtain)
  const m = getClothMesh(world, curtain)
  const label = meshPieces(m.indices, m.vertexCount)
  const hooked = new Set(hooks.map((h) => label[h]))
  const torn = tornParticles(world, curtain)
  const tornList: number[] = []
  for (let i = 0; i < c.count; i++) if (torn[i]) tornList.push(i)
  let best = Infinity, bx = aim[0], by = aim[1]
  for (let i = 0; i < c.count; i++) {
    if (!hooked.has(label[i]) || torn[i]) continue
    const x = c.pos[3 * i], y = c.pos[3 * i + 1], z = c.pos[3 * i + 2]
    const d = Math.hypot(x - aim[0], y - aim[1])
    if (d >= best || y < 0.6) continue
    if (tornList.some((j) => Math.hypot(c.pos[3 * j] - x, c.pos[3 * j + 1] - y, c.pos[3 * j + 2] - z) < 0.2)) continue
    best = d
    bx = x
    by = y
  }
  return [bx, by]
}
