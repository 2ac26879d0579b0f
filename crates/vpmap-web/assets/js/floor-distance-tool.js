// The floor-distance tool: two floor points a known distance apart set the scene's scale; two
// base corners of one box joined by an edge make that edge the scale instead.

import { handles } from './scene.js';
import { boxEdgeNames } from './box.js';
import { HIT_PX } from './snap.js';
import { PlacementTool, band, refuseAboveHorizon } from './placement-tool.js';

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
