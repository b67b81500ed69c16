import { mat4, quat, vec3 } from 'gl-matrix'

/** A triangle mesh the renderer can upload: xyz positions, xyz normals, and indices. */
export interface MeshData {
  positions: Float32Array
  normals: Float32Array
  indices: Uint32Array | Uint16Array
}

const VERTEX = `#version 300 es
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec3 a_color;
uniform mat4 u_viewProj;
uniform mat4 u_model;
uniform vec3 u_color;
uniform bool u_vertexColor;
out vec3 v_normal;
out vec3 v_color;
out vec3 v_world;
void main() {
  vec4 world = u_model * vec4(a_position, 1.0);
  v_world = world.xyz;
  v_normal = mat3(u_model) * a_normal;
  v_color = u_vertexColor ? a_color : u_color;
  gl_Position = u_viewProj * world;
}`

const FRAGMENT = `#version 300 es
precision highp float;
in vec3 v_normal;
in vec3 v_color;
in vec3 v_world;
uniform vec3 u_light;
uniform vec3 u_eye;
uniform float u_backShade;
out vec4 outColor;
void main() {
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;                       // two-sided lighting
  vec3 base = gl_FrontFacing ? v_color : v_color * u_backShade;
  float diffuse = max(dot(n, u_light), 0.0);
  float sky = 0.5 + 0.5 * n.y;                       // hemispheric ambient
  vec3 viewDir = normalize(u_eye - v_world);
  float spec = pow(max(dot(reflect(-u_light, n), viewDir), 0.0), 24.0) * 0.15;
  vec3 color = base * (0.25 + 0.2 * sky + 0.7 * diffuse) + spec;
  float fog = clamp(length(u_eye - v_world) / 60.0, 0.0, 1.0);
  outColor = vec4(mix(pow(color, vec3(1.0 / 1.1)), vec3(0.106, 0.114, 0.133), fog * fog), 1.0);
}`

interface GpuMesh {
  vao: WebGLVertexArrayObject
  position: WebGLBuffer
  normal: WebGLBuffer
  color: WebGLBuffer
  index: WebGLBuffer
  count: number
  indexType: number
}

/** Orbit camera: yaw/pitch/distance around a target point. */
export class OrbitCamera {
  yaw = 0.6
  pitch = 0.35
  distance = 4
  /**
   * Moves the picture sideways by this much of the viewport's half-width (NDC units), e.g. to
   * centre the scene in the part of the canvas that an overlay panel leaves free.
   */
  shiftX = 0
  readonly target = vec3.fromValues(0, 1, 0)
  readonly eye = vec3.create()
  readonly view = mat4.create()
  readonly proj = mat4.create()
  readonly viewProj = mat4.create()

  update(aspect: number): void {
    const cp = Math.cos(this.pitch)
    vec3.set(this.eye, Math.sin(this.yaw) * cp, Math.sin(this.pitch), Math.cos(this.yaw) * cp)
    vec3.scaleAndAdd(this.eye, this.target, this.eye, this.distance)
    mat4.lookAt(this.view, this.eye, this.target, [0, 1, 0])
    mat4.perspective(this.proj, (50 * Math.PI) / 180, aspect, 0.05, 200)
    this.proj[8] = -this.shiftX // x_ndc += shiftX (clip w = −z_view)
    mat4.multiply(this.viewProj, this.proj, this.view)
  }

  /** World-space ray through a point in normalised device coordinates. */
  ray(ndcX: number, ndcY: number, origin: vec3, dir: vec3): void {
    const inv = mat4.invert(mat4.create(), this.viewProj) ?? mat4.create()
    const near = vec3.transformMat4(vec3.create(), [ndcX, ndcY, -1], inv)
    const far = vec3.transformMat4(vec3.create(), [ndcX, ndcY, 1], inv)
    vec3.copy(origin, near)
    vec3.normalize(dir, vec3.subtract(dir, far, near))
  }
}

/** A minimal WebGL2 renderer for cloth meshes and solid shapes. */
export class Renderer {
  readonly gl: WebGL2RenderingContext
  readonly camera = new OrbitCamera()
  private readonly program: WebGLProgram
  private readonly uniforms: Record<string, WebGLUniformLocation | null> = {}
  private readonly shapes = new Map<string, GpuMesh>()
  private readonly dynamic = new Map<object, GpuMesh>()
  private readonly model = mat4.create()
  private readonly light = vec3.normalize(vec3.create(), [0.35, 0.75, 0.6])

  constructor(readonly canvas: HTMLCanvasElement) {
    const gl = canvas.getContext('webgl2', { antialias: true })
    if (!gl) throw new Error('WebGL2 is not available')
    this.gl = gl
    this.program = link(gl, VERTEX, FRAGMENT)
    for (const name of ['u_viewProj', 'u_model', 'u_color', 'u_vertexColor', 'u_light', 'u_eye', 'u_backShade']) {
      this.uniforms[name] = gl.getUniformLocation(this.program, name)
    }
    gl.enable(gl.DEPTH_TEST)
  }

  /** Starts a frame: resizes, clears, sets the camera. */
  begin(): void {
    const { gl, canvas } = this
    const dpr = Math.min(window.devicePixelRatio || 1, 2)
    const w = Math.floor(canvas.clientWidth * dpr), h = Math.floor(canvas.clientHeight * dpr)
    if (canvas.width !== w || canvas.height !== h) {
      canvas.width = w
      canvas.height = h
    }
    gl.viewport(0, 0, w, h)
    gl.clearColor(0.106, 0.114, 0.133, 1)
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT)
    this.camera.update(w / Math.max(h, 1))
    gl.useProgram(this.program)
    gl.uniformMatrix4fv(this.uniforms.u_viewProj, false, this.camera.viewProj as Float32Array)
    gl.uniform3fv(this.uniforms.u_light, this.light as Float32Array)
    gl.uniform3fv(this.uniforms.u_eye, this.camera.eye as Float32Array)
  }

  /** Draws a dynamic mesh (a cloth) whose arrays change every frame; `key` identifies its buffers. */
  drawDynamic(key: object, mesh: MeshData, colors: Float32Array | null, color: ArrayLike<number> = [0.8, 0.8, 0.8]): void {
    const { gl } = this
    let gpu = this.dynamic.get(key)
    if (!gpu) {
      gpu = this.createMesh()
      this.dynamic.set(key, gpu)
    }
    this.upload(gpu, mesh, colors, gl.DYNAMIC_DRAW)
    gl.disable(gl.CULL_FACE)
    mat4.identity(this.model)
    this.drawMesh(gpu, this.model, color, colors !== null, 0.72)
  }

  /** Forgets a dynamic mesh's buffers (when its cloth is removed). */
  release(key: object): void {
    const gpu = this.dynamic.get(key)
    if (!gpu) return
    const { gl } = this
    gl.deleteBuffer(gpu.position)
    gl.deleteBuffer(gpu.normal)
    gl.deleteBuffer(gpu.color)
    gl.deleteBuffer(gpu.index)
    gl.deleteVertexArray(gpu.vao)
    this.dynamic.delete(key)
  }

  sphere(center: ArrayLike<number>, radius: number, color: ArrayLike<number>): void {
    const m = mat4.fromRotationTranslationScale(this.model, quat.create(), center as vec3, [radius, radius, radius])
    this.drawShape('sphere', () => sphereMesh(24, 16), m, color)
  }

  /** A capsule along the local y axis of `rotation`, centred at `center`. */
  capsule(center: ArrayLike<number>, rotation: ArrayLike<number>, radius: number, halfHeight: number, color: ArrayLike<number>): void {
    const key = `capsule:${radius.toFixed(4)}:${halfHeight.toFixed(4)}`
    const m = mat4.fromRotationTranslation(this.model, rotation as quat, center as vec3)
    this.drawShape(key, () => capsuleMesh(radius, halfHeight, 24, 8), m, color)
  }

  box(center: ArrayLike<number>, rotation: ArrayLike<number>, halfExtents: ArrayLike<number>, color: ArrayLike<number>): void {
    const m = mat4.fromRotationTranslationScale(this.model, rotation as quat, center as vec3, halfExtents as vec3)
    this.drawShape('box', boxMesh, m, color)
  }

  /**
   * A convex hull (vertices xyz and outward triangles, e.g. from `getColliderHull`) at a pose,
   * flat-shaded; its mesh is cached under `key`.
   */
  convex(key: string, hull: { vertices: ArrayLike<number>; indices: ArrayLike<number> }, center: ArrayLike<number>, rotation: ArrayLike<number>, color: ArrayLike<number>): void {
    const m = mat4.fromRotationTranslation(this.model, rotation as quat, center as vec3)
    this.drawShape(`convex:${key}`, () => flatMesh(hull.vertices, hull.indices), m, color)
  }

  /** A solid mesh in world space (e.g. a convex hull), cached under `key`. */
  solid(key: string, build: () => MeshData, color: ArrayLike<number>, model: mat4 = mat4.create()): void {
    this.drawShape(key, build, model, color)
  }

  ground(y: number, size = 40): void {
    const m = mat4.fromRotationTranslationScale(this.model, quat.create(), [0, y, 0], [size, 1, size])
    this.drawShape('ground', groundMesh, m, [0.22, 0.24, 0.27])
  }

  private drawShape(key: string, build: () => MeshData, model: mat4, color: ArrayLike<number>): void {
    let gpu = this.shapes.get(key)
    if (!gpu) {
      gpu = this.createMesh()
      this.upload(gpu, build(), null, this.gl.STATIC_DRAW)
      this.shapes.set(key, gpu)
    }
    this.gl.enable(this.gl.CULL_FACE)
    this.drawMesh(gpu, model, color, false, 1)
  }

  private drawMesh(gpu: GpuMesh, model: mat4, color: ArrayLike<number>, vertexColor: boolean, backShade: number): void {
    const { gl } = this
    gl.uniformMatrix4fv(this.uniforms.u_model, false, model as Float32Array)
    gl.uniform3f(this.uniforms.u_color, color[0], color[1], color[2])
    gl.uniform1i(this.uniforms.u_vertexColor, vertexColor ? 1 : 0)
    gl.uniform1f(this.uniforms.u_backShade, backShade)
    gl.bindVertexArray(gpu.vao)
    gl.drawElements(gl.TRIANGLES, gpu.count, gpu.indexType, 0)
    gl.bindVertexArray(null)
  }

  private createMesh(): GpuMesh {
    const { gl } = this
    const vao = gl.createVertexArray()!
    const position = gl.createBuffer()!, normal = gl.createBuffer()!, color = gl.createBuffer()!, index = gl.createBuffer()!
    gl.bindVertexArray(vao)
    gl.bindBuffer(gl.ARRAY_BUFFER, position)
    gl.enableVertexAttribArray(0)
    gl.vertexAttribPointer(0, 3, gl.FLOAT, false, 0, 0)
    gl.bindBuffer(gl.ARRAY_BUFFER, normal)
    gl.enableVertexAttribArray(1)
    gl.vertexAttribPointer(1, 3, gl.FLOAT, false, 0, 0)
    gl.bindBuffer(gl.ARRAY_BUFFER, color)
    gl.enableVertexAttribArray(2)
    gl.vertexAttribPointer(2, 3, gl.FLOAT, false, 0, 0)
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, index)
    gl.bindVertexArray(null)
    return { vao, position, normal, color, index, count: 0, indexType: gl.UNSIGNED_INT }
  }

  private upload(gpu: GpuMesh, mesh: MeshData, colors: Float32Array | null, usage: number): void {
    const { gl } = this
    gl.bindVertexArray(gpu.vao)
    gl.bindBuffer(gl.ARRAY_BUFFER, gpu.position)
    gl.bufferData(gl.ARRAY_BUFFER, mesh.positions, usage)
    gl.bindBuffer(gl.ARRAY_BUFFER, gpu.normal)
    gl.bufferData(gl.ARRAY_BUFFER, mesh.normals, usage)
    gl.bindBuffer(gl.ARRAY_BUFFER, gpu.color)
    gl.bufferData(gl.ARRAY_BUFFER, colors ?? new Float32Array(mesh.positions.length), usage)
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, gpu.index)
    gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, mesh.indices, usage)
    gl.bindVertexArray(null)
    gpu.count = mesh.indices.length
    gpu.indexType = mesh.indices instanceof Uint16Array ? gl.UNSIGNED_SHORT : gl.UNSIGNED_INT
  }
}

function link(gl: WebGL2RenderingContext, vs: string, fs: string): WebGLProgram {
  const compile = (type: number, src: string) => {
    const s = gl.createShader(type)!
    gl.shaderSource(s, src)
    gl.compileShader(s)
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s) ?? 'shader error')
    return s
  }
  const p = gl.createProgram()!
  gl.attachShader(p, compile(gl.VERTEX_SHADER, vs))
  gl.attachShader(p, compile(gl.FRAGMENT_SHADER, fs))
  gl.linkProgram(p)
  if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(p) ?? 'link error')
  return p
}

// ---------------------------------------------------------------------------------------------
// Shape meshes

function sphereMesh(seg: number, rings: number): MeshData {
  const pos: number[] = [], idx: number[] = []
  for (let r = 0; r <= rings; r++) {
    const phi = (r / rings) * Math.PI
    for (let s = 0; s <= seg; s++) {
      const th = (s / seg) * 2 * Math.PI
      pos.push(Math.sin(phi) * Math.cos(th), Math.cos(phi), Math.sin(phi) * Math.sin(th))
    }
  }
  for (let r = 0; r < rings; r++) {
    for (let s = 0; s < seg; s++) {
      const a = r * (seg + 1) + s, b = a + seg + 1
      idx.push(a, a + 1, b, b, a + 1, b + 1)
    }
  }
  const p = Float32Array.from(pos)
  return { positions: p, normals: p.slice(), indices: Uint32Array.from(idx) }
}

function capsuleMesh(radius: number, halfHeight: number, seg: number, ringsPerCap: number): MeshData {
  const pos: number[] = [], nor: number[] = [], idx: number[] = []
  const rings = 2 * ringsPerCap + 1
  for (let r = 0; r <= rings; r++) {
    // top hemisphere, a cylinder band, bottom hemisphere
    const top = r <= ringsPerCap
    const phi = top ? (r / ringsPerCap) * (Math.PI / 2) : Math.PI / 2 + ((r - ringsPerCap - 1) / ringsPerCap) * (Math.PI / 2)
    const yOff = top ? halfHeight : -halfHeight
    for (let s = 0; s <= seg; s++) {
      const th = (s / seg) * 2 * Math.PI
      const nx = Math.sin(phi) * Math.cos(th), ny = Math.cos(phi), nz = Math.sin(phi) * Math.sin(th)
      pos.push(radius * nx, radius * ny + yOff, radius * nz)
      nor.push(nx, ny, nz)
    }
  }
  for (let r = 0; r < rings; r++) {
    for (let s = 0; s < seg; s++) {
      const a = r * (seg + 1) + s, b = a + seg + 1
      idx.push(a, a + 1, b, b, a + 1, b + 1)
    }
  }
  return { positions: Float32Array.from(pos), normals: Float32Array.from(nor), indices: Uint32Array.from(idx) }
}

function boxMesh(): MeshData {
  const pos: number[] = [], nor: number[] = [], idx: number[] = []
  const faces: [number[], number[], number[]][] = [
    [[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 0, 0], [0, 0, 1], [0, 1, 0]],
    [[0, 1, 0], [0, 0, 1], [1, 0, 0]], [[0, -1, 0], [1, 0, 0], [0, 0, 1]],
    [[0, 0, 1], [1, 0, 0], [0, 1, 0]], [[0, 0, -1], [0, 1, 0], [1, 0, 0]],
  ]
  for (const [n, u, v] of faces) {
    const base = pos.length / 3
    for (const [a, b] of [[-1, -1], [1, -1], [1, 1], [-1, 1]]) {
      pos.push(n[0] + a * u[0] + b * v[0], n[1] + a * u[1] + b * v[1], n[2] + a * u[2] + b * v[2])
      nor.push(...n)
    }
    idx.push(base, base + 1, base + 2, base, base + 2, base + 3)
  }
  return { positions: Float32Array.from(pos), normals: Float32Array.from(nor), indices: Uint32Array.from(idx) }
}

/** A flat-shaded copy of an indexed triangle mesh: three vertices per triangle, face normals. */
function flatMesh(vertices: ArrayLike<number>, indices: ArrayLike<number>): MeshData {
  const pos = new Float32Array(3 * indices.length), nor = new Float32Array(3 * indices.length)
  for (let t = 0; t < indices.length; t += 3) {
    const a = 3 * indices[t], b = 3 * indices[t + 1], c = 3 * indices[t + 2]
    const ux = vertices[b] - vertices[a], uy = vertices[b + 1] - vertices[a + 1], uz = vertices[b + 2] - vertices[a + 2]
    const vx = vertices[c] - vertices[a], vy = vertices[c + 1] - vertices[a + 1], vz = vertices[c + 2] - vertices[a + 2]
    let nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx
    const l = Math.hypot(nx, ny, nz) || 1
    nx /= l; ny /= l; nz /= l
    for (let k = 0; k < 3; k++) {
      const v = 3 * indices[t + k], o = 3 * (t + k)
      pos[o] = vertices[v]; pos[o + 1] = vertices[v + 1]; pos[o + 2] = vertices[v + 2]
      nor[o] = nx; nor[o + 1] = ny; nor[o + 2] = nz
    }
  }
  return { positions: pos, normals: nor, indices: Uint32Array.from({ length: indices.length }, (_, i) => i) }
}

function groundMesh(): MeshData {
  return {
    positions: Float32Array.from([-1, 0, -1, 1, 0, -1, 1, 0, 1, -1, 0, 1]),
    normals: Float32Array.from([0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0]),
    indices: Uint32Array.from([0, 2, 1, 0, 3, 2]),
  }
}
