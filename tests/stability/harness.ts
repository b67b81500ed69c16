/**
 * Scene runner of the stability suite. A case builds a scene, abuses it for some frames, releases
 * the abuse, lets it settle, and the runner checks after every frame that each watched cloth is
 *
 * - finite: positions, velocities and the render mesh (getClothMesh);
 * - bounded: no particle farther from the box around its cloth's pinned particles than
 *   `reach` × the cloth's size + `margin` (the size is the longest shortest path along its edges at
 *   rest; a cloth without pins may span at most that much);
 *
 * With `pieces: true` (torn cloths) the region is per connected piece of the render mesh: a piece
 * holding pinned particles stays within reach of the box around the cloth's pinned particles, a
 * piece without pins spans at most reach × size + margin; and with `floor`, no particle sinks below
 * it by more than the margin (pieces land on the ground instead of falling forever).
 *
 * and at the end that it recovered: settled back near the drape of an unabused twin of the scene
 * (`recover: 'drape'`), or at least came to rest (`'rest'`), or only stayed bounded (`'bounded'`,
 * for scenes that never settle, e.g. without damping). By default the explosion guard stays on but
 * may not fire (`resets: 0`): the solver itself must survive the case.
 *
 * Adding a case takes a few lines:
 *
 *   it('a collider moving 100 m in one step', () => {
 *     expectStable(runTorture({
 *       build: (world) => ({ cloths: [hangingSheet(world)], ball: addBall(world) }),
 *       abuse: (s, frame) => { if (frame === 30) setTransform(s.world, s.ball, [100, 0, 0]) },
 *       release: (s) => setTransform(s.world, s.ball, [0, -50, 0]),
 *     }))
 *   })
 */
import { createWorld } from 'bitecs'
import { expect } from 'vitest'
import { meshPieces } from '../tearing/util'
import {
  createCloth,
  getClothMesh,
  getClothState,
  getClothStats,
  getClothStretch,
  installClothPlugin,
  pinRow,
  stepCloth,
  wakeCloth,
  type ClothPluginOptions,
  type ClothStats,
  type CreateClothOptions,
} from '../../src/index'

/** What `build` returns: the cloths to watch plus anything the abuse needs. */
export interface SceneParts {
  cloths: number[]
  [key: string]: unknown
}

/** A built scene as handed to `abuse` and `release`. */
export type Scene<P extends SceneParts = SceneParts> = P & { world: object }

export interface TortureCase<P extends SceneParts = SceneParts> {
  /** Plugin options of the world. */
  world?: ClothPluginOptions
  /** Builds the scene in a fresh world (called again for the unabused twin). */
  build(world: object): P
  /** Abuse in frame `frame` (0-based), before it is stepped; returns the frame time (default 1/60 s). */
  abuse?(scene: Scene<P>, frame: number): number | void
  /** Frames of abuse. Default 120. */
  frames?: number
  /** Undoes the abuse once, after the last abused frame (pins back, inputs reset). */
  release?(scene: Scene<P>): void
  /** Frames of 1/60 s after the release. Default 600. */
  settle?: number
  /** How recovery is judged (see the file comment). Default 'drape'. */
  recover?: 'drape' | 'rest' | 'bounded'
  /** Allowed distance beyond the pins' box, in cloth sizes. Default 1.25. */
  reach?: number
  /** Extra allowed distance, m. Default 0.05. */
  margin?: number
  /** 'drape': largest allowed particle distance from the twin, in cloth sizes. Default 0.05. */
  drapeTolerance?: number
  /** 'rest'/'drape': largest allowed rms particle speed at the end, m/s. Default 0.05. */
  restSpeed?: number
  /**
   * 'rest'/'drape': largest allowed edge strain at the end (max over structural edges). A cloth
   * left tangled (folded through itself) rests with edges fighting at 15–35 %. Default 0.05.
   */
  restStretch?: number
  /** Guard resets allowed during the run. Default 0. */
  resets?: number
  /** Check every `checkEvery` frames during the abuse (long runs). Default 1. */
  checkEvery?: number
  /** Measure the region per connected piece of the render mesh (torn cloths). Default false. */
  pieces?: boolean
  /** Lowest allowed particle height (a ground the pieces land on), m; the margin applies. */
  floor?: number
}

export interface TortureResult {
  /** Every check found finite positions, velocities and mesh. */
  finite: boolean
  /** First frame with a non-finite value, or −1. */
  firstNonFinite: number
  /** Largest distance beyond the allowed region over all checks, m (≤ 0: always inside). */
  worstExcess: number
  /** Frame of the worst excess. */
  worstFrame: number
  /** The allowed region's size per cloth, m (reach × size + margin). */
  allowed: number[]
  /** Largest particle distance from the unabused twin at the end, in cloth sizes (drape only). */
  drapeError: number
  /** Rms particle speed at the end, m/s (largest over the cloths). */
  endSpeed: number
  /** Largest edge strain at the end (over the cloths). */
  endStretch: number
  /** Guard resets during the run. */
  resets: number
  /** Fixed steps run. */
  steps: number
  /** The world's work counters at the end (`getClothStats`). */
  stats: ClothStats
  /** The case as run (defaults filled in). */
  spec: Required<
    Pick<TortureCase, 'frames' | 'settle' | 'recover' | 'reach' | 'margin' | 'drapeTolerance' | 'restSpeed' | 'restStretch' | 'resets'>
  >
}

/** Runs a case (and its unabused twin for 'drape'). */
export function runTorture<P extends SceneParts>(tc: TortureCase<P>): TortureResult {
  const spec = {
    frames: tc.frames ?? 120,
    settle: tc.settle ?? 600,
    recover: tc.recover ?? 'drape',
    reach: tc.reach ?? 1.25,
    margin: tc.margin ?? 0.05,
    drapeTolerance: tc.drapeTolerance ?? 0.05,
    restSpeed: tc.restSpeed ?? 0.05,
    restStretch: tc.restStretch ?? 0.05,
    resets: tc.resets ?? 0,
  } as TortureResult['spec']
  const world = installClothPlugin(createWorld(), tc.world)
  const scene = { ...tc.build(world), world } as Scene<P>
  const sizes = scene.cloths.map((cl) => geodesicDiameter(world, cl))
  const allowed = sizes.map((s) => spec.reach * s + spec.margin)
  const result: TortureResult = {
    finite: true,
    firstNonFinite: -1,
    worstExcess: -Infinity,
    worstFrame: -1,
    allowed,
    drapeError: 0,
    endSpeed: 0,
    endStretch: 0,
    resets: 0,
    steps: 0,
    stats: getClothStats(world),
    spec,
  }
  const check = (frame: number) => {
    for (let k = 0; k < scene.cloths.length; k++) {
      const h = tc.pieces ? inspectPieces(world, scene.cloths[k], allowed[k], tc.floor ?? -Infinity, spec.margin)
        : inspect(world, scene.cloths[k], allowed[k])
      if (!h.finite && result.finite) {
        result.finite = false
        result.firstNonFinite = frame
      }
      if (h.excess > result.worstExcess) {
        result.worstExcess = h.excess
        result.worstFrame = frame
      }
    }
  }
  const every = tc.checkEvery ?? 1
  for (let f = 0; f < spec.frames; f++) {
    const dt = tc.abuse?.(scene, f)
    // abuse writes the cloths' arrays directly, which a sleeping cloth would not notice
    if (tc.abuse) { for (const cl of scene.cloths) wakeCloth(world, cl) }
    stepCloth(world, typeof dt === 'number' ? dt : 1 / 60)
    if (f % every === 0 || f === spec.frames - 1) check(f)
  }
  tc.release?.(scene)
  for (let f = 0; f < spec.settle; f++) {
    stepCloth(world, 1 / 60)
    check(spec.frames + f)
  }
  result.endSpeed = Math.max(...scene.cloths.map((cl) => rmsSpeed(world, cl)))
  result.endStretch = Math.max(...scene.cloths.map((cl) => getClothStretch(world, cl).max))
  result.resets = getClothStats(world).guardResets
  result.steps = getClothStats(world).steps
  result.stats = { ...getClothStats(world) }

  if (spec.recover === 'drape') {
    const twin = installClothPlugin(createWorld(), tc.world)
    const twinScene = { ...tc.build(twin), world: twin } as Scene<P>
    for (let f = 0; f < spec.frames + spec.settle; f++) stepCloth(twin, 1 / 60)
    let err = 0
    for (let k = 0; k < scene.cloths.length; k++) {
      const a = getClothState(world, scene.cloths[k]), b = getClothState(twin, twinScene.cloths[k])
      for (let i = 0; i < a.count; i++) {
        const d = Math.hypot(a.pos[3 * i] - b.pos[3 * i], a.pos[3 * i + 1] - b.pos[3 * i + 1], a.pos[3 * i + 2] - b.pos[3 * i + 2])
        err = Math.max(err, d / Math.max(sizes[k], 1e-9))
      }
    }
    result.drapeError = err
  }
  return result
}

/** Asserts what the case promised (see `TortureCase`), with readable failure messages. */
export function expectStable(r: TortureResult): void {
  expect(r.finite, `non-finite values from frame ${r.firstNonFinite}`).toBe(true)
  expect(r.worstExcess, `a particle left the allowed region by ${r.worstExcess} m at frame ${r.worstFrame}`).toBeLessThanOrEqual(0)
  expect(r.resets, 'guard resets').toBeLessThanOrEqual(r.spec.resets)
  if (r.spec.recover === 'drape')
    expect(r.drapeError, 'distance from the unabused drape, in cloth sizes').toBeLessThan(r.spec.drapeTolerance)
  if (r.spec.recover !== 'bounded') {
    expect(r.endSpeed, 'rms speed after settling, m/s').toBeLessThan(r.spec.restSpeed)
    expect(r.endStretch, 'largest edge strain after settling').toBeLessThan(r.spec.restStretch)
  }
}

/**
 * A known weakness, asserted exactly: the case stays finite, inside its region and within its reset
 * allowance (everything `expectStable` asks), yet does not recover: its drape error, speed or
 * stretch after settling is over the limit. It fails when the solver learns to recover (then move
 * the case up into the suite with `expectStable`) and when the case breaks in any other way.
 */
export function expectStuck(r: TortureResult): void {
  expect(r.finite, `non-finite values from frame ${r.firstNonFinite}`).toBe(true)
  expect(r.worstExcess, `a particle left the allowed region by ${r.worstExcess} m at frame ${r.worstFrame}`).toBeLessThanOrEqual(0)
  expect(r.resets, 'guard resets').toBeLessThanOrEqual(r.spec.resets)
  const draped = r.spec.recover !== 'drape' || r.drapeError < r.spec.drapeTolerance
  const rested = r.spec.recover === 'bounded' || (r.endSpeed < r.spec.restSpeed && r.endStretch < r.spec.restStretch)
  expect(draped && rested, `recovered: drape error ${r.drapeError}, speed ${r.endSpeed}, stretch ${r.endStretch}`).toBe(false)
}

// ---------------------------------------------------------------------------------------------
// Measures

/** Finite check (state and render mesh) and the distance beyond the allowed region. */
export function inspect(world: object, cloth: number, allowed: number): { finite: boolean; excess: number } {
  const c = getClothState(world, cloth)
  let finite = true
  for (let i = 0; i < 3 * c.count; i++) if (!Number.isFinite(c.pos[i]) || !Number.isFinite(c.vel[i])) finite = false
  const mesh = getClothMesh(world, cloth)
  for (let i = 0; i < mesh.positions.length; i++)
    if (!Number.isFinite(mesh.positions[i]) || !Number.isFinite(mesh.normals[i])) finite = false
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity]
  let pinned = 0
  for (let i = 0; i < c.count; i++) {
    if (c.pinCount[i] === 0) continue
    pinned++
    for (let k = 0; k < 3; k++) {
      lo[k] = Math.min(lo[k], c.pos[3 * i + k])
      hi[k] = Math.max(hi[k], c.pos[3 * i + k])
    }
  }
  let excess = -Infinity
  if (pinned > 0) {
    for (let i = 0; i < c.count; i++) {
      let d2 = 0
      for (let k = 0; k < 3; k++) {
        const x = c.pos[3 * i + k]
        const out = x < lo[k] ? lo[k] - x : x > hi[k] ? x - hi[k] : 0
        d2 += out * out
      }
      excess = Math.max(excess, Math.sqrt(d2) - allowed)
    }
  } else {
    for (let k = 0; k < 3; k++) {
      let a = Infinity, b = -Infinity
      for (let i = 0; i < c.count; i++) {
        a = Math.min(a, c.pos[3 * i + k])
        b = Math.max(b, c.pos[3 * i + k])
      }
      excess = Math.max(excess, b - a - allowed)
    }
  }
  if (!Number.isFinite(excess)) excess = finite ? excess : Infinity
  return { finite, excess }
}

/**
 * `inspect` per connected piece of the render mesh (torn cloths): a piece holding pinned particles
 * against the box of all the cloth's pinned particles (as the whole cloth before it tore), a piece
 * without pins against its own extent; plus a floor.
 */
export function inspectPieces(
  world: object,
  cloth: number,
  allowed: number,
  floor: number,
  margin: number,
): { finite: boolean; excess: number; pieces: number } {
  const c = getClothState(world, cloth)
  const { finite } = inspect(world, cloth, Infinity)
  const mesh = getClothMesh(world, cloth)
  const label = meshPieces(mesh.indices, c.count, true)
  let pieces = 0
  for (let i = 0; i < c.count; i++) pieces = Math.max(pieces, label[i] + 1)
  const lo = Array.from({ length: pieces }, () => [Infinity, Infinity, Infinity])
  const hi = Array.from({ length: pieces }, () => [-Infinity, -Infinity, -Infinity])
  const pinnedPiece = new Uint8Array(pieces)
  const pinLo = [Infinity, Infinity, Infinity], pinHi = [-Infinity, -Infinity, -Infinity]
  let excess = -Infinity
  for (let i = 0; i < c.count; i++) {
    const p = label[i]
    for (let k = 0; k < 3; k++) {
      const x = c.pos[3 * i + k]
      lo[p][k] = Math.min(lo[p][k], x)
      hi[p][k] = Math.max(hi[p][k], x)
      if (c.pinCount[i] > 0) {
        pinLo[k] = Math.min(pinLo[k], x)
        pinHi[k] = Math.max(pinHi[k], x)
      }
    }
    if (c.pinCount[i] > 0) pinnedPiece[p] = 1
    excess = Math.max(excess, floor - margin - c.pos[3 * i + 1])
  }
  for (let i = 0; i < c.count; i++) {
    if (!pinnedPiece[label[i]]) continue
    let d2 = 0
    for (let k = 0; k < 3; k++) {
      const x = c.pos[3 * i + k]
      const out = x < pinLo[k] ? pinLo[k] - x : x > pinHi[k] ? x - pinHi[k] : 0
      d2 += out * out
    }
    excess = Math.max(excess, Math.sqrt(d2) - allowed)
  }
  for (let p = 0; p < pieces; p++) {
    if (pinnedPiece[p]) continue
    for (let k = 0; k < 3; k++) excess = Math.max(excess, hi[p][k] - lo[p][k] - allowed)
  }
  if (!(excess === excess)) excess = Infinity
  return { finite, excess: finite ? excess : Infinity, pieces }
}

/** Rms particle speed, m/s. */
export function rmsSpeed(world: object, cloth: number): number {
  const c = getClothState(world, cloth)
  let s = 0
  for (let i = 0; i < 3 * c.count; i++) s += c.vel[i] * c.vel[i]
  return Math.sqrt(s / Math.max(1, c.count))
}

/** Exact geodesic diameter of the rest mesh (Dijkstra from every particle; suite meshes are small). */
export function geodesicDiameter(world: object, cloth: number): number {
  const t = getClothState(world, cloth).topology
  const n = t.particleCount
  const adj: [number, number][][] = Array.from({ length: n }, () => [])
  for (let e = 0; e < t.edgeCount; e++) {
    const a = t.edges[2 * e], b = t.edges[2 * e + 1]
    adj[a].push([b, t.edgeRest[e]])
    adj[b].push([a, t.edgeRest[e]])
  }
  let best = 0
  const dist = new Float64Array(n)
  const done = new Uint8Array(n)
  for (let s = 0; s < n; s++) {
    dist.fill(Infinity)
    done.fill(0)
    dist[s] = 0
    for (;;) {
      let u = -1
      for (let i = 0; i < n; i++) if (!done[i] && dist[i] < Infinity && (u < 0 || dist[i] < dist[u])) u = i
      if (u < 0) break
      done[u] = 1
      best = Math.max(best, dist[u])
      for (const [v, L] of adj[u]) if (dist[u] + L < dist[v]) dist[v] = dist[u] + L
    }
  }
  return best
}

// ---------------------------------------------------------------------------------------------
// Scene parts

/** A 1 m sheet hanging from its top row (world pins), `resolution` particles per side. */
export function hangingSheet(world: object, options: Partial<CreateClothOptions> = {}): number {
  const cloth = createCloth(world, { width: 1, height: 1, resolution: 8, position: [0, 2, 0], ...options })
  pinRow(world, cloth, 0)
  return cloth
}

/** An indexed grid mesh (n × n particles, spacing `s`, top row at y = 0) for createClothFromMesh. */
export function gridMesh(n: number, s: number): { positions: number[]; indices: number[] } {
  const positions: number[] = [], indices: number[] = []
  for (let r = 0; r < n; r++) for (let c = 0; c < n; c++) positions.push(c * s - ((n - 1) * s) / 2, -r * s, 0)
  for (let r = 0; r + 1 < n; r++) {
    for (let c = 0; c + 1 < n; c++) {
      const i = r * n + c
      if ((r + c) % 2 === 0) indices.push(i, i + n, i + 1, i + 1, i + n, i + n + 1)
      else indices.push(i, i + n, i + n + 1, i, i + n + 1, i + 1)
    }
  }
  return { positions, indices }
}
