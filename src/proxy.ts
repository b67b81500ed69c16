import { ClothError, MAX_COORDINATE, checkAtMost, checkKeys, checkObject, checkPositive, keysOf } from './core/errors'
import { FRAME_SIZE, updateProxySeams, updateProxyVertices } from './kernels/proxy'
import { bindProxy, type ProxyBinding } from './model/proxy'
import { checkMeshInput } from './model/options'
import { checkUvs } from './model/uvs'
import { getCloth, getClothWorld } from './world/access'
import type { ClothState, ClothWorldState } from './world/state'
import { notReadBeforeFrame, refreshClothRender } from './mesh'

/** Options of `createRenderProxy`: the render mesh, in the cloth's rest frame. */
export interface RenderProxyOptions {
  /**
   * Render vertices, xyz each, in the cloth's rest frame: for `createCloth`, the sheet's local
   * frame (x right, y up, front facing +z, the middle of the top edge at the origin: a finer grid
   * of the same sheet is `buildGridMesh` with the cloth's width and height); for
   * `createClothFromMesh`, the frame of the positions it was given.
   */
  positions: ArrayLike<number>
  /** Render triangles, 3 vertex indices each. */
  indices: ArrayLike<number>
  /** Texture coordinates, u v per vertex. Default: the cloth's uvs at each vertex's embedded point. */
  uvs?: ArrayLike<number>
  /**
   * Farthest a render vertex may lie from the cloth's rest surface, m: one farther is a ClothError
   * (the meshes are most likely in different frames). Default: a tenth of the diagonal of the
   * cloth's rest bounds.
   */
  maxOffset?: number
}

const PROXY_KEYS = keysOf<RenderProxyOptions>({ positions: true, indices: true, uvs: true, maxOffset: true })

/** A proxy's render mesh: views that stay the same objects for the proxy's life. */
export interface RenderProxyMesh {
  /** xyz per render vertex, m. */
  positions: Float32Array
  /** Unit normal per render vertex. */
  normals: Float32Array
  /** u v per render vertex. */
  uvs: Float32Array
  /** 3 render vertex indices per triangle; a triangle spanning a tear is collapsed onto one vertex. */
  indices: Uint32Array
  vertexCount: number
  triangleCount: number
  /** Bumped whenever `indices` changed (a tear hid triangles): upload them again. */
  indexVersion: number
}

/** A render proxy: pass it to `updateRenderProxy` and `removeRenderProxy`. */
export interface ClothRenderProxy {
  /** The cloth that drives it. */
  readonly cloth: number
  /** Its render mesh (what `updateRenderProxy` returns). */
  readonly mesh: RenderProxyMesh
  /** How its vertices are embedded in the cloth (rest data). */
  readonly binding: ProxyBinding
}

interface ProxyState extends ClothRenderProxy {
  world: ClothWorldState
  state: ClothState
  /** The cloth's `version` the mesh was written at (−1: never). */
  version: number
  frame: Float64Array
}

/** Live proxies (a removed one is forgotten, so using it again is a ClothError). */
const live = new WeakSet<object>()

/**
 * Each world's proxies, for `refreshFrameProxies` (weakly held: a proxy dropped without
 * `removeRenderProxy` is still collected).
 */
const proxiesOf = new WeakMap<ClothWorldState, WeakRef<ProxyState>[]>()

/**
 * Drives a finer render mesh with a cloth. Each render vertex is embedded once, here, in the cloth's
 * rest triangle closest to it (barycentric weights of the closest point, plus its offset from that
 * point and its rest normal in the frame of the interpolated normal there); `updateRenderProxy`
 * moves it with the triangle. Works for any cloth and render mesh that share a rest frame (a finer
 * grid of a grid cloth is the common case). Normals are the cloth's vertex normals interpolated
 * at each render vertex (turned by its rest normal's angle to them), so shading is smooth across
 * the simulated triangles instead of showing their facets. On a tearable cloth each render vertex
 * follows the triangle it was embedded in, and a render triangle that spans a tear is hidden.
 */
export function createRenderProxy(world: object, cloth: number, options: RenderProxyOptions): ClothRenderProxy {
  const state = getClothWorld(world)
  const c = getCloth(state, cloth)
  checkObject('options', options)
  checkKeys('options', options, PROXY_KEYS)
  const n = checkMeshInput(options.positions, options.indices, 'options.')
  const uvs = options.uvs === undefined ? undefined : checkUvs('options.uvs', options.uvs, n)
  const t = c.topology
  const maxOffset = options.maxOffset === undefined
    ? defaultMaxOffset(t.restPositions, c.count)
    : checkAtMost('options.maxOffset', checkPositive('options.maxOffset', options.maxOffset), MAX_COORDINATE, ' m')
  const binding = bindProxy(
    t.restPositions,
    t.triangles,
    t.triangleCount,
    c.count,
    options.positions,
    options.indices,
    maxOffset,
    'options.positions',
  )
  const mesh: RenderProxyMesh = {
    positions: new Float32Array(3 * n),
    normals: new Float32Array(3 * n),
    uvs: uvs === undefined ? embeddedUvs(binding, t.triangles, c.render.uvs) : Float32Array.from(uvs),
    indices: Uint32Array.from(binding.indices),
    vertexCount: n,
    triangleCount: binding.triangleCount,
    indexVersion: 0,
  }
  // render triangles spanning an existing cut (a torn cloth, or an authored seam) start hidden
  updateProxySeams(
    t.triangles,
    binding.seamStart,
    binding.seamTri,
    binding.seamCorner,
    binding.indices,
    binding.triangleCount,
    mesh.indices,
  )
  const proxy: ProxyState = { cloth, mesh, binding, world: state, state: c, version: -1, frame: new Float64Array(FRAME_SIZE) }
  live.add(proxy)
  let list = proxiesOf.get(state)
  if (list === undefined) proxiesOf.set(state, list = [])
  // (a world stepped only by stepCloth never refreshes its proxies: forget the dead ones here, each
  // time the list doubles, or 60,000 proxies made and removed held 2.3 MB)
  if (list.length >= 16 && list.length >= 2 * (sweptAt.get(list) ?? 0)) {
    forgetDead(state, list, false)
    sweptAt.set(list, list.length)
  }
  list.push(new WeakRef(proxy))
  return proxy
}

/** Each proxy list's length after its last sweep in `createRenderProxy`. */
const sweptAt = new WeakMap<WeakRef<ProxyState>[], number>()

/** Drops the proxies that were removed, collected or whose cloth is gone; `refresh`: brings the stale live ones up to date. */
function forgetDead(state: ClothWorldState, list: WeakRef<ProxyState>[], refresh: boolean): void {
  const cloths = state.components.Cloth.state
  for (let i = list.length - 1; i >= 0; i--) {
    const p = list[i].deref()
    if (p === undefined || !live.has(p) || cloths[p.cloth] !== p.state) {
      list[i] = list[list.length - 1]
      list.pop()
    } else if (refresh && p.version !== -1 && p.version !== p.state.version) writeProxy(p)
  }
}

/**
 * Brings a proxy's render mesh up to date with its cloth and returns it: the same arrays every
 * call, rewritten only when the cloth moved since the last call. Allocates nothing. Between
 * `beginClothStep` and `endClothStep` it gives the mesh of the last finished step (the frame's
 * start brought it up to date, see `refreshFrameProxies`), in every mode; a proxy never updated
 * before the frame began has none to give then (a ClothError).
 */
export function updateRenderProxy(world: object, proxy: ClothRenderProxy): RenderProxyMesh {
  const p = liveProxy(world, proxy)
  const c = p.state
  if (p.version === c.version) return p.mesh
  // the workers may be writing the particles
  if (p.world.frame.open && !p.world.frame.delivering) throw notReadBeforeFrame(world, p.cloth, 'render proxy')
  return writeProxy(p)
}

/** Rewrites a proxy's render mesh from its cloth's particles. */
function writeProxy(p: ProxyState): RenderProxyMesh {
  const c = p.state
  const r = refreshClothRender(c)
  const b = p.binding, m = p.mesh
  const tris = c.topology.triangles
  updateProxyVertices(c.pos, r.normals, tris, b.tri, b.bary, b.offset, b.normal, b.vertexCount, m.positions, m.normals, p.frame)
  if (c.tear !== null && updateProxySeams(tris, b.seamStart, b.seamTri, b.seamCorner, b.indices, b.triangleCount, m.indices) > 0)
    m.indexVersion++
  p.version = c.version
  return m
}

/** Forgets a proxy: later calls with it throw ClothError. Removing a cloth ends its proxies too. */
export function removeRenderProxy(world: object, proxy: ClothRenderProxy): void {
  liveProxy(world, proxy, true)
  live.delete(proxy)
}

/**
 * The proxies' part of `refreshFrameMeshes` (same moment, same reason): brings every live proxy
 * that was updated before and is stale up to date, so that reads until the step's finish give the
 * last finished step; forgets the proxies that were removed, collected or whose cloth is gone.
 * Allocates nothing.
 */
export function refreshFrameProxies(state: ClothWorldState): void {
  const list = proxiesOf.get(state)
  if (list !== undefined) forgetDead(state, list, true)
}

function liveProxy(world: object, proxy: ClothRenderProxy, removing = false): ProxyState {
  const state = getClothWorld(world)
  if (typeof proxy !== 'object' || proxy === null || !live.has(proxy)) {
    throw new ClothError('proxy', proxy, 'must be a render proxy from createRenderProxy that was not removed')
  }
  const p = proxy as ProxyState
  if (p.world !== state) throw new ClothError('proxy', proxy, 'belongs to another world')
  if (state.components.Cloth.state[p.cloth] !== p.state) {
    if (removing) return p
    throw new ClothError('proxy', proxy, `follows cloth ${p.cloth}, which was removed`)
  }
  return p
}

/** A tenth of the diagonal of the first `n` rest positions' bounds. */
function defaultMaxOffset(rest: Float64Array, n: number): number {
  let d2 = 0
  for (let k = 0; k < 3; k++) {
    let lo = Infinity, hi = -Infinity
    for (let i = 0; i < n; i++) {
      const x = rest[3 * i + k]
      if (x < lo) lo = x
      if (x > hi) hi = x
    }
    d2 += (hi - lo) * (hi - lo)
  }
  return 0.1 * Math.sqrt(d2)
}

/** The cloth's uvs interpolated at each render vertex's embedded point. */
function embeddedUvs(b: ProxyBinding, tris: Uint32Array, clothUvs: Float32Array): Float32Array {
  const out = new Float32Array(2 * b.vertexCount)
  for (let v = 0; v < b.vertexCount; v++) {
    const t = b.tri[v], w0 = b.bary[2 * v], w1 = b.bary[2 * v + 1], w2 = 1 - w0 - w1
    const i0 = 2 * tris[3 * t], i1 = 2 * tris[3 * t + 1], i2 = 2 * tris[3 * t + 2]
    out[2 * v] = w0 * clothUvs[i0] + w1 * clothUvs[i1] + w2 * clothUvs[i2]
    out[2 * v + 1] = w0 * clothUvs[i0 + 1] + w1 * clothUvs[i1 + 1] + w2 * clothUvs[i2 + 1]
  }
  return out
}
