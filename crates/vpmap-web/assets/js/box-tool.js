// The box tool: a box placed by the corners the user can see, in the corner or the face view
// (box.js holds the walk through the corners; this file its prompt, clicks and drawing).

import { resolvedVps, uniqueName } from './scene.js';
import { h } from './util.js';
import { BOX_STEPS, BoxAnnotation, CORNER_HELP, boxEdges, boxPoints, cornerWords, guideLines, neighbourCorner, offLineThroughLens } from './box.js';
import { lensOf } from './geometry.js';
import { SNAP_PX, cornerSnap, drawSnap } from './snap.js';
import { PlacementTool, band, clearRefusal, guide, refuseAboveHorizon } from './placement-tool.js';
import { PendingCovariances } from './covariances.js';
import { placedTarget, snapPlaced, snapWanted } from './photo-snap.js';

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
    this.covs = new PendingCovariances(); // corners snapped to the photo (photo-snap.js)
    this.committed = null; // {prefix: ['objects', i], name} once added
  }

  /** The box as it stands (photo-snap.js placedTarget). */
  draft() {
    return this.box.partial;
  }

  /** Move the clicked corner at `rel` (`[part, corner]`) to `p`. */
  draftSet([part, corner], p) {
    const h = this.box.history.find((x) => x.part === part && x.corner === corner && x.p);
    if (h) h.p = [p[0], p[1]];
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
    const lens = lensOf(this.app.state.scene);
    let best = null;
    for (const g of guideLines(this.box.partial, c.part, c.corner, vps, this.box.ownYaw)) {
      const r = offLineThroughLens(p, g.from, vps[g.vp], lens);
      if (r && r.px * view.s <= SNAP_PX && (!best || r.px < best.r.px)) best = { r, g };
    }
    if (best) return { p: best.r.foot, line: best.g, snapped: true };
    return { ...cornerSnap(this.app, p, view, free), line: null };
  }

  click(p, e, view) {
    if (this.box.current?.part === 'base' && refuseAboveHorizon(this.app, p)) return;
    clearRefusal(this.app);
    p = this.snapped(p, view, !!e?.altKey).p;
    const c = this.box.current;
    if (!this.box.click(p)) return;
    // The point is placed now; the photo may move it to its corner when the answer comes.
    if (c && snapWanted(this.app, e)) snapPlaced(this.app, p, placedTarget(this.app, this, [c.part, c.corner]));
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
    if (!this.box.canFinish || this.committed) return;
    const obj = this.box.object(uniqueName(this.app.state.scene, 'box'));
    this.app.addObject(obj, (scene, i) => {
      this.covs.commit(scene, ['objects', i], obj);
      this.committed = { prefix: ['objects', i], name: obj.name };
    });
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
