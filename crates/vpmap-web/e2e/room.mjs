// Browser test of a room of several photos (issue 29), in headless Chromium against
// `vpmap serve` (or the mock server with VPMAP_E2E_MOCK=1):
//
//   1. opening a room file (the bundled `examples/room.json`, 3 photos of one room) shows one
//      thumbnail per photo,
//      photo 1 active, and builds the room: the floor plan draws every camera of `map.cameras`
//      (a numbered disc each, photo 1's highlighted) and so does the 3D view;
//   2. a photo opened for the active thumbnail (a grey PNG of its size) keeps its annotations;
//      a click on photo 2's thumbnail (or its camera on the plan, or the keys [ and ]) makes it
//      the active one: its scene, its camera in the camera bar;
//   3. linking by name: photo 2's objects say which other photos show them; renamed so that it
//      shares no object, the build error names photo 2, its thumbnail gets the badge and the
//      same message shows beside the photo; one choice in "same as…" links it back and the
//      room builds;
//   4. a floor corner of photo 3 dragged above the horizon: the error names `photos[2]` and `floor[k]`,
//      the corner is ringed on photo 3 (not on another photo), undo (photo 3's own) takes it back;
//   5. Save writes the room file of every photo; removing photos (after a confirm) down to one
//      makes Save write a plain scene file; Add photo (two files at once) grows the room again.
//
// No console error or warning is allowed. Same environment as e2e.mjs (VPMAP_BIN, VPMAP_URL,
// VPMAP_E2E_MOCK, VPMAP_E2E_CHROMIUM, VPMAP_E2E_SCREENSHOT, VPMAP_E2E_HEADED); screenshots go
// next to the requested one as `<screenshot>-room-<what>.png`. Prints `ROOM PASSED`.

import { mkdtemp, readFile, writeFile } from 'node:fs/promises';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { REPO, greyPng, launchChromium, startServer, testRun } from './harness.mjs';

const TOTAL_MS = 150_000;
const SHOT = (what) => (process.env.VPMAP_E2E_SCREENSHOT || '/tmp/vpmap-e2e.png').replace(/(\.png)?$/, `-room-${what}.png`);
const ROOM_EXAMPLE = join(REPO, 'examples', 'room.json');

let server = null;
let browser = null;
let page = null;
let tmp = null;
const problems = [];
const { log, check, step, fail, pass } = testRun({
  label: 'ROOM',
  totalMs: TOTAL_MS,
  failureShot: SHOT('failed'),
  resources: () => ({ server, browser, page, tmp }),
});

const noProblems = () => check(problems.length === 0, problems.join('\n'));
/** Take the browser's log lines of the refused builds (the step expects them) out of the problems. */
function expectRefused() {
  const before = problems.length;
  for (let i = problems.length - 1; i >= 0; i--) if (problems[i].includes('status of 400')) problems.splice(i, 1);
  check(before > problems.length, 'the refused build left no trace in the console');
}
const status = () => page.evaluate(() => window.vpmap.status());
const sceneNow = () => page.evaluate(() => window.vpmap.scene());
const mapNow = () => page.evaluate(() => window.vpmap.map());

/** Wait until `builds` reaches `want` and nothing is pending; the last build's error or null. */
async function settle(what, want) {
  try {
    await page.waitForFunction((w) => {
      const s = window.vpmap.status();
      return !s.pending && s.busy.length === 0 && (s.builds >= w || s.buildError);
    }, want, { timeout: 60_000, polling: 50 });
  } catch {
    const s = await status();
    throw new Error(`${what} did not finish: ${JSON.stringify({ busy: s.busy, builds: s.builds, problem: s.problem })}`);
  }
  return status();
}

/** Wait for the next build answer (or error) after `action`. */
async function afterBuild(what, action) {
  const before = await status();
  await action();
  await page.waitForFunction(
    (b) => {
      const s = window.vpmap.status();
      return !s.pending && s.busy.length === 0 && (s.builds > b.builds || (s.buildError && s.buildError !== b.buildError));
    },
    { builds: before.builds, buildError: before.buildError },
    { timeout: 60_000, polling: 50 },
  ).catch(async () => {
    const s = await status();
    throw new Error(`${what}: no build answer: ${JSON.stringify({ busy: s.busy, builds: s.builds, problem: s.problem })}`);
  });
  return status();
}

async function main() {
  const url = await step('start the server', async () => {
    const s = await startServer({ mock: true, log });
    server = s.server;
    return s.url;
  });
  log(`server at ${url}`);
  await step('launch Chromium', async () => {
    browser = await launchChromium();
  });
  tmp = await mkdtemp(join(tmpdir(), 'vpmap-room-'));

  // The room: the bundled example room (3 photos of one room, exact clicks, from `vpmap synth
  // --photos 3`), in every checkout.
  const room = JSON.parse(await readFile(ROOM_EXAMPLE, 'utf8'));
  log(`room: ${ROOM_EXAMPLE}`);
  const roomFile = join(tmp, 'room.json');
  await writeFile(roomFile, JSON.stringify(room));
  const { width, height } = room.photos[0].image;
  const png = (name) => join(tmp, name);
  await writeFile(png('p1.png'), greyPng(width, height));
  await writeFile(png('p4.png'), greyPng(width, height));
  await writeFile(png('p5.png'), greyPng(640, 480));

  await step('load the page', async () => {
    page = await browser.newPage({ viewport: { width: 1600, height: 1000 }, acceptDownloads: true });
    page.on('console', (m) => {
      if (m.type() === 'error' || m.type() === 'warning') problems.push(`console ${m.type()}: ${m.text()}`);
    });
    page.on('pageerror', (e) => problems.push(`uncaught exception: ${e.message}`));
    page.on('dialog', (d) => d.accept().catch(() => {}));
    const res = await page.goto(url, { waitUntil: 'load' });
    check(res && res.ok(), `GET ${url} answered ${res && res.status()}`);
    await page.waitForFunction(() => !!window.vpmap, null, { timeout: 10_000 });
    check(await page.isHidden('#photo-strip'), 'the strip shows with no room');
  });

  await step('1. a room file: a thumbnail per photo, and every camera on the plan and in 3D', async () => {
    await page.setInputFiles('#scene-input', roomFile);
    await page.waitForFunction((n) => window.vpmap.status().photos === n, room.photos.length, { timeout: 10_000 });
    check(await page.isVisible('#photo-strip'), 'no strip of thumbnails');
    check((await page.locator('#photo-thumbs .thumb').count()) === room.photos.length, 'not one thumbnail per photo');
    check((await status()).active === 0, 'photo 1 is not the active one');
    check((await page.textContent('#btn-save-scene')).trim() === 'Save room', 'the save button does not say it saves the room');
    const s = await settle('building the room', 1);
    check(!s.buildError, `the room did not build: ${s.buildError}`);
    const map = await mapNow();
    check(Array.isArray(map.cameras) && map.cameras.length === room.photos.length, `map.cameras: ${JSON.stringify(map.cameras?.length)}`);
    await page.waitForSelector('#plan-host .vp-camera', { timeout: 10_000 });
    check((await page.locator('#plan-host .vp-camera').count()) === room.photos.length, 'the plan does not draw every camera');
    check((await page.locator('#plan-host .vp-camera.active').getAttribute('data-photo')) === '0', 'photo 1\'s camera is not the highlighted one');
    // Each disc at its camera's station point (1.5 px).
    for (const [i, c] of map.cameras.entries()) {
      const want = await page.evaluate(([x, y]) => window.vpmap.planMapToClient(x, y), [c.position[0], c.position[1]]);
      const box = await page.locator(`#plan-host .vp-camera[data-photo="${i}"] circle`).boundingBox();
      const got = [box.x + box.width / 2, box.y + box.height / 2];
      check(Math.hypot(got[0] - want[0], got[1] - want[1]) < 1.5, `camera ${i + 1} drawn at ${got}, its position is at ${want}`);
    }
    await page.waitForFunction((n) => document.getElementById('model-host').dataset.cameras === String(n), room.photos.length, { timeout: 20_000 })
      .catch(() => { throw new Error('the 3D view does not draw every camera'); });
    await page.screenshot({ path: SHOT('loaded') });
    noProblems();
  });

  await step('2. a photo for the active thumbnail; another thumbnail becomes the active photo', async () => {
    await page.setInputFiles('#photo-input', png('p1.png'));
    await page.waitForSelector('#photo-thumbs .thumb[data-photo="0"] img', { timeout: 10_000 });
    const sc = await sceneNow();
    check(sc.objects.length === room.photos[0].objects.length, 'opening the photo dropped its annotations');
    check((await status()).photos === room.photos.length, 'opening a photo changed the number of photos');
    await page.click('#photo-thumbs .thumb[data-photo="1"] .thumb-pick');
    await page.waitForFunction(() => window.vpmap.status().active === 1);
    const two = await sceneNow();
    check(JSON.stringify(two.objects.map((o) => o.name)) === JSON.stringify(room.photos[1].objects.map((o) => o.name)), `photo 2 shows ${JSON.stringify(two.objects.map((o) => o.name))}`);
    const map = await mapNow();
    const pitch = Number(await page.locator('#cam-pitch').getAttribute('data-value'));
    check(Math.abs(pitch - map.cameras[1].pitch_deg) < 1e-6, `the camera bar shows pitch ${pitch}, photo 2's camera has ${map.cameras[1].pitch_deg}`);
    check((await page.locator('#plan-host .vp-camera.active').getAttribute('data-photo')) === '1', 'photo 2\'s camera is not highlighted');
    // A click on photo 3's camera on the plan shows photo 3; then back to photo 2 by its thumbnail.
    await page.click('#plan-host .vp-camera[data-photo="2"] circle', { force: true });
    await page.waitForFunction(() => window.vpmap.status().active === 2, null, { timeout: 5000 }).catch(() => { throw new Error('a click on camera 3 did not show photo 3'); });
    check(!(await status()).start, 'the click on a camera set a path start');
    await page.click('#photo-thumbs .thumb[data-photo="1"] .thumb-pick');
    await page.waitForFunction(() => window.vpmap.status().active === 1);
    // ] and [ step through the photos.
    await page.focus('#photo-canvas');
    await page.keyboard.press(']');
    await page.waitForFunction(() => window.vpmap.status().active === 2, null, { timeout: 5000 }).catch(() => { throw new Error('] did not show photo 3'); });
    await page.keyboard.press('[');
    await page.waitForFunction(() => window.vpmap.status().active === 1, null, { timeout: 5000 }).catch(() => { throw new Error('[ did not show photo 2'); });
    noProblems();
  });

  await step('3. linking: shared objects are shown; an untied photo is named; one choice links it', async () => {
    const shared = await page.locator('#object-list .obj-shared').allTextContents();
    check(shared.some((t) => /same object in photo/.test(t)), `no object of photo 2 says it is shared: ${JSON.stringify(shared)}`);
    const names = (await sceneNow()).objects.map((o) => o.name);
    // Rename every object of photo 2, so it shares none.
    let s;
    for (const [i] of names.entries()) {
      s = await afterBuild(`renaming object ${i + 1}`, async () => {
        await page.fill(`#object-list li[data-index="${i}"] .obj-name`, `lonely ${i + 1}`);
      });
    }
    check(s.buildError && s.problemPhoto === 1, `renaming photo 2's objects gave ${JSON.stringify({ error: s.buildError, photo: s.problemPhoto })}`);
    check(/photo 2/.test(s.buildError), `the error does not name photo 2: ${s.buildError}`);
    check(await page.isVisible('#photo-thumbs .thumb[data-photo="1"] .thumb-badge'), 'photo 2\'s thumbnail has no badge');
    check(await page.isHidden('#photo-thumbs .thumb[data-photo="0"] .thumb-badge'), 'photo 1\'s thumbnail has a badge');
    const note = await page.textContent('#photo-note');
    check(note.includes(s.buildError), `beside the photo: "${note}", the error: "${s.buildError}"`);
    check((await page.textContent('#error-text')).includes(s.buildError), 'the error banner does not show the message');
    // The names of the other photos are offered; one choice links the first object back.
    const offered = await page.$$eval('#room-names option', (os) => os.map((o) => o.value));
    check(names.every((n) => offered.includes(n)), `the names offered (${offered}) do not include photo 2's old names (${names})`);
    await page.waitForTimeout(200);
    await page.screenshot({ path: SHOT('untied') });
    s = await afterBuild('linking object 1', async () => {
      await page.selectOption('#object-list li[data-index="0"] .obj-link', names[0]);
    });
    check(!s.buildError, `after linking, the room does not build: ${s.buildError}`);
    check(await page.isHidden('#photo-thumbs .thumb[data-photo="1"] .thumb-badge'), 'the badge stayed after the link');
    check(await page.isHidden('#photo-note'), 'the message stayed beside the photo');
    check((await sceneNow()).objects[0].name === names[0], 'the link did not name the object');
    // Name the others back too (the room as it was).
    for (const [i, n] of names.entries()) {
      if (i === 0) continue;
      await afterBuild(`naming object ${i + 1} back`, () => page.fill(`#object-list li[data-index="${i}"] .obj-name`, n));
    }
    expectRefused();
    noProblems();
  });

  await step('4. an error about photo 3\'s floor corner rings it on photo 3; its undo takes it back', async () => {
    await page.click('#photo-thumbs .thumb[data-photo="2"] .thumb-pick');
    await page.waitForFunction(() => window.vpmap.status().active === 2);
    const floor = (await sceneNow()).floor;
    const k = floor.findIndex((p) => p[0] > 5 && p[0] < width - 5 && p[1] > 5 && p[1] < height - 5);
    const corner = k >= 0 ? k : 0;
    await page.waitForTimeout(300);
    const from = await page.evaluate(([x, y]) => window.vpmap.imageToClient(x, y), floor[corner]);
    const to = await page.evaluate(([x, y]) => window.vpmap.imageToClient(x, y), [floor[corner][0], 5]);
    const s = await afterBuild('dragging the floor corner above the horizon', async () => {
      await page.mouse.move(from[0], from[1]);
      await page.mouse.down();
      await page.mouse.move(to[0], to[1], { steps: 8 });
      await page.mouse.up();
    });
    check(s.buildError && s.problemPhoto === 2, `the error is ${JSON.stringify({ error: s.buildError, photo: s.problemPhoto })}`);
    // `photos[2].floor[k]`, or `photos[2] (photo 3): \`floor[k]\`` as vpmap serve words it.
    check(new RegExp(`photos\\[2\\](\\.| \\(photo 3\\): \`)floor\\[${corner}\\]`).test(s.buildError), `the error does not name photos[2] and floor[${corner}]: ${s.buildError}`);
    check(JSON.stringify(s.marked) === JSON.stringify(['floor', corner]), `marked on the photo: ${JSON.stringify(s.marked)}`);
    check(await page.isVisible('#photo-thumbs .thumb[data-photo="2"] .thumb-badge'), 'photo 3\'s thumbnail has no badge');
    await page.waitForTimeout(200);
    await page.screenshot({ path: SHOT('marked') });
    // Not ringed on another photo.
    await page.click('#photo-thumbs .thumb[data-photo="0"] .thumb-pick');
    await page.waitForFunction(() => window.vpmap.status().active === 0);
    check((await status()).marked === null, 'the ring shows on photo 1');
    check(await page.isHidden('#photo-note'), 'photo 3\'s message shows beside photo 1');
    check(await page.isDisabled('#btn-undo'), 'photo 1 offers an undo of photo 3\'s edit');
    await page.click('#photo-thumbs .thumb[data-photo="2"] .thumb-pick');
    await page.waitForFunction(() => window.vpmap.status().active === 2);
    const t = await afterBuild('undoing the drag', () => page.click('#btn-undo'));
    check(!t.buildError, `after undo: ${t.buildError}`);
    check(JSON.stringify((await sceneNow()).floor[corner]) === JSON.stringify(floor[corner]), 'undo did not bring the corner back');
    expectRefused();
    noProblems();
  });

  await step('5. Save writes the room; removing photos down to one saves a scene; Add photo adds', async () => {
    let [dl] = await Promise.all([page.waitForEvent('download'), page.click('#btn-save-scene')]);
    let saved = JSON.parse(await readFile(await dl.path(), 'utf8'));
    check(dl.suggestedFilename() === 'p1.room.json', `saved as ${dl.suggestedFilename()}`);
    check(saved.version === 1 && saved.photos.length === room.photos.length, `saved ${JSON.stringify(Object.keys(saved))}`);
    check(JSON.stringify(saved.photos.map((p) => p.objects.map((o) => o.name))) === JSON.stringify(room.photos.map((p) => p.objects.map((o) => o.name))), 'the saved room differs from the one opened');
    for (let n = room.photos.length; n > 1; n--) {
      await page.click(`#photo-thumbs .thumb[data-photo="${n - 1}"] .thumb-remove`);
      await page.waitForFunction((m) => window.vpmap.status().photos === m, n - 1, { timeout: 5000 });
    }
    check(await page.isHidden('#photo-strip'), 'the strip shows for one photo');
    [dl] = await Promise.all([page.waitForEvent('download'), page.click('#btn-save-scene')]);
    saved = JSON.parse(await readFile(await dl.path(), 'utf8'));
    check(dl.suggestedFilename() === 'p1.scene.json' && !saved.photos && saved.image.width === width, `one photo saved as ${dl.suggestedFilename()}: ${JSON.stringify(Object.keys(saved))}`);
    await page.setInputFiles('#add-photo-input', [png('p4.png'), png('p5.png')]);
    await page.waitForFunction(() => window.vpmap.status().photos === 3, null, { timeout: 10_000 });
    const s = await status();
    check(s.active === 2, `the last photo added is not the active one (${s.active})`);
    check((await sceneNow()).image.width === 640, 'the added photo has not its own scene');
    check(s.problemPhoto === 1 || s.problemPhoto === 2, `an added photo with no vanishing points is not named as what blocks the build: ${JSON.stringify(s.problem)}`);
    await page.screenshot({ path: SHOT('added') });
    noProblems();
  });

}

main()
  .then(pass)
  .catch((err) => fail(err && err.stack ? err.stack : String(err)));
