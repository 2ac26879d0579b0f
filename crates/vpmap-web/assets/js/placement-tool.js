// What the placement tools share (box-tool.js, outline-tools.js, floor-distance-tool.js,
// vp-line-tool.js): their base class, the rubber band and vanishing-point guide lines they
// draw, and the refusal of a floor point on or above the horizon.
//
// A placement tool walks the user through clicking points with a step prompt; it talks to the
// page through `app` (main.js): `state`, `edit(fn, opts)`, `endTool()`, `promptChanged()`,
// `addObject(obj)`, `detachVpPoint(k)`, `showError(msg)`, `clearError()`, `syncForms()` and
// `setStatus(msg)`.

import { VP_COLOURS } from './scene.js';
import { aboveHorizon, lensOf, lineThroughLens, pinholeVp, undistortPx } from './geometry.js';
import { hexAlpha } from './photo-view.js';

/** Draw a rubber band and guide lines in image coordinates. */
export function band(view, a, b, colour, dash = [6, 4]) {
  view.path([a, b]);
  view.strokeHalo(colour, 1.5, dash);
}

/**
 * A faint line from `from` towards the vanishing point `k` (where an edge from `from` must run):
 * straight in the pinhole camera's image, so through a photo's lens (`lens_distortion`) a curve,
 * as the photo shows the edge.
 */
export function guide(view, app, from, k) {
  const scene = app.state.scene;
  const lens = lensOf(scene);
  const vp = pinholeVp(scene?.vanishing_points?.[k], lens);
  if (!vp || !from) return;
  const a = undistortPx(from, lens);
  if (!(Math.hypot(vp[0] - a[0], vp[1] - a[1]) > 1)) return;
  // Both ways: the corner may lie on either side of `from`.
  const pts = lineThroughLens(from, vp, lens, 4000 / view.s, GUIDE_CURVE_SAMPLES);
  if (!pts || pts.length < 2) return;
  view.path(pts);
  view.ctx.strokeStyle = hexAlpha(VP_COLOURS[k], 0.55);
  view.ctx.lineWidth = 1;
  view.ctx.setLineDash([2, 4]);
  view.ctx.stroke();
  view.ctx.setLineDash([]);
}

/** Points of a guide line drawn through a photo's lens (a curve; straight without a lens). */
const GUIDE_CURVE_SAMPLES = 96;

const HORIZON_REFUSAL = 'That point is ';

/** Take away the refusal of refuseAboveHorizon (a point was taken), not any other message. */
export function clearRefusal(app) {
  if (document.getElementById('error-text')?.textContent.startsWith(HORIZON_REFUSAL)) app.clearError();
}

/**
 * Refuse a floor point on or above the horizon of the last build (it cannot be on the floor):
 * true, with a message, when `p` is refused. No build yet: nothing to check against.
 */
export function refuseAboveHorizon(app, p) {
  const hz = app.state.camera?.horizon;
  if (!Array.isArray(hz) || hz.length !== 2) return false;
  // The horizon is the pinhole camera's: the click is taken there through the photo's lens
  // (the distance is then in pinhole pixels, within a few per cent of the photo's).
  const up = aboveHorizon(undistortPx(p, lensOf(app.state.scene)), hz[0], hz[1]);
  if (up === null || up < 0) return false;
  app.showError(`${HORIZON_REFUSAL}${up.toFixed(0)} px above the horizon (the yellow dashed line): a point on the floor must lie below it. Click it again below the horizon.`);
  return true;
}

export class PlacementTool {
  constructor(app) {
    this.app = app;
    this.loupe = true;
  }

  cursor(view) {
    return view.cursor;
  }

  canUndo() {
    return false;
  }
}
