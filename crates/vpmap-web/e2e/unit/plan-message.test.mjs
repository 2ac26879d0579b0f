// The plan pane's wording of the server's planning errors (requests.js planMessage).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { planMessage } from '../../assets/js/requests.js';

test('planning errors name the pane\'s options by their labels, with short numbers', () => {
  const msg = 'start (-0.8749999510612101, 9.325000064501705) m lies on unknown floor (outside what the photo shows, or hidden behind an object; set unknown_passable or hidden_free to allow it): cell (59, 11)';
  assert.equal(
    planMessage(msg),
    'start (-0.87, 9.33) m lies on unknown floor (outside what the photo shows, or hidden behind an object; tick “unknown as passable” or “hidden floor as free” under the floor plan to allow it): cell (59, 11)',
  );
  assert.equal(planMessage('goal (1.5, 2) m lies on an obstacle (or within robot_radius 0.2 m of one)'), 'goal (1.5, 2) m lies on an obstacle (or within “Robot radius” 0.2 m of one)');
  assert.equal(planMessage('hidden_free is off'), '“hidden floor as free” is off');
});
