/**
 * Connected pieces of a triangle mesh (triangles joined through shared vertices), numbered from 0
 * in vertex order. A vertex no triangle uses is labelled −1, or with `unusedAlone` a piece of its own.
 */
export function meshPieces(indices: ArrayLike<number>, vertexCount: number, unusedAlone = false): Int32Array {
  const parent = Int32Array.from({ length: vertexCount }, (_, i) => i)
  const find = (x: number): number => {
    while (parent[x] !== x) x = parent[x] = parent[parent[x]]
    return x
  }
  for (let t = 0; t < indices.length; t += 3) {
    const a = find(indices[t])
    parent[find(indices[t + 1])] = a
    parent[find(indices[t + 2])] = a
  }
  const label = new Int32Array(vertexCount).fill(-1)
  const used = new Uint8Array(vertexCount)
  for (let t = 0; t < indices.length; t++) used[indices[t]] = 1
  const ids = new Map<number, number>()
  for (let i = 0; i < vertexCount; i++) {
    if (!used[i] && !unusedAlone) continue
    const r = find(i)
    if (!ids.has(r)) ids.set(r, ids.size)
    label[i] = ids.get(r)!
  }
  return label
}

export function pieceCount(label: Int32Array): number {
  let m = -1
  for (const l of label) m = Math.max(m, l)
  return m + 1
}
