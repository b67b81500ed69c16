import { addEntity, createWorld, hasComponent, observe, onRemove, removeComponent, removeEntity } from 'bitecs'
import { describe, expect, it } from 'vitest'
import {
  addSphereCollider,
  createCloth,
  getClothComponents,
  getClothState,
  getColliders,
  getCollisionComponents,
  installClothPlugin,
  removeCollider,
  setTransform,
  stepCloth,
} from '../../src/index'
import { SHEET_OVER_BALL } from '../fixtures/drape'

/** A sheet draped over a ball on its own entity, for one second. */
function draped() {
  const world = installClothPlugin(createWorld())
  const ball = addEntity(world)
  setTransform(world, ball, [0, 0, 0])
  addSphereCollider(world, ball, { radius: 0.5 })
  const cloth = createCloth(world, SHEET_OVER_BALL)
  for (let f = 0; f < 60; f++) stepCloth(world, 1 / 60)
  return { world, ball, cloth }
}

describe('collider lifetimes', () => {
  it('a collider whose own entity loses its Transform is removed, as removeCollider does: the cloth on it falls', () => {
    const run = (lose: 'transform' | 'collider') => {
      const { world, ball, cloth } = draped()
      const { Collider } = getCollisionComponents(world)
      let released = 0
      observe(world, onRemove(Collider), () => released++)
      if (lose === 'transform') removeComponent(world, ball, getClothComponents(world).Transform)
      else removeCollider(world, ball)
      expect(getColliders(world)).toEqual([])
      expect(hasComponent(world, ball, Collider)).toBe(false)
      expect(released).toBe(1)
      for (let f = 0; f < 30; f++) stepCloth(world, 1 / 60)
      return Array.from(getClothState(world, cloth).pos)
    }
    const removed = run('collider'), lost = run('transform')
    expect(lost).toEqual(removed)
    let top = -Infinity
    for (let i = 1; i < lost.length; i += 3) top = Math.max(top, lost[i])
    expect(top).toBeLessThan(0) // fell through where the ball was (it rested at 0.5 m)
  })

  it('removing a collider entity, or its body, still releases each collider once', () => {
    const world = installClothPlugin(createWorld())
    const { Collider } = getCollisionComponents(world)
    const hero = addEntity(world)
    setTransform(world, hero, [0, 0, 0])
    const head = addEntity(world)
    addSphereCollider(world, head, { body: hero, offset: [0, 1.7, 0], radius: 0.1 })
    const ball = addEntity(world)
    setTransform(world, ball, [3, 0, 0])
    addSphereCollider(world, ball, { radius: 0.5 })
    let released = 0
    observe(world, onRemove(Collider), () => released++)
    removeEntity(world, ball)
    expect(getColliders(world)).toEqual([head])
    expect(released).toBe(1)
    removeEntity(world, hero)
    expect(getColliders(world)).toEqual([])
    expect(released).toBe(2)
  })
})
