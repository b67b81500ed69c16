/** Shape of a wind zone. */
export type WindShape = 'global' | 'box' | 'sphere'

/** Per-world wind state (`ClothWorldState.wind`). */
export interface WindWorld {
  /** Zone entities in creation order (the order zones are summed in, never query order). */
  zones: number[]
  /** World air density, kg/m³, in a one-slot array (read by the kernels). */
  airDensity: Float64Array
  /** [0] wind time, s (advances one fixed step per step). */
  time: Float64Array
  /** Compiled zone blocks for the current step, ZONE_STRIDE doubles per zone (see `kernels/wind.ts`). */
  params: Float64Array
  /** Zone blocks active for the cloth being prepared (offsets into `params`). */
  active: Int32Array
  /** Cloth bounds scratch (min xyz, max xyz). */
  bounds: Float64Array
  /** Noise scratch. */
  scratch: Float64Array
  /** True once `params` holds this step's zones. */
  compiled: boolean
  /**
   * The aerodynamics' stability clamp (`limitAerodynamics`), always on in use. Only tests turn it
   * off, to show what it prevents (and that the explosion guard catches it).
   */
  clamp: boolean
}

/** Per-cloth aerodynamics buffers (`ClothState.wind`, allocated when a wind zone exists). */
export interface ClothWind {
  /** ux uy uz ρ per particle (stride 4), or once in [0..3] when the air is uniform. */
  air: Float64Array
  /** Aerodynamic acceleration per particle, m/s²; `ClothState.accel` points here while wind acts. */
  accel: Float64Array
  /** Smoothed normals for the aerodynamics and their scratch, xyz per particle. */
  normals: Float64Array
  scratch: Float64Array
  /** Kernel parameters (see `kernels/aero.ts`). */
  params: Float64Array
  /** 1 while some zone reaches the cloth this step. */
  active: number
}
