// The select tool of the photo canvas: picks an object or a vanishing-point line by a click and
// drags existing points (Shift: slowly; snapped as snap.js says, Alt: not).
//
// A tool talks to the page through `app` (main.js); this one through `state`, `edit(fn, opts)`,
// `beginDrag()`, `endDrag()`, `select(sel)` and `detachVpPoint(k)`.

import { handles, objectHull, polygonArea, setAt } from './scene.js';
import { distToSegment, pointInPolygon } from './geometry.js';
import { HIT_PX, dragSnap, drawSnap } from './snap.js';
import { dropCovariance, pathKey } from './covariances.js';

/** A drag with Shift held moves the point this many times slower than the pointer (sub-pixel placement at any zoom). */
export const FINE_DRAG = 10;

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
        // Moved by hand: a covariance from snapping no longer describes the point.
        dropCovariance(scene, pathKey(hd.path));
      }
      hd.p = p;
    },
    { live, undo: !live },
  );
}
