// The vanishing-point line tool: edges drawn towards one vanishing point (press, drag, release,
// or click both ends), which replace a point given for it.

import { VP_COLOURS, VP_NAMES } from './scene.js';
import { PlacementTool } from './placement-tool.js';

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
