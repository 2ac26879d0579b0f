// Tools of the photo canvas. The select tool drags existing points; the placement tools walk
// the user through clicking a box's corners, a footprint polygon and its top, the floor
// corners, a known floor distance, or edges towards a vanishing point, with a step prompt.
//
// A tool talks to the page through `app` (main.js): `state`, `edit(fn, opts)`,
// `beginDrag()`, `endDrag()`, `select(sel)`, `endTool()`, `promptChanged()`,
// `objectAdded(i)` and `detachVpPoint(k)`.

import { VP_COLOURS, VP_NAMES, handles, objectHull, polygonArea, resolvedVps, setAt, uniqueName } from './scene.js';
import { aboveHorizon, distToSegment, pointInPolygon, segmentCorners, vpPoint } from './geometry.js';
import { hexAlpha } from './photo-view.js';
import { h } from './util.js';
import { BOX_STEPS, BoxAnnotation, CORNER_HELP, boxEdgeNames, boxEdges, boxPoints, cornerWords, guideLines, neighbourCorner, offLine } from './box.js';

const HIT_PX = 8;
/** A box corner clicked this close (screen px) to its guide line is put on it (Alt: where clicked). */
const SNAP_PX = 6;

/** Draw a rubber band and guide lines in image coordinates. */
function band(view, a, b, colour, dash = [6, 4]) {
  view.path([a, b]);
  view.strokeHalo(colour, 1.5, dash);
}

/** A faint line from `from` towards the vanishing point `k` (where an edge from `from` must run). */
function guide(view, app, from, k) {
  const vp = vpPoint(app.state.scene?.vanishing_points?.[k]);
  if (!vp || !from) return;
  const d = [vp[0] - from[0], vp[1] - from[1]];
  const len = Math.hypot(d[0], d[1]);
  if (!(len > 1)) return;
  // Both ways: the corner may lie on either side of `from`.
  const reach = 4000 / view.s;
  const u = [d[0] / len, d[1] / len];
  const a = [from[0] - u[0] * reach, from[1] - u[1] * reach];
  const b = len < reach ? vp : [from[0] + u[0] * reach, from[1] + u[1] * reach];
  view.path([a, b]);
  view.ctx.strokeStyle = hexAlpha(VP_COLOURS[k], 0.55);
  view.ctx.lineWidth = 1;
  view.ctx.setLineDash([2, 4]);
  view.ctx.stroke();
  view.ctx.setLineDash([]);
}

// ---- select and drag ------------------------------------------------------------------

export class SelectTool {
  constructor(app) {
    this.app = app;
    this.drag = null;
  }

  /** The handle under `p` (image pixels), preferring the selected object's. */
  hit(p, view) {
    const st = this.app.state;
    const r = HIT_PX * view.px;
    let best = null;
    let bestD = r;
    const sel = st.selection;
    for (const hd of handles(st.scene)) {
      // A vanishing-point line's ends move only once the line is selected (a click on it), and
      // never while the segments are hidden: a pan that starts on one of the many detected
      // lines pans, it does not move a vanishing point.
      if (hd.kind === 'vp' && !(st.showSegments && sel?.type === 'vpline' && hd.owner === sel.vp && hd.path[3] === sel.line)) continue;
      let d = Math.hypot(hd.p[0] - p[0], hd.p[1] - p[1]);
      // Where points coincide (a corner is often the end of edges towards several vanishing
      // points): the selected object's or line's point first, then annotations, then lines
      // in order.
      if (sel && sel.type === 'object' && hd.kind === 'object' && hd.owner === sel.index) d *= 0.6;
      if (sel && sel.type === 'vpline' && hd.kind === 'vp' && hd.owner === sel.vp && hd.path[3] === sel.line) d *= 0.6;
      if (hd.kind === 'vp') d *= 1.15;
      if (d < bestD) {
        bestD = d;
        best = hd;
      }
    }
    return best;
  }

  wantsGrab(p, view) {
    return !!this.hit(p, view);
  }

  pointerDown(p, e, view) {
    const hd = this.hit(p, view);
    if (!hd) return false;
    this.drag = { hd, off: [hd.p[0] - p[0], hd.p[1] - p[1]], moved: false, snap: null, fine: null, pointer: p, target: [hd.p[0], hd.p[1]] };
    this.app.state.handle = { path: hd.path, end: hd.end };
    if (hd.kind === 'object') this.app.select({ type: 'object', index: hd.owner });
    else if (hd.kind === 'vp') this.app.select({ type: 'vpline', vp: hd.owner, line: hd.path[3] });
    return true;
  }

  pointerMove(p, e, view) {
    const d = this.drag;
    if (!d) return;
    if (!d.moved) {
      d.moved = true;
      this.app.beginDrag();
    }
    // Shift: the point follows the pointer FINE_DRAG times slower, from where it was when Shift
    // was first seen (the previous pointer position).
    if (e?.shiftKey) {
      if (!d.fine) d.fine = { from: d.pointer, at: d.target };
      d.target = [d.fine.at[0] + (p[0] - d.fine.from[0]) / FINE_DRAG, d.fine.at[1] + (p[1] - d.fine.from[1]) / FINE_DRAG];
    } else {
      if (d.fine) {
        // Shift released: keep the point where it is and follow the pointer from here.
        d.off = [d.target[0] - p[0], d.target[1] - p[1]];
        d.fine = null;
      }
      d.target = [p[0] + d.off[0], p[1] + d.off[1]];
    }
    d.pointer = p;
    d.snap = view && !e?.shiftKey ? dragSnap(this.app, d.hd, d.target, view, !!e?.altKey) : { p: d.target, snapped: false };
    moveHandle(this.app, d.hd, d.snap.p, true);
  }

  pointerUp() {
    if (this.drag?.moved) this.app.endDrag();
    this.drag = null;
  }

  draw(ctx, view) {
    if (this.drag?.snap) drawSnap(view, this.drag.snap);
  }

  click(p, e, view) {
    const st = this.app.state;
    if (!st.scene) return;
    st.handle = null;
    // An object under the pointer, anywhere in its outline with its top (the smallest such, so
    // that an object in front of a larger one can be picked)?
    let hit = -1;
    let hitArea = Infinity;
    st.scene.objects.forEach((o, i) => {
      const ring = objectHull(o);
      const area = ring.length >= 3 && pointInPolygon(p, ring) ? polygonArea(ring) : Infinity;
      if (area < hitArea) {
        hit = i;
        hitArea = area;
      }
    });
    if (hit >= 0) {
      this.app.select({ type: 'object', index: hit });
      return;
    }
    // A vanishing-point line near it (when they are shown)?
    const r = 6 * view.px;
    let best = null;
    if (st.showSegments) st.scene.vanishing_points.forEach((vp, k) => {
      (vp.lines || []).forEach((s, j) => {
        const dd = distToSegment(p, [s[0], s[1]], [s[2], s[3]]);
        if (dd < r && (!best || dd < best.d)) best = { d: dd, vp: k, line: j };
      });
    });
    this.app.select(best ? { type: 'vpline', vp: best.vp, line: best.line } : null);
  }
}

/** Move a handle (see scene.handles) to `p`. */
export function moveHandle(app, hd, p, live) {
  app.edit(
    (scene) => {
      if (hd.kind === 'vp') {
        const s = scene.vanishing_points[hd.path[1]].lines[hd.path[3]];
        if (hd.end === 0) { s[0] = p[0]; s[1] = p[1]; } else { s[2] = p[0]; s[3] = p[1]; }
        app.detachVpPoint(hd.path[1], scene);
      } else {
        setAt(scene, hd.path, [p[0], p[1]]);
      }
      hd.p = p;
    },
    { live, undo: !live },
  );
}

// ---- placement tools -------------------------------------------------------------------

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
/** A drag with Shift held moves the point this many times slower than the pointer (sub-pixel placement at any zoom). */
export const FINE_DRAG = 10;

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
function cornerSnap(app, p, view, free) {
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
function dragSnap(app, hd, p, view, free) {
  if (free || hd.kind === 'vp') return { p, snapped: false };
  const [, i, part, corner] = hd.path;
  const o = hd.kind === 'object' ? app.state.scene?.objects?.[i] : null;
  if (o?.base && (part === 'base' || part === 'top')) {
    const vps = resolvedVps(app.state.scene);
    let best = null;
    for (const g of guideLines(o, part, corner, vps, !!o.own_yaw)) {
      const r = offLine(p, g.from, vps[g.vp]);
      if (r && r.px * view.s <= SNAP_PX && (!best || r.px < best.px)) best = r;
    }
    if (best) return { p: best.foot, snapped: true };
  }
  return cornerSnap(app, p, view, false);
}

/** A white ring where a click at the cursor would put the point, when it snaps. */
function drawSnap(view, s) {
  if (!s || !s.snapped) return;
  const q = view.imageToScreen(s.p);
  view.ctx.beginPath();
  view.ctx.arc(q[0], q[1], 6, 0, Math.PI * 2);
  view.strokeHalo('#ffffff', 1.5);
}

const HORIZON_REFUSAL = 'That point is ';

/** Take away the refusal of refuseAboveHorizon (a point was taken), not any other message. */
function clearRefusal(app) {
  if (document.getElementById('error-text')?.textContent.startsWith(HORIZON_REFUSAL)) app.clearError();
}

/**
 * Refuse a floor point on or above the horizon of the last build (it cannot be on the floor):
 * true, with a message, when `p` is refused. No build yet: nothing to check against.
 */
function refuseAboveHorizon(app, p) {
  const hz = app.state.camera?.horizon;
  if (!Array.isArray(hz) || hz.length !== 2) return false;
  const up = aboveHorizon(p, hz[0], hz[1]);
  if (up === null || up < 0) return false;
  app.showError(`${HORIZON_REFUSAL}${up.toFixed(0)} px above the horizon (the yellow dashed line): a point on the floor must lie below it. Click it again below the horizon.`);
  return true;
}

class PlacementTool {
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

/**
 * A box by the corners the user can see (box.js): choose the corner view (near, right, left,
 * far) or the face view (front/back, left/right) before the first click, then click each
 * corner the prompt names or skip it (hidden), base and top; Done (Enter) once any corner is
 * placed. The server says when the corners do not fix the box, naming the corner to add.
 */
export class BoxTool extends PlacementTool {
  constructor(app, view = 'corner') {
    super(app);
    this.kind = 'box';
    this.box = new BoxAnnotation(view);
  }

  /** Steps taken (clicked or skipped). */
  get step() {
    return this.box.history.length;
  }

  prompt() {
    const box = this.box;
    const c = box.current;
    const total = BOX_STEPS[box.view].length;
    const controls = h('span', { class: 'box-controls' });
    if (!box.canUndo) {
      const sel = h('select', { id: 'prompt-box-view', 'aria-label': 'How the box is seen' },
        h('option', { value: 'corner', text: 'corner view', title: 'seen across a vertical edge: corners near, right, left, far' }),
        h('option', { value: 'face', text: 'face view', title: 'seen face-on: corners front left, front right, back left, back right' }));
      sel.value = box.view;
      sel.addEventListener('change', () => {
        box.setView(sel.value);
        this.app.promptChanged();
        document.getElementById('prompt-box-view')?.focus();
      });
      controls.append(sel);
    }
    const yaw = h('input', { type: 'checkbox', id: 'prompt-own-yaw', checked: box.ownYaw });
    yaw.addEventListener('change', () => {
      box.ownYaw = yaw.checked;
      this.app.promptChanged();
    });
    controls.append(h('label', { class: 'check', title: 'The box is turned on the floor by its own angle, not lined up with the room' }, yaw, ' own yaw'));
    if (c) {
      const skip = h('button', { type: 'button', class: 'small', id: 'prompt-skip', title: 'The corner is hidden: go to the next one (S)', text: 'Skip' });
      skip.addEventListener('click', () => this.skip());
      controls.append(skip);
    }
    return {
      text: c ? `Box ${this.step + 1}/${total}: ${cornerWords(c.corner)} ${c.part} corner` : 'Box: every corner asked; Done to add it',
      help: c ? `${c.part === 'top' ? 'top: ' : ''}${CORNER_HELP[c.corner]}; S if hidden` : 'Enter to add the box',
      extra: controls,
      canUndo: box.canUndo,
      finish: box.canFinish ? 'Done' : null,
    };
  }

  canUndo() {
    return this.box.canUndo;
  }

  /** Where a click at `p` puts the current corner: on its guide line when that is near (SNAP_PX), else `p`. */
  snapped(p, view, free = false) {
    const c = this.box.current;
    if (!c || free || !view) return { p, line: null, snapped: false };
    const vps = resolvedVps(this.app.state.scene);
    let best = null;
    for (const g of guideLines(this.box.partial, c.part, c.corner, vps, this.box.ownYaw)) {
      const r = offLine(p, g.from, vps[g.vp]);
      if (r && r.px * view.s <= SNAP_PX && (!best || r.px < best.r.px)) best = { r, g };
    }
    if (best) return { p: best.r.foot, line: best.g, snapped: true };
    return { ...cornerSnap(this.app, p, view, free), line: null };
  }

  click(p, e, view) {
    if (this.box.current?.part === 'base' && refuseAboveHorizon(this.app, p)) return;
    clearRefusal(this.app);
    p = this.snapped(p, view, !!e?.altKey).p;
    this.box.click(p);
    if (this.box.done) this.finish();
    else this.app.promptChanged();
  }

  skip() {
    this.box.skip();
    if (this.box.done && this.box.canFinish) this.finish();
    else this.app.promptChanged();
  }

  undo() {
    this.box.undo();
    this.app.promptChanged();
  }

  finish() {
    if (!this.box.canFinish) return;
    this.app.addObject(this.box.object(uniqueName(this.app.state.scene, 'box')));
  }

  draw(ctx, view) {
    const box = this.box;
    const o = box.partial;
    const c = box.current;
    const colour = '#5ec8ff';
    for (const e of boxEdges(o)) {
      view.path([e.a, e.b]);
      view.strokeHalo(colour, 2, e.part === 'top' ? [5, 4] : []);
    }
    if (c) {
      // Where the asked corner must lie: along a box edge from a neighbouring corner (towards
      // a horizontal vanishing point, unless the box has its own yaw), or straight above or
      // below the same corner (towards the vertical one).
      const other = c.part === 'base' ? 'top' : 'base';
      const from = neighbourCorner(o, c.part, c.corner);
      const below = o[other]?.[c.corner] || null;
      if (from && !box.ownYaw) {
        guide(view, this.app, from, 0);
        guide(view, this.app, from, 1);
      }
      if (below) guide(view, this.app, below, 2);
      const anchor = below || from;
      if (anchor && view.cursor) band(view, anchor, view.cursor, colour);
    }
    // Where a click here would put the corner: on the guide line when near it.
    if (c && view.cursor) drawSnap(view, this.snapped(view.cursor, view));
    for (const { part, corner, p } of boxPoints(o)) {
      view.dot(p, 4, colour);
      view.label(p, `${part === 'top' ? 'top ' : ''}${cornerWords(corner)}`, colour);
    }
  }
}

export class FootprintTool extends PlacementTool {
  constructor(app) {
    super(app);
    this.kind = 'footprint';
    this.pts = [];
    this.stage = 'polygon';
    this.above = 0;
  }

  prompt() {
    if (this.stage === 'polygon') {
      return {
        text: `Footprint: click the base polygon's corners (${this.pts.length} so far)`,
        help: 'Enter when done (3 or more)',
        canUndo: this.pts.length > 0,
        finish: this.pts.length >= 3 ? 'Polygon done' : null,
      };
    }
    const sel = h('select', { id: 'prompt-above', 'aria-label': 'Vertex below the top point' });
    this.pts.forEach((_, i) => sel.append(h('option', { value: i, text: `vertex ${i + 1}` })));
    sel.value = String(this.above);
    sel.addEventListener('change', () => {
      this.above = Number(sel.value);
      this.app.promptChanged();
      document.getElementById('prompt-above')?.focus();
    });
    return {
      text: `Footprint: click the top above vertex ${this.above + 1}`,
      help: 'Enter to skip: height unknown',
      extra: h('label', { class: 'check' }, 'above ', sel),
      canUndo: true,
      finish: 'Skip',
    };
  }

  canUndo() {
    return this.pts.length > 0;
  }

  click(p, e, view) {
    if (this.stage === 'polygon') {
      // Clicking the first corner again closes the polygon.
      if (this.pts.length >= 3 && Math.hypot(p[0] - this.pts[0][0], p[1] - this.pts[0][1]) < HIT_PX * view.px) {
        this.finish();
        return;
      }
      p = cornerSnap(this.app, p, view, !!e?.altKey).p;
      if (refuseAboveHorizon(this.app, p)) return;
      clearRefusal(this.app);
      this.pts.push(p);
      this.app.promptChanged();
    } else {
      this.commit(p);
    }
  }

  undo() {
    if (this.stage === 'top') this.stage = 'polygon';
    else this.pts.pop();
    this.app.promptChanged();
  }

  finish() {
    if (this.stage === 'polygon') {
      if (this.pts.length < 3) return;
      this.stage = 'top';
      this.above = 0;
      this.app.promptChanged();
    } else this.commit(null);
  }

  commit(top) {
    const obj = { name: uniqueName(this.app.state.scene, 'footprint'), footprint: this.pts };
    if (top) obj.top = { above: this.above, point: top };
    this.app.addObject(obj);
  }

  draw(ctx, view) {
    const colour = '#ffb74d';
    const c = view.cursor;
    if (c && this.stage === 'polygon') drawSnap(view, cornerSnap(this.app, c, view, false));
    if (this.pts.length) {
      view.path(this.pts, this.stage === 'top');
      view.strokeHalo(colour, 2);
    }
    if (this.stage === 'polygon' && c && this.pts.length) band(view, this.pts[this.pts.length - 1], c, colour);
    if (this.stage === 'top') {
      const base = this.pts[this.above];
      guide(view, this.app, base, 2);
      if (c) band(view, base, c, colour);
      view.dot(base, 6, '#fff', colour);
    }
    this.pts.forEach((p) => view.dot(p, 4, colour));
  }
}

export class FloorTool extends PlacementTool {
  constructor(app) {
    super(app);
    this.kind = 'floor';
    this.pts = [];
  }

  prompt() {
    return {
      text: `Floor: click the corners in order around the outline (${this.pts.length} so far)`,
      help: 'Enter when done (3 or more)',
      canUndo: this.pts.length > 0,
      finish: this.pts.length >= 3 ? 'Done' : null,
    };
  }

  canUndo() {
    return this.pts.length > 0;
  }

  click(p, e, view) {
    if (this.pts.length >= 3 && Math.hypot(p[0] - this.pts[0][0], p[1] - this.pts[0][1]) < HIT_PX * view.px) {
      this.finish();
      return;
    }
    p = cornerSnap(this.app, p, view, !!e?.altKey).p;
    if (refuseAboveHorizon(this.app, p)) return;
    clearRefusal(this.app);
    this.pts.push(p);
    this.app.promptChanged();
  }

  undo() {
    this.pts.pop();
    this.app.promptChanged();
  }

  finish() {
    if (this.pts.length < 3) return;
    const pts = this.pts;
    this.app.edit((scene) => {
      scene.floor = pts;
    });
    this.app.endTool();
  }

  draw(ctx, view) {
    const colour = '#7ee08f';
    if (view.cursor) drawSnap(view, cornerSnap(this.app, view.cursor, view, false));
    if (this.pts.length) {
      view.path(this.pts);
      view.strokeHalo(colour, 2);
      if (view.cursor) band(view, this.pts[this.pts.length - 1], view.cursor, colour);
    }
    this.pts.forEach((p) => view.dot(p, 4, colour));
  }
}

export class FloorDistanceTool extends PlacementTool {
  constructor(app, meters) {
    super(app);
    this.kind = 'floor-distance';
    this.pts = [];
    this.snapped = []; // the scene handle each point was taken from (null: a free point)
    this.meters = meters;
  }

  prompt() {
    return {
      text: `Known distance: click the ${this.pts.length ? 'second' : 'first'} floor point`,
      help: `the two points are ${this.meters} m apart`,
      canUndo: this.pts.length > 0,
      finish: null,
    };
  }

  canUndo() {
    return this.pts.length > 0;
  }

  /** The scene's floor point (a floor, box base or footprint corner) within reach of `p`, or null. */
  snap(p, view) {
    let best = null;
    let bestD = HIT_PX * view.px;
    for (const hd of handles(this.app.state.scene)) {
      // Floor points only: floor corners, box base corners, footprint corners (not tops).
      if (hd.kind !== 'floor' && !(hd.kind === 'object' && (hd.path[2] === 'base' || hd.path[2] === 'footprint'))) continue;
      const d = Math.hypot(hd.p[0] - p[0], hd.p[1] - p[1]);
      if (d < bestD) {
        bestD = d;
        best = hd;
      }
    }
    return best;
  }

  click(p, e, view) {
    // A click near a corner takes the corner itself, so that the distance is between the very
    // points the box or floor uses.
    const hd = view ? this.snap(p, view) : null;
    if (!hd && refuseAboveHorizon(this.app, p)) return;
    this.pts.push(hd ? [hd.p[0], hd.p[1]] : p);
    this.snapped.push(hd);
    if (this.pts.length < 2) {
      this.app.promptChanged();
      return;
    }
    const [from, to] = this.pts;
    const edge = this.boxEdge();
    this.app.edit((s) => {
      s.scale = edge ? { object: edge.object, edge: edge.edge, meters: this.meters } : { floor_distance: { from, to, meters: this.meters } };
    });
    this.app.endTool();
    if (edge) {
      // The box's own edge: the box is then exactly this long, and so is the distance.
      this.app.syncForms();
      this.app.setStatus(`Both points are corners of “${edge.object}”: the scale is its edge ${edge.edge[0]} – ${edge.edge[1]} = ${this.meters} m, so the box and the scale agree.`);
    }
  }

  /** `{object, edge}` when both points are base corners of one box joined by an edge, else null. */
  boxEdge() {
    const [a, b] = this.snapped || [];
    const at = (hd) => (hd && hd.kind === 'object' && hd.path[2] === 'base' ? hd.path : null);
    const pa = at(a), pb = at(b);
    if (!pa || !pb || pa[1] !== pb[1]) return null;
    const o = this.app.state.scene.objects[pa[1]];
    const want = new Set([`base.${pa[3]}`, `base.${pb[3]}`]);
    const e = boxEdgeNames(o).find((x) => want.has(x.a) && want.has(x.b) && x.a !== x.b);
    return e ? { object: o.name, edge: [e.a, e.b] } : null;
  }

  undo() {
    this.pts.pop();
    this.snapped?.pop();
    this.app.promptChanged();
  }

  draw(ctx, view) {
    if (this.pts.length === 1 && view.cursor) band(view, this.pts[0], view.cursor, '#fff', [3, 3]);
    this.pts.forEach((p) => view.dot(p, 4, '#fff'));
  }
}

/** Draw edge segments towards vanishing point `k`: press, drag along an edge, release (or click both ends). */
export class VpLineTool extends PlacementTool {
  constructor(app, k) {
    super(app);
    this.kind = 'vp-line';
    this.vpIndex = k;
    this.start = null;
    this.pressed = false;
  }

  prompt() {
    const n = (this.app.state.scene.vanishing_points[this.vpIndex]?.lines || []).length;
    return {
      text: `${VP_NAMES[this.vpIndex]}: drag along an edge that runs towards it (${n} line${n === 1 ? '' : 's'})`,
      help: 'or click both ends; two or more long edges; Enter when done',
      canUndo: n > 0 || !!this.start,
      finish: 'Done',
    };
  }

  canUndo() {
    return !!this.start || (this.app.state.scene.vanishing_points[this.vpIndex]?.lines || []).length > 0;
  }

  pointerDown(p) {
    if (!this.start) {
      this.start = p;
      this.pressed = true;
    }
    return true;
  }

  pointerMove() {}

  pointerUp(p, e, view, cancelled) {
    if (cancelled || !this.start) return;
    const far = Math.hypot(p[0] - this.start[0], p[1] - this.start[1]) * view.s > 6;
    if (this.pressed && !far) {
      // A click: wait for the second click.
      this.pressed = false;
      this.app.promptChanged();
      return;
    }
    if (!far) return;
    const seg = [this.start[0], this.start[1], p[0], p[1]];
    this.start = null;
    this.pressed = false;
    const k = this.vpIndex;
    this.app.edit((scene) => {
      const vp = scene.vanishing_points[k];
      if (!Array.isArray(vp.lines)) vp.lines = [];
      vp.lines.push(seg);
      this.app.detachVpPoint(k, scene);
    });
    this.app.promptChanged();
  }

  undo() {
    if (this.start) {
      this.start = null;
    } else {
      const k = this.vpIndex;
      this.app.edit((scene) => {
        scene.vanishing_points[k].lines?.pop();
      });
    }
    this.app.promptChanged();
  }

  finish() {
    this.app.endTool();
  }

  draw(ctx, view) {
    if (this.start && view.cursor) {
      view.path([this.start, view.cursor]);
      view.strokeHalo(VP_COLOURS[this.vpIndex], 2);
      view.dot(this.start, 3.5, '#fff', VP_COLOURS[this.vpIndex]);
    }
  }
}
