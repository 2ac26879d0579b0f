// The floor plan's map-to-picture transform, read from the SVG's data-svg-from-map attribute.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { parseAffine, applyAffine, invertAffine, composeAffine, occupancyToSvg } from '../../assets/js/geometry.js';
import { svgFromMap, SVG_FROM_MAP_ATTR } from '../../assets/js/plan-view.js';

const near = (a, b, tol = 1e-9) => assert.ok(a.length === b.length && a.every((v, i) => Math.abs(v - b[i]) <= tol), `${a} != ${b}`);

/** A parsed SVG document as far as `svgFromMap` looks at it. */
const fakeDoc = (attrs) => ({
  documentElement: {
    hasAttribute: (k) => Object.hasOwn(attrs, k),
    getAttribute: (k) => (Object.hasOwn(attrs, k) ? attrs[k] : null),
  },
});

test('parseAffine reads "a b c d e f" in SVG matrix order', () => {
  // What vpmap-render writes: s 0 0 -s e f (one scale, y up the page).
  const m = parseAffine('80 0 0 -80 412.5 730.25');
  assert.deepEqual(m, { a: 80, b: 0, c: 0, d: -80, e: 412.5, f: 730.25 });
  near(applyAffine(m, [0, 0]), [412.5, 730.25]);
  near(applyAffine(m, [1, 2]), [492.5, 570.25]);
  // Commas, extra spaces and exponents are fine; a rotation is as good as a scale.
  assert.deepEqual(parseAffine(' 0,1, -1 0  1e2 -2.5 '), { a: 0, b: 1, c: -1, d: 0, e: 100, f: -2.5 });
});

test('parseAffine refuses what is not six finite numbers of an invertible transform', () => {
  for (const bad of [null, undefined, '', '1 0 0 1 0', '1 0 0 1 0 0 0', '1 0 0 1 0 x', '1 0 0 1 0 NaN', '1 0 0 1 Infinity 0', '1 2 2 4 0 0', '0 0 0 0 1 1']) {
    assert.equal(parseAffine(bad), null, String(bad));
  }
});

test('invertAffine undoes the transform, composeAffine applies right then left', () => {
  const m = { a: 2, b: 0.5, c: -1, d: 3, e: 7, f: -4 };
  const inv = invertAffine(m);
  for (const p of [[0, 0], [1, -2], [123.4, 56.7]]) {
    near(applyAffine(inv, applyAffine(m, p)), p);
    near(applyAffine(m, applyAffine(inv, p)), p);
  }
  const n = { a: 1, b: 0, c: 0, d: -1, e: 5, f: 9 };
  const p = [3, 4];
  near(applyAffine(composeAffine(m, n), p), applyAffine(m, applyAffine(n, p)));
  assert.equal(invertAffine({ a: 1, b: 2, c: 2, d: 4, e: 0, f: 0 }), null);
});

test('occupancyToSvg puts the grid image where its cells are on the map', () => {
  const m = parseAffine('80 0 0 -80 400 700');
  const grid = { width: 40, height: 30, resolution: 0.05, origin: [-1, -0.5] };
  const img = occupancyToSvg(m, grid);
  // The image's top-left pixel corner is the grid's top-left: (origin x, origin y + height).
  near(applyAffine(img, [0, 0]), applyAffine(m, [-1, 1]));
  // Its bottom-right pixel corner is (origin x + width, origin y).
  near(applyAffine(img, [40, 30]), applyAffine(m, [1, -0.5]));
  // The centre of pixel (column 3, row 0) is the centre of the top row's fourth cell.
  near(applyAffine(img, [3.5, 0.5]), applyAffine(m, [-1 + 3.5 * 0.05, 1 - 0.5 * 0.05]));
});

test('svgFromMap reads the root element and refuses a plan without the attribute', () => {
  assert.equal(SVG_FROM_MAP_ATTR, 'data-svg-from-map');
  assert.deepEqual(svgFromMap(fakeDoc({ 'data-svg-from-map': '10 0 0 -10 5 6' })), { a: 10, b: 0, c: 0, d: -10, e: 5, f: 6 });
  assert.throws(() => svgFromMap(fakeDoc({})), /has no data-svg-from-map attribute/);
  assert.throws(() => svgFromMap(fakeDoc({ 'data-svg-from-map': '1 2 3' })), /"1 2 3" is not an invertible transform/);
});
