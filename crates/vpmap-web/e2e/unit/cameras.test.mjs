// The room's cameras on the floor plan (plan-cameras.js) and in the 3D view (model-cameras.js),
// checked against a camera built here from its heading and pitch (an independent pinhole).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { cameraOnFloor, floorDirection } from '../../assets/js/plan-cameras.js';
import { frustumSegments, toGltf } from '../../assets/js/model-cameras.js';

const close = (a, b, eps = 1e-9) => a.every((v, i) => Math.abs(v - b[i]) < eps);

/** Map-from-camera rotation (OpenCV camera: x right, y down, z forward) of a camera turned `headingDeg` counter-clockwise from +y and pitched `pitchDeg` down. */
function rotation(headingDeg, pitchDeg) {
  const h = (headingDeg * Math.PI) / 180, p = (pitchDeg * Math.PI) / 180;
  const fwd = [-Math.sin(h) * Math.cos(p), Math.cos(h) * Math.cos(p), -Math.sin(p)];
  const right = [Math.cos(h), Math.sin(h), 0];
  // down = forward x right (right-handed: x right, y down, z forward).
  const down = [fwd[1] * right[2] - fwd[2] * right[1], fwd[2] * right[0] - fwd[0] * right[2], fwd[0] * right[1] - fwd[1] * right[0]];
  // Columns: camera x, y, z in the map frame.
  return [0, 1, 2].map((r) => [right[r], down[r], fwd[r]]);
}

test('a camera on the floor: its heading (given, or from its rotation) and its field of view', () => {
  assert.ok(close(floorDirection(0), [0, 1]));
  assert.ok(close(floorDirection(90), [-1, 0]), '90 degrees counter-clockwise from +y is -x');
  const cam = { position: [2, 3, 1.5], heading_deg: 90, horizontal_fov_deg: [-30, 30] };
  const f = cameraOnFloor(cam);
  assert.deepEqual(f.at, [2, 3]);
  assert.ok(close(f.forward, [-1, 0]));
  // Looking along -x, the image's left edge is towards -y, its right edge towards +y.
  assert.ok(close(f.left, floorDirection(120)));
  assert.ok(f.left[1] < 0 && f.right[1] > 0);
  // Without heading_deg: from the rotation's optical axis.
  const g = cameraOnFloor({ position: [0, 0, 1.2], rotation_map_from_camera: rotation(-40, 20) });
  assert.ok(Math.abs(g.heading_deg - -40) < 1e-9);
  assert.equal(g.left, null, 'no field of view given');
  assert.equal(cameraOnFloor({}), null);
  assert.equal(cameraOnFloor({ position: [NaN, 0, 1] }), null);
});

test('a camera\'s viewing pyramid goes through its image corners, in the glTF frame', () => {
  const cam = {
    position: [1, 2, 1.5],
    rotation_map_from_camera: rotation(30, 25),
    k_matrix: [[1000, 0, 800], [0, 1000, 600], [0, 0, 1]],
    image: { width: 1600, height: 1200 },
  };
  const segs = frustumSegments(cam, 0.5);
  assert.equal(segs.length, 8);
  const apex = toGltf(cam.position);
  assert.deepEqual(segs[0][0], apex);
  // The centre of the image rectangle lies on the optical axis, 0.5 deep: back to map (x, y, z) = (a, -c, b).
  const corners = segs.slice(0, 4).map((s) => s[1]);
  const mid = [0, 1, 2].map((k) => corners.reduce((t, c) => t + c[k], 0) / 4);
  const midMap = [mid[0], -mid[2], mid[1]];
  const axis = rotation(30, 25).map((row) => row[2]);
  assert.ok(close(midMap, cam.position.map((v, k) => v + 0.5 * axis[k]), 1e-9));
  // The top-left corner (pixel 0, 0) is up and to the left of the axis: higher than the centre.
  assert.ok(corners[0][1] > mid[1]);
  // The same from focal_px and principal_point.
  const alt = frustumSegments({ ...cam, k_matrix: undefined, focal_px: 1000, principal_point: [800, 600] }, 0.5);
  assert.deepEqual(alt, segs);
  assert.equal(frustumSegments({ ...cam, rotation_map_from_camera: undefined }, 0.5), null);
  assert.equal(frustumSegments({ ...cam, position: [1, 2] }, 0.5), null);
});
