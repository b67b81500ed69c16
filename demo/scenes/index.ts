import type { DemoScene } from '../scene'
import { capeScene } from './cape'
import { collisionsScene } from './collisions'
import { sheetScene } from './sheet'
import { flagScene } from './flag'
import { curtainScene } from './curtain'
import { accuracyScene } from './accuracy'
import { materialsScene } from './materials'

/** Every scene in the menu, in order. */
export const scenes: DemoScene[] = [capeScene, sheetScene, flagScene, curtainScene, accuracyScene, materialsScene, collisionsScene]
