import type { ClothState } from '../../world/state'
import { copyGuardParticle } from '../guard/api'
import { copyCharacterParticle } from '../character/api'
import type { ClothTear } from './types'

/**
 * Splitting one particle so that a crack runs through it (see the tearing module comment in
 * api.ts). Everything here works on the rest shape, where a particle's fan is undistorted, and on
 * the triangles around each particle (`ClothTear.vertTris`, kept current by the splits).
 *
 * Scratch layout: the fan of particle v is gathered into `fan` (triangle), `fanCorner` (v's corner)
 * and `fanP`/`fanQ` (its two other particles); `walk` orders it into chains of triangles that share
 * an edge through v: chain c holds walk[chains[3c] .. chains[3c] + chains[3c + 1]), closed when
 * chains[3c + 2] is 1, and `walkW[i]` is the particle shared by walk[i] and walk[i + 1] (the
 * chain's exit vertex for its last triangle). `fanSide` marks the triangles that move to the new
 * particle.
 */

/** `vec` slots: principal direction e1, fan normal N, crack direction n, scratch. */
const E1 = 0, NRM = 3, CRK = 6, GAP = 9

/** Gathers particle v's fan and orders it into chains. Returns the number of chains. */
export function gatherFan(T: ClothTear, v: number): number {
  const tris = T.topology.triangles
  const start = T.vertStart[v], len = T.vertLen[v]
  for (let f = 0; f < len; f++) {
    const t = T.vertTris[start + f]
    const k = tris[3 * t] === v ? 0 : tris[3 * t + 1] === v ? 1 : 2
    T.fan[f] = t
    T.fanCorner[f] = k
    T.fanP[f] = tris[3 * t + ((k + 1) % 3)]
    T.fanQ[f] = tris[3 * t + ((k + 2) % 3)]
    T.fanSide[f] = 0 // here: walked yet
  }
  T.fanCount = len
  let w = 0, nc = 0
  // open chains first (they start at a triangle with an edge through v no other fan triangle
  // shares), then closed cycles
  for (let pass = 0; pass < 2; pass++) {
    for (let f = 0; f < len; f++) {
      if (T.fanSide[f] !== 0) continue
      let entry = -1
      if (pass === 0) {
        if (!sharedByOther(T, f, T.fanP[f])) entry = T.fanP[f]
        else if (!sharedByOther(T, f, T.fanQ[f])) entry = T.fanQ[f]
        else continue
      } else entry = T.fanP[f]
      const entry0 = entry
      const first = w
      let cur = f
      for (;;) {
        T.fanSide[cur] = 1
        T.walk[w] = cur
        const exit = T.fanP[cur] === entry ? T.fanQ[cur] : T.fanP[cur]
        T.walkW[w] = exit
        w++
        let next = -1
        for (let g = 0; g < len && next < 0; g++) if (T.fanSide[g] === 0 && (T.fanP[g] === exit || T.fanQ[g] === exit)) next = g
        if (next < 0) break
        entry = exit
        cur = next
      }
      T.chains[3 * nc] = first
      T.chains[3 * nc + 1] = w - first
      T.chains[3 * nc + 2] = pass === 1 && T.walkW[w - 1] === entry0 ? 1 : 0
      // the particle across the chain's first edge through v (an open chain's border there)
      T.chainEntry[nc] = entry0
      nc++
    }
  }
  for (let f = 0; f < len; f++) T.fanSide[f] = 0
  T.chainCount = nc
  return nc
}

function sharedByOther(T: ClothTear, f: number, u: number): boolean {
  for (let g = 0; g < T.fanCount; g++) if (g !== f && (T.fanP[g] === u || T.fanQ[g] === u)) return true
  return false
}

/**
 * The direction of greatest tension at particle v, into vec[E1..E1+2] (rest space): the principal
 * axis of Σ max(0, strain)·u⊗u over v's edges (u: the edge's rest direction), by power iteration
 * from the direction of the edge v – o that broke. Also the fan's rest normal into vec[NRM..].
 */
export function tensionAt(c: ClothState, T: ClothTear, v: number, o: number): void {
  const rest = T.topology.restPositions, pos = c.pos, m = T.mat, vec = T.vec
  for (let j = 0; j < 9; j++) m[j] = 0
  let nx = 0, ny = 0, nz = 0
  for (let f = 0; f < T.fanCount; f++) {
    // each edge v – p once (p: the vertex after v in the triangle's winding); normals by area
    for (let s = 0; s < 2; s++) {
      const u = s === 0 ? T.fanP[f] : T.fanQ[f]
      const rx = rest[3 * u] - rest[3 * v], ry = rest[3 * u + 1] - rest[3 * v + 1], rz = rest[3 * u + 2] - rest[3 * v + 2]
      if (s === 0) {
        const q = T.fanQ[f]
        const qx = rest[3 * q] - rest[3 * v], qy = rest[3 * q + 1] - rest[3 * v + 1], qz = rest[3 * q + 2] - rest[3 * v + 2]
        nx += ry * qz - rz * qy
        ny += rz * qx - rx * qz
        nz += rx * qy - ry * qx
      }
      const r2 = rx * rx + ry * ry + rz * rz
      if (r2 === 0) continue
      const dx = pos[3 * u] - pos[3 * v], dy = pos[3 * u + 1] - pos[3 * v + 1], dz = pos[3 * u + 2] - pos[3 * v + 2]
      const strain = Math.sqrt((dx * dx + dy * dy + dz * dz) / r2) - 1
      if (!(strain > 0)) continue
      // each edge is seen from both its triangles (or once on a border): weight ½ either way
      const wgt = (0.5 * strain) / r2
      m[0] += wgt * rx * rx
      m[1] += wgt * rx * ry
      m[2] += wgt * rx * rz
      m[4] += wgt * ry * ry
      m[5] += wgt * ry * rz
      m[8] += wgt * rz * rz
    }
  }
  m[3] = m[1]
  m[6] = m[2]
  m[7] = m[5]
  let ex = rest[3 * o] - rest[3 * v], ey = rest[3 * o + 1] - rest[3 * v + 1], ez = rest[3 * o + 2] - rest[3 * v + 2]
  for (let it = 0; it < 12; it++) {
    const x = m[0] * ex + m[1] * ey + m[2] * ez
    const y = m[3] * ex + m[4] * ey + m[5] * ez
    const z = m[6] * ex + m[7] * ey + m[8] * ez
    const l = Math.sqrt(x * x + y * y + z * z)
    if (!(l > 1e-300)) break
    ex = x / l
    ey = y / l
    ez = z / l
  }
  const el = Math.sqrt(ex * ex + ey * ey + ez * ez) || 1
  vec[E1] = ex / el
  vec[E1 + 1] = ey / el
  vec[E1 + 2] = ez / el
  const nl = Math.sqrt(nx * nx + ny * ny + nz * nz) || 1
  vec[NRM] = nx / nl
  vec[NRM + 1] = ny / nl
  vec[NRM + 2] = nz / nl
  // the crack runs across the tension, in the cloth's plane: n = N × e1
  const cx = vec[NRM + 1] * vec[E1 + 2] - vec[NRM + 2] * vec[E1 + 1]
  const cy = vec[NRM + 2] * vec[E1] - vec[NRM] * vec[E1 + 2]
  const cz = vec[NRM] * vec[E1 + 1] - vec[NRM + 1] * vec[E1]
  const cl = Math.sqrt(cx * cx + cy * cy + cz * cz) || 1
  vec[CRK] = cx / cl
  vec[CRK + 1] = cy / cl
  vec[CRK + 2] = cz / cl
}

/** Rest direction v → u projected on vec[o..o+2], over the edge's length. */
function along(T: ClothTear, v: number, u: number, o: number): number {
  const rest = T.topology.restPositions, vec = T.vec
  const rx = rest[3 * u] - rest[3 * v], ry = rest[3 * u + 1] - rest[3 * v + 1], rz = rest[3 * u + 2] - rest[3 * v + 2]
  const l = Math.sqrt(rx * rx + ry * ry + rz * rz)
  return l > 0 ? (rx * vec[o] + ry * vec[o + 1] + rz * vec[o + 2]) / l : 0
}

/** Smallest |cos| between a cut edge and the crack direction for a cut to be made (about 53°). */
const MIN_ALIGN = 0.6

/**
 * Chooses how to split v (its fan gathered, the tension known): marks in `fanSide` (by fan index)
 * the triangles that move to the new particle and writes the seam's far ends (the particles the
 * crack now reaches) into seam[0], seam[1] (−1: none). `strict`: only along edges within about
 * 53° of the crack direction (else the best there is). Returns false when no cut fits:
 * - several chains (v only pinches pieces together): the smallest chain moves;
 * - one closed fan (v inside the cloth): a slit across the tension, along the two edges of v that
 *   best follow the crack direction on either side;
 * - one open fan (v on a crack or on the cloth's border): the crack goes on through the edge that
 *   best follows the crack direction away from the opening.
 */
export function chooseCut(T: ClothTear, v: number, strict: boolean): boolean {
  const align = strict ? MIN_ALIGN : -1
  const nc = T.chainCount
  T.seam[0] = -1
  T.seam[1] = -1
  if (nc === 0) return false
  if (nc > 1) {
    let best = 0
    for (let k = 1; k < nc; k++) if (T.chains[3 * k + 1] < T.chains[3 * best + 1]) best = k
    markWalk(T, T.chains[3 * best], T.chains[3 * best + 1], 0, T.chains[3 * best + 1])
    return true
  }
  const first = T.chains[0], len = T.chains[1]
  if (T.chains[2] === 1) {
    // closed: the interior edges are walkW[first + i], between walk[i] and walk[i + 1 (mod len)]
    if (len < 3) return false
    let i1 = -1, i2 = -1, hi = -2, lo = 2
    for (let i = 0; i < len; i++) {
      const a = along(T, v, T.walkW[first + i], CRK)
      if (a > hi) {
        hi = a
        i1 = i
      }
      if (a < lo) {
        lo = a
        i2 = i
      }
    }
    if (i1 === i2 || hi < align || lo > -align) return false
    // the arc after i1 up to i2 moves
    const from = (i1 + 1) % len
    const count = (i2 - i1 + len) % len
    markWalk(T, first, len, from, count)
    T.seam[0] = T.walkW[first + i1]
    T.seam[1] = T.walkW[first + i2]
    return true
  }
  // open: interior edges walkW[first + i], i < len − 1; the opening lies between the two border edges
  if (len < 2) return false
  const vec = T.vec
  const rest = T.topology.restPositions
  const b0 = T.chainEntry[0], b1 = T.walkW[first + len - 1]
  for (let j = 0; j < 3; j++) {
    const l0 = dist(rest, v, b0), l1 = dist(rest, v, b1)
    vec[GAP + j] = (rest[3 * b0 + j] - rest[3 * v + j]) / (l0 || 1) + (rest[3 * b1 + j] - rest[3 * v + j]) / (l1 || 1)
  }
  // forward: along the crack direction, away from the opening
  const g = vec[GAP] * vec[CRK] + vec[GAP + 1] * vec[CRK + 1] + vec[GAP + 2] * vec[CRK + 2]
  const sign = g > 0 ? -1 : 1
  let best = -1, score = -2
  for (let i = 0; i < len - 1; i++) {
    const a = sign * along(T, v, T.walkW[first + i], CRK)
    if (a > score) {
      score = a
      best = i
    }
  }
  if (best < 0 || score < align) return false
  markWalk(T, first, len, best + 1, len - best - 1)
  T.seam[0] = T.walkW[first + best]
  return true
}

function dist(rest: Float64Array, a: number, b: number): number {
  const x = rest[3 * b] - rest[3 * a], y = rest[3 * b + 1] - rest[3 * a + 1], z = rest[3 * b + 2] - rest[3 * a + 2]
  return Math.sqrt(x * x + y * y + z * z)
}

/** Marks `count` triangles of the chain at walk[first..first+len), from position `from` on (cyclically). */
function markWalk(T: ClothTear, first: number, len: number, from: number, count: number): void {
  for (let f = 0; f < T.fanCount; f++) T.fanSide[f] = 0
  for (let i = 0; i < count; i++) T.fanSide[T.walk[first + ((from + i) % len)]] = 1
}

/**
 * Whether splitting v as marked in `fanSide` would cut free a piece of fewer than `min`
 * triangles: a flood fill through shared particles from each side (v counting as two particles,
 * one per side), stopped as soon as it meets the other side or has `min` triangles.
 */
export function cutsSmallPiece(T: ClothTear, v: number, min: number): boolean {
  if (min <= 1) return false
  const tris = T.topology.triangles
  // side of each fan triangle, by triangle: 1 stays with v, 2 moves
  for (let f = 0; f < T.fanCount; f++) T.triSide[T.fan[f]] = T.fanSide[f] === 1 ? 2 : 1
  let small = false
  for (let side = 1; side <= 2 && !small; side++) {
    const stamp = ++T.stamp
    let head = 0, tail = 0, seen = 0, met = false
    for (let f = 0; f < T.fanCount && seen < min; f++) {
      const t = T.fan[f]
      if (T.triSide[t] !== side) continue
      T.seen[t] = stamp
      T.queue[tail++] = t
      seen++
    }
    while (head < tail && seen < min && !met) {
      const t = T.queue[head++]
      for (let k = 0; k < 3 && seen < min && !met; k++) {
        const u = tris[3 * t + k]
        const s = T.vertStart[u], n = T.vertLen[u]
        for (let q = 0; q < n; q++) {
          const x = T.vertTris[s + q]
          const xs = T.triSide[x]
          if (u === v && xs !== side) continue // through v only to this side's triangles
          if (xs !== 0 && xs !== side) {
            met = true // joined to the other side by another path
            break
          }
          if (T.seen[x] === stamp) continue
          T.seen[x] = stamp
          T.queue[tail++] = x
          if (++seen >= min) break
        }
      }
    }
    if (!met && seen < min) small = true
  }
  for (let f = 0; f < T.fanCount; f++) T.triSide[T.fan[f]] = 0
  return small
}

/**
 * Splits particle v as marked in `fanSide`: the marked triangles are re-indexed to a new particle
 * (a copy of v: position, velocity, rest position, texture coordinates; the mass shared by the
 * rest area of the two sides, neither below 20 %), and v's triangle list is split between the two. Returns the new
 * particle.
 */
export function applySplit(c: ClothState, T: ClothTear, v: number): number {
  const t = T.topology
  const tris = t.triangles
  const rest = t.restPositions
  const pos = c.pos
  const nv = c.count
  let areaPlus = 0, areaAll = 0
  for (let f = 0; f < T.fanCount; f++) {
    const base = 3 * T.fan[f]
    const ra = 3 * tris[base], rb = 3 * tris[base + 1], rc = 3 * tris[base + 2]
    const ux = rest[rb] - rest[ra], uy = rest[rb + 1] - rest[ra + 1], uz = rest[rb + 2] - rest[ra + 2]
    const vx = rest[rc] - rest[ra], vy = rest[rc + 1] - rest[ra + 1], vz = rest[rc + 2] - rest[ra + 2]
    const cx = uy * vz - uz * vy, cy = uz * vx - ux * vz, cz = ux * vy - uy * vx
    const A = Math.sqrt(cx * cx + cy * cy + cz * cz) // twice the area: only ratios matter
    areaAll += A
    if (T.fanSide[f] === 1) {
      areaPlus += A
      tris[base + T.fanCorner[f]] = nv
    }
  }
  // v's triangle list: those that stay first, those that move after them (the new particle's list)
  const s = T.vertStart[v]
  let keep = 0
  for (let f = 0; f < T.fanCount; f++) if (T.fanSide[f] === 0) T.vertTris[s + keep++] = T.fan[f]
  let moved = keep
  for (let f = 0; f < T.fanCount; f++) if (T.fanSide[f] === 1) T.vertTris[s + moved++] = T.fan[f]
  T.vertLen[v] = keep
  T.vertStart[nv] = s + keep
  T.vertLen[nv] = moved - keep
  for (let j = 0; j < 3; j++) {
    pos[3 * nv + j] = pos[3 * v + j]
    c.prev[3 * nv + j] = c.prev[3 * v + j]
    c.vel[3 * nv + j] = c.vel[3 * v + j]
    rest[3 * nv + j] = rest[3 * v + j]
  }
  const uvs = c.render.uvs
  uvs[2 * nv] = uvs[2 * v]
  uvs[2 * nv + 1] = uvs[2 * v + 1]
  copyGuardParticle(c, v, nv)
  // share the mass by rest area, neither part below 20 % (extreme mass ratios hurt Gauss-Seidel)
  let frac = areaAll > 0 ? areaPlus / areaAll : 0.5
  if (frac < 0.2) frac = 0.2
  else if (frac > 0.8) frac = 0.8
  const m = 1 / c.baseInvMass[v]
  const mPlus = m * frac, mMinus = m - mPlus
  t.masses[nv] = mPlus
  t.masses[v] = mMinus
  c.baseInvMass[nv] = 1 / mPlus
  c.baseInvMass[v] = 1 / mMinus
  c.invMass[nv] = 1 / mPlus
  if (c.pinCount[v] === 0) c.invMass[v] = 1 / mMinus
  c.pinCount[nv] = 0
  copyCharacterParticle(c, v, nv) // (after the pin count: a particle held on its reference stays held)
  c.count = nv + 1
  t.particleCount = nv + 1
  return nv
}
