// The refusal of a floor point on or above the horizon (placement-tool.js) on a photo with a
// lens: the horizon of the build is the pinhole camera's, so the click is taken through the
// photo's lens before it is compared with it.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { refuseAboveHorizon } from '../../assets/js/placement-tool.js';

/** An app with a build whose pinhole horizon is the row y = 300 of a 1600 x 1200 photo. */
function app(lens) {
  const errors = [];
  return {
    errors,
    state: {
      camera: { horizon: [[0, 300], [1600, 300]] },
      scene: { image: { width: 1600, height: 1200 }, ...(lens ? { lens_distortion: lens } : {}) },
    },
    showError: (text) => errors.push(text),
  };
}

test('a floor click is compared with the horizon where the photo shows it, through the lens', () => {
  // Barrel distortion k = -0.1 bends the horizon (300 px above the centre) towards the centre
  // at the photo's sides: at x = 50 the photo shows it near y = 319 (the pinhole pixel of
  // (50, 310) is 600 - 290 / (1 - 0.1 (750^2 + 290^2) / 1000^2) = 290.3, above 300).
  const lensed = app({ k: -0.1, k_sd: 0.01 });
  assert.equal(refuseAboveHorizon(lensed, [50, 310]), true);
  assert.match(lensed.errors[0], /px above the horizon/);
  // Below the curve there: taken.
  assert.equal(refuseAboveHorizon(lensed, [50, 335]), false);
  // At the centre column the curve and the line nearly meet: 310 is below both.
  assert.equal(refuseAboveHorizon(lensed, [800, 310]), false);
  // A pinhole photo: the straight horizon, (50, 310) lies below it.
  const pinhole = app(null);
  assert.equal(refuseAboveHorizon(pinhole, [50, 310]), false);
  assert.equal(refuseAboveHorizon(pinhole, [50, 290]), true);
});
