// Plane geometry for drawing and hit testing.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { aboveHorizon, distortPx, lensOf, lineThroughLens, pinholeVp, undistortPx, segmentCorners, intersectSegments, vpPoint, clipLine, distToSegment, pointInPolygon } from '../../assets/js/geometry.js';

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

// The division model written out here, not taken from geometry.js: photo pixel p -> pinhole
// c + (p - c) / (1 + k r^2), r = |p - c| / h (docs/scene-format.md); its inverse by bisection on
// the photo radius.
const LENS_SCENE = { image: { width: 1600, height: 1200 }, lens_distortion: { k: -0.1 } };
const C = [800, 600], H = 1000, K = -0.1;
const toPinhole = (p) => {
  const d = [p[0] - C[0], p[1] - C[1]];
  const s = 1 + K * (d[0] * d[0] + d[1] * d[1]) / (H * H);
  return [C[0] + d[0] / s, C[1] + d[1] / s];
};
const toPhoto = (q) => {
  const d = [q[0] - C[0], q[1] - C[1]];
  const ru = Math.hypot(d[0], d[1]) / H;
  if (ru === 0) return q;
  // r / (1 + K r^2) = ru, r in [0, ru] for barrel (K < 0: the photo radius is the smaller).
  let lo = 0, hi = ru;
  for (let i = 0; i < 200; i += 1) {
    const mid = (lo + hi) / 2;
    if (mid / (1 + K * mid * mid) < ru) lo = mid; else hi = mid;
  }
  const r = (lo + hi) / 2;
  return [C[0] + d[0] * (r / ru), C[1] + d[1] * (r / ru)];
};
const offPinholeLine = (p, a, v) => {
  // Distance of pinhole point p from the line through a and v.
  const d = [v[0] - a[0], v[1] - a[1]];
  return Math.abs((p[0] - a[0]) * d[1] - (p[1] - a[1]) * d[0]) / Math.hypot(d[0], d[1]);
};

test('a guide line through a lens: every point is on the straight pinhole line, drawn where the photo shows it', () => {
  const lens = lensOf(LENS_SCENE);
  const vp = [5200, 760]; // pinhole
  const from = toPhoto([300, 1000]);
  const pts = lineThroughLens(from, vp, lens, 600, 32);
  assert.equal(pts.length, 33);
  const a = toPinhole(from);
  for (const q of pts) assert.ok(offPinholeLine(toPinhole(q), a, vp) < 1e-6, `${q}`);
  // It runs 600 pinhole px both ways from the corner.
  near(toPinhole(pts[0]), [a[0] - 600 * (vp[0] - a[0]) / Math.hypot(vp[0] - a[0], vp[1] - a[1]), a[1] - 600 * (vp[1] - a[1]) / Math.hypot(vp[0] - a[0], vp[1] - a[1])], 1e-6);
  // The photo shows it bowed: its middle lies off the chord between its ends.
  const mid = pts[16], chord = offPinholeLine(mid, pts[0], pts[32]);
  assert.ok(chord > 3, `bow ${chord} px`);
  // No lens: the two ends of the straight line, not past the vanishing point.
  const plain = lineThroughLens([0, 0], [100, 0], null, 600);
  near(plain[0], [-600, 0]);
  near(plain[1], [100, 0]);
  // From the vanishing point itself (as the photo shows it): no line.
  assert.equal(lineThroughLens(toPhoto([900, 700]), [900, 700], lens, 10), null);
});

test('a vanishing point given as lines through a lens is where their pinhole lines meet', () => {
  const lens = lensOf(LENS_SCENE);
  const vp = [-2600, 420]; // pinhole
  // Two scene edges towards it, clicked on the photo: their ends are photo pixels.
  const seg = (a, t) => {
    const b = [a[0] + t * (vp[0] - a[0]), a[1] + t * (vp[1] - a[1])];
    const [pa, pb] = [toPhoto(a), toPhoto(b)];
    return [pa[0], pa[1], pb[0], pb[1]];
  };
  const entry = { lines: [seg([1500, 1100], 0.2), seg([1400, 150], 0.2)] };
  near(pinholeVp(entry, lens), vp, 1e-6);
  // Intersected as photo pixels, the bowed edges' chords meet elsewhere.
  const raw = vpPoint(entry);
  assert.ok(Math.hypot(raw[0] - vp[0], raw[1] - vp[1]) > 50, `${raw}`);
  // Without a lens, or a point (the pinhole camera's already): as vpPoint.
  near(pinholeVp(entry, null), raw);
  near(pinholeVp({ point: [1, 2] }, lens), [1, 2]);
});
