import * as THREE from 'three'

/**
 * Textures drawn on canvases at startup (the demo downloads no assets): colour maps for each
 * cloth, tileable normal maps for the weave of fabric and the grain of leather, and the ground's
 * tiles. Each is made once and shared by every scene that asks for it.
 */

const cache = new Map<string, THREE.Texture>()

function cached(key: string, make: () => THREE.Texture): THREE.Texture {
  let t = cache.get(key)
  if (!t) cache.set(key, t = make())
  return t
}

function canvas(w: number, h = w): [HTMLCanvasElement, CanvasRenderingContext2D] {
  const c = document.createElement('canvas')
  c.width = w
  c.height = h
  return [c, c.getContext('2d', { willReadFrequently: true })!]
}

function colorTexture(c: HTMLCanvasElement, repeat = 1): THREE.CanvasTexture {
  const t = new THREE.CanvasTexture(c)
  t.colorSpace = THREE.SRGBColorSpace
  t.wrapS = t.wrapT = THREE.RepeatWrapping
  t.repeat.set(repeat, repeat)
  return t
}

/** Tileable value noise in [0, 1) on a `period`-cell lattice (smoothstep interpolation). */
function noise2(x: number, y: number, period: number, seed: number): number {
  const hash = (i: number, j: number) => {
    i = ((i % period) + period) % period
    j = ((j % period) + period) % period
    let h = (i * 374761393 + j * 668265263 + seed * 2147483647) | 0
    h = Math.imul(h ^ (h >>> 13), 1274126177)
    return ((h ^ (h >>> 16)) >>> 0) / 4294967296
  }
  const xi = Math.floor(x), yi = Math.floor(y)
  const fx = x - xi, fy = y - yi
  const sx = fx * fx * (3 - 2 * fx), sy = fy * fy * (3 - 2 * fy)
  const a = hash(xi, yi), b = hash(xi + 1, yi), c = hash(xi, yi + 1), d = hash(xi + 1, yi + 1)
  return a + (b - a) * sx + (c - a) * sy + (a - b - c + d) * sx * sy
}

/** Fractal noise in about [0, 1), tileable over `size` pixels. */
function fbm(x: number, y: number, size: number, base: number, octaves: number, seed: number): number {
  let v = 0, amp = 0.5, norm = 0
  for (let o = 0; o < octaves; o++) {
    const period = base << o
    v += amp * noise2((x / size) * period, (y / size) * period, period, seed + o)
    norm += amp
    amp *= 0.5
  }
  return v / norm
}

/** A tangent-space normal map from a height field (Sobel, tileable), as a linear texture. */
function normalMapFrom(height: Float32Array, size: number, strength: number, repeat: number): THREE.Texture {
  const [c, ctx] = canvas(size)
  const img = ctx.createImageData(size, size)
  const h = (x: number, y: number) => height[((y + size) % size) * size + ((x + size) % size)]
  for (let y = 0; y < size; y++) {
    for (let x = 0; x < size; x++) {
      const dx = (h(x + 1, y - 1) + 2 * h(x + 1, y) + h(x + 1, y + 1) - h(x - 1, y - 1) - 2 * h(x - 1, y) - h(x - 1, y + 1)) * strength
      const dy = (h(x - 1, y + 1) + 2 * h(x, y + 1) + h(x + 1, y + 1) - h(x - 1, y - 1) - 2 * h(x, y - 1) - h(x + 1, y - 1)) * strength
      const len = Math.hypot(dx, dy, 1)
      const i = 4 * (y * size + x)
      img.data[i] = ((-dx / len) * 0.5 + 0.5) * 255
      img.data[i + 1] = ((dy / len) * 0.5 + 0.5) * 255 // canvas y runs down, texture v runs up
      img.data[i + 2] = ((1 / len) * 0.5 + 0.5) * 255
      img.data[i + 3] = 255
    }
  }
  ctx.putImageData(img, 0, 0)
  const t = new THREE.CanvasTexture(c)
  t.wrapS = t.wrapT = THREE.RepeatWrapping
  t.repeat.set(repeat, repeat)
  return t
}

/**
 * The relief of a plain weave (one thread over, one under), tileable: threads run across and
 * down, each rounded, rising where it passes over its crossing thread. `threads` per tile side.
 */
export function weaveNormal(repeat: number, threads = 8): THREE.Texture {
  return cached(`weave:${repeat}:${threads}`, () => {
    const size = 128
    const cell = size / threads
    const height = new Float32Array(size * size)
    for (let y = 0; y < size; y++) {
      for (let x = 0; x < size; x++) {
        const i = Math.floor(x / cell), j = Math.floor(y / cell)
        const u = (x % cell) / cell, v = (y % cell) / cell
        const across = Math.sin(Math.PI * v) // a thread running along x, round across its width
        const down = Math.sin(Math.PI * u)
        const overAcross = (i + j) % 2 === 0
        // the thread on top shows its whole rounded width; the one below dips where it is covered
        const ha = across * (overAcross ? 1 : 0.45 + 0.35 * Math.abs(2 * u - 1))
        const hb = down * (overAcross ? 0.45 + 0.35 * Math.abs(2 * v - 1) : 1)
        height[y * size + x] = Math.max(ha, hb) + 0.08 * noise2(x / 3, y / 3, size / 3, 5)
      }
    }
    return normalMapFrom(height, size, 1.2, repeat)
  })
}

/** Pebbled grain of leather, tileable. */
export function leatherNormal(repeat: number): THREE.Texture {
  return cached(`leather:${repeat}`, () => {
    const size = 256
    const height = new Float32Array(size * size)
    for (let y = 0; y < size; y++) {
      for (let x = 0; x < size; x++) {
        // cells: 1 − the distance to the nearest of jittered points gives rounded pebbles
        const n = fbm(x, y, size, 24, 2, 17)
        const cracks = Math.abs(fbm(x, y, size, 12, 3, 3) - 0.5)
        height[y * size + x] = 0.7 * n + 0.6 * Math.min(0.12, cracks)
      }
    }
    return normalMapFrom(height, size, 2.5, repeat)
  })
}

/** A soft fine noise normal map (rubber, painted wood). */
export function grainNormal(repeat: number): THREE.Texture {
  return cached(`grain:${repeat}`, () => {
    const size = 128
    const height = new Float32Array(size * size)
    for (let y = 0; y < size; y++) for (let x = 0; x < size; x++) height[y * size + x] = fbm(x, y, size, 16, 3, 29)
    return normalMapFrom(height, size, 0.6, repeat)
  })
}

/** Mottles a canvas with fractal noise (dyed cloth is never one flat colour). */
function mottle(ctx: CanvasRenderingContext2D, w: number, h: number, amount: number, seed: number, base = 6): void {
  const img = ctx.getImageData(0, 0, w, h)
  const d = img.data
  for (let y = 0; y < h; y++) {
    for (let x = 0; x < w; x++) {
      const f = 1 + amount * (fbm(x, y, Math.max(w, h), base, 4, seed) - 0.5) * 2
      const i = 4 * (y * w + x)
      d[i] = Math.min(255, d[i] * f)
      d[i + 1] = Math.min(255, d[i + 1] * f)
      d[i + 2] = Math.min(255, d[i + 2] * f)
    }
  }
  ctx.putImageData(img, 0, 0)
}

/** Ground: 1 m stone tiles, four by four per texture, with grout and per-tile shade. */
export function groundTextures(): { map: THREE.Texture; normalMap: THREE.Texture } {
  const map = cached('ground', () => {
    const size = 512, tiles = 4, px = size / tiles
    const [c, ctx] = canvas(size)
    const img = ctx.createImageData(size, size)
    for (let y = 0; y < size; y++) {
      for (let x = 0; x < size; x++) {
        const ti = Math.floor(x / px), tj = Math.floor(y / px)
        const shade = 0.93 + 0.1 * noise2(ti * 7.3, tj * 3.1, 1000, 41)
        const n = fbm(x, y, size, 4, 3, 9)
        const gx = Math.min(x % px, px - (x % px)), gy = Math.min(y % px, px - (y % px))
        const g = Math.min(gx, gy)
        const grout = g < 1 ? 0.72 : g < 2 ? 0.88 : 1
        const v = shade * (0.9 + 0.14 * n) * grout
        const i = 4 * (y * size + x)
        img.data[i] = 168 * v
        img.data[i + 1] = 160 * v
        img.data[i + 2] = 148 * v
        img.data[i + 3] = 255
      }
    }
    ctx.putImageData(img, 0, 0)
    return colorTexture(c)
  })
  const normalMap = cached('groundNormal', () => {
    const size = 256, px = size / 4
    const height = new Float32Array(size * size)
    for (let y = 0; y < size; y++) {
      for (let x = 0; x < size; x++) {
        const gx = Math.min(x % px, px - (x % px)), gy = Math.min(y % px, px - (y % px))
        const edge = Math.min(1, Math.min(gx, gy) / 1.5)
        height[y * size + x] = 0.6 * edge + 0.25 * fbm(x, y, size, 16, 3, 13)
      }
    }
    return normalMapFrom(height, size, 1.5, 1)
  })
  return { map, normalMap }
}

/**
 * A hero's cape: deep red wool with a gold braid along the hem and sides and a small clasp
 * emblem at the collar. u runs across the cape, v from the collar (v = 0) to the hem.
 */
export function capeTexture(): THREE.Texture {
  return cached('cape', () => {
    const w = 512, h = 1024
    const [c, ctx] = canvas(w, h)
    ctx.fillStyle = '#a61e2a'
    ctx.fillRect(0, 0, w, h)
    // a faint vertical twill rib
    ctx.globalAlpha = 0.08
    for (let x = 0; x < w; x += 6) {
      ctx.fillStyle = x % 12 === 0 ? '#000' : '#fff'
      ctx.fillRect(x, 0, 3, h)
    }
    ctx.globalAlpha = 1
    mottle(ctx, w, h, 0.18, 3)
    const braid = (x: number, y: number, bw: number, bh: number) => {
      ctx.fillStyle = '#c9a23c'
      ctx.fillRect(x, y, bw, bh)
      ctx.fillStyle = '#7a5a16'
      const horizontal = bw > bh
      for (let k = 0; k < (horizontal ? bw : bh); k += 14) {
        if (horizontal) ctx.fillRect(x + k, y + 3, 6, bh - 6)
        else ctx.fillRect(x + 3, y + k, bw - 6, 6)
      }
    }
    // the canvas's top row is the cloth's first row (the collar), its bottom the hem
    braid(0, h - 54, w, 26)
    braid(14, 0, 18, h - 28)
    braid(w - 32, 0, 18, h - 28)
    // a thin line above the hem braid
    ctx.fillStyle = '#d8b452'
    ctx.fillRect(0, h - 75, w, 5)
    return colorTexture(c)
  })
}

/** A flag: a deep blue field, a gold chevron and a white eight-pointed star. */
export function flagTexture(): THREE.Texture {
  return cached('flag', () => {
    const w = 768, h = 512
    const [c, ctx] = canvas(w, h)
    ctx.fillStyle = '#163e8c'
    ctx.fillRect(0, 0, w, h)
    // chevron from the hoist (left edge)
    ctx.fillStyle = '#e8b923'
    ctx.beginPath()
    ctx.moveTo(0, 0)
    ctx.lineTo(w * 0.42, h / 2)
    ctx.lineTo(0, h)
    ctx.closePath()
    ctx.fill()
    ctx.fillStyle = '#b3242c'
    ctx.beginPath()
    ctx.moveTo(0, h * 0.1)
    ctx.lineTo(w * 0.33, h / 2)
    ctx.lineTo(0, h * 0.9)
    ctx.closePath()
    ctx.fill()
    // a white stripe along the fly
    ctx.fillStyle = '#f3f0e6'
    ctx.fillRect(w * 0.5, h * 0.44, w * 0.5, h * 0.12)
    // an eight-pointed star in the upper fly
    const star = (cx: number, cy: number, r: number) => {
      ctx.beginPath()
      for (let k = 0; k < 16; k++) {
        const a = (k * Math.PI) / 8 - Math.PI / 2
        const rr = k % 2 === 0 ? r : r * 0.45
        ctx.lineTo(cx + rr * Math.cos(a), cy + rr * Math.sin(a))
      }
      ctx.closePath()
      ctx.fill()
    }
    ctx.fillStyle = '#f3f0e6'
    star(w * 0.72, h * 0.22, 70)
    // a hem line along the edges
    ctx.strokeStyle = 'rgba(0,0,0,0.25)'
    ctx.lineWidth = 6
    ctx.strokeRect(3, 3, w - 6, h - 6)
    mottle(ctx, w, h, 0.08, 21)
    return colorTexture(c)
  })
}

/** Curtain velvet: wine red with a repeating damask lozenge and a darker hem band. */
export function curtainTexture(): THREE.Texture {
  return cached('curtain', () => {
    const w = 1024, h = 1024
    const [c, ctx] = canvas(w, h)
    ctx.fillStyle = '#7c1424'
    ctx.fillRect(0, 0, w, h)
    // damask: lozenges with a flourish in each, 6 across, 6 down
    const nx = 6, ny = 6
    const cw = w / nx, ch = (h - 80) / ny
    for (let j = 0; j < ny; j++) {
      for (let i = 0; i < nx; i++) {
        const cx = (i + 0.5 + (j % 2) * 0.5) * cw, cy = (j + 0.5) * ch
        ctx.strokeStyle = 'rgba(230, 170, 110, 0.35)'
        ctx.lineWidth = 5
        ctx.beginPath()
        ctx.moveTo(cx, cy - ch * 0.4)
        ctx.lineTo(cx + cw * 0.3, cy)
        ctx.lineTo(cx, cy + ch * 0.4)
        ctx.lineTo(cx - cw * 0.3, cy)
        ctx.closePath()
        ctx.stroke()
        ctx.fillStyle = 'rgba(240, 180, 120, 0.28)'
        ctx.beginPath()
        ctx.ellipse(cx, cy, cw * 0.08, ch * 0.16, 0, 0, 2 * Math.PI)
        ctx.fill()
        for (const s of [-1, 1]) {
          ctx.beginPath()
          ctx.ellipse(cx + s * cw * 0.12, cy - ch * 0.05, cw * 0.06, ch * 0.05, s * 0.7, 0, 2 * Math.PI)
          ctx.fill()
        }
      }
    }
    // a hem band along the bottom (the canvas's top row is the cloth's first row, at the rail)
    ctx.fillStyle = '#4e0c16'
    ctx.fillRect(0, h - 56, w, 56)
    ctx.fillStyle = '#c89a4a'
    ctx.fillRect(0, h - 64, w, 8)
    mottle(ctx, w, h, 0.12, 8)
    return colorTexture(c)
  })
}

/** Gingham (cotton): two-colour check from overlapping translucent stripes. */
export function ginghamTexture(color: string, checks = 8): THREE.Texture {
  return cached(`gingham:${color}:${checks}`, () => {
    const s = 512
    const [c, ctx] = canvas(s)
    ctx.fillStyle = '#f2efe8'
    ctx.fillRect(0, 0, s, s)
    const step = s / checks
    ctx.globalAlpha = 0.5
    ctx.fillStyle = color
    for (let k = 0; k < checks; k++) {
      ctx.fillRect(k * step, 0, step / 2, s)
      ctx.fillRect(0, k * step, s, step / 2)
    }
    ctx.globalAlpha = 1
    mottle(ctx, s, s, 0.08, 12)
    return colorTexture(c)
  })
}

/** A plain dyed fabric with a faint mottle (`stripes` adds thin woven stripes). */
export function plainTexture(color: string, stripes?: string): THREE.Texture {
  return cached(`plain:${color}:${stripes}`, () => {
    const s = 256
    const [c, ctx] = canvas(s)
    ctx.fillStyle = color
    ctx.fillRect(0, 0, s, s)
    if (stripes) {
      ctx.fillStyle = stripes
      for (let x = 0; x < s; x += 32) ctx.fillRect(x, 0, 6, s)
    }
    mottle(ctx, s, s, 0.12, 31, 4)
    return colorTexture(c)
  })
}

/** Leather: tanned brown, darker at the edges, with a stitched border. */
export function leatherTexture(): THREE.Texture {
  return cached('leatherMap', () => {
    const s = 512
    const [c, ctx] = canvas(s)
    const g = ctx.createRadialGradient(s / 2, s / 2, s * 0.1, s / 2, s / 2, s * 0.75)
    g.addColorStop(0, '#8a5430')
    g.addColorStop(1, '#4e2c17')
    ctx.fillStyle = g
    ctx.fillRect(0, 0, s, s)
    mottle(ctx, s, s, 0.25, 44, 5)
    ctx.strokeStyle = '#d9b98a'
    ctx.lineWidth = 3
    ctx.setLineDash([10, 8])
    ctx.strokeRect(18, 18, s - 36, s - 36)
    return colorTexture(c)
  })
}

/**
 * A measuring grid (the accuracy scene's patches): a light sheet with a line every tenth of its
 * width, so stretch shows as squares drawn out into rectangles.
 */
export function gridTexture(tint: string): THREE.Texture {
  return cached(`grid:${tint}`, () => {
    const s = 512, n = 10
    const [c, ctx] = canvas(s)
    ctx.fillStyle = tint
    ctx.fillRect(0, 0, s, s)
    mottle(ctx, s, s, 0.06, 50)
    ctx.strokeStyle = 'rgba(30, 36, 48, 0.55)'
    ctx.lineWidth = 3
    for (let k = 0; k <= n; k++) {
      const p = Math.min(s - 1.5, Math.max(1.5, (k * s) / n))
      ctx.beginPath()
      ctx.moveTo(p, 0)
      ctx.lineTo(p, s)
      ctx.moveTo(0, p)
      ctx.lineTo(s, p)
      ctx.stroke()
    }
    return colorTexture(c)
  })
}

/** A bath towel: terry white with two coloured bands near each end. */
export function towelTexture(band: string): THREE.Texture {
  return cached(`towel:${band}`, () => {
    const s = 512
    const [c, ctx] = canvas(s)
    ctx.fillStyle = '#ece8df'
    ctx.fillRect(0, 0, s, s)
    ctx.fillStyle = band
    for (const y of [0.08, 0.14, 0.84, 0.9]) ctx.fillRect(0, y * s, s, s * 0.035)
    mottle(ctx, s, s, 0.1, 61, 16)
    return colorTexture(c)
  })
}

/** Wood: warm planks along u, for rails, poles and crates. */
export function woodTexture(): THREE.Texture {
  return cached('wood', () => {
    const w = 512, h = 128
    const [c, ctx] = canvas(w, h)
    const img = ctx.createImageData(w, h)
    for (let y = 0; y < h; y++) {
      for (let x = 0; x < w; x++) {
        const ring = Math.sin((y / h) * 40 + 6 * fbm(x, y, w, 4, 3, 71)) * 0.5 + 0.5
        const v = 0.75 + 0.25 * ring
        const i = 4 * (y * w + x)
        img.data[i] = 150 * v
        img.data[i + 1] = 100 * v
        img.data[i + 2] = 60 * v
        img.data[i + 3] = 255
      }
    }
    ctx.putImageData(img, 0, 0)
    return colorTexture(c)
  })
}
