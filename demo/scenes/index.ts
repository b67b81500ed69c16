import type { DemoScene } from '../scene'
import { accuracyScene } from './accuracy'
import { capeScene } from './cape'
import { collisionsScene } from './collisions'
import { crowdScene } from './crowd'
import { curtainScene } from './curtain'
import { flagScene } from './flag'
import { materialsScene } from './materials'
import { sheetScene } from './sheet'

/** Every scene in the menu, in order. */
export const scenes: DemoScene[] = [
  capeScene,
  flagScene,
  curtainScene,
  materialsScene,
  collisionsScene,
  crowdScene,
  accuracyScene,
  sheetScene,
]
