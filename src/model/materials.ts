import { ClothError, MAX_COORDINATE, checkAtMost, checkKeys, checkNonNegative, checkPositive } from '../core/errors'

/**
 * A cloth material in physical units. Compliance is inverse stiffness (XPBD, Macklin et al. 2016):
 * 0 is perfectly stiff, larger is softer, and the answer it converges to does not depend on the
 * time step or iteration count. A cloth with few substeps × iterations has not converged and
 * stretches more than its material (an 11×11 silk sheet without tethers: 121 mm at 1 × 1 where
 * compliance predicts 0.05 mm; README, Materials).
 *
 * How the solver turns these into per-constraint compliance (see `src/model/assembly.ts`):
 * - stretch: membrane compliance 1/(E·t) in m/N. An edge of length L whose adjacent triangles cover
 *   area A gets L²/A × stretchCompliance, which is exactly stretchCompliance on a square grid, so the
 *   converged fabric stretches the same at any resolution.
 * - shear: 1/(G·t) in m/N, applied to the two diagonals of each quad (their energy adds up to the
 *   continuum shear energy of the cell).
 * - bend: 1/B in 1/(N·m), B the flexural rigidity per unit width. A dihedral hinge with edge e and
 *   triangle areas A1 + A2 gets (A1 + A2)/(3|e|²) × bendCompliance (discrete shells); a skip-one
 *   distance constraint of half-length L gets L²/48 × bendCompliance, matched to the hinge energy at a
 *   1 rad fold.
 */
export interface ClothMaterialSpec {
  /** Display name, e.g. 'cotton'. */
  readonly name: string
  /** Areal density in kg/m²; particle masses come from it and the triangle areas. */
  readonly density: number
  /** Membrane stretch compliance 1/(E·t), m/N. */
  readonly stretchCompliance: number
  /** In-plane shear compliance 1/(G·t), m/N. */
  readonly shearCompliance: number
  /** Bending compliance 1/B, 1/(N·m). */
  readonly bendCompliance: number
  /**
   * Velocity damping rate, 1/s (0 = none): linear drag toward still air, the cheap stand-in for
   * aerodynamics when no wind zone acts on the cloth. Presets use ≈ 0.15/density: air drag on a
   * cape moving at a few m/s is several times its weight, so light fabrics are damped most.
   */
  readonly damping: number
  /**
   * Internal damping of stretching, 1/s: the rate at which relative velocity along structural
   * edges dies out (applied once per fixed step). It damps only stretch vibrations, not swinging
   * or folding, and keeps stiff over-determined sheets from buzzing: a pinned 64×64 leather sheet
   * jittered at up to 2.8 m/s rms without it; at 60/s all 120 tested sheets (4 materials, row or
   * corner pins, 3 tether slacks, 1-32 substeps) rest.
   */
  readonly stretchDamping: number
  /** Coulomb friction coefficient against colliders (combined with the collider's). */
  readonly friction: number
  /** Engineering strain at which a tearable edge breaks (0.2 = 20 % longer than rest). */
  readonly tearStrain: number
  /** Aerodynamic drag coefficient (along the triangle normal), dimensionless, at most 1000. */
  readonly drag: number
  /** Aerodynamic lift coefficient (extra normal force where the air grazes the cloth), dimensionless, at most 1000. */
  readonly lift: number
  /** Collision thickness (particle radius), m, at most 1e9. */
  readonly thickness: number
}

const preset = (m: ClothMaterialSpec): ClothMaterialSpec => Object.freeze(m)

/**
 * Built-in presets. Densities are typical fabric weights; stiffnesses are order-of-magnitude
 * figures for the woven or sheet material (real woven fabric stretches well under 1 % under its own
 * weight, so the presets differ mostly in weight, bending and shear).
 */
export const ClothMaterial = Object.freeze({
  /** Light silk or chiffon: very light, floppy, tears easily. */
  SILK: preset({
    name: 'silk',
    density: 0.05,
    stretchCompliance: 2e-4,
    shearCompliance: 1e-1,
    bendCompliance: 2e5,
    damping: 3,
    stretchDamping: 60,
    friction: 0.2,
    tearStrain: 0.25,
    drag: 1.0,
    lift: 0.6,
    thickness: 0.004,
  }),
  /** Shirt-weight cotton: the all-round default. */
  COTTON: preset({
    name: 'cotton',
    density: 0.15,
    stretchCompliance: 1e-4,
    shearCompliance: 5e-2,
    bendCompliance: 5e4,
    damping: 1,
    stretchDamping: 60,
    friction: 0.5,
    tearStrain: 0.3,
    drag: 1.0,
    lift: 0.4,
    thickness: 0.005,
  }),
  /** Ripstop nylon for flags, sails and kites: light, stiff in-plane, crisp. */
  NYLON: preset({
    name: 'nylon',
    density: 0.06,
    stretchCompliance: 5e-5,
    shearCompliance: 3e-2,
    bendCompliance: 1e5,
    damping: 2.5,
    stretchDamping: 60,
    friction: 0.3,
    tearStrain: 0.35,
    drag: 1.1,
    lift: 0.5,
    thickness: 0.004,
  }),
  /** Wool or felt: soft, warm, a little stretchy. */
  WOOL: preset({
    name: 'wool',
    density: 0.3,
    stretchCompliance: 3e-4,
    shearCompliance: 8e-2,
    bendCompliance: 2e4,
    damping: 0.5,
    stretchDamping: 60,
    friction: 0.7,
    tearStrain: 0.4,
    drag: 1.2,
    lift: 0.3,
    thickness: 0.006,
  }),
  /** Heavy denim: heavy, stiffer to bend. */
  DENIM: preset({
    name: 'denim',
    density: 0.4,
    stretchCompliance: 3e-5,
    shearCompliance: 2e-2,
    bendCompliance: 1e4,
    damping: 0.4,
    stretchDamping: 60,
    friction: 0.6,
    tearStrain: 0.35,
    drag: 1.1,
    lift: 0.3,
    thickness: 0.006,
  }),
  /** Canvas or sailcloth: stiff in every mode. */
  CANVAS: preset({
    name: 'canvas',
    density: 0.45,
    stretchCompliance: 2e-5,
    shearCompliance: 1e-2,
    bendCompliance: 2e3,
    damping: 0.35,
    stretchDamping: 60,
    friction: 0.6,
    tearStrain: 0.4,
    drag: 1.2,
    lift: 0.4,
    thickness: 0.006,
  }),
  /** Velvet or heavy curtain fabric: heavy and soft, strongly damped. */
  VELVET: preset({
    name: 'velvet',
    density: 0.35,
    stretchCompliance: 2e-4,
    shearCompliance: 8e-2,
    bendCompliance: 2e4,
    damping: 0.45,
    stretchDamping: 60,
    friction: 0.8,
    tearStrain: 0.35,
    drag: 1.3,
    lift: 0.2,
    thickness: 0.007,
  }),
  /** Leather: heavy, resists bending and shear, hard to tear. */
  LEATHER: preset({
    name: 'leather',
    density: 0.9,
    stretchCompliance: 2e-5,
    shearCompliance: 2e-3,
    bendCompliance: 5e2,
    damping: 0.2,
    stretchDamping: 60,
    friction: 0.8,
    tearStrain: 0.6,
    drag: 1.2,
    lift: 0.2,
    thickness: 0.008,
  }),
  /** A 1 mm rubber sheet: visibly elastic, springy. */
  RUBBER: preset({
    name: 'rubber',
    density: 1.1,
    stretchCompliance: 2e-3,
    shearCompliance: 6e-3,
    bendCompliance: 6e3,
    damping: 0.15,
    stretchDamping: 60,
    friction: 1.0,
    tearStrain: 1.5,
    drag: 1.0,
    lift: 0.2,
    thickness: 0.006,
  }),
  /** Chainmail: very heavy, inextensible, shears and bends freely. */
  CHAINMAIL: preset({
    name: 'chainmail',
    density: 6.0,
    stretchCompliance: 1e-6,
    shearCompliance: 2e-1,
    bendCompliance: 2e4,
    damping: 0.1,
    stretchDamping: 60,
    friction: 0.4,
    tearStrain: 0.15,
    drag: 0.4,
    lift: 0.05,
    thickness: 0.01,
  }),
})

export type ClothMaterialName = keyof typeof ClothMaterial

/** Largest accepted drag or lift coefficient (a flat plate's drag is about 2). */
export const MAX_AERO_COEFFICIENT = 1000

const NUMERIC_FIELDS = [
  'density',
  'stretchCompliance',
  'shearCompliance',
  'bendCompliance',
  'damping',
  'stretchDamping',
  'friction',
  'tearStrain',
  'drag',
  'lift',
  'thickness',
] as const

/**
 * Defines a custom material. Fields not given are taken from `base` (cotton by default); the
 * result is validated and frozen.
 *
 * @example const oilcloth = defineMaterial({ name: 'oilcloth', density: 0.5, bendCompliance: 1e3 })
 */
export function defineMaterial(
  fields: Partial<ClothMaterialSpec>,
  base: ClothMaterialSpec | string = ClothMaterial.COTTON,
): ClothMaterialSpec {
  if (typeof fields !== 'object' || fields === null) throw new ClothError('fields', fields, 'must be an object of material fields')
  checkKeys('fields', fields, ['name', ...NUMERIC_FIELDS]) // (a misspelt field kept the base's value)
  const from = resolveMaterial(base, 'base')
  const out = { ...from, ...fields, name: fields.name ?? `custom ${from.name}` }
  validateMaterial(out, 'material')
  return Object.freeze(out)
}

/**
 * Accepts a preset name ('silk', 'COTTON', ...), a preset object or any object with the material
 * fields, and returns a validated, frozen material (a copy when the object given is not frozen).
 * Throws ClothError for unknown names or bad values.
 */
export function resolveMaterial(material: unknown, argument = 'options.material'): ClothMaterialSpec {
  if (material === undefined) return ClothMaterial.COTTON
  if (typeof material === 'string') {
    const key = material.toUpperCase() as ClothMaterialName
    const found = Object.hasOwn(ClothMaterial, key) ? ClothMaterial[key] : undefined
    if (!found) {
      const names = Object.keys(ClothMaterial).map((k) => k.toLowerCase())
      throw new ClothError(argument, material, `is not a known material (known: ${names.join(', ')})`)
    }
    return found
  }
  if (typeof material !== 'object' || material === null) {
    throw new ClothError(argument, material, 'must be a material name or a ClothMaterialSpec object')
  }
  if (Object.isFrozen(material) && (Object.values(ClothMaterial) as unknown[]).includes(material)) {
    return material as ClothMaterialSpec
  }
  // a frozen copy: the solver reads the material every substep, so a later edit of the caller's
  // object must not reach it unvalidated
  const m = Object.isFrozen(material) ? material : Object.freeze({ ...material })
  validateMaterial(m as Record<string, unknown>, argument)
  return m as ClothMaterialSpec
}

function validateMaterial(m: Record<string, unknown>, argument: string): void {
  for (const field of NUMERIC_FIELDS) {
    if (!(field in m)) throw new ClothError(`${argument}.${field}`, undefined, 'is required')
    checkNonNegative(`${argument}.${field}`, m[field])
  }
  checkPositive(`${argument}.density`, m.density)
  // squared in the collision reach, multiplied by air density and speed in the wind: bounded so those stay finite
  checkAtMost(`${argument}.thickness`, m.thickness as number, MAX_COORDINATE, ' m')
  checkAtMost(`${argument}.drag`, m.drag as number, MAX_AERO_COEFFICIENT, '')
  checkAtMost(`${argument}.lift`, m.lift as number, MAX_AERO_COEFFICIENT, '')
  checkPositive(`${argument}.tearStrain`, m.tearStrain)
  if (typeof m.name !== 'string') throw new ClothError(`${argument}.name`, m.name, 'must be a string')
}
