/**
 * A small SVG chart writer for the accuracy report: scatter panels with log axes, a legend, and a
 * highlighted front. No dependencies; the output renders on GitHub.
 */

export interface Series {
  name: string
  color: string
  /** Marker: circle, square, triangle or diamond. */
  marker: 'circle' | 'square' | 'triangle' | 'diamond'
  points: { x: number; y: number; label?: string }[]
}

export interface Panel {
  title: string
  xLabel: string
  yLabel: string
  series: Series[]
  /** Points to join with a line (e.g. the Pareto front), in x order. */
  front?: { x: number; y: number }[]
  /** Horizontal and vertical reference lines (goals), drawn dotted with a label. */
  guides?: { axis: 'x' | 'y'; value: number; label: string }[]
}

const esc = (s: string) => s.replace(/&/g, '&amp;').replace(/</g, '&lt;').replace(/>/g, '&gt;')

function logTicks(min: number, max: number): number[] {
  const ticks: number[] = []
  for (let e = Math.floor(Math.log10(min)); e <= Math.ceil(Math.log10(max)); e++) {
    for (const m of [1, 2, 5]) {
      const v = m * 10 ** e
      if (v >= min * 0.999 && v <= max * 1.001) ticks.push(v)
    }
  }
  return ticks
}

function fmtTick(v: number): string {
  if (v >= 1000 || v < 0.001) return v.toExponential(0)
  return String(Number(v.toPrecision(2)))
}

function marker(kind: Series['marker'], x: number, y: number, color: string): string {
  const r = 4
  switch (kind) {
    case 'square':
      return `<rect x="${x - r}" y="${y - r}" width="${2 * r}" height="${2 * r}" fill="${color}" fill-opacity="0.75"/>`
    case 'triangle':
      return `<path d="M${x},${y - r - 1} L${x + r + 1},${y + r} L${x - r - 1},${y + r} Z" fill="${color}" fill-opacity="0.75"/>`
    case 'diamond':
      return `<path d="M${x},${y - r - 1} L${x + r + 1},${y} L${x},${y + r + 1} L${x - r - 1},${y} Z" fill="${color}" fill-opacity="0.75"/>`
    default:
      return `<circle cx="${x}" cy="${y}" r="${r}" fill="${color}" fill-opacity="0.75"/>`
  }
}

/** Renders panels side by side into one SVG document. */
export function scatterPanels(title: string, panels: Panel[], note = ''): string {
  const pw = 360, ph = 300, ml = 62, mr = 14, mt = 48, mb = 52
  const width = Math.max(panels.length * (pw + ml + mr) + 20, 900) // room for the title and legend
  const legendH = 26
  const height = mt + ph + mb + legendH + (note ? 18 : 0)
  const out: string[] = []
  out.push(
    `<svg xmlns="http://www.w3.org/2000/svg" width="${width}" height="${height}" viewBox="0 0 ${width} ${height}" font-family="system-ui, sans-serif" font-size="11">`,
  )
  out.push(`<rect width="${width}" height="${height}" fill="#ffffff"/>`)
  out.push(`<text x="12" y="20" font-size="14" font-weight="600">${esc(title)}</text>`)
  panels.forEach((p, i) => {
    const ox = 10 + i * (pw + ml + mr) + ml, oy = mt
    const all = p.series.flatMap((s) => s.points).filter((q) => q.x > 0 && q.y > 0)
    const xmin = Math.min(...all.map((q) => q.x)) / 1.3, xmax = Math.max(...all.map((q) => q.x)) * 1.3
    const ymin = Math.min(...all.map((q) => q.y)) / 1.5, ymax = Math.max(...all.map((q) => q.y)) * 1.5
    const sx = (x: number) => ox + ((Math.log10(x) - Math.log10(xmin)) / (Math.log10(xmax) - Math.log10(xmin))) * pw
    const sy = (y: number) => oy + ph - ((Math.log10(y) - Math.log10(ymin)) / (Math.log10(ymax) - Math.log10(ymin))) * ph
    out.push(`<text x="${ox}" y="${oy - 10}" font-size="12" font-weight="600">${esc(p.title)}</text>`)
    out.push(`<rect x="${ox}" y="${oy}" width="${pw}" height="${ph}" fill="none" stroke="#999"/>`)
    for (const t of logTicks(xmin, xmax)) {
      const x = sx(t)
      out.push(`<line x1="${x}" y1="${oy}" x2="${x}" y2="${oy + ph}" stroke="#eee"/>`)
      out.push(`<text x="${x}" y="${oy + ph + 14}" text-anchor="middle" fill="#444">${fmtTick(t)}</text>`)
    }
    for (const t of logTicks(ymin, ymax)) {
      const y = sy(t)
      out.push(`<line x1="${ox}" y1="${y}" x2="${ox + pw}" y2="${y}" stroke="#eee"/>`)
      out.push(`<text x="${ox - 5}" y="${y + 3}" text-anchor="end" fill="#444">${fmtTick(t)}</text>`)
    }
    out.push(`<text x="${ox + pw / 2}" y="${oy + ph + 32}" text-anchor="middle">${esc(p.xLabel)}</text>`)
    out.push(`<text transform="translate(${ox - 46},${oy + ph / 2}) rotate(-90)" text-anchor="middle">${esc(p.yLabel)}</text>`)
    for (const g of p.guides ?? []) {
      if (g.axis === 'y' && g.value > ymin && g.value < ymax) {
        const y = sy(g.value)
        out.push(`<line x1="${ox}" y1="${y}" x2="${ox + pw}" y2="${y}" stroke="#2b8a3e" stroke-dasharray="2,3"/>`)
        out.push(`<text x="${ox + pw - 4}" y="${y - 4}" text-anchor="end" fill="#2b8a3e">${esc(g.label)}</text>`)
      } else if (g.axis === 'x' && g.value > xmin && g.value < xmax) {
        const x = sx(g.value)
        out.push(`<line x1="${x}" y1="${oy}" x2="${x}" y2="${oy + ph}" stroke="#2b8a3e" stroke-dasharray="2,3"/>`)
        out.push(`<text x="${x + 4}" y="${oy + 12}" fill="#2b8a3e">${esc(g.label)}</text>`)
      }
    }
    if (p.front && p.front.length > 1) {
      const d = p.front.map((q, k) => `${k === 0 ? 'M' : 'L'}${sx(q.x).toFixed(1)},${sy(q.y).toFixed(1)}`).join(' ')
      out.push(`<path d="${d}" fill="none" stroke="#111" stroke-width="1.5" stroke-dasharray="5,3"/>`)
    }
    for (const s of p.series) {
      for (const q of s.points) if (q.x > 0 && q.y > 0) out.push(marker(s.marker, sx(q.x), sy(q.y), s.color))
    }
    if (p.front) {
      for (const q of p.front) out.push(`<circle cx="${sx(q.x)}" cy="${sy(q.y)}" r="6.5" fill="none" stroke="#111" stroke-width="1.2"/>`)
    }
  })
  // legend (from the first panel's series)
  let lx = 12
  const ly = mt + ph + mb + 8
  for (const s of panels[0]?.series ?? []) {
    out.push(marker(s.marker, lx + 5, ly, s.color))
    out.push(`<text x="${lx + 14}" y="${ly + 4}">${esc(s.name)}</text>`)
    lx += 24 + 6.5 * s.name.length
  }
  out.push(`<path d="M${lx},${ly} L${lx + 24},${ly}" stroke="#111" stroke-width="1.5" stroke-dasharray="5,3"/>`)
  out.push(`<circle cx="${lx + 12}" cy="${ly}" r="6.5" fill="none" stroke="#111" stroke-width="1.2"/>`)
  out.push(`<text x="${lx + 30}" y="${ly + 4}">Pareto front (nothing both faster and more accurate)</text>`)
  if (note) out.push(`<text x="12" y="${ly + 22}" fill="#555">${esc(note)}</text>`)
  out.push('</svg>')
  return out.join('\n')
}

/** The points not dominated by any other (lower x and lower y is better), sorted by x. */
export function paretoFront<T extends { x: number; y: number }>(points: T[]): T[] {
  const sorted = [...points].filter((p) => p.x > 0 && p.y > 0).sort((a, b) => a.x - b.x || a.y - b.y)
  const front: T[] = []
  let best = Infinity
  for (const p of sorted) {
    if (p.y < best) {
      front.push(p)
      best = p.y
    }
  }
  return front
}
