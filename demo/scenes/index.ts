import type { DemoScene } from '../scene'
import { capeScene } from './cape'
import { collisionsScene } from './collisions'
import { sheetScene } from './sheet'

/** Every scene in the menu, in order. */
export const scenes: DemoScene[] = [capeScene, sheetScene, collisionsScene]
