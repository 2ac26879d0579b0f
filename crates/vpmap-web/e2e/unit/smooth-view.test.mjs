// The smooth planner's pure page logic (smooth-view.js): fields typed, the request's extra
// fields, the tightest turn's mark, the cusps and the row's words.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { arcMidpoint, cuspPoints, headingTowards, parseHeading, parseTurningRadius, pathHeadings, reverseLength, smoothDetail, smoothRequest, tightestTurn, wrapHeading } from '../../assets/js/smooth-view.js';

const near = (a, b, tol = 1e-9) => assert.ok(Math.abs(a - b) <= tol, `${a} vs ${b}`);

test('headings wrap into (-180, 180] and typed ones are read or refused', () => {
  assert.equal(wrapHeading(270), -90);
  assert.equal(wrapHeading(-180), 180);
  assert.equal(wrapHeading(540), 180);
  assert.equal(wrapHeading(-0.04), 0);
  assert.equal(parseHeading(''), null);
  assert.equal(parseHeading('  '), null);
  assert.equal(parseHeading('90°'), 90);
  assert.equal(parseHeading('-450'), -90);
  assert.equal(parseHeading('north'), undefined);
  assert.equal(parseHeading('Infinity'), undefined);
  assert.equal(parseTurningRadius(''), null);
  assert.equal(parseTurningRadius('0.3'), 0.3);
  assert.equal(parseTurningRadius('0'), undefined);
  assert.equal(parseTurningRadius('-1'), undefined);
  assert.equal(parseTurningRadius('1e999'), undefined);
});

test('the heading towards a point is atan2(dy, dx) in map coordinates', () => {
  assert.equal(headingTowards([1, 1], [1, 3]), 90);
  assert.equal(headingTowards([1, 1], [0, 1]), 180);
  assert.equal(headingTowards([0, 0], [1, -1]), -45);
  assert.equal(headingTowards([2, 2], [2, 2]), null);
});

test('a turning radius adds the smooth planner and only the headings that are set', () => {
  const base = ['mbpp', 'optimal'];
  assert.deepEqual(smoothRequest({ turning_radius: null, start_heading: 90 }, base), { planners: base });
  assert.deepEqual(smoothRequest({ turning_radius: 0.3, start_heading: null, goal_heading: null }, base), { planners: [...base, 'smooth'], turning_radius: 0.3 });
  assert.deepEqual(smoothRequest({ turning_radius: 0.3, start_heading: -90, goal_heading: 0 }, base), {
    planners: [...base, 'smooth'], turning_radius: 0.3, start_heading_deg: -90, goal_heading_deg: 0,
  });
  assert.deepEqual(base, ['mbpp', 'optimal']);
});

test('reverse is asked for only when allowed, and only with a turning radius', () => {
  const base = ['optimal'];
  assert.deepEqual(smoothRequest({ turning_radius: 0.5, reverse: true }, base), { planners: ['optimal', 'smooth'], turning_radius: 0.5, reverse: true });
  assert.deepEqual(smoothRequest({ turning_radius: 0.5, reverse: false }, base), { planners: ['optimal', 'smooth'], turning_radius: 0.5 });
  assert.deepEqual(smoothRequest({ turning_radius: null, reverse: true }, base), { planners: ['optimal'] });
});

test('cusps are where the direction changes, at the later segment\'s start', () => {
  const seg = (direction, start, length = 1) => ({ type: 'line', direction, start, length });
  const s = { segments: [seg('forward', [0, 0, 0]), seg('forward', [1, 0, 0]), seg('reverse', [2, 0, 0], 0.5), seg('reverse', [1.5, 0, 0], 0.25), seg('forward', [1.25, 0, 0], 2)] };
  assert.deepEqual(cuspPoints(s), [
    { at: [2, 0], from: 'forward', to: 'reverse' },
    { at: [1.25, 0], from: 'reverse', to: 'forward' },
  ]);
  near(reverseLength(s), 0.75);
  assert.deepEqual(cuspPoints({ segments: [seg('forward', [0, 0, 0]), seg('forward', [1, 0, 0])] }), []);
  assert.deepEqual(cuspPoints(undefined), []);
  assert.equal(reverseLength({ segments: [] }), 0);
  assert.equal(
    smoothDetail({ found: true, max_curvature: 2, min_clearance: 0.1, cusps: 2, segments: s.segments }, 'm'),
    'max curvature 2.00 /m (radius 0.50 m), min clearance 0.10 m, 2 cusps (0.75 m in reverse)',
  );
});

test('the middle of an arc: a quarter circle each way about the origin', () => {
  const s = Math.SQRT1_2;
  // Left: from (1, 0) heading 90 degrees, anticlockwise.
  const left = arcMidpoint({ centre: [0, 0], start: [1, 0, 90], radius: 1, length: Math.PI / 2, turn: 'left', direction: 'forward' });
  near(left[0], s); near(left[1], s);
  // Right: from (0, 1) heading 0, clockwise.
  const right = arcMidpoint({ centre: [0, 0], start: [0, 1, 0], radius: 1, length: Math.PI / 2, turn: 'right', direction: 'forward' });
  near(right[0], s); near(right[1], s);
  // In reverse with the heading growing (left): from (1, 0) heading -90, backing up anticlockwise.
  const back = arcMidpoint({ centre: [0, 0], start: [1, 0, -90], radius: 1, length: Math.PI / 2, turn: 'left', direction: 'reverse' });
  near(back[0], s); near(back[1], s);
  // Off the origin, radius 2, a half circle: the middle is the far side.
  const half = arcMidpoint({ centre: [3, 4], start: [5, 4, 90], radius: 2, length: 2 * Math.PI, turn: 'left', direction: 'forward' });
  near(half[0], 3); near(half[1], 6);
});

test('the tightest turn is the named arc; a line or none marks nothing', () => {
  const arc = { type: 'arc', centre: [0, 0], start: [1, 0, 90], radius: 1, length: 1, turn: 'left' };
  const t = tightestTurn({ segments: [{ type: 'line' }, arc], tightest_turn: 1 });
  assert.equal(t.radius, 1);
  near(Math.hypot(...t.mid), 1);
  assert.equal(tightestTurn({ segments: [{ type: 'line' }], tightest_turn: 0 }), null);
  assert.equal(tightestTurn({ segments: [arc], tightest_turn: null }), null);
  assert.equal(tightestTurn(undefined), null);
});

test('the row says curvature, radius, clearance and cusps; the ends their headings', () => {
  assert.equal(smoothDetail({ found: true, max_curvature: 5, min_clearance: 0.05, cusps: 0 }, 'm'), 'max curvature 5.00 /m (radius 0.20 m), min clearance 0.05 m, 0 cusps');
  assert.equal(smoothDetail({ found: true, max_curvature: 0, min_clearance: 1, cusps: 1 }, 'm'), 'straight, min clearance 1.00 m, 1 cusp');
  assert.equal(smoothDetail({ found: false }, 'm'), '');
  assert.deepEqual(pathHeadings({ smooth: { found: true, poses: [[0, 0, 270], [1, 1, 45]] } }), [-90, 45]);
  assert.deepEqual(pathHeadings({ smooth: { found: false } }), [null, null]);
  assert.deepEqual(pathHeadings(undefined), [null, null]);
});
