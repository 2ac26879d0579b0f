// The room of several photos (room.js) and the state that holds it (state.js): saving and
// loading, what blocks a build, which photo a server message is about, linking names.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync, existsSync } from 'node:fs';
import {
  roomBody, isRoomFile, parseRoom, roomBlocker, messagePhoto, roomProblem, linkCandidates, sharedWith, photoList, roomFileName, cameraOf,
} from '../../assets/js/room.js';
import { createState, createSlot, roomScenes } from '../../assets/js/state.js';
import { emptyScene } from '../../assets/js/scene.js';

const box = (name) => ({ name, base: { near: [100, 500], right: [300, 520], left: [20, 450] }, top: { near: [100, 300] } });
const ready = (names = []) => ({
  ...emptyScene(1600, 1200),
  vanishing_points: [{ point: [-2000, 500] }, { point: [3000, 520] }, { point: [800, 9000] }],
  objects: names.map(box),
});

test('one photo is saved as its own scene file, several as a room file', () => {
  const a = ready(['sofa']);
  assert.equal(roomBody([a]), a, 'a single photo: the scene itself, unchanged');
  const b = ready(['sofa', 'table']);
  assert.deepEqual(roomBody([a, b]), { version: 1, photos: [a, b] });
});

test('loading accepts a scene file and a room file, and names the photo at fault', () => {
  const one = parseRoom(ready(['sofa']));
  assert.equal(one.room, false);
  assert.equal(one.scenes.length, 1);
  const two = parseRoom({ version: 1, photos: [ready(['sofa']), { version: 1, image: { width: 800, height: 600 } }] });
  assert.equal(two.room, true);
  assert.equal(two.scenes.length, 2);
  assert.deepEqual(two.scenes[1].objects, [], 'each photo is normalised (lists the page relies on filled in)');
  assert.ok(isRoomFile({ photos: [] }));
  assert.ok(!isRoomFile(ready()));
  assert.match(parseRoom({ version: 1, photos: [] }).error, /no photos/);
  assert.match(parseRoom({ version: 2, photos: [ready()] }).error, /version 2/);
  assert.match(parseRoom({ version: 1, photos: [ready(), { version: 1 }] }).error, /^photo 2 \(`photos\[1\]`\): the scene has no valid `image`/);
  assert.match(parseRoom([1, 2]).error, /not a JSON object/);
});

test('the bundled multi-view room file loads (when ../shared/data is there)', { skip: !existsSync(new URL('../../../../../shared/data/multiview-scenes/mv01.json', import.meta.url)) }, () => {
  const mv = JSON.parse(readFileSync(new URL('../../../../../shared/data/multiview-scenes/mv01.json', import.meta.url), 'utf8'));
  const r = parseRoom(mv);
  assert.equal(r.scenes.length, 3);
  assert.equal(roomBlocker(r.scenes), null);
  assert.deepEqual(linkCandidates(r.scenes, 1).map((c) => c.name), ['box0', 'box2']);
  assert.deepEqual(sharedWith(r.scenes, 1).get('box3'), [0, 2]);
});

test('a build is blocked by the first photo that cannot be built, named when there are several', () => {
  assert.equal(roomBlocker([ready()]), null);
  const unready = emptyScene(800, 600);
  assert.deepEqual(roomBlocker([unready]), { photo: 0, message: 'Horizontal A vanishing point needs a point or at least two lines' });
  assert.deepEqual(roomBlocker([ready(), unready]), { photo: 1, message: 'photo 2: Horizontal A vanishing point needs a point or at least two lines' });
  assert.equal(roomBlocker([]).photo, null);
});

test('the photo a server message is about: a field path (0-based) or "photo N" (1-based)', () => {
  assert.equal(messagePhoto('`photos[2].objects[1].base.near` is above the horizon', 3), 2);
  assert.equal(messagePhoto('photo 3 is not tied to photo 1: no object is named in both', 3), 2);
  assert.equal(messagePhoto('`objects[1].base.near` is above the horizon', 1), 0, 'a single scene: its one photo');
  assert.equal(messagePhoto('no vanishing point', 2), null, 'a room message naming no photo');
  assert.equal(messagePhoto('photo 7 is not tied to photo 1', 3), null, 'a photo the room does not have');
  assert.equal(messagePhoto('`photos[0].floor[2]` ...', 2), 0);
});

test('a room message about a point is ringed on that photo', () => {
  const a = ready(['sofa']);
  const b = ready(['sofa', 'table']);
  b.floor = [[10, 1100], [900, 1150], [1500, 1000]];
  const p = roomProblem('`photos[1].floor[2]` is above the horizon', [a, b]);
  assert.deepEqual(p, { photo: 1, message: '`photos[1].floor[2]` is above the horizon', path: ['floor', 2], p: [1500, 1000], note: null });
  const q = roomProblem('photos[1].objects[1].base.near is on the wrong side; add `base.left`', [a, b]);
  assert.equal(q.photo, 1);
  assert.deepEqual(q.path, ['objects', 1, 'base', 'near']);
  assert.deepEqual(q.p, [100, 500]);
  assert.equal(q.note, 'add base.left');
  const r = roomProblem('photo 2 is not tied to photo 1: no object is named in both', [a, b]);
  assert.deepEqual(r, { photo: 1, message: 'photo 2 is not tied to photo 1: no object is named in both' });
  assert.equal(roomProblem('the fit did not converge', [a, b]), null);
  // As vpmap serve words them: the photo first, then the field in that photo's scene.
  const s = roomProblem('scene: photos[1] (photo 2): `floor[2]` at (1500.000, 1000.000) is 413.000 px above the horizon; a point on the floor must lie below it', [a, b]);
  assert.equal(s.photo, 1);
  assert.deepEqual(s.p, [1500, 1000]);
  const t = roomProblem('scene: photos[1] (photo 2): scene field `objects[0].base` is invalid: the corners of object "sofa" (base.near, base.right) do not fix its extent from `near` towards `left`: add `base.left` (or `top.left`)', [a, b]);
  assert.deepEqual([t.photo, t.object, t.note], [1, 0, 'add base.left']);
  const u = roomProblem('scene: scene field `photos[1]` is invalid: photo 2 is not tied to photo 1: no object is named the same in it and in photo 1 or photo 3; annotate an object that both show in both, under one name (e.g. "sofa")', [a, b, a]);
  assert.equal(u.photo, 1);
  assert.equal(u.p, undefined);
  // A single scene: its messages name no photo, and are about photo 0.
  assert.deepEqual(roomProblem('`objects[0]` needs a top', [a]).object, 0);
});

test('linking offers the names of the other photos that this photo does not use yet', () => {
  const scenes = [ready(['sofa', 'table']), ready(['box 1']), ready(['table', 'lamp', 'sofa'])];
  assert.deepEqual(linkCandidates(scenes, 1), [
    { name: 'sofa', photos: [0, 2] },
    { name: 'table', photos: [0, 2] },
    { name: 'lamp', photos: [2] },
  ]);
  assert.deepEqual(linkCandidates(scenes, 0), [{ name: 'box 1', photos: [1] }, { name: 'lamp', photos: [2] }]);
  assert.deepEqual(linkCandidates([scenes[0]], 0), [], 'one photo: nothing to link to');
  const shared = sharedWith(scenes, 2);
  assert.deepEqual(shared.get('table'), [0]);
  assert.deepEqual(shared.get('lamp'), []);
  assert.deepEqual(shared.get('sofa'), [0]);
  assert.equal(photoList([1]), 'photo 2');
  assert.equal(photoList([0, 2]), 'photos 1 and 3');
  assert.equal(photoList([0, 1, 3]), 'photos 1, 2 and 4');
  assert.equal(roomFileName('kitchen.jpg'), 'kitchen.room.json');
  assert.equal(roomFileName(''), 'room.room.json');
});

test('the camera of each photo: the answer\'s own for photo 1 and single photos, map.cameras[i] for the others', () => {
  const camera = { pitch_deg: 20, roll_deg: 1, focal_px: 1000, principal_point: [800, 600], height: 1.5, horizon: [[-2000, 500], [3000, 520]] };
  const single = { camera, map: { camera: { uncertainty: { pitch_deg_sd: 0.1 } } } };
  assert.deepEqual(cameraOf(single, 0), { ...camera, uncertainty: { pitch_deg_sd: 0.1 } });
  assert.equal(cameraOf(single, 1), null);
  assert.equal(cameraOf(null, 0), null);
  const second = { pitch_deg: 10, roll_deg: -2, focal_px: 900, principal_point: [790, 610], height: 1.2, vanishing_points: [[-1000, 600], [4000, 580], [800, 8000]], heading_deg: 90 };
  const room = { camera, map: { camera: {}, cameras: [{ ...camera, heading_deg: 0 }, second] } };
  assert.equal(cameraOf(room, 0).pitch_deg, 20);
  assert.deepEqual(cameraOf(room, 1), { pitch_deg: 10, roll_deg: -2, focal_px: 900, principal_point: [790, 610], height: 1.2, horizon: [[-1000, 600], [4000, 580]], lens_distortion: null, uncertainty: null });
  assert.equal(cameraOf(room, 2), null);
  // A photo's lens, as the map reports it, goes with its camera (the camera bar shows it).
  const lensed = { camera, map: { camera: {}, cameras: [{ ...camera, heading_deg: 0 }, { ...second, lens_distortion: { k: -0.05, k_sd: 0.01 } }] } };
  assert.deepEqual(cameraOf(lensed, 1).lens_distortion, { k: -0.05, k_sd: 0.01 });
});

test('the state keeps a room: the active photo\'s fields are its slot\'s', () => {
  const s = createState();
  assert.equal(s.scene, null);
  assert.equal(s.photos.length, 1);
  assert.deepEqual(roomScenes(s), []);
  s.scene = ready(['sofa']);
  s.photoName = 'a.jpg';
  s.photos.push(createSlot({ scene: ready(['table']), photoName: 'b.jpg' }));
  assert.equal(s.photoName, 'a.jpg');
  s.active = 1;
  assert.equal(s.photoName, 'b.jpg');
  assert.equal(s.scene.objects[0].name, 'table');
  assert.notEqual(s.photos[0].history, s.history, 'each photo has its own undo history');
  s.history.record(s.scene);
  assert.equal(s.photos[1].history.canUndo, true);
  assert.equal(s.photos[0].history.canUndo, false);
  s.savedVpPoints[0] = [1, 2];
  assert.deepEqual(s.photos[1].savedVpPoints[0], [1, 2]);
  assert.deepEqual(s.photos[0].savedVpPoints[0], null);
  assert.deepEqual(roomScenes(s).map((x) => x.objects[0].name), ['sofa', 'table']);
  // The true map is known for a page of one photo only.
  s.active = 0;
  s.truth = 'example';
  assert.equal(s.truth, null);
  s.photos.pop();
  assert.equal(s.truth, 'example');
});

test('a page with no photo gets its first slot on the first write', () => {
  const s = createState();
  s.photos = [];
  s.active = 0;
  assert.equal(s.scene, null);
  assert.deepEqual(s.savedVpPoints, [null, null, null]);
  s.scene = ready();
  assert.equal(s.photos.length, 1);
  assert.equal(s.active, 0);
});
