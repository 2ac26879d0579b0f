// Browser test of a room's tie and its swap (issue 39), in headless Chromium against
// `vpmap serve` (the mock server does not fit rooms, so it is not used here):
//
//   1. a room whose photo 2 is tied to photo 1 by one box only and whose photos show no floor
//      outline (the room fit's fixture `room-mv00.json` with photo 2's second shared box named
//      apart and the floors left out): the map has one `alternative` (photo 2 turned by 180°),
//      and the page lists it under the warnings with its photo, turn and both costs and a Swap
//      button, the map's tie warning's advice in that row and not again in the warnings list;
//   2. a plan from one side of where a box only photo 2 shows goes after the swap to the
//      other, on a line clear of every box of the first map (unknown cells passable): straight;
//   3. Swap: the room file sent has photo 2's `placement_turn_deg`, the map follows it (photo
//      2's camera and its own box turned by a half turn about the shared box's centre, checked
//      against the first map; the shared box where it was), the plan draws photo 2's camera at
//      its new place, the page lists photo 2 as pinned (with Unpin), and the plan, re-run on
//      the new map, goes round the box that now stands in its way;
//   4. Unpin: the first map again;
//   5. two tied photos swapped together: the same room with a third photo, a copy of photo 2
//      whose objects other than the shared box are named apart, so that photos 2 and 3 are
//      each tied by one box: two alternatives, each with a check box; both checked and
//      **Swap checked together**: one build, the room file pins both, both cameras move to the
//      first map's turned by a half turn about the shared box, both photos listed as pinned,
//      and the map's warnings that they are pinned are not said again in the warnings list.
//
// No console error or warning is allowed. Same environment as e2e.mjs (VPMAP_BIN, VPMAP_URL,
// VPMAP_E2E_CHROMIUM, VPMAP_E2E_SCREENSHOT, VPMAP_E2E_HEADED); screenshots go next to the
// requested one as `<screenshot>-swap-<what>.png`. Prints `SWAP PASSED`.

import { mkdtemp, readFile, writeFile } from 'node:fs/promises';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { REPO, launchChromium, startServer, testRun } from './harness.mjs';

const TOTAL_MS = 120_000;
const SHOT = (what) => (process.env.VPMAP_E2E_SCREENSHOT || '/tmp/vpmap-e2e.png').replace(/(\.png)?$/, `-swap-${what}.png`);
const FIXTURE = join(REPO, 'crates', 'vpmap-metrology', 'tests', 'fixtures', 'room-mv00.json');
/** Photo 2's own box (named apart from photo 1's box3, so photo 2 shares box2 only). */
const OWN = 'box3-seen-from-2';
const SHARED = 'box2';

let server = null;
let browser = null;
let page = null;
let tmp = null;
const problems = [];
const { log, check, step, fail, pass } = testRun({
  label: 'SWAP',
  totalMs: TOTAL_MS,
  failureShot: SHOT('failed'),
  resources: () => ({ server, browser, page, tmp }),
});

const noProblems = () => check(problems.length === 0, problems.join('\n'));
const status = () => page.evaluate(() => window.vpmap.status());
const mapNow = () => page.evaluate(() => window.vpmap.map());
const roomNow = () => page.evaluate(() => window.vpmap.room());
const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1]);
const centroid = (map, name) => {
  const o = map.objects.find((x) => x.name === name);
  if (!o) throw new Error(`the map has no object ${name}`);
  return o.centroid;
};
const camera2 = (map) => map.cameras[1].position.slice(0, 2);
const turned = (p, c) => [2 * c[0] - p[0], 2 * c[1] - p[1]];

/** Wait until a counter (`builds`, `plans`) passes `before` and nothing is pending. */
async function settle(what, counter, before) {
  try {
    await page.waitForFunction(([k, b]) => {
      const s = window.vpmap.status();
      return !s.pending && s.busy.length === 0 && (s[k] > b || s.buildError || (k === 'plans' && s.planError));
    }, [counter, before], { timeout: 60_000, polling: 50 });
  } catch {
    const s = await status();
    throw new Error(`${what} did not finish: ${JSON.stringify({ busy: s.busy, builds: s.builds, plans: s.plans, problem: s.problem })}`);
  }
  return status();
}

/** Whether segments ab and cd cross. */
function crosses(a, b, c, d) {
  const orient = (p, q, r) => Math.sign((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]));
  return orient(a, b, c) * orient(a, b, d) < 0 && orient(c, d, a) * orient(c, d, b) < 0;
}

/** Distance from point p to segment ab. */
function pointSegmentDistance(p, a, b) {
  const ab = [b[0] - a[0], b[1] - a[1]];
  const t = Math.max(0, Math.min(1, ((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1]) / (ab[0] ** 2 + ab[1] ** 2 || 1)));
  return dist(p, [a[0] + t * ab[0], a[1] + t * ab[1]]);
}

/** Whether p lies inside the polygon (even-odd rule). */
function inside(p, poly) {
  let odd = false;
  for (let i = 0, j = poly.length - 1; i < poly.length; j = i++) {
    const [a, b] = [poly[i], poly[j]];
    if ((a[1] > p[1]) !== (b[1] > p[1]) && p[0] < ((b[0] - a[0]) * (p[1] - a[1])) / (b[1] - a[1]) + a[0]) odd = !odd;
  }
  return odd;
}

/** Distance from p to the polygon's area (0 inside). */
function pointPolygonDistance(p, poly) {
  if (inside(p, poly)) return 0;
  return Math.min(...poly.map((a, i) => pointSegmentDistance(p, a, poly[(i + 1) % poly.length])));
}

/** Distance from segment ab to the polygon's area (0 when they meet). */
function segmentPolygonDistance(a, b, poly) {
  if (inside(a, poly) || inside(b, poly)) return 0;
  let best = Infinity;
  for (const [i, c] of poly.entries()) {
    const d = poly[(i + 1) % poly.length];
    if (crosses(a, b, c, d)) return 0;
    best = Math.min(best, pointSegmentDistance(c, a, b), pointSegmentDistance(d, a, b), pointSegmentDistance(a, c, d), pointSegmentDistance(b, c, d));
  }
  return best;
}

/** The MBPP path's length in the last plan, or null. */
const mbppLength = (s) => s.plan?.results?.find((r) => r.planner === 'mbpp' && r.found)?.length_m ?? null;

async function main() {
  if (process.env.VPMAP_E2E_MOCK === '1') {
    console.log('SWAP SKIPPED: the mock server fits no room (run it against vpmap serve)');
    process.exit(0);
  }
  const url = await step('start the server', async () => {
    const s = await startServer({ log });
    server = s.server;
    return s.url;
  });
  log(`server at ${url}`);
  await step('launch Chromium', async () => {
    browser = await launchChromium();
  });
  tmp = await mkdtemp(join(tmpdir(), 'vpmap-swap-'));
  const room = JSON.parse(await readFile(FIXTURE, 'utf8'));
  for (const o of room.photos[1].objects) if (o.name === 'box3') o.name = OWN;
  for (const p of room.photos) p.floor = [];
  const roomFile = join(tmp, 'tie.room.json');
  await writeFile(roomFile, JSON.stringify(room));

  await step('load the page', async () => {
    page = await browser.newPage({ viewport: { width: 1600, height: 1000 } });
    page.on('console', (m) => {
      if (m.type() === 'error' || m.type() === 'warning') problems.push(`console ${m.type()}: ${m.text()}`);
    });
    page.on('pageerror', (e) => problems.push(`uncaught exception: ${e.message}`));
    page.on('dialog', (d) => d.accept().catch(() => {}));
    const res = await page.goto(url, { waitUntil: 'load' });
    check(res && res.ok(), `GET ${url} answered ${res && res.status()}`);
    await page.waitForFunction(() => !!window.vpmap, null, { timeout: 10_000 });
    check(await page.isHidden('#placements'), 'the placements show with no room');
  });

  const first = await step('1. a room with a tie: the alternative is listed with a Swap button', async () => {
    await page.setInputFiles('#scene-input', roomFile);
    await page.waitForFunction((n) => window.vpmap.status().photos === n, room.photos.length, { timeout: 10_000 });
    const s = await settle('building the room', 'builds', 0);
    check(!s.buildError, `the room did not build: ${s.buildError}`);
    const map = await mapNow();
    check(Array.isArray(map.alternatives) && map.alternatives.length === 1, `map.alternatives: ${JSON.stringify(map.alternatives)}`);
    const alt = map.alternatives[0];
    check(alt.photo === 2 && alt.turn_deg === 180, `the alternative: ${JSON.stringify(alt)}`);
    check(await page.isVisible('#placements'), 'the alternative is not shown');
    const row = page.locator('#placements li.alternative[data-photo="1"]');
    check((await row.count()) === 1, 'no row for photo 2\'s alternative');
    const text = await row.textContent();
    check(/Photo 2 fits about as well turned by 180°/.test(text) && text.includes(`${alt.cost_px2.toFixed(3)} against the map's ${alt.chosen_cost_px2.toFixed(3)} px²`), `the row says: ${text}`);
    check(await row.locator('button.swap').isVisible(), 'no Swap button');
    // The tie is said once: the map warns of it, the row carries its advice, and the
    // warnings list does not say it again (issue 39).
    const tie = map.warnings.find((w) => w.startsWith('photo 2 is tied to the room only by'));
    check(tie, `the map does not warn of the tie: ${JSON.stringify(map.warnings)}`);
    const listed = await page.locator('#warnings li').allTextContents();
    check(!listed.some((w) => w.includes('is tied to the room only by')), `the warnings list says the tie again: ${JSON.stringify(listed)}`);
    check(text.includes('Photo 2 is tied to the room only by') && text.includes('to be sure, name one more object seen in photo 2 and another photo'), `the row does not carry the tie's advice: ${text}`);
    await page.locator('#placements').scrollIntoViewIfNeeded();
    await page.screenshot({ path: SHOT('tie') });
    noProblems();
    return map;
  });

  // Photo 2's objects that photo 1 does not show turn with it by a half turn about the shared
  // box: the swapped map's boxes follow from the first map's.
  const c = centroid(first, SHARED);
  const own = first.objects.find((x) => x.name === OWN);
  const ownAfter = turned(own.centroid, c);
  const inPhoto1 = new Set(room.photos[0].objects.map((x) => x.name));
  const moving = first.objects.filter((x) => !inPhoto1.has(x.name));
  check(moving.some((x) => x.name === OWN), `photo 2's own box ${OWN} is not among the boxes only photo 2 shows`);
  const before = first.objects.map((x) => x.footprint);
  const after = first.objects.map((x) => (inPhoto1.has(x.name) ? x.footprint : x.footprint.map((p) => turned(p, c))));
  // Each map's grid covers its boxes and cameras and 0.5 m around them (vpmap-pipeline's
  // GRID_MARGIN_M): the ends stay within 0.3 m of them.
  const MARGIN = 0.3;
  const bounds = (polys, cams) => {
    const pts = [...polys.flat(), ...cams];
    const xs = pts.map((p) => p[0]);
    const ys = pts.map((p) => p[1]);
    return [Math.min(...xs) - MARGIN, Math.max(...xs) + MARGIN, Math.min(...ys) - MARGIN, Math.max(...ys) + MARGIN];
  };
  const cam1 = first.cameras[0].position.slice(0, 2);
  const within = (p, [x0, x1, y0, y1]) => p[0] > x0 && p[0] < x1 && p[1] > y0 && p[1] < y1;
  const boundsBefore = bounds(before, [cam1, camera2(first)]);
  const boundsAfter = bounds(after, [cam1, turned(camera2(first), c)]);
  // A start and a goal on either side of where a box of photo 2's goes after the swap, inside
  // both maps and clear (by the robot's radius and 0.15 m) of every box of either, the straight
  // line between them clear of every box of the first map: the first of 16 directions and
  // three reaches that is, about each such box. After the swap the box stands in the way.
  const clearance = 0.2 + 0.15;
  let route = null;
  for (const m of moving) {
    const place = m.footprint.map((p) => turned(p, c));
    const centre = turned(m.centroid, c);
    for (const reach of [0.5, 1.0, 1.5]) {
      for (let k = 0; k < 16 && !route; k++) {
        const a = (k * Math.PI) / 8;
        const d = [Math.cos(a), Math.sin(a)];
        const far = reach + Math.max(...place.map((p) => Math.abs((p[0] - centre[0]) * d[0] + (p[1] - centre[1]) * d[1])));
        const s = [centre[0] - far * d[0], centre[1] - far * d[1]];
        const g = [centre[0] + far * d[0], centre[1] + far * d[1]];
        const inMaps = [s, g].every((p) => within(p, boundsBefore) && within(p, boundsAfter));
        const ends = [...before, ...after].every((poly) => pointPolygonDistance(s, poly) > clearance && pointPolygonDistance(g, poly) > clearance);
        const line = before.every((poly) => segmentPolygonDistance(s, g, poly) > clearance);
        if (inMaps && ends && line) route = { start: s, goal: g, box: m.name };
      }
      if (route) break;
    }
    if (route) break;
  }
  check(route, 'no start and goal on either side of a box of photo 2\'s after the swap are clear of the boxes of either map');
  log(`start ${route.start.map((v) => v.toFixed(3))}, goal ${route.goal.map((v) => v.toFixed(3))}: across where ${route.box} goes after the swap`);
  const { start, goal } = route;
  const straight = dist(start, goal);

  const lengthBefore = await step('2. a plan across where a box of photo 2\'s goes after the swap', async () => {
    await page.check('#opt-unknown-passable');
    const s0 = await status();
    await page.fill('#plan-start', `${start[0].toFixed(3)}, ${start[1].toFixed(3)}`);
    await page.dispatchEvent('#plan-start', 'change');
    await page.fill('#plan-goal', `${goal[0].toFixed(3)}, ${goal[1].toFixed(3)}`);
    await page.dispatchEvent('#plan-goal', 'change');
    const s = await settle('planning', 'plans', s0.plans);
    check(!s.planError, `the plan failed: ${s.planError}`);
    const len = mbppLength(s);
    check(len !== null, `no MBPP path: ${JSON.stringify(s.plan?.results?.map((r) => [r.planner, r.found]))}`);
    log(`before the swap: MBPP ${len.toFixed(3)} m, straight ${straight.toFixed(3)} m`);
    check(len < straight * 1.01 + 0.1, `the path (${len.toFixed(3)} m) is not straight on a clear line (${straight.toFixed(3)} m)`);
    noProblems();
    return len;
  });

  await step('3. Swap: the room file pins photo 2, the map, the plan and the cameras follow', async () => {
    const s0 = await status();
    const alt = first.alternatives[0];
    await page.click('#placements li.alternative[data-photo="1"] button.swap');
    const s = await settle('building the swapped room', 'builds', s0.builds);
    check(!s.buildError, `the swapped room did not build: ${s.buildError}`);
    const sent = await roomNow();
    check(sent.photos[1].placement_turn_deg === alt.placement_turn_deg, `photo 2's placement_turn_deg: ${sent.photos[1].placement_turn_deg}, the alternative's: ${alt.placement_turn_deg}`);
    check(sent.photos[0].placement_turn_deg === undefined, 'photo 1 got a placement_turn_deg');
    const map = await mapNow();
    check(!map.alternatives || map.alternatives.length === 0, `alternatives after the swap: ${JSON.stringify(map.alternatives)}`);
    check(dist(centroid(map, SHARED), c) < 1e-6, `the shared box moved: ${centroid(map, SHARED)} vs ${c}`);
    const want = turned(camera2(first), c);
    check(dist(camera2(map), want) < 1e-6, `photo 2's camera at ${camera2(map)}, the alternative puts it at ${want}`);
    check(dist(camera2(map), camera2(first)) > 0.5, 'photo 2\'s camera did not move');
    check(dist(centroid(map, OWN), ownAfter) < 1e-6, `photo 2's box at ${centroid(map, OWN)}, the alternative puts it at ${ownAfter}`);
    check(map.warnings.some((w) => w.includes('photo 2\'s placement is pinned')), `no warning that photo 2 is pinned: ${JSON.stringify(map.warnings)}`);
    // The plan draws photo 2's camera at its new place.
    await page.waitForFunction(() => document.querySelectorAll('#plan-host .vp-camera').length === 2, null, { timeout: 10_000 });
    const disc = await page.locator('#plan-host .vp-camera[data-photo="1"] circle').boundingBox();
    const at = await page.evaluate(([x, y]) => window.vpmap.planMapToClient(x, y), want);
    check(Math.hypot(disc.x + disc.width / 2 - at[0], disc.y + disc.height / 2 - at[1]) < 1.5, `camera 2 drawn at ${[disc.x, disc.y]}, its position is at ${at}`);
    // The page lists photo 2 as pinned, with Unpin.
    const row = page.locator('#placements li.pinned[data-photo="1"]');
    check((await row.count()) === 1 && (await row.locator('button.unpin').isVisible()), 'photo 2 is not listed as pinned with Unpin');
    check((await page.locator('#placements li.alternative').count()) === 0, 'an alternative is still offered');
    // The plan is re-run on the swapped map: the box now stands in the way.
    const p = await settle('planning on the swapped map', 'plans', s0.plans);
    check(!p.planError, `the plan on the swapped map failed: ${p.planError}`);
    const len = mbppLength(p);
    check(len !== null, 'no MBPP path on the swapped map');
    log(`after the swap: MBPP ${len.toFixed(3)} m (before ${lengthBefore.toFixed(3)} m, straight ${straight.toFixed(3)} m)`);
    check(len > straight + 0.05 && len > lengthBefore + 0.05, `the path (${len.toFixed(3)} m) does not go round ${route.box}, now in its way (straight ${straight.toFixed(3)} m, before the swap ${lengthBefore.toFixed(3)} m)`);
    await page.locator('#placements').scrollIntoViewIfNeeded();
    await page.waitForTimeout(200);
    await page.screenshot({ path: SHOT('swapped') });
    noProblems();
  });

  await step('4. Unpin: the fit chooses again, the first map comes back', async () => {
    const s0 = await status();
    await page.click('#placements li.pinned[data-photo="1"] button.unpin');
    const s = await settle('building the unpinned room', 'builds', s0.builds);
    check(!s.buildError, `the unpinned room did not build: ${s.buildError}`);
    check((await roomNow()).photos[1].placement_turn_deg === undefined, 'photo 2 is still pinned');
    const map = await mapNow();
    check(dist(camera2(map), camera2(first)) < 1e-6, `photo 2's camera at ${camera2(map)}, first at ${camera2(first)}`);
    check((await page.locator('#placements li.alternative[data-photo="1"]').count()) === 1, 'the alternative is not offered again');
    check((await page.locator('#placements input.swap-pick').count()) === 0, 'check boxes for a single alternative');
    noProblems();
  });

  // Photo 3: photo 2 again, its objects other than the shared box named apart.
  const three = JSON.parse(JSON.stringify(room));
  const copy = JSON.parse(JSON.stringify(room.photos[1]));
  for (const o of copy.objects) if (o.name !== SHARED) o.name = `${o.name}-seen-from-3`;
  three.photos.push(copy);
  const threeFile = join(tmp, 'two-ties.room.json');
  await writeFile(threeFile, JSON.stringify(three));
  const cameraOf = (map, k) => map.cameras[k].position.slice(0, 2);

  const tied = await step('5a. a room with two tied photos: two alternatives, each with a check box', async () => {
    const s0 = await status();
    await page.setInputFiles('#scene-input', threeFile);
    await page.waitForFunction((n) => window.vpmap.status().photos === n, three.photos.length, { timeout: 10_000 });
    const s = await settle('building the room of two ties', 'builds', s0.builds);
    check(!s.buildError, `the room did not build: ${s.buildError}`);
    const map = await mapNow();
    const photos = (map.alternatives || []).map((a) => a.photo).sort();
    check(photos.length === 2 && photos[0] === 2 && photos[1] === 3, `map.alternatives: ${JSON.stringify(map.alternatives)}`);
    check(map.alternatives.every((a) => a.turn_deg === 180), `the turns: ${JSON.stringify(map.alternatives)}`);
    for (const photo of [1, 2]) {
      check((await page.locator(`#placements li.alternative[data-photo="${photo}"] input.swap-pick`).count()) === 1, `no check box for photo ${photo + 1}`);
    }
    const together = page.locator('#placements button.swap-together');
    check((await together.count()) === 1 && (await together.isDisabled()), 'Swap checked together is missing or enabled with nothing checked');
    await page.locator('#placements').scrollIntoViewIfNeeded();
    await page.screenshot({ path: SHOT('two-ties') });
    noProblems();
    return map;
  });

  await step('5b. both checked and swapped together: one build, both pinned, both cameras turned', async () => {
    const c3 = centroid(tied, SHARED);
    const s0 = await status();
    await page.check('#placements li.alternative[data-photo="1"] input.swap-pick');
    await page.check('#placements li.alternative[data-photo="2"] input.swap-pick');
    check(await page.isEnabled('#placements button.swap-together'), 'Swap checked together stays disabled');
    await page.click('#placements button.swap-together');
    const s = await settle('building the room with both photos swapped', 'builds', s0.builds);
    check(!s.buildError, `the swapped room did not build: ${s.buildError}`);
    check(s.builds === s0.builds + 1, `${s.builds - s0.builds} builds for one swap of two photos`);
    const sent = await roomNow();
    for (const a of tied.alternatives) {
      check(sent.photos[a.photo - 1].placement_turn_deg === a.placement_turn_deg, `photo ${a.photo}'s placement_turn_deg: ${sent.photos[a.photo - 1].placement_turn_deg}, its alternative's: ${a.placement_turn_deg}`);
    }
    const map = await mapNow();
    check(!map.alternatives || map.alternatives.length === 0, `alternatives after the swap: ${JSON.stringify(map.alternatives)}`);
    check(dist(centroid(map, SHARED), c3) < 1e-6, `the shared box moved: ${centroid(map, SHARED)} vs ${c3}`);
    for (const k of [1, 2]) {
      const want = turned(cameraOf(tied, k), c3);
      check(dist(cameraOf(map, k), want) < 1e-6, `photo ${k + 1}'s camera at ${cameraOf(map, k)}, its alternative puts it at ${want}`);
      check(dist(cameraOf(map, k), cameraOf(tied, k)) > 0.5, `photo ${k + 1}'s camera did not move`);
      check((await page.locator(`#placements li.pinned[data-photo="${k}"] button.unpin`).count()) === 1, `photo ${k + 1} is not listed as pinned with Unpin`);
      check(map.warnings.some((w) => w.startsWith(`photo ${k + 1}'s placement is pinned`)), `the map does not warn that photo ${k + 1} is pinned`);
    }
    // Said once: the pinned rows, not the warnings list as well.
    const listed = await page.locator('#warnings li').allTextContents();
    check(!listed.some((w) => w.includes('placement is pinned')), `the warnings list says the pins again: ${JSON.stringify(listed)}`);
    check((await page.locator('#placements li.alternative').count()) === 0, 'an alternative is still offered');
    await page.locator('#placements').scrollIntoViewIfNeeded();
    await page.waitForTimeout(200);
    await page.screenshot({ path: SHOT('together') });
    noProblems();
  });
}

main()
  .then(pass)
  .catch((err) => fail(err && err.stack ? err.stack : String(err)));
