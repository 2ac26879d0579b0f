// Snapped clicks' covariances (covariances.js, photo-snap.js): the scene's
// click_covariances_px2 table follows its points through snapping, moves, removals and undo.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { COV_FIELD, PendingCovariances, dropCovariance, dropFloor, objectRemoved, pathKey, setCovariance } from '../../assets/js/covariances.js';
import { knownVps, placedTarget, snapRequest, withLens } from '../../assets/js/photo-snap.js';
import { BoxAnnotation, guideLines, offLine } from '../../assets/js/box.js';
import { History } from '../../assets/js/state.js';
import { setAt } from '../../assets/js/scene.js';

const C = [[0.04, 0.01], [0.01, 0.05]];

function scene() {
  return {
    version: 1,
    image: { width: 100, height: 80 },
    vanishing_points: [{ point: [-500, 10] }, { point: [600, 12] }, { point: [50, 4000] }],
    objects: [{ name: 'a', base: { near: [10, 20] } }, { name: 'b', footprint: [[1, 2], [3, 4], [5, 6]], top: { above: 0, point: [1, 0] } }],
    floor: [[0, 70], [90, 70], [50, 40]],
  };
}

test('field paths are the scene reader\'s', () => {
  assert.equal(pathKey(['objects', 0, 'base', 'near']), 'objects[0].base.near');
  assert.equal(pathKey(['objects', 1, 'footprint', 2]), 'objects[1].footprint[2]');
  assert.equal(pathKey(['objects', 1, 'top', 'point']), 'objects[1].top.point');
  assert.equal(pathKey(['floor', 3]), 'floor[3]');
});

test('a point moved by hand loses its covariance; undo brings back both', () => {
  const history = new History();
  let s = scene();
  setCovariance(s, 'objects[0].base.near', C);
  setCovariance(s, 'floor[1]', [[0.02, 0.0], [1e-17, 0.03]]);
  assert.deepEqual(s[COV_FIELD]['floor[1]'], [[0.02, 5e-18], [5e-18, 0.03]], 'made exactly symmetric');
  // A drag: the undo step records the scene before it (main.js beginDrag), then the move.
  history.record(s);
  const path = ['objects', 0, 'base', 'near'];
  setAt(s, path, [12, 21]);
  dropCovariance(s, pathKey(path));
  assert.deepEqual(Object.keys(s[COV_FIELD]), ['floor[1]']);
  s = history.undo(s);
  assert.deepEqual(s.objects[0].base.near, [10, 20]);
  assert.deepEqual(s[COV_FIELD]['objects[0].base.near'], C);
  // The last entry gone: the table goes too.
  dropCovariance(s, 'objects[0].base.near');
  dropFloor(s);
  assert.equal(COV_FIELD in s, false);
});

test('removing an object drops its entries and renumbers those after it', () => {
  const s = scene();
  s.objects.push({ name: 'c', base: { near: [4, 4] } });
  setCovariance(s, 'objects[0].base.near', C);
  setCovariance(s, 'objects[1].footprint[2]', C);
  setCovariance(s, 'objects[2].base.near', C);
  setCovariance(s, 'floor[0]', C);
  s.objects.splice(1, 1);
  objectRemoved(s, 1);
  assert.deepEqual(Object.keys(s[COV_FIELD]).sort(), ['floor[0]', 'objects[0].base.near', 'objects[1].base.near']);
  s.objects.splice(0, 2);
  objectRemoved(s, 0);
  objectRemoved(s, 0);
  assert.deepEqual(Object.keys(s[COV_FIELD]), ['floor[0]']);
});

/** A page of one scene, enough for placedTarget: edits apply at once. */
function fakeApp(s) {
  const app = { state: { scene: s }, renders: 0, edits: 0 };
  app.requestRender = () => app.renders++;
  app.edit = (fn) => {
    app.edits++;
    fn(app.state.scene);
  };
  return app;
}

/** The box tool's bookkeeping (box-tool.js): a draft box, its pending covariances, its commit. */
function fakeBoxTool() {
  const box = new BoxAnnotation();
  return {
    box,
    covs: new PendingCovariances(),
    committed: null,
    draft: () => box.partial,
    draftSet([part, corner], p) {
      const h = box.history.find((x) => x.part === part && x.corner === corner && x.p);
      if (h) h.p = [p[0], p[1]];
    },
  };
}

test('a corner snapped while the box is drawn keeps its covariance into the scene; one taken back does not', () => {
  const s = scene();
  const app = fakeApp(s);
  const tool = fakeBoxTool();
  tool.box.click([40, 50]);
  const near = placedTarget(app, tool, ['base', 'near']);
  assert.deepEqual(near.get(), [40, 50]);
  near.set([41.2, 49.5], C); // the answer arrives
  assert.deepEqual(tool.box.partial.base.near, [41.2, 49.5]);
  tool.box.click([70, 52]);
  placedTarget(app, tool, ['base', 'right']).set([70.5, 52.5], C);
  tool.box.undo(); // the right corner taken back, and clicked again elsewhere without snapping
  tool.box.click([72, 53]);
  const obj = { name: 'box 1', ...tool.box.object('box 1') };
  s.objects.push(obj);
  tool.covs.commit(s, ['objects', 2], obj);
  tool.committed = { prefix: ['objects', 2], name: 'box 1' };
  assert.deepEqual(Object.keys(s[COV_FIELD]), ['objects[2].base.near']);
  // An answer after the box was added edits the scene, if the point is still where it was.
  const late = placedTarget(app, tool, ['base', 'right']);
  assert.deepEqual(late.get(), [72, 53]);
  late.set([72.4, 53.1], C);
  assert.deepEqual(s.objects[2].base.right, [72.4, 53.1]);
  assert.deepEqual(s[COV_FIELD]['objects[2].base.right'], C);
  // The box removed: a late answer changes nothing.
  s.objects.pop();
  objectRemoved(s, 2);
  assert.equal(late.get(), null);
  late.set([1, 1], C);
  assert.equal(s[COV_FIELD], undefined);
});

test('the next corner slides along the guide lines from the corners placed', () => {
  const vps = [[-500, 10], [600, 12], [50, 4000]];
  const o = { base: { near: [50, 60] } };
  const lines = guideLines(o, 'base', 'right', vps);
  assert.deepEqual(lines.map((g) => g.vp), [0, 1]);
  // A click 2 px off the line towards B lands on it.
  const onB = [50 + 0.8 * (600 - 50), 60 + 0.8 * (12 - 60)];
  const click = [onB[0] + 2 * 0.0869, onB[1] + 2 * 0.9962];
  const r = offLine(click, lines[1].from, vps[1]);
  assert.ok(Math.abs(r.px - 2) < 0.01, `${r.px}`);
  assert.ok(Math.hypot(r.foot[0] - onB[0], r.foot[1] - onB[1]) < 0.01);
  // The top corner: up the vertical through its base corner.
  assert.deepEqual(guideLines(o, 'top', 'near', vps), [{ from: [50, 60], vp: 2 }]);
});

test('the vanishing points sent for snapping: the known ones up to the first unknown', () => {
  assert.deepEqual(knownVps(scene()), [[-500, 10], [600, 12], [50, 4000]]);
  const s = scene();
  s.vanishing_points = [{ point: [1, 2] }, { lines: [] }, { point: [3, 4] }];
  assert.deepEqual(knownVps(s), [[1, 2]]);
});

test('a snap request carries the photo\'s lens and its centre, and nothing of a lens without one', () => {
  const plain = snapRequest(scene(), 'p1', [10, 20], 1.5);
  assert.deepEqual(plain, { photo: 'p1', click: [10, 20], vanishing_points: [[-500, 10], [600, 12], [50, 4000]], click_sigma: 1.5 });
  const s = scene();
  s.lens_distortion = { k: -0.12, k_sd: 0.01 };
  const lensed = snapRequest(s, 'p1', [10, 20]);
  assert.deepEqual(lensed.lens_distortion, { k: -0.12 });
  assert.deepEqual(lensed.principal_point, [50, 40], 'the image centre without a principal point');
  s.principal_point = [48, 41];
  assert.deepEqual(snapRequest(s, 'p1', [10, 20]).principal_point, [48, 41]);
  s.lens_distortion = { k: 0 };
  assert.equal(snapRequest(s, 'p1', [10, 20]).lens_distortion, undefined, 'k = 0 is a pinhole');
});

test('a propose request carries the lens too', () => {
  const s = scene();
  assert.deepEqual(withLens(s, { photo: 'p1' }), { photo: 'p1' });
  s.lens_distortion = { k: -0.1 };
  assert.deepEqual(withLens(s, { photo: 'p1' }), { photo: 'p1', lens_distortion: { k: -0.1 }, principal_point: [50, 40] });
});
