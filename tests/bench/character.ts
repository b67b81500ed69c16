import { setClothInertia, setClothMotionConstraints } from '../../src/index'
import { capeCrowd } from './budget'
import { fmt, saveJson, table } from './harness'

const N = 24 // the crowd's capes are 24×24

/**
 * What character cloth costs: the 64-cape crowd (`capeCrowd`) with every cape simulated in its
 * character's frame (inertia 0.5, a teleport angle) and held near its reference pose (max distance
 * painted from 0 at the collar to 0.6 m at the hem, a backstop), against the same crowd without.
 * Both run in one process, alternating every few frames; each round's ratio pairs two runs made
 * moments apart, so a busy machine slows both alike. The median ratio is the goal (≤ 1.1).
 */
export function characterCost(): void {
  const maxDistance = Array.from({ length: N * N }, (_, i) => (0.6 * Math.floor(i / N)) / (N - 1))
  const configure = (world: object, hero: number, cape: number) => {
    setClothInertia(world, cape, { frame: hero, linear: 0.5, angular: 0.5, centrifugal: 0.5, teleport: { angle: Math.PI / 2 } })
    setClothMotionConstraints(world, cape, { maxDistance, backstop: { distance: 0.02, radius: 0.5 } })
  }
  const off = capeCrowd(), on = capeCrowd(configure)
  for (let f = 0; f < 120; f++) {
    off.step()
    on.step()
  }
  const frames = 4, rounds = 41
  const tOff: number[] = [], tOn: number[] = [], ratio: number[] = []
  for (let r = 0; r < rounds; r++) {
    // alternate which goes first, so neither always follows the other's cache traffic
    const order = r % 2 === 0 ? [off, on] : [on, off]
    const t: number[] = []
    for (const crowd of order) {
      const t0 = performance.now()
      for (let f = 0; f < frames; f++) crowd.step()
      t.push((performance.now() - t0) / frames)
    }
    const [a, b] = r % 2 === 0 ? t : [t[1], t[0]]
    tOff.push(a)
    tOn.push(b)
    ratio.push(b / a)
  }
  const median = (xs: number[]) => [...xs].sort((p, q) => p - q)[xs.length >> 1]
  const quartiles = (xs: number[]) => {
    const s = [...xs].sort((p, q) => p - q)
    return `${fmt(s[Math.floor(s.length / 4)], 3)}–${fmt(s[Math.floor((3 * s.length) / 4)], 3)}`
  }
  table(`Character cloth: 64 capes of 24×24 on running characters with inertia 0.5 and motion constraints (max distance, backstop), against the same crowd without (${rounds} paired rounds of ${frames} frames)`, [
    { 'without (ms/frame)': fmt(median(tOff), 2), 'with (ms/frame)': fmt(median(tOn), 2), 'ratio, median': `${fmt(median(ratio), 3)} (goal ≤ 1.1)`, 'ratio, middle half': quartiles(ratio) },
  ])
  saveJson('character', { tOff, tOn, ratio })
}
