import * as THREE from 'three'
import { groundTextures } from './textures'

/**
 * The three.js side of the demo: renderer, a generated sky, a sun with soft shadows, a hemisphere
 * light with the sky's and the ground's colours, a tiled ground, and an orbit camera. (No
 * prefiltered environment map: filtering one costs seconds of startup in software WebGL.) Scenes
 * add their objects to `root`, which is emptied (and its
 * geometries and materials disposed) when the scene changes.
 */
export class View {
  readonly renderer: THREE.WebGLRenderer
  readonly scene = new THREE.Scene()
  readonly camera = new THREE.PerspectiveCamera(45, 1, 0.05, 600)
  readonly root = new THREE.Group()
  readonly sun: THREE.DirectionalLight
  readonly hemi: THREE.HemisphereLight
  readonly ground: THREE.Mesh
  /** Orbit camera: yaw and pitch (rad) and distance (m) around `target`. */
  readonly orbit = { yaw: 0.6, pitch: 0.3, distance: 4, target: new THREE.Vector3(0, 1, 0) }
  /**
   * The part of the canvas the picture is framed in, CSS pixels from its top left (the canvas
   * the overlays leave free), or null for the whole canvas: the camera looks at the middle of this
   * rectangle, and the rest of the canvas shows what lies around it.
   */
  frame: { x: number; y: number; width: number; height: number } | null = null
  /**
   * Narrowest aspect ratio (width / height) of `frame` at which the picture keeps its vertical
   * field of view; a narrower frame (a window upright, the panel beside it) zooms out so that as
   * much shows across as at this ratio. 0: never zoom out.
   */
  fit = 0
  /** Half-size of the sun's shadow box around the camera's target, m (scenes set it). */
  shadowRadius = 4
  /** Direction toward the sun (unit); the sky's glow follows it. */
  readonly sunDir = new THREE.Vector3(-0.45, 0.8, 0.4).normalize()

  constructor(readonly canvas: HTMLCanvasElement, options: { antialias?: boolean } = {}) {
    const r =
      (this.renderer = new THREE.WebGLRenderer({ canvas, antialias: options.antialias ?? true, powerPreference: 'high-performance' }))
    r.shadowMap.enabled = true
    r.shadowMap.type = THREE.PCFShadowMap
    r.toneMapping = THREE.ACESFilmicToneMapping
    r.toneMappingExposure = 1.0
    r.outputColorSpace = THREE.SRGBColorSpace

    const horizon = new THREE.Color(0xc9d6e3)
    this.scene.fog = new THREE.Fog(horizon, 30, 140)
    const sky = makeSky(this.sunDir, horizon)
    this.scene.add(sky)
    this.hemi = new THREE.HemisphereLight(0xcfe0ff, 0x7a6a58, 1.4)
    this.scene.add(this.hemi)
    const sun = (this.sun = new THREE.DirectionalLight(0xfff1dc, 2.6))
    sun.castShadow = true
    sun.shadow.mapSize.set(2048, 2048)
    sun.shadow.bias = -0.0004
    sun.shadow.normalBias = 0.02
    sun.shadow.radius = 3
    this.scene.add(sun, sun.target)

    const { map, normalMap } = groundTextures()
    const g = new THREE.PlaneGeometry(400, 400).rotateX(-Math.PI / 2)
    const groundMap = map.clone()
    groundMap.repeat.set(100, 100)
    const groundNormal = normalMap.clone()
    groundNormal.repeat.set(100, 100)
    // Lambert: the ground is matte stone, and it fills most of the picture (a third of the cost
    // of a standard material per pixel in software WebGL)
    this.ground = new THREE.Mesh(
      g,
      new THREE.MeshLambertMaterial({ map: groundMap, normalMap: groundNormal, normalScale: new THREE.Vector2(0.6, 0.6) }),
    )
    this.ground.receiveShadow = true
    this.scene.add(this.ground, this.root)
  }

  /** Points the sun (and its glow in the sky) along `dir`; sizes its shadow map. */
  setSun(dir: ArrayLike<number>, mapSize: number): void {
    this.sunDir.set(dir[0], dir[1], dir[2]).normalize()
    const shadow = this.sun.shadow
    if (shadow.mapSize.x !== mapSize) {
      shadow.mapSize.set(mapSize, mapSize)
      shadow.map?.dispose()
      shadow.map = null
    }
  }

  /** Removes and disposes everything scenes added (textures are shared and kept). */
  clear(): void {
    this.root.traverse((o) => {
      const m = o as THREE.Mesh
      if (m.geometry) m.geometry.dispose()
      const mats = Array.isArray(m.material) ? m.material : m.material ? [m.material] : []
      for (const mat of mats) mat.dispose()
    })
    this.root.clear()
  }

  /** Places the camera from the orbit, sizes the canvas, moves the sun's shadow box along. */
  update(): void {
    const r = this.renderer
    const w = this.canvas.clientWidth, h = this.canvas.clientHeight
    const size = r.getSize(new THREE.Vector2())
    if (size.x !== w || size.y !== h) r.setSize(w, h, false)
    const { yaw, pitch, distance, target } = this.orbit
    const cp = Math.cos(pitch)
    this.camera.position.set(Math.sin(yaw) * cp, Math.sin(pitch), Math.cos(yaw) * cp).multiplyScalar(distance).add(target)
    this.camera.lookAt(target)
    const f = this.frame
    const fw = Math.max(1, f?.width ?? w), fh = Math.max(1, f?.height ?? h)
    this.camera.zoom = this.fit > 0 ? Math.min(1, fw / fh / this.fit) : 1
    if (f) {
      // the frame is the full picture, the canvas a window around it (it may reach past the
      // frame on every side): the camera is not turned, the image is moved and cut
      this.camera.setViewOffset(fw, fh, -f.x, -f.y, Math.max(1, w), Math.max(1, h))
    } else {
      this.camera.clearViewOffset()
      this.camera.aspect = w / Math.max(1, h)
      this.camera.updateProjectionMatrix()
    }
    this.camera.updateMatrixWorld()
    // the sun's orthographic shadow box follows what the camera looks at, snapped to its texels
    // so shadows do not shimmer as it moves
    const R = this.shadowRadius
    const cam = this.sun.shadow.camera
    cam.left = cam.bottom = -R
    cam.right = cam.top = R
    cam.near = 0.5
    cam.far = 4 * R + 40
    cam.updateProjectionMatrix()
    const texel = (2 * R) / this.sun.shadow.mapSize.x
    const t = target.clone()
    t.x = Math.round(t.x / texel) * texel
    t.z = Math.round(t.z / texel) * texel
    t.y = 0
    this.sun.target.position.copy(t)
    this.sun.position.copy(t).addScaledVector(this.sunDir, 2 * R + 15)
    this.sun.target.updateMatrixWorld()
  }

  render(): void {
    this.renderer.render(this.scene, this.camera)
  }

  /** The world-space ray through a point of the canvas given in normalised device coordinates. */
  ray(x: number, y: number, origin: THREE.Vector3, direction: THREE.Vector3): void {
    origin.setFromMatrixPosition(this.camera.matrixWorld)
    direction.set(x, y, 0.5).unproject(this.camera).sub(origin).normalize()
  }

  /** Where a world point appears on the canvas, in CSS pixels from its top left (and whether in front). */
  project(p: ArrayLike<number>, out: { x: number; y: number; visible: boolean }): void {
    const v = scratch.set(p[0], p[1], p[2]).applyMatrix4(this.camera.matrixWorldInverse)
    out.visible = v.z < -0.05
    v.applyMatrix4(this.camera.projectionMatrix)
    out.x = ((v.x + 1) / 2) * this.canvas.clientWidth
    out.y = ((1 - v.y) / 2) * this.canvas.clientHeight
  }
}

const scratch = new THREE.Vector3()

/**
 * A sky dome: a gradient from the horizon haze to a deeper blue overhead, a warm glow around the
 * sun and the sun's disc; it draws behind everything and ignores fog.
 */
function makeSky(sunDir: THREE.Vector3, horizon: THREE.Color): THREE.Mesh {
  const material = new THREE.ShaderMaterial({
    side: THREE.BackSide,
    depthWrite: false,
    fog: false,
    uniforms: {
      sunDir: { value: sunDir },
      horizon: { value: horizon.clone().convertSRGBToLinear() },
      zenith: { value: new THREE.Color(0x4f7fc0).convertSRGBToLinear() },
      below: { value: new THREE.Color(0x8a8478).convertSRGBToLinear() },
    },
    vertexShader: /* glsl */ `
      varying vec3 vDir;
      void main() {
        vDir = normalize(position);
        vec4 p = projectionMatrix * modelViewMatrix * vec4(position, 1.0);
        gl_Position = p.xyww;
      }`,
    fragmentShader: /* glsl */ `
      uniform vec3 sunDir, horizon, zenith, below;
      varying vec3 vDir;
      void main() {
        vec3 d = normalize(vDir);
        float up = max(d.y, 0.0);
        vec3 col = mix(horizon, zenith, pow(up, 0.55));
        col = mix(col, below, smoothstep(0.0, -0.08, d.y));
        float s = max(dot(d, sunDir), 0.0);
        col += vec3(1.0, 0.85, 0.6) * (0.35 * pow(s, 12.0) + 0.6 * pow(s, 200.0));
        col += vec3(1.0, 0.95, 0.85) * smoothstep(0.9993, 0.9997, s) * 8.0;
        gl_FragColor = vec4(col, 1.0);
        #include <tonemapping_fragment>
        #include <colorspace_fragment>
      }`,
  })
  const sky = new THREE.Mesh(new THREE.SphereGeometry(450, 32, 16), material)
  sky.frustumCulled = false
  sky.renderOrder = -1
  return sky
}
