import * as THREE from 'three'
import {
  capeTexture,
  curtainTexture,
  flagTexture,
  ginghamTexture,
  grainNormal,
  gridTexture,
  leatherNormal,
  leatherTexture,
  plainTexture,
  towelTexture,
  weaveNormal,
  woodTexture,
} from './textures'

/**
 * Physically based materials for the demo's cloths and props. Fabrics are two-sided
 * MeshPhysicalMaterials with sheen (the soft rim light of fibres), a colour map and a woven
 * normal map; leather and rubber have none of the sheen and their own surface relief.
 */

interface FabricOptions {
  map: THREE.Texture
  normalMap?: THREE.Texture
  normalScale?: number
  roughness?: number
  sheen?: number
  sheenColor?: THREE.ColorRepresentation
  sheenRoughness?: number
  clearcoat?: number
  clearcoatRoughness?: number
  color?: THREE.ColorRepresentation
}

function fabric(o: FabricOptions): THREE.MeshPhysicalMaterial {
  return new THREE.MeshPhysicalMaterial({
    map: o.map,
    color: o.color ?? 0xffffff,
    normalMap: o.normalMap ?? null,
    normalScale: new THREE.Vector2(o.normalScale ?? 0.5, o.normalScale ?? 0.5),
    roughness: o.roughness ?? 0.85,
    metalness: 0,
    sheen: o.sheen ?? 1,
    sheenColor: new THREE.Color(o.sheenColor ?? 0xffffff),
    sheenRoughness: o.sheenRoughness ?? 0.5,
    clearcoat: o.clearcoat ?? 0,
    clearcoatRoughness: o.clearcoatRoughness ?? 0.3,
    side: THREE.DoubleSide,
  })
}

/** The hero's red wool cape with gold braid. */
export const capeFabric = () =>
  fabric({
    map: capeTexture(),
    normalMap: weaveNormal(60, 8),
    normalScale: 0.45,
    roughness: 0.9,
    sheenColor: 0xff9a8a,
    sheenRoughness: 0.45,
  })

/** A nylon flag: smoother and a little glossy. */
export const flagFabric = () =>
  fabric({
    map: flagTexture(),
    normalMap: weaveNormal(40, 8),
    normalScale: 0.25,
    roughness: 0.55,
    sheen: 0.4,
    sheenColor: 0xffffff,
    sheenRoughness: 0.3,
  })

/** Curtain velvet: strong sheen, a deep pile. */
export const curtainFabric = () =>
  fabric({
    map: curtainTexture(),
    normalMap: weaveNormal(70, 8),
    normalScale: 0.3,
    roughness: 0.95,
    sheen: 1,
    sheenColor: 0xff8c98,
    sheenRoughness: 0.35,
  })

/** A plain dyed cotton (collision sheets, the hanging sheet, crowd capes). */
export const cottonFabric = (color: string, stripes?: string) =>
  fabric({
    map: plainTexture(color, stripes),
    normalMap: weaveNormal(30, 8),
    normalScale: 0.5,
    roughness: 0.9,
    sheenColor: 0xffffff,
    sheenRoughness: 0.6,
    sheen: 0.6,
  })

/** A plain dyed cotton as a standard material (no sheen): for many cloths seen from afar. */
export const simpleCotton = (color: string) =>
  new THREE.MeshStandardMaterial({
    map: plainTexture(color),
    normalMap: weaveNormal(30, 8),
    normalScale: new THREE.Vector2(0.5, 0.5),
    roughness: 0.9,
    side: THREE.DoubleSide,
  })

/** Checked cotton. */
export const ginghamFabric = (color: string, checks = 8) =>
  fabric({
    map: ginghamTexture(color, checks),
    normalMap: weaveNormal(30, 8),
    normalScale: 0.5,
    roughness: 0.9,
    sheen: 0.6,
    sheenRoughness: 0.6,
  })

/** Terry towel. */
export const towelFabric = (band: string) =>
  fabric({ map: towelTexture(band), normalMap: weaveNormal(50, 4), normalScale: 0.9, roughness: 1, sheen: 0.8, sheenRoughness: 0.8 })

/** The accuracy scene's measuring sheet. */
export const gridFabric = (tint: string) =>
  fabric({ map: gridTexture(tint), normalMap: weaveNormal(30, 8), normalScale: 0.3, roughness: 0.85, sheen: 0.5, sheenRoughness: 0.6 })

/** Silk: smooth, strong coloured sheen, low roughness. */
export const silkFabric = () =>
  fabric({
    map: plainTexture('#c9a64a'),
    normalMap: weaveNormal(80, 8),
    normalScale: 0.12,
    roughness: 0.38,
    sheen: 1,
    sheenColor: 0xfff0c0,
    sheenRoughness: 0.25,
  })

/** Leather: no sheen, grain relief, a soft gloss. */
export const leatherMaterial = () =>
  new THREE.MeshPhysicalMaterial({
    map: leatherTexture(),
    normalMap: leatherNormal(3),
    normalScale: new THREE.Vector2(0.7, 0.7),
    roughness: 0.55,
    clearcoat: 0.25,
    clearcoatRoughness: 0.5,
    side: THREE.DoubleSide,
  })

/** Rubber: smooth, slightly glossy, a faint grain. */
export const rubberMaterial = () =>
  new THREE.MeshPhysicalMaterial({
    map: plainTexture('#1f6f66'),
    normalMap: grainNormal(6),
    normalScale: new THREE.Vector2(0.25, 0.25),
    roughness: 0.42,
    clearcoat: 0.6,
    clearcoatRoughness: 0.35,
    side: THREE.DoubleSide,
  })

/** Chain mail: a dark metal strip. */
export const chainMaterial = () =>
  new THREE.MeshStandardMaterial({
    color: 0x8c9099,
    metalness: 0.5,
    roughness: 0.38,
    normalMap: weaveNormal(20, 4),
    side: THREE.DoubleSide,
  })

/** Brushed steel (rails, poles, hooks). */
export const steel = () => new THREE.MeshStandardMaterial({ color: 0xb8bcc4, metalness: 0.45, roughness: 0.3 })

/** Brass (finials, rings). */
export const brass = () => new THREE.MeshStandardMaterial({ color: 0xc8a04a, metalness: 0.55, roughness: 0.3 })

/** Varnished wood. */
export const wood = () => new THREE.MeshStandardMaterial({ map: woodTexture(), roughness: 0.55, metalness: 0 })

/** Painted matte surface (colliders, props). */
export const paint = (color: THREE.ColorRepresentation, roughness = 0.6) =>
  new THREE.MeshStandardMaterial({ color, roughness, metalness: 0, normalMap: grainNormal(2), normalScale: new THREE.Vector2(0.15, 0.15) })

/** Marks a mesh (and its children) as casting and receiving shadows. */
export function shadows<T extends THREE.Object3D>(o: T, cast = true, receive = true): T {
  o.traverse((c) => {
    c.castShadow = cast
    c.receiveShadow = receive
  })
  return o
}
