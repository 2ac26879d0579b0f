// Plane geometry for drawing and hit testing.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { aboveHorizon, distortPx, lensOf, undistortPx, segmentCorners, intersectSegments, vpPoint, clipLine, distToSegment, pointInPolygon } from '../../assets/js/geometry.js';

const near = (a, b, tol = 1e-9) => assert.ok(a.length === b.length && a.every((v, i) => Math.abs(v - b[i]) <= tol), `${a} != ${b}`);

test('intersectSegments finds the common point of lines through it, in the least-squares sense', () => {
  // Three lines through (3, -2).
  near(intersectSegments([[0, -2, 1, -2], [3, 0, 3, 5], [1, -4, 2, -3]]), [3, -2]);
  // Two nearly parallel lines are refused, as are fewer than two usable segments.
  assert.equal(intersectSegments([[0, 0, 1, 0], [0, 1, 1, 1]]), null);
  assert.equal(intersectSegments([[0, 0, 1, 0], [2, 2, 2, 2]]), null);
  // A third line off by one pulls the answer between the candidates.
  const p = intersectSegments([[0, 0, 1, 0], [0, 0, 0, 1], [0, 1, 1, 1]]);
  near(p, [0, 0.5]);
});

test('vpPoint prefers the point over the lines', () => {
  assert.deepEqual(vpPoint({ point: [7, 8], lines: [[0, 0, 1, 0], [0, 0, 0, 1]] }), [7, 8]);
  near(vpPoint({ lines: [[0, 0, 1, 0], [5, 0, 5, 1]] }), [5, 0]);
  assert.equal(vpPoint(null), null);
  assert.equal(vpPoint({}), null);
});

test('clipLine keeps the part of an infinite line inside a rectangle', () => {
  near(clipLine([0, 5], [1, 5], [0, 0, 10, 10]).flat(), [0, 5, 10, 5]);
  near(clipLine([-5, -5], [-4, -4], [0, 0, 10, 10]).flat(), [0, 0, 10, 10]);
  assert.equal(clipLine([0, 20], [1, 20], [0, 0, 10, 10]), null);
  assert.equal(clipLine([1, 1], [1, 1], [0, 0, 10, 10]), null);
});

test('distToSegment measures to the nearest point of the segment, ends included', () => {
  assert.equal(distToSegment([5, 3], [0, 0], [10, 0]), 3);
  assert.equal(distToSegment([13, 4], [0, 0], [10, 0]), 5);
  assert.equal(distToSegment([3, 4], [0, 0], [0, 0]), 5);
});

test('pointInPolygon, even-odd', () => {
  const square = [[0, 0], [4, 0], [4, 4], [0, 4]];
  assert.equal(pointInPolygon([2, 2], square), true);
  assert.equal(pointInPolygon([5, 2], square), false);
  const u = [[0, 0], [6, 0], [6, 6], [4, 6], [4, 2], [2, 2], [2, 6], [0, 6]];
  assert.equal(pointInPolygon([3, 4], u), false, 'inside the notch of a U');
  assert.equal(pointInPolygon([1, 4], u), true);
});

test('aboveHorizon: positive above the horizon, negative below, whichever way it is given', () => {
  for (const [a, b] of [[[0, 100], [1000, 100]], [[1000, 100], [0, 100]]]) {
    assert.equal(aboveHorizon([500, 40], a, b), 60);
    assert.equal(aboveHorizon([500, 130], a, b), -30);
  }
  // A rolled horizon: 45 degrees, the point straight below its middle.
  assert.ok(Math.abs(aboveHorizon([0, 10], [-10, -10], [10, 10]) + Math.SQRT1_2 * 10) < 1e-9);
  assert.equal(aboveHorizon([0, 0], [1, 1], [1, 1]), null);
});

test('segmentCorners: where edges of different directions meet near their ends', () => {
  const a = [[0, 0, 100, -10]]; // towards A
  const b = [[-1, -0.2, -100, -20], [500, 500, 600, 480]]; // towards B: one meets a's first end, one is far
  const v = [[0.5, 0, 0.5, -80]]; // vertical, from the same corner
  const corners = segmentCorners([a, b, v], 5);
  assert.equal(corners.length, 3);
  for (const c of corners) assert.ok(Math.hypot(c[0], c[1]) < 3, `corner ${c}`);
  assert.deepEqual(segmentCorners([a, b], 0.9), []); // too far from b's end (1.02)
  assert.deepEqual(segmentCorners([a, a], 5).length, 0); // parallel lines do not meet
});

test('a photo\'s lens: the division model of docs/scene-format.md, both ways', () => {
  // 1600 x 1200: half the diagonal is 1000 px; no principal point: the image centre.
  const scene = { image: { width: 1600, height: 1200 }, lens_distortion: { k: -0.1, k_sd: 0.01 } };
  const lens = lensOf(scene);
  near(lens.centre, [800, 600]);
  assert.equal(lens.unit, 1000);
  // The photo's corner (0, 0) lies r = 1 from the centre: its pinhole pixel is c + (p - c) / 0.9.
  near(undistortPx([0, 0], lens), [800 - 800 / 0.9, 600 - 600 / 0.9]);
  // And back: the photo pixel of that pinhole pixel is the corner again.
  near(distortPx([800 - 800 / 0.9, 600 - 600 / 0.9], lens), [0, 0], 1e-9);
  near(distortPx([800, 600], lens), [800, 600]);
  // A given principal point is the centre.
  near(lensOf({ ...scene, principal_point: [790, 610] }).centre, [790, 610]);
  // No lens, k = 0, or no image size: a pinhole, points unchanged.
  assert.equal(lensOf({ image: scene.image }), null);
  assert.equal(lensOf({ ...scene, lens_distortion: { k: 0 } }), null);
  assert.equal(lensOf({ lens_distortion: { k: -0.1 } }), null);
  near(undistortPx([3, 4], null), [3, 4]);
  // Pincushion far out: beyond the lens's reach, no photo pixel.
  assert.equal(distortPx([800 + 5000, 600], lensOf({ ...scene, lens_distortion: { k: 0.5 } })), null);
});
