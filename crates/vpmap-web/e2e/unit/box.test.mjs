// Boxes by the corners the user can see (box.js): the box tool's walk through the corners,
// the scene objects it makes, and how the page draws and selects such boxes.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import {
  BOX_STEPS, BoxAnnotation, boxBaseOutline, boxEdges, boxOutline, boxPoints, boxView, convexHull, describeBox, guideLines, guideOffsets, neighbourCorner, offLineThroughLens,
} from '../../assets/js/box.js';
import { lensOf } from '../../assets/js/geometry.js';
import { handles, objectOutline } from '../../assets/js/scene.js';
import { fmtSd } from '../../assets/js/util.js';

test('the old flow (base near, right, left, top near, left, Done) makes the old scene object', () => {
  const box = new BoxAnnotation();
  assert.equal(box.view, 'corner');
  assert.equal(box.canFinish, false);
  for (const p of [[10, 20], [30, 18], [2, 15], [10, 5], [2, 1]]) assert.ok(box.click(p));
  assert.deepEqual(box.current, { part: 'top', corner: 'right' });
  assert.ok(box.canFinish);
  assert.deepEqual(box.object('box 1'), {
    name: 'box 1',
    base: { near: [10, 20], right: [30, 18], left: [2, 15] },
    top: { near: [10, 5], left: [2, 1] },
  });
  // Three base corners only: no top, as before.
  const flat = new BoxAnnotation();
  for (const p of [[10, 20], [30, 18], [2, 15]]) flat.click(p);
  assert.deepEqual(flat.object('b'), { name: 'b', base: { near: [10, 20], right: [30, 18], left: [2, 15] } });
});

test('a face-on box: front base corners, front and back top corners, hidden back base skipped, own yaw', () => {
  const box = new BoxAnnotation();
  assert.ok(box.setView('face'));
  box.ownYaw = true;
  const asked = [];
  for (const p of [[0, 100], [50, 100], [0, 60], [50, 60], [5, 55], [45, 55]]) {
    asked.push(`${box.current.part}.${box.current.corner}`);
    box.click(p);
  }
  assert.deepEqual(asked, ['base.front_left', 'base.front_right', 'top.front_left', 'top.front_right', 'top.back_left', 'top.back_right']);
  assert.ok(box.skip());
  assert.ok(box.skip());
  assert.ok(box.done);
  assert.equal(box.current, null);
  assert.equal(box.click([1, 1]), false, 'no corner is left to click');
  assert.deepEqual(box.object('cupboard'), {
    name: 'cupboard',
    base: { front_left: [0, 100], front_right: [50, 100] },
    top: { front_left: [0, 60], front_right: [50, 60], back_left: [5, 55], back_right: [45, 55] },
    own_yaw: true,
  });
});

test('a skipped hidden corner is asked no more; undo takes back clicks and skips in order', () => {
  const box = new BoxAnnotation();
  box.click([10, 20]);
  box.click([30, 18]);
  box.skip(); // base.left hidden
  assert.deepEqual(box.current, { part: 'top', corner: 'near' });
  box.click([10, 5]);
  assert.equal(box.clicked, 3);
  assert.deepEqual(box.object('x').base, { near: [10, 20], right: [30, 18] });
  assert.ok(box.undo());
  assert.ok(box.undo()); // the skip
  assert.deepEqual(box.current, { part: 'base', corner: 'left' });
  assert.ok(box.undo() && box.undo());
  assert.equal(box.canUndo, false);
  assert.equal(box.undo(), false);
  assert.equal(box.canFinish, false);
});

test('the view is chosen before the first corner only, and must be known', () => {
  const box = new BoxAnnotation();
  box.click([1, 2]);
  assert.equal(box.setView('face'), false);
  assert.equal(box.view, 'corner');
  assert.throws(() => new BoxAnnotation('side'), /unknown box view "side"/);
  // Every view asks for all eight corners once.
  for (const steps of Object.values(BOX_STEPS)) {
    assert.equal(new Set(steps.map((s) => s.join('.'))).size, 8);
  }
});

test('boxPoints, boxView and describeBox read any corners', () => {
  const o = { name: 'bed', base: { near: [0, 0], far: [9, 9] }, top: { left: [1, -5] }, own_yaw: true };
  assert.deepEqual(boxPoints(o).map((x) => `${x.part}.${x.corner}`), ['base.near', 'base.far', 'top.left']);
  assert.equal(boxView(o), 'corner');
  assert.equal(boxView({ base: { back_right: [0, 0] } }), 'face');
  assert.equal(describeBox(o), '2 base + 1 top corner, own yaw');
  assert.equal(describeBox({ base: { front_left: [0, 0], front_right: [1, 0] } }), '2 base corners, no top (face view)');
  assert.equal(describeBox({ base: { near: [0, 0], right: [1, 0], left: [2, 0] }, top: { near: [0, -1], left: [2, -1] } }), '3 base + 2 top corners');
});

test('boxEdges joins corners one grid step apart on a face, and each corner to the one above it', () => {
  const o = { base: { near: [0, 0], right: [4, 1], far: [3, 4] }, top: { near: [0, -3], far: [3, 1] } };
  const key = (e) => `${e.part}:${e.a}-${e.b}`;
  assert.deepEqual(boxEdges(o).map(key).sort(), [
    'base:0,0-4,1', // near-right
    'base:4,1-3,4', // right-far
    'vertical:0,0-0,-3',
    'vertical:3,4-3,1',
  ].sort());
  assert.deepEqual(neighbourCorner(o, 'base', 'left'), [0, 0]);
  assert.equal(neighbourCorner(o, 'top', 'right'), o.top.near);
  assert.equal(neighbourCorner({ base: { front_left: [1, 1] } }, 'base', 'right'), null, 'no neighbour across views');
});

test('the base outline is completed to a parallelogram from any three base corners', () => {
  const near = [0, 0], right = [4, 1], left = [-1, 3], far = [3, 4];
  assert.deepEqual(boxBaseOutline({ base: { near, right, left } }), [near, right, far, left]);
  assert.deepEqual(boxBaseOutline({ base: { right, left, far } }), [near, right, far, left]);
  assert.deepEqual(boxBaseOutline({ base: { near, right, far } }), [near, right, far, left]);
  assert.deepEqual(boxBaseOutline({ base: { near, right } }), []);
  // Fewer base corners: the hull of every corner, for selection.
  const o = { base: { front_left: [0, 10], front_right: [10, 10] }, top: { front_left: [0, 0], front_right: [10, 0] } };
  assert.deepEqual(boxOutline(o), convexHull([[0, 10], [10, 10], [0, 0], [10, 0]]));
  assert.equal(boxOutline(o).length, 4);
  assert.deepEqual(objectOutline(o), boxOutline(o));
  assert.deepEqual(convexHull([[0, 0], [1, 1], [2, 2]]), [], 'collinear points have no outline');
});

test('handles list every named corner of a box, so any of them can be dragged', () => {
  const scene = { objects: [{ name: 'b', base: { front_left: [1, 2], back_right: [3, 4] }, top: { front_right: [5, 6] } }], floor: [], vanishing_points: [] };
  assert.deepEqual(handles(scene).map((x) => x.path.join('.')), ['objects.0.base.front_left', 'objects.0.base.back_right', 'objects.0.top.front_right']);
});

test('fmtSd never shows a small error bar as zero', () => {
  assert.equal(fmtSd(0.0349, 2), '0.03');
  assert.equal(fmtSd(0.004, 2), '<0.01');
  assert.equal(fmtSd(0.04, 1), '<0.1');
  assert.equal(fmtSd(0, 2), '0.00');
  assert.equal(fmtSd(Number.NaN, 2), '–');
});

test('a box names its edges for scale.edge, and the form value round-trips', async () => {
  const { boxEdgeNames, edgeChoice, parseEdgeChoice } = await import('../../assets/js/box.js');
  const o = { base: { near: [0, 0], right: [4, 1], left: [-1, 3] }, top: { near: [0, -3] } };
  assert.deepEqual(boxEdgeNames(o).map((e) => `${e.a} ${e.b} ${e.part}`), [
    'base.near base.right base', 'base.near base.left base', 'base.near top.near vertical',
  ]);
  const v = edgeChoice(['base.near', 'top.near']);
  assert.equal(v, 'edge:base.near,top.near');
  assert.deepEqual(parseEdgeChoice(v), ['base.near', 'top.near']);
  assert.equal(parseEdgeChoice('length'), null);
  assert.equal(parseEdgeChoice('edge:base.near'), null);
});

test('guideOffsets: how far base corners are from the lines from the near corner, and tops from the vertical', () => {
  // Near at the origin; A up right, B up left; V straight down far away. Right 3 px off the
  // line towards A, left on the line towards B, top near 0.5 px off the vertical.
  const vps = [[1000, -200], [-1000, -300], [0, 100000]];
  const n = [200 / Math.hypot(1000, 200), 1000 / Math.hypot(1000, 200)];
  const o = { name: 'b', base: { near: [0, 0], right: [100 + 3 * n[0], -20 + 3 * n[1]], left: [-100, -30] }, top: { near: [0.5, -50] } };
  const g = Object.fromEntries(guideOffsets(o, vps).map((x) => [`${x.part}.${x.corner}`, x]));
  assert.equal(g['base.right'].vp, 0);
  assert.ok(Math.abs(g['base.right'].px - 3) < 1e-9);
  assert.ok(Math.hypot(g['base.right'].foot[0] - 100, g['base.right'].foot[1] + 20) < 1e-9);
  assert.equal(g['base.left'].vp, 1);
  assert.ok(g['base.left'].px < 1e-9);
  assert.ok(Math.abs(g['top.near'].px - 0.5) < 1e-3);
  // Own yaw: the base edges need not run to the room's vanishing points.
  assert.equal(guideOffsets({ ...o, own_yaw: true }, vps).filter((x) => x.part === 'base').length, 0);
  // No vanishing points known: nothing to say.
  assert.deepEqual(guideOffsets(o, [null, null, null]), []);
});

test('guideLines: base corners next to the anchor run towards A or B, top corners up the vertical', () => {
  const vps = [[1000, -200], [-1000, -300], [0, 100000]];
  const o = { base: { near: [0, 0] } };
  assert.deepEqual(guideLines(o, 'base', 'right', vps).map((g) => g.vp), [0, 1]);
  assert.deepEqual(guideLines(o, 'base', 'right', vps, true), []); // own yaw
  assert.deepEqual(guideLines(o, 'base', 'far', vps), []); // diagonal to near
  assert.deepEqual(guideLines(o, 'top', 'near', vps), [{ from: [0, 0], vp: 2 }]);
  assert.deepEqual(guideLines(o, 'top', 'left', vps), []); // no base.left yet
  assert.deepEqual(guideLines({}, 'base', 'right', vps), []);
});

test('on a photo with a lens, corners on their pinhole lines are on their lines, and one off is off by what the photo shows', () => {
  // The division model written out (docs/scene-format.md), not taken from geometry.js.
  const C = [800, 600], H = 1000, K = -0.12;
  const toPhoto = (q) => {
    const d = [q[0] - C[0], q[1] - C[1]];
    const ru = Math.hypot(d[0], d[1]) / H;
    let lo = 0, hi = ru;
    for (let i = 0; i < 200; i += 1) {
      const mid = (lo + hi) / 2;
      if (mid / (1 + K * mid * mid) < ru) lo = mid; else hi = mid;
    }
    const r = (lo + hi) / 2;
    return ru === 0 ? q : [C[0] + d[0] * (r / ru), C[1] + d[1] * (r / ru)];
  };
  const lens = lensOf({ image: { width: 1600, height: 1200 }, lens_distortion: { k: K } });
  const vps = [[5200, 760], [-2600, 420], [820, 40000]]; // pinhole
  const along = (a, v, t) => [a[0] + t * (v[0] - a[0]), a[1] + t * (v[1] - a[1])];
  const nearU = [250, 1050];
  const rightU = along(nearU, vps[0], 0.22);
  const topU = along(nearU, vps[2], -0.018); // up the vertical
  const o = { base: { near: toPhoto(nearU), right: toPhoto(rightU) }, top: { near: toPhoto(topU) } };
  const through = guideOffsets(o, vps, lens);
  assert.equal(through.length, 2);
  for (const g of through) assert.ok(g.px < 1e-6, `${g.part}.${g.corner} ${g.px} px`);
  // Measured straight on the photo, the bowed edge puts the right corner off its line.
  const straight = guideOffsets(o, vps).find((g) => g.corner === 'right');
  assert.ok(straight.px > 2, `${straight.px} px`);
  // A corner 3 px (photo pixels) across the line is 3 px off, its foot on the line.
  const r = offLineThroughLens([o.base.right[0], o.base.right[1] - 3], o.base.near, vps[0], lens);
  assert.ok(Math.abs(r.px - 3) < 0.05, `${r.px}`);
  assert.ok(Math.hypot(r.foot[0] - o.base.right[0], r.foot[1] - o.base.right[1]) < 0.05);
});
