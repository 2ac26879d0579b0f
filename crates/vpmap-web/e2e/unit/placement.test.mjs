// The room's placements the clicks leave open (placement.js): what the panel lists for a map's
// `alternatives` and the photos' `placement_turn_deg`, and the edits Swap and Unpin make.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { placementRows, pinPlacement, unpinPlacement } from '../../assets/js/placement.js';
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
