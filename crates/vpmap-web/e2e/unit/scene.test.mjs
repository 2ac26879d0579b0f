// Scene editing helpers: the scene file as the page keeps it.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import {
  emptyScene, normaliseScene, vpUsable, buildBlocker, uniqueName, getAt, setAt, handles, objectOutline, segmentOwners, cloneScene, resolvedVps, messagePoint, objectHull, polygonArea,
} from '../../assets/js/scene.js';
import { pointInPolygon } from '../../assets/js/geometry.js';

const lines = (n) => Array.from({ length: n }, (_, i) => [0, i, 10, i + 1]);

test('an empty scene can be saved but not built', () => {
  const s = emptyScene(640, 480);
  assert.deepEqual(s, { version: 1, image: { width: 640, height: 480 }, vanishing_points: [{ lines: [] }, { lines: [] }], objects: [], floor: [] });
  assert.equal(normaliseScene(s), null);
  assert.match(buildBlocker(s), /Horizontal A vanishing point/);
  assert.equal(buildBlocker(null), 'open a photo or a scene');
});

test('normaliseScene rejects what is not a scene and fills in the lists', () => {
  assert.match(normaliseScene([]), /not a JSON object/);
  assert.match(normaliseScene({ version: 2, image: { width: 1, height: 1 } }), /unsupported scene version 2/);
  assert.match(normaliseScene({ version: 1, image: { width: 0, height: 1 } }), /no valid `image`/);
  assert.match(normaliseScene({ version: 1, image: { width: 1, height: 1 }, vanishing_points: [{ lines: 3 }] }), /must be a list/);
  const s = { version: 1, image: { width: 4, height: 3 }, extra: 'kept' };
  assert.equal(normaliseScene(s), null);
  assert.deepEqual(s.vanishing_points, [{ lines: [] }, { lines: [] }]);
  assert.deepEqual(s.objects, []);
  assert.deepEqual(s.floor, []);
  assert.equal(s.extra, 'kept', 'unknown fields survive');
});

test('a vanishing point is usable with a point or two lines; buildBlocker names what is missing', () => {
  assert.equal(vpUsable({ lines: lines(1) }), false);
  assert.equal(vpUsable({ lines: lines(2) }), true);
  assert.equal(vpUsable({ point: [1, 2], lines: [] }), true);
  assert.equal(vpUsable({ direction: [0, 1] }), true, 'a vertical at infinity (a level camera)');
  assert.equal(vpUsable(undefined), false);
  const s = emptyScene(100, 100);
  s.vanishing_points = [{ point: [-500, 50] }, { lines: lines(1) }];
  assert.match(buildBlocker(s), /^Horizontal B vanishing point/);
  s.vanishing_points[1].lines = lines(2);
  assert.equal(buildBlocker(s), null);
  s.vanishing_points.push({ lines: [] });
  assert.match(buildBlocker(s), /^Vertical vanishing point/);
  s.vanishing_points.length = 2;
  s.floor = [[0, 0], [1, 1]];
  assert.equal(buildBlocker(s), 'the floor needs at least 3 corners');
  s.floor.push([2, 0]);
  assert.equal(buildBlocker(s), null);
});

test('uniqueName skips the names in use', () => {
  const s = emptyScene(1, 1);
  assert.equal(uniqueName(s, 'box'), 'box 1');
  s.objects.push({ name: 'box 1' }, { name: 'box 3' });
  assert.equal(uniqueName(s, 'box'), 'box 2');
});

test('getAt and setAt follow a path of keys', () => {
  const o = { a: [{ b: 1 }] };
  assert.equal(getAt(o, ['a', 0, 'b']), 1);
  assert.equal(getAt(o, ['x', 0, 'b']), undefined);
  setAt(o, ['a', 0, 'b'], 2);
  assert.deepEqual(o, { a: [{ b: 2 }] });
});

test('handles lists every draggable point with the path that moves it', () => {
  const s = emptyScene(100, 100);
  s.objects.push({ name: 'box 1', base: { near: [1, 2], right: [3, 4], left: [5, 6] }, top: { near: [1, 0] } });
  s.objects.push({ name: 'fp 1', footprint: [[0, 0], [1, 0], [1, 1]] });
  s.floor = [[9, 9]];
  s.vanishing_points[0].lines = [[0, 1, 2, 3]];
  const hs = handles(s);
  assert.deepEqual(hs.map((h) => h.path.join('.')), [
    'objects.0.base.near', 'objects.0.base.right', 'objects.0.base.left', 'objects.0.top.near',
    'objects.1.footprint.0', 'objects.1.footprint.1', 'objects.1.footprint.2',
    'floor.0',
    'vanishing_points.0.lines.0', 'vanishing_points.0.lines.0',
  ]);
  for (const h of hs.filter((x) => x.end === undefined)) assert.deepEqual(getAt(s, h.path), h.p);
  assert.deepEqual(hs.slice(-2).map((h) => [h.end, h.p]), [[0, [0, 1]], [1, [2, 3]]]);
  assert.deepEqual(handles(null), []);
});

test('objectOutline completes a box base to a parallelogram', () => {
  assert.deepEqual(objectOutline({ base: { near: [0, 0], right: [4, 1], left: [-1, 3] } }), [[0, 0], [4, 1], [3, 4], [-1, 3]]);
  assert.deepEqual(objectOutline({ footprint: [[1, 1], [2, 2], [3, 1]] }), [[1, 1], [2, 2], [3, 1]]);
  assert.deepEqual(objectOutline({ base: { near: [0, 0] } }), []);
});

test('segmentOwners maps detected segments to the scene vanishing point in the same direction', () => {
  const s = emptyScene(200, 100); // principal point (100, 50)
  // The scene lists its horizontal points in the other order than the detector.
  s.vanishing_points = [{ point: [1100, 60] }, { point: [-400, 600] }, { point: [100, 5000] }];
  const res = {
    segments: [[0, 0, 1, 1], [0, 0, 1, 1], [0, 0, 1, 1], [0, 0, 1, 1], [0, 0, 1, 1]],
    vanishing_points: [
      { point: [-800, 900], segments: [0, 1] },
      { point: [2000, 70], segments: [2] },
      { point: [90, 9000], vertical: true, segments: [3, 99] },
    ],
  };
  assert.deepEqual(segmentOwners(res, s), [1, 1, 0, 2, -1]);
});

test('cloneScene and resolvedVps', () => {
  const s = emptyScene(10, 10);
  s.vanishing_points = [{ point: [1, 2] }, { lines: [[0, 0, 1, 0], [0, 1, 1, 2]] }];
  const c = cloneScene(s);
  c.vanishing_points[0].point[0] = 5;
  assert.equal(s.vanishing_points[0].point[0], 1);
  assert.equal(cloneScene(null), null);
  const vps = resolvedVps(s);
  assert.deepEqual(vps[0], [1, 2]);
  assert.ok(Math.abs(vps[1][0] - -1) < 1e-9 && Math.abs(vps[1][1]) < 1e-9, String(vps[1]));
});

test('messagePoint finds the scene point a server message names', () => {
  const s = emptyScene(100, 100);
  s.floor = [[1, 2], [3, 4], [5, 6]];
  s.objects = [{ name: 'b', base: { near: [7, 8] }, top: { near: [7, 1] } }, { name: 'f', footprint: [[1, 1], [2, 2], [3, 1]], top: { above: 0, point: [1, 0] } }];
  assert.deepEqual(messagePoint('scene: `floor[2]` at (5, 6) is 3 px above the horizon', s), { path: ['floor', 2], p: [5, 6], note: null });
  assert.deepEqual(messagePoint('`objects[0].base.near` lies ...', s), { path: ['objects', 0, 'base', 'near'], p: [7, 8], note: null });
  assert.deepEqual(messagePoint('x `objects[1].footprint[1]` y', s), { path: ['objects', 1, 'footprint', 1], p: [2, 2], note: null });
  assert.deepEqual(messagePoint('`objects[1].top.point`', s), { path: ['objects', 1, 'top', 'point'], p: [1, 0], note: null });
  assert.deepEqual(messagePoint('degenerate geometry at `objects[1]`: add `base.far`', s), { path: ['objects', 1], object: 1, note: 'add base.far' });
  assert.deepEqual(messagePoint('field `objects[0].base` is invalid: add `base.left` (or `top.left`)', s), { path: ['objects', 0], object: 0, note: 'add base.left' });
  assert.equal(messagePoint('`floor[9]` is missing', s), null);
  assert.equal(messagePoint('no field here', s), null);
});

test('objectHull covers a box\'s faces and a footprint\'s top, for selecting by a click inside', () => {
  const box = { name: 'b', base: { near: [10, 100], right: [30, 90], left: [0, 90] }, top: { near: [10, 40], left: [0, 35] } };
  const hull = objectHull(box);
  assert.ok(pointInPolygon([8, 60], hull)); // on the face between base and top
  assert.ok(!pointInPolygon([8, 60], objectOutline(box)));
  assert.equal(polygonArea([[0, 0], [2, 0], [2, 3], [0, 3]]), 6);
  const fp = { name: 'f', footprint: [[0, 10], [10, 10], [5, 12]], top: { above: 0, point: [0, 0] } };
  assert.ok(pointInPolygon([2, 5], objectHull(fp)));
});
