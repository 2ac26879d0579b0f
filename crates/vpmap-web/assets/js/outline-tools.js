// The tools that click an outline on the floor corner by corner: a footprint object (its base
// polygon, then optionally the top above one vertex) and the room's floor corners.

import { uniqueName } from './scene.js';
import { h } from './util.js';
import { HIT_PX, cornerSnap, drawSnap } from './snap.js';
import { PlacementTool, band, clearRefusal, guide, refuseAboveHorizon } from './placement-tool.js';
import { PendingCovariances, dropFloor } from './covariances.js';
import { placedTarget, snapPlaced, snapWanted } from './photo-snap.js';

export class FootprintTool extends PlacementTool {
  constructor(app) {
    super(app);
    this.kind = 'footprint';
    this.pts = [];
    this.stage = 'polygon';
    this.above = 0;
    this.covs = new PendingCovariances(); // vertices snapped to the photo (photo-snap.js)
    this.committed = null;
  }

  draft() {
    return { footprint: this.pts };
  }

  draftSet([, k], p) {
    if (this.pts[k]) this.pts[k] = [p[0], p[1]];
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
      if (snapWanted(this.app, e)) snapPlaced(this.app, p, placedTarget(this.app, this, ['footprint', this.pts.length - 1]));
      this.app.promptChanged();
    } else {
      this.commit(p);
      if (snapWanted(this.app, e)) snapPlaced(this.app, p, placedTarget(this.app, this, ['top', 'point']));
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
    if (this.committed) return;
    this.app.addObject(obj, (scene, i) => {
      this.covs.commit(scene, ['objects', i], obj);
      this.committed = { prefix: ['objects', i], name: obj.name };
    });
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
    this.covs = new PendingCovariances(); // corners snapped to the photo (photo-snap.js)
    this.committed = null;
  }

  draft() {
    return { floor: this.pts };
  }

  draftSet([, k], p) {
    if (this.pts[k]) this.pts[k] = [p[0], p[1]];
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
    if (snapWanted(this.app, e)) snapPlaced(this.app, p, placedTarget(this.app, this, ['floor', this.pts.length - 1]));
    this.app.promptChanged();
  }

  undo() {
    this.pts.pop();
    this.app.promptChanged();
  }

  finish() {
    if (this.pts.length < 3 || this.committed) return;
    const pts = this.pts;
    this.app.edit((scene) => {
      scene.floor = pts;
      dropFloor(scene);
      this.covs.commit(scene, [], { floor: pts });
    });
    this.committed = { prefix: [] };
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
