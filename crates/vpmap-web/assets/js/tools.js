// Tools of the photo canvas. The select tool drags existing points; the placement tools walk
// the user through clicking a box's corners, a footprint polygon and its top, the floor
// corners, a known floor distance, or edges towards a vanishing point, with a step prompt.
//
// A tool talks to the page through `app` (main.js): `state`, `edit(fn, opts)`,
// `beginDrag()`, `endDrag()`, `select(sel)`, `endTool()`, `promptChanged()`,
// `objectAdded(i)` and `detachVpPoint(k)`.

import { VP_COLOURS, VP_NAMES, handles, objectOutline, setAt, uniqueName } from './scene.js';
import { distToSegment, pointInPolygon, vpPoint } from './geometry.js';
import { hexAlpha } from './photo-view.js';
import { h } from './util.js';

const HIT_PX = 8;

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
    this.drag = { hd, off: [hd.p[0] - p[0], hd.p[1] - p[1]], moved: false };
    this.app.state.handle = { path: hd.path, end: hd.end };
    if (hd.kind === 'object') this.app.select({ type: 'object', index: hd.owner });
    else if (hd.kind === 'vp') this.app.select({ type: 'vpline', vp: hd.owner, line: hd.path[3] });
    return true;
  }

  pointerMove(p) {
    const d = this.drag;
    if (!d) return;
    if (!d.moved) {
      d.moved = true;
      this.app.beginDrag();
    }
    moveHandle(this.app, d.hd, [p[0] + d.off[0], p[1] + d.off[1]], true);
  }

  pointerUp() {
    if (this.drag?.moved) this.app.endDrag();
    this.drag = null;
  }

  click(p, e, view) {
    const st = this.app.state;
    if (!st.scene) return;
    st.handle = null;
    // An object under the pointer (last drawn first)?
    for (let i = st.scene.objects.length - 1; i >= 0; i--) {
      const ring = objectOutline(st.scene.objects[i]);
      if (ring.length >= 3 && pointInPolygon(p, ring)) {
        this.app.select({ type: 'object', index: i });
        return;
      }
    }
    // A vanishing-point line near it?
    const r = 6 * view.px;
    let best = null;
    st.scene.vanishing_points.forEach((vp, k) => {
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

const BOX_STEPS = [
  { key: ['base', 'near'], text: 'near base corner', help: 'where the two visible bottom edges meet' },
  { key: ['base', 'right'], text: 'right base corner', help: 'the right end of the visible bottom edges' },
  { key: ['base', 'left'], text: 'left base corner', help: 'the left end of the visible bottom edges' },
  { key: ['top', 'near'], text: 'top above the near corner', help: 'Enter to skip: height unknown' },
  { key: ['top', 'left'], text: 'top above the left corner', help: 'optional; Enter to finish' },
];

export class BoxTool extends PlacementTool {
  constructor(app) {
    super(app);
    this.kind = 'box';
    this.pts = [];
  }

  get step() {
    return this.pts.length;
  }

  prompt() {
    const s = BOX_STEPS[this.step];
    return {
      text: `Box: click the ${s.text}`,
      help: s.help,
      canUndo: this.pts.length > 0,
      finish: this.step === 3 ? 'Skip' : this.step === 4 ? 'Done' : null,
    };
  }

  canUndo() {
    return this.pts.length > 0;
  }

  click(p) {
    this.pts.push(p);
    if (this.pts.length === BOX_STEPS.length) this.finish();
    else this.app.promptChanged();
  }

  undo() {
    this.pts.pop();
    this.app.promptChanged();
  }

  finish() {
    if (this.pts.length < 3) return;
    const [near, right, left, tnear, tleft] = this.pts;
    const obj = { name: uniqueName(this.app.state.scene, 'box'), base: { near, right, left } };
    if (tnear) obj.top = tleft ? { near: tnear, left: tleft } : { near: tnear };
    this.app.addObject(obj);
  }

  draw(ctx, view) {
    const [near, right, left, tnear, tleft] = this.pts;
    const c = view.cursor;
    const colour = '#5ec8ff';
    const step = this.step;
    // The base corners lie on the lines from the near corner towards the horizontal
    // vanishing points; the tops straight above their corners, towards the vertical one.
    if (step === 1 || step === 2) {
      guide(view, this.app, near, 0);
      guide(view, this.app, near, 1);
    }
    if (step === 3) guide(view, this.app, near, 2);
    if (step === 4) guide(view, this.app, left, 2);
    if (near && right) { view.path([right, near]); view.strokeHalo(colour, 2); }
    if (near && left) { view.path([near, left]); view.strokeHalo(colour, 2); }
    if (near && tnear) { view.path([near, tnear]); view.strokeHalo(colour, 2); }
    if (c) {
      if (step === 1 || step === 2 || step === 3) band(view, near, c, colour);
      if (step === 4) band(view, left, c, colour);
    }
    this.pts.forEach((p) => view.dot(p, 4, colour));
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

  click(p) {
    this.pts.push(p);
    if (this.pts.length < 2) {
      this.app.promptChanged();
      return;
    }
    const [from, to] = this.pts;
    this.app.edit((scene) => {
      scene.scale = { floor_distance: { from, to, meters: this.meters } };
    });
    this.app.endTool();
  }

  undo() {
    this.pts.pop();
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
