import {
  clothEvents,
  clothGuard,
  clothPhases,
  clothSubstepCount,
  clothSync,
  getClothState,
  setClothInertia,
  setClothMotionConstraints,
  setClothSubstep,
} from '../../src/index'
import { predictPositions, updateVelocities } from '../../src/kernels/integrate'
import { constrainAndUpdateVelocities, predictInFrame } from '../../src/kernels/motion'
import { capeCrowd } from './budget'
import { fmt, saveJson, table } from './harness'

const N = 24 // the crowd's capes are 24×24

/** Max distance by row: `paint(row / (N − 1))` for each particle of a 24×24 cape. */
const painted = (paint: (u: number) => number) => Array.from({ length: N * N }, (_, i) => paint(Math.floor(i / N) / (N - 1)))

/**
 * What character cloth costs: the 64-cape crowd (`capeCrowd`: 24×24 capes on characters running
 * 1 m circles at 3 m/s, 8 substeps, one iteration) with every cape simulated in its character's
 * frame (inertia 0.5, a teleport angle) and held near its reference pose (painted max distance, a
 * backstop), against the same crowd without. The crowds alternate every few frames in one process
 * and each round's ratio pairs two runs made moments apart; time is the process's CPU time, which
 * a busy machine's other processes do not add to. The median ratio is the goal (≤ 1.1).
 */
export function characterCost(): void {
  const demo = painted((u) => (u >= 1 ? Infinity : 0.9 * u * u))
  const linear = painted((u) => 0.6 * u)
  const runs: [string, number[], number][] = [
    ['max distance 0 at the collar, 0.9·u² m below, free at the hem (the demo cape)', demo, 1],
    ['the same, constraints every 2nd substep (every: 2)', demo, 2],
    ['the same, every 4th substep (every: 4)', demo, 4],
    ["the same, the step's last substep only (every: 8)", demo, 8],
    ['max distance 0 at the collar to 0.6 m at the hem, linear (tighter: more particles at their limit)', linear, 1],
    ['the same, every 4th substep (every: 4)', linear, 4],
  ]
  const rows: Record<string, string>[] = []
  const results: Record<string, number[]> = {}
  const reference = new Map<number[], Float64Array[]>() // each painting's capes at every substep, for the deviation column
  for (const [name, maxDistance, every] of runs) {
    const configure = (world: object, hero: number, cape: number) => {
      setClothInertia(world, cape, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5, teleport: { angle: Math.PI / 2 } })
      setClothMotionConstraints(world, cape, { maxDistance, backstop: { distance: 0.02, radius: 0.5 }, every })
    }
    const off = capeCrowd(), on = capeCrowd(configure)
    for (let f = 0; f < 120; f++) {
      off.step()
      on.step()
    }
    // how far the capes are, after these 2 s, from where constraints at every substep put them
    const at = on.capes.map((e) => getClothState(on.world, e).pos.slice())
    if (every === 1) reference.set(maxDistance, at)
    const ref = reference.get(maxDistance)!
    let sum = 0, count = 0
    for (let k = 0; k < at.length; k++) {
      for (let j = 0; j < at[k].length; j++) sum += (at[k][j] - ref[k][j]) ** 2
      count += at[k].length / 3
    }
    const deviation = Math.sqrt(sum / count)
    const frames = 3, rounds = 31
    const tOff: number[] = [], tOn: number[] = [], ratio: number[] = []
    const cpu = () => {
      const u = process.cpuUsage()
      return (u.user + u.system) / 1000
    }
    for (let r = 0; r < rounds; r++) {
      // alternate which goes first, so neither always follows the other's cache traffic
      const order = r % 2 === 0 ? [off, on] : [on, off]
      const t: number[] = []
      for (const crowd of order) {
        const t0 = cpu()
        for (let f = 0; f < frames; f++) crowd.step()
        t.push((cpu() - t0) / frames)
      }
      const [a, b] = r % 2 === 0 ? t : [t[1], t[0]]
      tOff.push(a)
      tOn.push(b)
      ratio.push(b / a)
    }
    const sorted = (xs: number[]) => [...xs].sort((p, q) => p - q)
    const median = (xs: number[]) => sorted(xs)[xs.length >> 1]
    const s = sorted(ratio)
    rows.push({
      painting: name,
      'RMS from every substep, cm': fmt(100 * deviation, 2),
      'without (CPU ms/frame)': fmt(median(tOff), 1),
      'with (CPU ms/frame)': fmt(median(tOn), 1),
      'ratio, median': `${fmt(median(ratio), 3)} (goal ≤ 1.1)`,
      'middle half': `${fmt(s[Math.floor(s.length / 4)], 3)}–${fmt(s[Math.floor((3 * s.length) / 4)], 3)}`,
    })
    results[name] = ratio
  }
  table(
    'Character cloth: the 64-cape crowd with inertia 0.5, max distance and a backstop, against the same crowd without (31 paired rounds of 3 frames; RMS: particle positions after the 2 s warm-up against the same painting at every substep)',
    rows,
  )
  saveJson('character', results)
  phaseSplit()
  kernelCost()
}

/**
 * Where the overhead goes: the 64-cape crowd without and with character cloth (the demo painting
 * at every substep), stepped phase by phase through the public scheduling API (`clothSync`, then
 * `clothPhases` per substep, `clothGuard`, `clothEvents`: the same step as `clothFixedStep`),
 * each phase's wall time summed over 150 frames, the two crowds alternating frame by frame. Each
 * phase's extra time is given as a share of the whole step without.
 */
function phaseSplit(): void {
  const maxDistance = painted((u) => (u >= 1 ? Infinity : 0.9 * u * u))
  const names = ['sync', ...clothPhases.map((p) => p.name.replace(/^cloth/, '').toLowerCase()), 'guard and events']
  const crowds = [
    capeCrowd(),
    capeCrowd((world, hero, cape) => {
      setClothInertia(world, cape, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5, teleport: { angle: Math.PI / 2 } })
      setClothMotionConstraints(world, cape, { maxDistance, backstop: { distance: 0.02, radius: 0.5 } })
    }),
  ]
  const times = crowds.map(() => new Float64Array(names.length))
  let into: Float64Array = times[0]
  const timed = (world: object) => {
    let t0 = performance.now()
    const lap = (q: number) => {
      const t1 = performance.now()
      into[q] += t1 - t0
      t0 = t1
    }
    clothSync(world)
    lap(0)
    for (let s = 0; s < clothSubstepCount(world); s++) {
      setClothSubstep(world, s)
      for (let q = 0; q < clothPhases.length; q++) {
        clothPhases[q](world)
        lap(q + 1)
      }
    }
    clothGuard(world)
    clothEvents(world)
    lap(names.length - 1)
  }
  for (let f = 0; f < 270; f++) {
    if (f === 120) { for (const t of times) t.fill(0) // after the warm-up
     }
    crowds.forEach((crowd, q) => {
      into = times[q]
      crowd.step(timed)
    })
  }
  const total = times[0].reduce((a, b) => a + b, 0)
  table(
    'Character cloth, by phase: ms per frame of the 64-cape crowd without and with inertia 0.5, the demo painting and a backstop at every substep (150 frames, alternating)',
    names.map((name, q) => ({
      phase: name,
      'without (ms/frame)': fmt(times[0][q] / 150, 2),
      'with (ms/frame)': fmt(times[1][q] / 150, 2),
      'extra, share of the step without': `${fmt((100 * (times[1][q] - times[0][q])) / total, 1)} %`,
    })),
  )
}

/**
 * The per-particle cost of the character kernels against the world-space ones they replace, on
 * the 64 capes of a configured crowd as they stand after 120 frames (CPU time, median of 9 rounds
 * of 40 passes over all capes). The kernels run on copies, so the crowd's state is untouched.
 */
function kernelCost(): void {
  const maxDistance = painted((u) => (u >= 1 ? Infinity : 0.9 * u * u))
  const crowd = capeCrowd((world, hero, cape) => {
    setClothInertia(world, cape, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5 })
    setClothMotionConstraints(world, cape, { maxDistance, backstop: { distance: 0.02, radius: 0.5 } })
  })
  for (let f = 0; f < 120; f++) crowd.step()
  const cloths = crowd.capes.map((e) => {
    const c = getClothState(crowd.world, e)
    const ch = c.character!
    return {
      c,
      ch,
      pos: c.pos.slice(),
      prev: c.prev.slice(),
      vel: c.vel.slice(),
      params: c.params.slice(),
      inv3: c.invMass3.slice(),
      held: ch.limitHeld.slice(),
    }
  })
  const reset = () => {
    for (const k of cloths) {
      k.pos.set(k.c.pos)
      k.prev.set(k.c.prev)
      k.vel.set(k.c.vel)
    }
  }
  const kernels: [string, () => void][] = [
    ['predict, world space (predictPositions)', () => {
      for (const k of cloths) predictPositions(k.pos, k.prev, k.vel, k.c.invMass, null, k.params, k.c.count)
    }],
    ['predict in the frame (predictInFrame)', () => {
      for (const k of cloths) predictInFrame(k.pos, k.prev, null, k.vel, k.c.invMass, null, k.params, k.ch.frameParams, k.c.count)
    }],
    ['writeback (updateVelocities)', () => {
      for (const k of cloths) updateVelocities(k.pos, k.prev, k.vel, k.params, k.c.count)
    }],
    ['writeback with motion constraints (constrainAndUpdateVelocities)', () => {
      for (const k of cloths)
        constrainAndUpdateVelocities(
          k.pos,
          k.prev,
          k.ch.start,
          k.vel,
          k.c.invMass,
          k.inv3,
          k.held,
          k.ch.ref,
          k.ch.lim,
          k.ch.refParams,
          k.params,
          1,
          k.c.count,
        )
    }],
  ]
  const particles = cloths.reduce((n, k) => n + k.c.count, 0)
  const cpu = () => {
    const u = process.cpuUsage()
    return (u.user + u.system) / 1000
  }
  const samples = kernels.map(() => [] as number[])
  for (let r = 0; r < 9; r++) {
    kernels.forEach(([, run], q) => {
      reset()
      const t0 = cpu()
      for (let i = 0; i < 40; i++) run()
      samples[q].push(((cpu() - t0) / 40 / particles) * 1e6)
    })
  }
  table(
    'Character kernels: ns per particle and pass, on the 64 capes (CPU time, median of 9 rounds)',
    kernels.map(([name], q) => ({ kernel: name, 'ns/particle': fmt([...samples[q]].sort((a, b) => a - b)[4], 2) })),
  )
}
