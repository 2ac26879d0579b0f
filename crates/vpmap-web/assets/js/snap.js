// Where a click or a drag puts a point on the photo: on a box corner's guide line, on a corner
// where two vanishing-point lines meet, or (zoomed in) on a line's or detected segment's end;
// Alt puts it where the pointer is. Also the reach of the pointer (HIT_PX) and the white ring
// that shows where a point would go.

import { resolvedVps } from './scene.js';
import { segmentCorners } from './geometry.js';
import { guideLines, offLineThroughLens } from './box.js';
import { lensOf } from './geometry.js';

/** How near (screen px) the pointer must be to a point to grab it or to close a polygon on it. */
export const HIT_PX = 8;
/** A box corner clicked this close (screen px) to its guide line is put on it (Alt: where clicked). */
export const SNAP_PX = 6;

/** How near (screen px) a click must be to a corner of the vanishing-point lines to go on it. */
const CORNER_SNAP_PX = 6;
/** How near (image px) two lines' ends must be to their crossing to make a corner. */
const CORNER_REACH_PX = 12;
/**
 * A line's or detected segment's end attracts points only at this zoom (screen px per image px)
 * or closer. Segment detectors stop a few pixels short of corners: at the fitted zoom, snapping
 * to ends moved clicks made exactly on the example's corners by up to 2.9 px (1.2 px without;
 * e2e.mjs "place the example's corners"), so ends are a target only once the user zooms in and
 * sees the end being aimed at.
 */
const END_SNAP_MIN_ZOOM = 1;

/** The last snap targets and what they were computed from (the lists are rebuilt only when a line changes). */
let snapCache = { key: null, targets: { corners: [], ends: [] } };

/**
 * Where points snap to, in image pixels: `corners`, where two vanishing-point lines of different
 * directions meet (segmentCorners), and `ends`, the ends of those lines and, when shown, of the
 * detected segments. The crossings of detected segments are not used: among hundreds of them,
 * texture and clutter give crossings a dozen pixels from the true corner at the fitted zoom.
 */
function snapTargets(app) {
  const st = app.state;
  const groups = (st.scene?.vanishing_points || []).map((vp) => vp.lines || []);
  const det = st.showSegments ? st.detection : null;
  const segments = det && Array.isArray(det.segments) ? det.segments : [];
  // A cheap signature of every line: the cache holds while nothing moved.
  let sig = 0;
  for (const g of groups) for (const s of g) sig = (sig * 31 + s[0] + 3 * s[1] + 7 * s[2] + 11 * s[3]) % 1e12;
  const key = `${groups.map((g) => g.length).join(',')}:${segments.length}:${sig}`;
  if (snapCache.key === key && snapCache.det === det) return snapCache.targets;
  const corners = segmentCorners(groups, CORNER_REACH_PX);
  const ends = [];
  for (const s of [...groups.flat(), ...segments]) ends.push([s[0], s[1]], [s[2], s[3]]);
  snapCache = { key, det, targets: { corners, ends } };
  return snapCache.targets;
}

/** The point of `points` nearest to `p` within `reach`, or null. */
function nearest(points, p, reach) {
  let best = null;
  let bestD = reach;
  for (const c of points) {
    const d = Math.hypot(c[0] - p[0], c[1] - p[1]);
    if (d < bestD) {
      bestD = d;
      best = c;
    }
  }
  return best;
}

/**
 * Where a click at `p` puts a point (snapTargets): on the nearest corner where two lines of
 * different directions meet within CORNER_SNAP_PX screen px; else, zoomed in to
 * END_SNAP_MIN_ZOOM or more, on the nearest line's or detected segment's end within
 * CORNER_SNAP_PX screen px; else
 * `p`. `free` (Alt held): `p`. Returns `{p, snapped}`.
 */
export function cornerSnap(app, p, view, free) {
  if (free || !view || !app.state.scene) return { p, snapped: false };
  const { corners, ends } = snapTargets(app);
  const reach = CORNER_SNAP_PX / view.s;
  const best = nearest(corners, p, reach) || (view.s >= END_SNAP_MIN_ZOOM ? nearest(ends, p, reach) : null);
  return best ? { p: [best[0], best[1]], snapped: true } : { p, snapped: false };
}

/**
 * Where a dragged handle goes when the pointer is at `p`: a box corner on the guide line it
 * belongs on (guideLines: from the anchor towards A or B, or the vertical through its base
 * corner) when within SNAP_PX, else like a click (cornerSnap); segment ends are not snapped.
 */
export function dragSnap(app, hd, p, view, free) {
  if (free || hd.kind === 'vp') return { p, snapped: false };
  const [, i, part, corner] = hd.path;
  const o = hd.kind === 'object' ? app.state.scene?.objects?.[i] : null;
  if (o?.base && (part === 'base' || part === 'top')) {
    const vps = resolvedVps(app.state.scene);
    const lens = lensOf(app.state.scene);
    let best = null;
    for (const g of guideLines(o, part, corner, vps, !!o.own_yaw)) {
      const r = offLineThroughLens(p, g.from, vps[g.vp], lens);
      if (r && r.px * view.s <= SNAP_PX && (!best || r.px < best.px)) best = r;
    }
    if (best) return { p: best.foot, snapped: true };
  }
  return cornerSnap(app, p, view, false);
}

/** A white ring where a click at the cursor would put the point, when it snaps. */
export function drawSnap(view, s) {
  if (!s || !s.snapped) return;
  const q = view.imageToScreen(s.p);
  view.ctx.beginPath();
  view.ctx.arc(q[0], q[1], 6, 0, Math.PI * 2);
  view.strokeHalo('#ffffff', 1.5);
}
