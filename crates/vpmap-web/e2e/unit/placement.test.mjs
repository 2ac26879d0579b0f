// The room's placements the clicks leave open (placement.js): what the panel lists for a map's
// `alternatives` and the photos' `placement_turn_deg`, and the edits Swap and Unpin make.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { placementRows, pinPlacement, pinnedWarningPhoto, tieWarning, unpinPlacement } from '../../assets/js/placement.js';
import { roomBody } from '../../assets/js/room.js';

const scene = (extra = {}) => ({ version: 1, image: { width: 800, height: 600 }, vanishing_points: [], objects: [], floor: [], ...extra });
const alt = { photo: 2, turn_deg: 180, placement_turn_deg: 270, cost_px2: 0.52, chosen_cost_px2: 0.51 };

test('an alternative is listed with its photo, turn and both costs', () => {
  const rows = placementRows({ alternatives: [alt] }, [scene(), scene()]);
  assert.equal(rows.length, 1);
  const [r] = rows;
  assert.equal(r.kind, 'alternative');
  assert.equal(r.photo, 1, 'photo 2 of the map is scene 1 (from 0)');
  assert.equal(r.placement_turn_deg, 270);
  assert.match(r.text, /^Photo 2 fits about as well turned by 180° \(cost 0\.520 against the map's 0\.510 px²\)/);
});

test('no alternative without a room, for a stale map, or out of range', () => {
  assert.deepEqual(placementRows({ alternatives: [alt] }, [scene()]), [], 'one photo');
  assert.deepEqual(placementRows({ alternatives: [alt] }, [scene(), scene()], { stale: true }), [], 'the last build failed');
  assert.deepEqual(placementRows({ alternatives: [{ ...alt, photo: 3 }] }, [scene(), scene()]), [], 'no photo 3');
  assert.deepEqual(placementRows({ alternatives: [{ ...alt, photo: 1 }] }, [scene(), scene()]), [], 'photo 1 sets the frame');
  assert.deepEqual(placementRows({ alternatives: [{ ...alt, placement_turn_deg: 45 }] }, [scene(), scene()]), [], 'not a quarter turn');
  assert.deepEqual(placementRows(null, [scene(), scene()]), []);
});

test('Swap pins the photo to the alternative and the room file carries it; Unpin removes it', () => {
  const scenes = [scene(), scene()];
  pinPlacement(scenes[1], alt.placement_turn_deg);
  assert.equal(roomBody(scenes).photos[1].placement_turn_deg, 270);
  // Pinned: listed as pinned (also while the last build failed), the alternative no more.
  for (const stale of [false, true]) {
    const rows = placementRows({ alternatives: [alt] }, scenes, { stale });
    assert.deepEqual(rows.map((r) => [r.kind, r.photo, r.placement_turn_deg]), [['pinned', 1, 270]]);
    assert.match(rows[0].text, /^Photo 2's placement is pinned \(placement_turn_deg 270°\)/);
  }
  unpinPlacement(scenes[1]);
  assert.equal('placement_turn_deg' in scenes[1], false);
  assert.deepEqual(placementRows({}, scenes), []);
});

test('several tied photos pinned together: the room file carries each pin and each is listed as pinned', () => {
  const alt3 = { photo: 3, turn_deg: 90, placement_turn_deg: 90, cost_px2: 0.6, chosen_cost_px2: 0.51 };
  const scenes = [scene(), scene(), scene()];
  const map = { alternatives: [alt, alt3] };
  const rows = placementRows(map, scenes);
  assert.deepEqual(rows.map((r) => [r.kind, r.photo, r.placement_turn_deg]), [['alternative', 1, 270], ['alternative', 2, 90]]);
  for (const r of rows) pinPlacement(scenes[r.photo], r.placement_turn_deg);
  const body = roomBody(scenes);
  assert.deepEqual(body.photos.map((p) => p.placement_turn_deg), [undefined, 270, 90]);
  assert.deepEqual(placementRows(map, scenes).map((r) => [r.kind, r.photo]), [['pinned', 1], ['pinned', 2]]);
  // One unpinned: its alternative is offered again, the other stays pinned.
  unpinPlacement(scenes[2]);
  assert.deepEqual(placementRows(map, scenes).map((r) => [r.kind, r.photo]), [['alternative', 2], ['pinned', 1]]);
});

test('the map warning of a pinned photo is recognised (the page says the pin once, in its row)', () => {
  // vpmap-metrology's words (room/fit.rs), photo 3 of the room file.
  const w = "photo 3's placement is pinned by its `placement_turn_deg` (90 degrees): the room fit tried no other turn of it; remove the field to let the fit choose";
  assert.equal(pinnedWarningPhoto(w), 2);
  assert.equal(pinnedWarningPhoto("photo 2 is tied to the room only by \"box2\", which fit about as well with photo 2 turned by 180 degrees"), null);
  assert.equal(pinnedWarningPhoto("photo 12's placement is pinned by its `placement_turn_deg` (0 degrees)"), 11);
  assert.equal(pinnedWarningPhoto(undefined), null);
});

// vpmap-metrology's words (room/choose.rs) for photo 2 tied by one box, undecided and decided.
const TIE = 'photo 2 is tied to the room only by object "box2", which fits about as well with photo 2 turned by 180 degrees (cost 0.520 against 0.510 px^2): the map uses the better one; to be sure, name one more object seen in photo 2 and another photo';
const DECIDED = 'photo 3 is tied to the room only by objects "a", "b", which fit about as well with photo 3 turned by 90 degrees (cost 0.600 against 0.510 px^2): the map takes the turn the room\'s physical checks favour (0 violations against 2: cameras, floor corners and boxes inside the walls the photos\' floor outlines show, boxes not overlapping, no camera inside a box); to be sure, name one more object seen in photo 3 and another photo';

test('a tie warning is read: its photo, the objects tying it and its advice', () => {
  assert.deepEqual(tieWarning(TIE), { photo: 1, by: 'object "box2"', advice: 'to be sure, name one more object seen in photo 2 and another photo', warning: TIE });
  const d = tieWarning(DECIDED);
  assert.equal(d.photo, 2);
  assert.equal(d.by, 'objects "a", "b"');
  assert.equal(tieWarning("photo 3's placement is pinned by its `placement_turn_deg` (90 degrees)"), null);
  assert.equal(tieWarning('photo 2 is tied to the room only by object "box2"'), null, 'worded otherwise: not taken');
  assert.equal(tieWarning(undefined), null);
});

test('the alternative\'s row carries its tie warning\'s advice, so the tie is said once', () => {
  const map = { alternatives: [alt], warnings: ['the floor is poorly fixed', TIE, DECIDED] };
  const [r] = placementRows(map, [scene(), scene(), scene()]);
  assert.equal(r.warning, TIE, 'the row takes the warning of its own photo only');
  assert.ok(r.text.endsWith(' Photo 2 is tied to the room only by object "box2": to be sure, name one more object seen in photo 2 and another photo.'), r.text);
  // No tie warning for the photo: the row as before, and no warning taken.
  const [plain] = placementRows({ alternatives: [alt], warnings: [DECIDED] }, [scene(), scene(), scene()]);
  assert.equal(plain.warning, null);
  assert.match(plain.text, /cannot tell which is right\.$/);
});
