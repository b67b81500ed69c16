/**
 * Particle–particle collision kernels (self-collision and cloth–cloth), after the scheme of
 * Müller's "Ten Minute Physics" lesson on self-collision: a spatial hash of particles built once
 * per fixed step, candidate pairs gathered from it once per step within a radius that covers how
 * far particles can travel relative to each other during the step, and those pairs pushed apart
 * every substep. What keeps it stable:
 * - pairs that are close in the rest shape (mesh neighbours, closer than 1.5 × the collision
 *   distance) are never pushed apart, so collisions do not fight the distance constraints;
 * - each particle's predicted motion relative to its cloth's mean motion is clamped per substep to
 *   what the pair radius assumed, so no pair the hash did not see comes into contact by inertia
 *   (the solve's corrections are left whole: clamped, a knot's were spread over substeps as
 *   motion at the limit, and a cape heaped under its crouching character boiled at 3–5 m/s);
 * - friction pulls touching particles toward their common velocity.
 *
 * Scalars travel in a parameter block (slots below).
 */

/** Inverse of the hash cell size, 1/m. */
export const S_INV_CELL = 0
/** Pair search radius, m. */
export const S_RADIUS = 1
/** Collision distance between two particles, m. */
export const S_DIST = 2
/** Static and kinetic friction between touching particles. */
export const S_MU_S = 3
export const S_MU_K = 4
/** Inverse-mass scale of the first and second cloth (0 while a cloth sits a substep out). */
export const S_W_A = 5
export const S_W_B = 6
/** Largest motion of a particle relative to its cloth's mean per substep, m (the clamp). */
export const S_LIMIT = 7
/**
 * Inverse-mass scale of a particle that touched a collider in the previous substep (0.2: five
 * times heavier). A cloth lying on the ground then holds up the layers above it instead of being
 * pushed into the ground and back by every contact, so stacks and folds settle (NvCloth and Unity
 * call this the collision mass scale).
 */
export const S_CONTACT_SCALE = 8
/**
 * Separation per substep, m, a pair may gain from the push-out before the rest is taken out of its
 * velocity (the depenetration speed × h). Below it the push counts as a contact force: a resting
 * stack is held up by the overlaps the ground correction recreates every substep, and these must
 * turn into velocity (and friction load). Above it an old overlap is resolved without a pop.
 */
export const S_SLOP = 9
/** Rest distance, m, below which a self pair is never gathered (mesh neighbours). */
export const S_REST_FILTER = 10
export const SELF_PARAM_COUNT = 11

const H1 = 92837111, H2 = 689287499, H3 = 283923481

/** Hash bucket of integer cell (ix, iy, iz) in a table of mask + 1 buckets (a power of two). */
export function hashCell(ix: number, iy: number, iz: number, mask: number): number {
  return (Math.imul(ix, H1) ^ Math.imul(iy, H2) ^ Math.imul(iz, H3)) & mask
}

/**
 * Counting-sort spatial hash of `count` particles: afterwards the particles of bucket b are
 * entries[start[b] .. start[b + 1]) (ascending), and `sorted` holds their positions in that order
 * (xyz, so the queries read neighbours from contiguous memory). `start` has mask + 2 slots;
 * `bucket` one per particle. Particles with `skip[i]` = 1 (vertices no triangle uses) are left
 * out. Returns the number of entries (pass it to `gatherPairs` as the count).
 */
export function buildHash(
  pos: Float64Array,
  count: number,
  start: Int32Array,
  entries: Int32Array,
  bucket: Int32Array,
  sorted: Float64Array,
  mask: number,
  p: Float64Array,
  skip: Uint8Array | null = null,
): number {
  const inv = p[S_INV_CELL]
  start.fill(0)
  for (let i = 0; i < count; i++) {
    if (skip !== null && skip[i] === 1) {
      bucket[i] = -1
      continue
    }
    const j = 3 * i
    const b = hashCell(Math.floor(pos[j] * inv) | 0, Math.floor(pos[j + 1] * inv) | 0, Math.floor(pos[j + 2] * inv) | 0, mask)
    bucket[i] = b
    start[b]++
  }
  // running sum: start[b] = end of bucket b
  let sum = 0
  for (let b = 0; b <= mask; b++) {
    sum += start[b]
    start[b] = sum
  }
  start[mask + 1] = sum
  // placing back to front leaves start[b] at the bucket's first entry, particles ascending
  for (let i = count - 1; i >= 0; i--) if (bucket[i] >= 0) entries[--start[bucket[i]]] = i
  for (let e = 0; e < sum; e++) {
    const j = 3 * entries[e]
    sorted[3 * e] = pos[j]
    sorted[3 * e + 1] = pos[j + 1]
    sorted[3 * e + 2] = pos[j + 2]
  }
  return sum
}

/**
 * Candidate pairs (i of cloth A, k of cloth B) closer than p[S_RADIUS] now, found through B's hash
 * (`start`, `entriesB`, `sortedB`) and appended to `pairs` (2 particle indices each) from
 * `offset`, at most up to `capacity` pairs in total. A's particles are visited in its own hash
 * order (`entriesA`, `sortedA`, `countA` entries as `buildHash` returned), so consecutive queries
 * touch the same buckets.
 *
 * With `restA` given (self-collision, A = B) each pair is taken once (from the particle earlier in
 * hash order), and pairs closer than p[S_REST_FILTER] in the rest shape (mesh neighbours, which
 * the distance constraints keep apart) are skipped. Pairs of two immovable particles are skipped.
 * `visited` (mask + 2 ints, B's) keeps a bucket from being scanned twice for one particle when two
 * of its cells share it. Returns the new pair count.
 */
export function gatherPairs(
  sortedA: Float64Array,
  entriesA: Int32Array,
  invMassA: Float64Array,
  countA: number,
  restA: Float64Array | null,
  sortedB: Float64Array,
  entriesB: Int32Array,
  invMassB: Float64Array,
  start: Int32Array,
  mask: number,
  visited: Int32Array,
  pairs: Int32Array,
  offset: number,
  capacity: number,
  p: Float64Array,
): number {
  const R = p[S_RADIUS], R2 = R * R, inv = p[S_INV_CELL]
  const F = p[S_REST_FILTER], F2 = F * F
  const self = restA !== null
  // visited[b] = stamp of the last query that scanned bucket b; the running stamp is visited[mask + 1]
  let stamp = visited[mask + 1]
  if (stamp > 0x3fffffff - countA) {
    visited.fill(0)
    stamp = 0
  }
  let n = offset
  for (let si = 0; si < countA; si++) {
    stamp++
    const i = entriesA[si]
    const x = sortedA[3 * si], y = sortedA[3 * si + 1], z = sortedA[3 * si + 2]
    const wa = invMassA[i]
    const x0 = Math.floor((x - R) * inv) | 0, x1 = Math.floor((x + R) * inv) | 0
    const y0 = Math.floor((y - R) * inv) | 0, y1 = Math.floor((y + R) * inv) | 0
    const z0 = Math.floor((z - R) * inv) | 0, z1 = Math.floor((z + R) * inv) | 0
    for (let cx = x0; cx <= x1; cx++) {
      const hx = Math.imul(cx, H1)
      for (let cy = y0; cy <= y1; cy++) {
        const hxy = hx ^ Math.imul(cy, H2)
        for (let cz = z0; cz <= z1; cz++) {
          const b = (hxy ^ Math.imul(cz, H3)) & mask
          if (visited[b] === stamp) continue
          visited[b] = stamp
          const end = start[b + 1]
          let e = start[b]
          if (self && e <= si) e = si + 1 // each self pair once: from the earlier particle
          for (; e < end; e++) {
            const dx = sortedB[3 * e] - x, dy = sortedB[3 * e + 1] - y, dz = sortedB[3 * e + 2] - z
            if (dx * dx + dy * dy + dz * dz > R2) continue
            const k = entriesB[e]
            if (wa === 0 && invMassB[k] === 0) continue
            if (self) {
              const ja = 3 * i, jb = 3 * k
              const rx = restA[jb] - restA[ja], ry = restA[jb + 1] - restA[ja + 1], rz = restA[jb + 2] - restA[ja + 2]
              if (rx * rx + ry * ry + rz * rz < F2) continue
            }
            if (n >= capacity) {
              visited[mask + 1] = stamp
              return n
            }
            pairs[2 * n] = i
            pairs[2 * n + 1] = k
            n++
          }
        }
      }
    }
  }
  visited[mask + 1] = stamp
  return n
}

/**
 * Pushes the particles of each pair (i in A, j in B) apart to at least p[S_DIST], weighted by
 * inverse mass (scaled by p[S_W_A], p[S_W_B], and by p[S_CONTACT_SCALE] for particles flagged in
 * `touchedA`/`touchedB`, those resting on a collider). As with colliders, separation beyond the pair's
 * approach this substep (and beyond p[S_SLOP]) goes into `prev` too (an old overlap resolved
 * without a pop), and the
 * tangential relative motion is reduced by Coulomb friction (static: both move with their common,
 * mass-weighted velocity). Pairs [first, first + count). Returns the number of pairs in contact.
 */
export function solvePairs(
  posA: Float64Array,
  prevA: Float64Array,
  invMassA: Float64Array,
  touchedA: Uint8Array,
  posB: Float64Array,
  prevB: Float64Array,
  invMassB: Float64Array,
  touchedB: Uint8Array,
  pairs: Int32Array,
  first: number,
  count: number,
  p: Float64Array,
): number {
  const D = p[S_DIST], D2 = D * D, muS = p[S_MU_S], muK = p[S_MU_K], sa = p[S_W_A], sb = p[S_W_B]
  const heavy = p[S_CONTACT_SCALE], slop = p[S_SLOP]
  let contacts = 0
  const end = first + count
  for (let q = first; q < end; q++) {
    const i = pairs[2 * q], k = pairs[2 * q + 1]
    const ja = 3 * i, jb = 3 * k
    let dx = posB[jb] - posA[ja], dy = posB[jb + 1] - posA[ja + 1], dz = posB[jb + 2] - posA[ja + 2]
    const d2 = dx * dx + dy * dy + dz * dz
    if (d2 >= D2 || d2 < 1e-24) continue
    // the push treats a particle resting on a collider as heavier; friction uses the true masses,
    // so it only exchanges momentum between the two (a scaled split here fed a folded sheet energy)
    const ua = invMassA[i] * sa, ub = invMassB[k] * sb
    const wa = touchedA[i] === 1 ? ua * heavy : ua
    const wb = touchedB[k] === 1 ? ub * heavy : ub
    const W = wa + wb
    if (W === 0) continue
    contacts++
    const d = Math.sqrt(d2), invD = 1 / d, invW = 1 / W
    const nx = dx * invD, ny = dy * invD, nz = dz * invD
    const push = D - d
    const fa = wa * invW, fb = wb * invW
    posA[ja] -= nx * push * fa
    posA[ja + 1] -= ny * push * fa
    posA[ja + 2] -= nz * push * fa
    posB[jb] += nx * push * fb
    posB[jb + 1] += ny * push * fb
    posB[jb + 2] += nz * push * fb
    // relative motion of B's particle with respect to A's this substep
    dx = posB[jb] - prevB[jb] - (posA[ja] - prevA[ja])
    dy = posB[jb + 1] - prevB[jb + 1] - (posA[ja + 1] - prevA[ja + 1])
    dz = posB[jb + 2] - prevB[jb + 2] - (posA[ja + 2] - prevA[ja + 2])
    const dn = dx * nx + dy * ny + dz * nz
    const excess = dn - slop
    const shift = excess > 0 ? (excess < push ? excess : push) : 0
    if (shift > 0) {
      prevA[ja] -= nx * shift * fa
      prevA[ja + 1] -= ny * shift * fa
      prevA[ja + 2] -= nz * shift * fa
      prevB[jb] += nx * shift * fb
      prevB[jb + 1] += ny * shift * fb
      prevB[jb + 2] += nz * shift * fb
    }
    dx -= dn * nx
    dy -= dn * ny
    dz -= dn * nz
    const t2 = dx * dx + dy * dy + dz * dz
    const load = push - shift
    const ms = muS * load
    let f = 1
    if (t2 > ms * ms) {
      f = (muK * load) / Math.sqrt(t2)
      if (f > 1) f = 1
    }
    const fU = f / (ua + ub)
    const ga = fU * ua, gb = fU * ub
    posA[ja] += dx * ga
    posA[ja + 1] += dy * ga
    posA[ja + 2] += dz * ga
    posB[jb] -= dx * gb
    posB[jb + 1] -= dy * gb
    posB[jb + 2] -= dz * gb
  }
  return contacts
}

/**
 * Clamps each free particle's motion this substep, relative to the mass-weighted mean motion of the
 * cloth's free particles, to p[S_LIMIT] metres: the speed limit under which the step's pair list
 * stays complete. A cloth carried along by a running character is not slowed; only fast motion
 * within the cloth is. With `conserve` (a cloth nothing pins), the momentum the clamped particles
 * lose is given back to all free particles as one common motion (which changes no relative motion,
 * so the limit still holds between any two of them): clamping only the fast side of an uneven
 * spread would otherwise shift the cloth's mean motion every substep, and a crumpled
 * self-colliding sheet propelled itself to 80 m/s that way. A pinned cloth trades momentum with its
 * pins anyway and lets it go: given back, it pushed the whole heap of a cape against its pins and
 * the ground every substep.
 */
export function clampRelativeMotion(
  pos: Float64Array,
  prev: Float64Array,
  invMass: Float64Array,
  count: number,
  p: Float64Array,
  conserve: boolean,
): void {
  let mx = 0, my = 0, mz = 0, m = 0
  for (let i = 0; i < count; i++) {
    const w = invMass[i]
    if (w === 0) continue
    const j = 3 * i
    const mi = 1 / w
    mx += mi * (pos[j] - prev[j])
    my += mi * (pos[j + 1] - prev[j + 1])
    mz += mi * (pos[j + 2] - prev[j + 2])
    m += mi
  }
  if (!(m > 0)) return
  mx /= m
  my /= m
  mz /= m
  const lim = p[S_LIMIT], lim2 = lim * lim
  // momentum taken out by the clamp (Σ m·Δx)
  let lx = 0, ly = 0, lz = 0
  for (let i = 0; i < count; i++) {
    if (invMass[i] === 0) continue
    const j = 3 * i
    const dx = pos[j] - prev[j] - mx, dy = pos[j + 1] - prev[j + 1] - my, dz = pos[j + 2] - prev[j + 2] - mz
    const d2 = dx * dx + dy * dy + dz * dz
    if (d2 <= lim2) continue
    const f = lim / Math.sqrt(d2)
    const g = (1 - f) / invMass[i]
    lx += dx * g
    ly += dy * g
    lz += dz * g
    pos[j] = prev[j] + mx + dx * f
    pos[j + 1] = prev[j + 1] + my + dy * f
    pos[j + 2] = prev[j + 2] + mz + dz * f
  }
  if (!conserve || (lx === 0 && ly === 0 && lz === 0)) return
  lx /= m
  ly /= m
  lz /= m
  for (let i = 0; i < count; i++) {
    if (invMass[i] === 0) continue
    const j = 3 * i
    pos[j] += lx
    pos[j + 1] += ly
    pos[j + 2] += lz
  }
}
