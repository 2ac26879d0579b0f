// Browser checks of the page's usability, the way a new user meets it (the bugs of issue 14,
// "first contact as people expect it"), each in a fresh page of headless Chromium against
// `vpmap serve`:
//
//   1. the page never scrolls off screen (wheel over the top bar and the plan legend, Tab to
//      "Set start"), at 1366 x 768 and 1920 x 1080;
//   2. the 3D view frames the model when it changes from empty to something (open a photo,
//      Detect, add a box);
//   3. a box's base corner dragged off its guide line stays on it, so a floor distance set on
//      two of the box's corners and the box report the same length;
//   4. opening a photo of another size clears the undo history, and Save writes its size;
//   5. a planning error names the plan pane's own options ("unknown as passable", "hidden floor
//      as free", checkboxes that work), with rounded numbers, and the pane keeps its size;
//   6. hovering a pressed tool button keeps its label readable;
//   7. a floor corner above the horizon is refused while placing, and the point a build error
//      names is marked on the photo;
//   and no lost work: the annotations are kept per photo in the browser and come back when the
//   same photo is opened again; leaving with unsaved changes asks first.
//
// No console error or warning is allowed in any page (except where a step expects the
// browser's own log line of a refused request). Same environment as e2e.mjs (VPMAP_BIN,
// VPMAP_URL, VPMAP_E2E_CHROMIUM, VPMAP_E2E_SCREENSHOT, VPMAP_E2E_HEADED); exits 0 with
// `USABILITY PASSED`, or 1 naming the failed step.

import { mkdtemp, readFile, writeFile } from 'node:fs/promises';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { greyPng, launchChromium, startServer, testRun } from './harness.mjs';
import { segmentCorners } from '../assets/js/geometry.js';

const TOTAL_MS = 150_000;
const SCREENSHOT = (process.env.VPMAP_E2E_SCREENSHOT || '/tmp/vpmap-e2e.png').replace(/(\.png)?$/, '-usability.png');
// Free floor of the example (map metres), as in e2e.mjs.
const PLAN_GOAL = [0.2, 5.0];

let server = null;
let browser = null;
let page = null;
let tmp = null;
// USABILITY_ONLY=2,3: run only the numbered steps given (for working on one bug).
const ONLY = (process.env.USABILITY_ONLY || '').split(',').filter(Boolean);
const { log, check, step, fail, pass } = testRun({
  label: 'USABILITY',
  totalMs: TOTAL_MS,
  failureShot: SCREENSHOT.replace(/(\.png)?$/, '-failed.png'),
  resources: () => ({ server, browser, page, tmp }),
  only: ONLY,
});

let url;
let problems = [];
const noProblems = () => check(problems.length === 0, problems.join('\n'));
/** Take the browser's log line of a refused request (expected by the step) out of the problems. */
function expectRefused(status) {
  const i = problems.findIndex((m) => m.includes(`status of ${status}`));
  check(i >= 0, `the refused request (${status}) left no trace in the console`);
  problems.splice(i, 1);
}

/** A fresh page (closing the last one) of `width` x `height`, with the console watched. */
async function freshPage(width = 1600, height = 1000, context = null) {
  if (page) await page.close();
  page = await (context || browser).newPage({ viewport: { width, height }, acceptDownloads: true });
  page.on('console', (m) => {
    if (m.type() === 'error' || m.type() === 'warning') problems.push(`console ${m.type()}: ${m.text()}`);
  });
  page.on('pageerror', (e) => problems.push(`uncaught exception: ${e.message}`));
  page.on('request', (r) => {
    const u = r.url();
    if (!u.startsWith(url) && !u.startsWith('data:') && !u.startsWith('blob:')) problems.push(`external request: ${u}`);
  });
  const res = await page.goto(url, { waitUntil: 'load' });
  check(res && res.ok(), `GET ${url} answered ${res && res.status()}`);
  await page.waitForFunction(() => !!window.vpmap, null, { timeout: 10_000 });
  return page;
}

const status = () => page.evaluate(() => window.vpmap.status());
const sceneNow = () => page.evaluate(() => window.vpmap.scene());
const mapNow = () => page.evaluate(() => window.vpmap.map());

/** Wait until the counters reach `want` and nothing is pending or running; throws on a build error unless `allowError`. */
async function settle(what, want, { timeout = 30_000, allowError = false } = {}) {
  try {
    await page.waitForFunction(
      (w) => {
        const s = window.vpmap.status();
        return !s.pending && s.busy.length === 0 && Object.entries(w).every(([k, v]) => s[k] >= v);
      },
      want,
      { timeout, polling: 50 },
    );
  } catch {
    const s = await status();
    throw new Error(`${what} did not finish: ${JSON.stringify({ busy: s.busy, builds: s.builds, plans: s.plans, detects: s.detects, buildError: s.buildError })}`);
  }
  const s = await status();
  if (s.buildError && !allowError) throw new Error(`the build failed: ${s.buildError}`);
  return s;
}

async function loadExample() {
  await page.click('#btn-example');
  await settle('building the example', { builds: 1 }, { timeout: 60_000 });
  await page.waitForSelector('#plan-host svg', { timeout: 10_000 });
}

const client = (p) => page.evaluate(([x, y]) => window.vpmap.imageToClient(x, y), p);
/**
 * Viewport coordinates of an image point once the photo view has stopped moving (a build that
 * lands re-lays the page out, and the fitted photo shifts under the pointer): two readings
 * 150 ms apart agree.
 */
async function stableClient(p) {
  let a = await client(p);
  for (let k = 0; k < 40; k++) {
    await page.waitForTimeout(150);
    const b = await client(p);
    if (Math.hypot(b[0] - a[0], b[1] - a[1]) < 0.01) return b;
    a = b;
  }
  throw new Error(`the photo view kept moving: image point ${p} at ${a}`);
}
async function clickImage(p) {
  const [x, y] = await client(p);
  await page.mouse.click(x, y);
}
const planClient = (p) => page.evaluate(([x, y]) => window.vpmap.planMapToClient(x, y), p);

/** Scroll offsets of the document and of the window. */
const scrolled = () => page.evaluate(() => ({
  top: document.scrollingElement.scrollTop,
  left: document.scrollingElement.scrollLeft,
  y: window.scrollY,
  height: document.scrollingElement.scrollHeight,
  inner: window.innerHeight,
}));

/** WCAG contrast ratio of two CSS rgb() colours. */
function contrast(a, b) {
  const lum = (c) => {
    const v = c.match(/\d+(\.\d+)?/g).slice(0, 3).map((x) => Number(x) / 255).map((x) => (x <= 0.03928 ? x / 12.92 : ((x + 0.055) / 1.055) ** 2.4));
    return 0.2126 * v[0] + 0.7152 * v[1] + 0.0722 * v[2];
  };
  const [l1, l2] = [lum(a), lum(b)].sort((x, y) => y - x);
  return (l1 + 0.05) / (l2 + 0.05);
}

async function main() {
  url = await step('start the server', async () => {
    const started = await startServer({ log });
    server = started.server;
    return started.url;
  });
  log(`server at ${url}`);
  await step('launch Chromium', async () => {
    browser = await launchChromium();
  });
  tmp = await mkdtemp(join(tmpdir(), 'vpmap-usability-'));
  const example = await (await fetch(`${url}api/example`)).json();
  const examplePng = join(tmp, 'office.png');
  await writeFile(examplePng, Buffer.from(example.photo_png_base64, 'base64'));
  const crate = example.scene.objects.findIndex((o) => o.name === 'crate');
  // Another photo: 800 x 600 grey (a PNG with one zlib-stored row per line).
  await writeFile(join(tmp, 'other.png'), greyPng(800, 600));
  // Small and far: a few pixels off its edge's line are many centimetres.
  const bookcase = example.scene.objects.findIndex((o) => o.name === 'bookcase');

  for (const [w, h] of [[1366, 768], [1920, 1080]]) {
    await step(`1. the page stays put at ${w} x ${h}`, async () => {
      await freshPage(w, h);
      await loadExample();
      // A plan, so that its results table (and its caption) is there too.
      await page.fill('#plan-start', '1.1, 1.7');
      await page.press('#plan-start', 'Tab');
      await page.fill('#plan-goal', PLAN_GOAL.join(', '));
      await page.press('#plan-goal', 'Tab');
      await settle('planning', { plans: 1 }, { timeout: 60_000 });
      let s = await scrolled();
      check(s.height <= s.inner, `the document is ${s.height} px high in a ${s.inner} px window`);
      for (const sel of ['.topbar', '.layers', '#plan-table', '.camera-bar']) {
        const box = await page.locator(sel).boundingBox();
        check(box, `${sel} is not shown`);
        await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
        await page.mouse.wheel(0, 600);
        await page.waitForTimeout(150);
        s = await scrolled();
        check(s.top === 0 && s.y === 0 && s.left === 0, `a wheel over ${sel} scrolled the page by ${s.top} px`);
      }
      // Tab from the top of the page to "Set start".
      await page.mouse.click(5, 5);
      let reached = false;
      for (let i = 0; i < 120 && !reached; i++) {
        await page.keyboard.press('Tab');
        reached = await page.evaluate(() => document.activeElement?.id === 'pick-start');
      }
      check(reached, 'Tab never reached "Set start"');
      s = await scrolled();
      check(s.top === 0 && s.y === 0, `tabbing to "Set start" scrolled the page by ${s.top} px`);
      const top = await page.locator('.topbar').boundingBox();
      check(top && top.y === 0, `the top bar is at y ${top?.y}`);
      noProblems();
      if (w === 1366) await page.screenshot({ path: SCREENSHOT.replace(/(\.png)?$/, '-1366.png') });
    });
  }

  await step('2. the 3D view frames the model once it has objects', async () => {
    await freshPage();
    await page.setInputFiles('#photo-input', examplePng);
    await page.waitForFunction(() => !!window.vpmap.scene(), null, { timeout: 10_000 });
    await page.click('#btn-detect');
    await settle('detection and its build', { detects: 1, builds: 1 });
    await page.waitForFunction(() => window.vpmap.view3d()?.loads >= 1, null, { timeout: 30_000 });
    const first = await page.evaluate(() => window.vpmap.view3d());
    const o = example.scene.objects[crate];
    const builds = (await status()).builds;
    await page.click('#btn-add-box');
    for (const p of [o.base.near, o.base.right, o.base.left, o.top.near, o.top.left]) await clickImage(p);
    await page.keyboard.press('Enter');
    await page.waitForSelector('#prompt[data-tool="select"]');
    await page.keyboard.press('Escape');
    await settle('the build with a box', { builds: builds + 1 });
    await page.waitForFunction((n) => window.vpmap.view3d()?.loads > n, first.loads, { timeout: 30_000 });
    const v = await page.evaluate(() => window.vpmap.view3d());
    // Every corner of the model's bounding box in view, and the model not a speck.
    const out = v.corners.filter(([x, y, z]) => !(Math.abs(x) <= 1 && Math.abs(y) <= 1 && z < 1));
    check(out.length === 0, `${out.length} of the model's bounding-box corners are outside the 3D view: ${JSON.stringify(v)}`);
    const xs = v.corners.map((c) => c[0]), ys = v.corners.map((c) => c[1]);
    const span = Math.max(Math.max(...xs) - Math.min(...xs), Math.max(...ys) - Math.min(...ys)) / 2;
    check(span > 0.3, `the model fills ${(100 * span).toFixed(0)} % of the 3D view`);
    await page.locator('#model-host').screenshot({ path: SCREENSHOT.replace(/(\.png)?$/, '-3d.png') });
    noProblems();
  });

  await step('3. a box and a floor distance on its corners agree', async () => {
    await freshPage();
    await loadExample();
    let s = await status();
    const box = (await sceneNow()).objects[bookcase].base;
    // Drag the right base corner 8 px across its edge (near -> right), with Alt: a plain drag
    // keeps a corner this near its line on it (step 16).
    const d = [box.right[0] - box.near[0], box.right[1] - box.near[1]];
    const len = Math.hypot(d[0], d[1]);
    const off = [box.right[0] - (8 * d[1]) / len, box.right[1] + (8 * d[0]) / len];
    const a = await stableClient(box.right);
    const b = await client(off);
    await page.mouse.move(a[0], a[1]);
    await page.mouse.down();
    await page.keyboard.down('Alt');
    for (let i = 1; i <= 5; i++) await page.mouse.move(a[0] + ((b[0] - a[0]) * i) / 5, a[1] + ((b[1] - a[1]) * i) / 5);
    await page.mouse.up();
    await page.keyboard.up('Alt');
    s = await settle('the build after the drag', { builds: s.builds + 1 });
    const moved = (await sceneNow()).objects[bookcase].base;
    check(Math.hypot(moved.right[0] - box.right[0], moved.right[1] - box.right[1]) > 1, 'the drag did not move the corner');
    // Said where the user looks: the object list gives the distance off the line.
    const info = await page.locator(`#object-list li[data-index="${bookcase}"] .obj-info`).textContent();
    check(/base\.right is \d+\.\d px off/.test(info), `the object list does not say the corner is off its line: ${JSON.stringify(info)}`);
    // A floor distance of 1.6 m on the same two corners.
    await page.fill('#scale-floor-m', '1.6');
    await page.click('#btn-floor-distance');
    await clickImage(moved.near);
    await clickImage(moved.right);
    s = await settle('the build with the floor distance', { builds: s.builds + 1 });
    const sc = (await sceneNow()).scale;
    check((sc?.floor_distance?.meters ?? sc?.meters) === 1.6, `the scale is ${JSON.stringify(sc)}`);
    const fp = (await mapNow()).objects[bookcase].footprint;
    const edge = Math.hypot(fp[1][0] - fp[0][0], fp[1][1] - fp[0][1]);
    log(`  floor distance 1.6 m; the box's near-right edge ${edge.toFixed(3)} m`);
    await page.screenshot({ path: SCREENSHOT.replace(/(\.png)?$/, '-off-line.png') });
    check(Math.abs(edge - 1.6) <= 0.016, `the floor distance says 1.6 m, the box's edge on the same corners ${edge.toFixed(3)} m`);
    noProblems();
  });

  await step('4. undo stops at a change of photo', async () => {
    await freshPage();
    await loadExample();
    const halfPng = join(tmp, 'other.png');
    await page.setInputFiles('#photo-input', halfPng);
    await page.waitForFunction(() => window.vpmap.scene()?.image.width === 800, null, { timeout: 10_000 });
    check(await page.isDisabled('#btn-undo'), 'Undo is offered right after opening another photo');
    await page.focus('#photo-canvas');
    await page.keyboard.press('Control+z');
    const sc = await sceneNow();
    check(sc.objects.length === 0 && sc.image.width === 800 && sc.image.height === 600, `undo brought back ${sc.objects.length} objects for a ${sc.image.width} x ${sc.image.height} photo`);
    const [dl] = await Promise.all([page.waitForEvent('download'), page.click('#btn-save-scene')]);
    const saved = JSON.parse(await readFile(await dl.path(), 'utf8'));
    check(dl.suggestedFilename() === 'other.scene.json', `saved as ${dl.suggestedFilename()}`);
    check(saved.image.width === 800 && saved.image.height === 600, `Save wrote ${JSON.stringify(saved.image)} for an 800 x 600 photo`);
    noProblems();
  });


  await step('5. a planning error names the pane\'s own options', async () => {
    // A cell of hidden floor (unknown, behind an object) away from anything else, from the
    // build the page makes of the example (same settings: robot radius 0.2 m).
    const built = await (await fetch(`${url}api/build?resolution=0.05&robot_radius=0.2`, {
      method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(example.scene),
    })).json();
    const occ = built.occupancy;
    const pgm = Buffer.from(occ.pgm_base64, 'base64');
    let pos = 0, fields = 0;
    while (fields < 4) {
      while (/\s/.test(String.fromCharCode(pgm[pos]))) pos++;
      while (!/\s/.test(String.fromCharCode(pgm[pos]))) pos++;
      fields++;
    }
    pos++;
    const cell = (c, r) => pgm[pos + r * occ.width + c];
    const inside = (p, ring) => {
      let inn = false;
      for (let i = 0, j = ring.length - 1; i < ring.length; j = i++) {
        const [xi, yi] = ring[i], [xj, yj] = ring[j];
        if ((yi > p[1]) !== (yj > p[1]) && p[0] < ((xj - xi) * (p[1] - yi)) / (yj - yi) + xi) inn = !inn;
      }
      return inn;
    };
    const unknown = cell(0, 0);
    let hidden = null;
    for (let r = 6; r < occ.height - 6 && !hidden; r++) {
      for (let c = 6; c < occ.width - 6 && !hidden; c++) {
        const p = [occ.origin[0] + (c + 0.5) * occ.resolution, occ.origin[1] + (occ.height - r - 0.5) * occ.resolution];
        if (!built.map.hidden.some((hd) => inside(p, hd.exterior))) continue;
        let all = true;
        for (let dr = -6; dr <= 6 && all; dr++) for (let dc = -6; dc <= 6 && all; dc++) all = cell(c + dc, r + dr) === unknown;
        if (all) hidden = p;
      }
    }
    check(hidden, 'the example has no hidden floor to start on');
    await freshPage();
    await loadExample();
    const host = await page.locator('#plan-host').boundingBox();
    for (const p of [hidden, PLAN_GOAL]) {
      const q = await planClient(p);
      await page.mouse.click(q[0], q[1]);
    }
    await page.waitForFunction(() => window.vpmap.status().planError, null, { timeout: 30_000 });
    expectRefused(400);
    const text = await page.textContent('#plan-status');
    log(`  ${text}`);
    await page.screenshot({ path: SCREENSHOT.replace(/(\.png)?$/, '-plan-error.png') });
    check(!/unknown_passable|hidden_free/.test(text), `the error names API fields: ${text}`);
    check(text.includes('“unknown as passable”') && text.includes('“hidden floor as free”'), `the error does not name the pane's options: ${text}`);
    check(!/\d\.\d{4,}/.test(text), `the error prints long numbers: ${text}`);
    const after = await page.locator('#plan-host').boundingBox();
    check(Math.abs(after.height - host.height) < 0.5 && Math.abs(after.width - host.width) < 0.5, `the floor plan went from ${host.width} x ${host.height} to ${after.width} x ${after.height}`);
    // The options named are there and do what they say.
    let s = await status();
    await page.getByLabel('unknown as passable').check();
    s = await settle('planning through unknown floor', { plans: s.plans + 1 });
    check(s.planError === null && s.plan.results.some((r) => r.found), `with “unknown as passable”: ${s.planError}`);
    await page.getByLabel('unknown as passable').uncheck();
    await page.waitForFunction(() => window.vpmap.status().planError, null, { timeout: 30_000 });
    expectRefused(400);
    s = await status();
    await page.getByLabel('hidden floor as free').check();
    s = await settle('the build and plan with hidden floor free', { builds: s.builds + 1, plans: s.plans + 1 });
    check(s.planError === null && s.plan.results.some((r) => r.found), `with “hidden floor as free”: ${s.planError}`);
    noProblems();
  });


  await step('6. a pressed tool button keeps its label under the pointer', async () => {
    await freshPage();
    await loadExample();
    await page.click('#btn-add-box');
    check(await page.getAttribute('#btn-add-box', 'aria-pressed') === 'true', 'Add box is not shown pressed while placing');
    const b = await page.locator('#btn-add-box').boundingBox();
    await page.mouse.move(b.x + b.width / 2, b.y + b.height / 2);
    await page.waitForTimeout(100);
    const look = await page.evaluate(() => {
      const st = getComputedStyle(document.getElementById('btn-add-box'));
      return { color: st.color, background: st.backgroundColor, accent: getComputedStyle(document.documentElement).getPropertyValue('--accent') };
    });
    const ratio = contrast(look.color, look.background);
    check(ratio >= 4.5, `hovered and pressed, Add box reads ${look.color} on ${look.background} (contrast ${ratio.toFixed(2)})`);
    await page.keyboard.press('Escape');
    noProblems();
  });

  await step('7. floor points above the horizon are refused; a build error marks its point', async () => {
    await freshPage();
    await loadExample();
    const cam = (await status()).camera;
    const [h0, h1] = cam.horizon;
    const x = 800;
    const hy = h0[1] + ((h1[1] - h0[1]) * (x - h0[0])) / (h1[0] - h0[0]);
    await page.click('#btn-floor');
    await clickImage([x, hy - 30]);
    const prompt = await page.textContent('#prompt-text');
    check(/\(0 so far\)/.test(prompt), `a floor corner above the horizon was taken: "${prompt}"`);
    const said = `${await page.textContent('#prompt')} ${await page.textContent('#error-text')}`;
    check(/above the horizon/.test(said), `nothing says the point is above the horizon: "${said}"`);
    await clickImage([x, hy + 300]);
    check(/\(1 so far\)/.test(await page.textContent('#prompt-text')), 'a floor corner below the horizon was not taken');
    await page.keyboard.press('Escape');
    // A floor corner dragged above the horizon: the build fails and marks that corner.
    const sc = await sceneNow();
    const i = sc.floor.reduce((best, p, j) => (p[1] < sc.floor[best][1] ? j : best), 0);
    const a = await stableClient(sc.floor[i]);
    const b = await client([sc.floor[i][0], hy - 40]);
    const builds = (await status()).builds;
    await page.mouse.move(a[0], a[1]);
    await page.mouse.down();
    for (let k = 1; k <= 5; k++) await page.mouse.move(a[0], a[1] + ((b[1] - a[1]) * k) / 5);
    await page.mouse.up();
    await page.waitForFunction(() => window.vpmap.status().buildError && !window.vpmap.status().pending && window.vpmap.status().busy.length === 0, null, { timeout: 30_000 });
    expectRefused(400);
    const s = await status();
    check(s.buildError.includes(`floor[${i}]`), `the build error is about something else: ${s.buildError}`);
    check(JSON.stringify(s.marked) === JSON.stringify(['floor', i]), `the photo marks ${JSON.stringify(s.marked)}, not floor[${i}]`);
    await page.screenshot({ path: SCREENSHOT.replace(/(\.png)?$/, '-marked.png') });
    await page.keyboard.press('Control+z');
    await settle('the build after undo', { builds: builds + 1 });
    check((await status()).marked === null, 'the mark stays after the error is gone');
    noProblems();
  });


  await step('8. no lost work: kept per photo, asked before leaving', async () => {
    // One browser profile (context) for both visits, as a user's browser.
    const context = await browser.newContext({ acceptDownloads: true });
    await freshPage(1600, 1000, context);
    await page.setInputFiles('#photo-input', examplePng);
    await page.waitForFunction(() => !!window.vpmap.scene(), null, { timeout: 10_000 });
    const floor = [[200, 1100], [1400, 1100], [1300, 700]];
    await page.click('#btn-floor');
    for (const p of floor) await clickImage(p);
    await page.keyboard.press('Enter');
    await page.waitForSelector('#prompt[data-tool="select"]');
    check((await sceneNow()).floor.length === 3, 'the floor was not placed');
    await page.waitForTimeout(700); // the autosave's delay
    // Leaving asks first; staying keeps the page.
    const asked = [];
    page.on('dialog', (d) => {
      asked.push(d.type());
      d.dismiss().catch(() => {});
    });
    const dirty = await page.evaluate(() => window.vpmap.status().unsaved);
    await page.close({ runBeforeUnload: true });
    await new Promise((r) => setTimeout(r, 500));
    check(asked.includes('beforeunload'), `leaving with unsaved changes (${dirty}) did not ask (dialogs: ${JSON.stringify(asked)})`);
    check(!page.isClosed(), 'the page closed although the user chose to stay');
    // Saved to a file: leaving asks nothing.
    await Promise.all([page.waitForEvent('download'), page.click('#btn-save-scene')]);
    asked.length = 0;
    await page.close({ runBeforeUnload: true });
    await new Promise((r) => setTimeout(r, 500));
    check(asked.length === 0 && page.isClosed(), `leaving after Save asked ${JSON.stringify(asked)}`);
    page = null;
    // The same photo again, in a new visit: the floor comes back; another photo starts empty.
    await freshPage(1600, 1000, context);
    await page.setInputFiles('#photo-input', examplePng);
    await page.waitForFunction(() => !!window.vpmap.scene(), null, { timeout: 10_000 });
    const back = await sceneNow();
    check(back.floor.length === 3 && back.floor.every((p, i) => Math.hypot(p[0] - floor[i][0], p[1] - floor[i][1]) < 3), `reopening the photo gave floor ${JSON.stringify(back.floor)}`);
    check(/are back/.test(await page.textContent('#status')), `the status does not say the annotations came back: ${await page.textContent('#status')}`);
    check(await page.isDisabled('#btn-undo'), 'Undo is offered right after reopening');
    await page.setInputFiles('#photo-input', join(tmp, 'other.png'));
    await page.waitForFunction(() => window.vpmap.scene()?.image.width === 800, null, { timeout: 10_000 });
    check((await sceneNow()).floor.length === 0, 'another photo got the kept floor');
    noProblems();
    await page.close();
    page = null;
    await context.close();
  });


  await step('9. a click inside an object selects it', async () => {
    await freshPage();
    await loadExample();
    // The middle of the bookcase's left face: above its base, inside its outline in the photo.
    const o = example.scene.objects[bookcase];
    const pts = [o.base.near, o.base.left, o.top.near, o.top.left];
    const mid = [pts.reduce((a, p) => a + p[0], 0) / 4, pts.reduce((a, p) => a + p[1], 0) / 4];
    await clickImage(mid);
    const sel = await page.evaluate(() => document.querySelector('#object-list li.selected')?.dataset.index ?? null);
    check(sel === String(bookcase), `a click on the bookcase's face selected ${sel === null ? 'nothing' : `object ${sel}`}`);
    noProblems();
  });


  await step('10. detected lines stay out of the way', async () => {
    await freshPage();
    await loadExample();
    await page.click('#btn-new-scene');
    await page.click('#btn-detect');
    await settle('detection', { detects: 1 });
    const lines = async () => (await sceneNow()).vanishing_points.map((v) => v.lines || []);
    const before = await lines();
    // The longest detected line of the first direction.
    const k = 0;
    const j = before[k].reduce((b, l, i, all) => (Math.hypot(l[2] - l[0], l[3] - l[1]) > Math.hypot(all[b][2] - all[b][0], all[b][3] - all[b][1]) ? i : b), 0);
    const l = before[k][j];
    const drag = async (p, dx, dy) => {
      const a = await stableClient(p);
      await page.mouse.move(a[0], a[1]);
      await page.mouse.down();
      for (let i = 1; i <= 4; i++) await page.mouse.move(a[0] + (dx * i) / 4, a[1] + (dy * i) / 4);
      await page.mouse.up();
    };
    // A drag that starts on a line's end pans the photo: the line stays.
    await drag([l[0], l[1]], 40, 30);
    check(JSON.stringify(await lines()) === JSON.stringify(before), 'a drag from a detected line\'s end moved it (it should pan)');
    await page.click('#btn-fit');
    // Selected (a click on it), its ends can be dragged.
    await clickImage([(l[0] + l[2]) / 2, (l[1] + l[3]) / 2]);
    check(JSON.stringify((await status()).selection) === JSON.stringify({ type: 'vpline', vp: k, line: j }), `a click on the line selected ${JSON.stringify((await status()).selection)}`);
    await drag([l[0], l[1]], 20, 0);
    const moved = (await lines())[k][j];
    check(Math.hypot(moved[0] - l[0], moved[1] - l[1]) > 5, 'the selected line\'s end did not follow the drag');
    // "Show detected segments" off: no line can be selected or dragged.
    await page.keyboard.press('Control+z');
    await page.uncheck('#show-segments');
    check((await status()).selection === null, 'hiding the segments kept a line selected');
    await clickImage([(l[0] + l[2]) / 2, (l[1] + l[3]) / 2]);
    check((await status()).selection === null, 'a hidden line was selected');
    await drag([l[0], l[1]], 20, 0);
    check(JSON.stringify(await lines()) === JSON.stringify(before), 'a hidden line was dragged');
    noProblems();
  });


  await step('11. guidance fits at 1366 x 768: prompt, camera bar, keys', async () => {
    await freshPage(1366, 768);
    await loadExample();
    /** Elements (selectors) whose text is cut: clipped by their own box or outside their container's. */
    const cut = (sels, container) => page.evaluate(([list, c]) => {
      const outer = document.querySelector(c).getBoundingClientRect();
      const bad = [];
      for (const sel of list) {
        for (const el of document.querySelectorAll(sel)) {
          if (!el.offsetParent || !el.textContent.trim()) continue;
          const r = el.getBoundingClientRect();
          const clipped = el.scrollWidth > el.clientWidth + 1 || el.scrollHeight > el.clientHeight + 1;
          const outside = r.left < outer.left - 0.5 || r.right > outer.right + 0.5 || r.top < outer.top - 0.5 || r.bottom > outer.bottom + 0.5;
          if (clipped || outside) bad.push(`${sel} "${el.textContent.trim().slice(0, 40)}"${clipped ? ' clipped' : ''}${outside ? ' outside' : ''}`);
        }
      }
      return bad;
    }, [sels, container]);
    let bad = await cut(['.cam-values > span'], '.cam-values');
    check(bad.length === 0, `the camera bar cuts: ${bad.join('; ')}`);
    const photo = await page.locator('#photo-canvas').boundingBox();
    // B: a box, its prompt in full.
    await page.focus('#photo-canvas');
    await page.keyboard.press('b');
    await page.waitForSelector('#prompt[data-tool="box"]');
    bad = await cut(['#prompt-text', '#prompt-extra', '#prompt-control', '.prompt-buttons'], '#prompt');
    check(bad.length === 0, `the box prompt is cut: ${bad.join('; ')}`);
    const during = await page.locator('#photo-canvas').boundingBox();
    check(JSON.stringify(during) === JSON.stringify(photo), `the photo moved when the prompt changed: ${JSON.stringify(photo)} -> ${JSON.stringify(during)}`);
    await page.keyboard.press('Escape');
    // P: a footprint; at its top, "Enter to skip" is shown in full.
    await page.keyboard.press('p');
    await page.waitForSelector('#prompt[data-tool="footprint"]');
    for (const p of [[700, 1000], [900, 1000], [800, 1100]]) await clickImage(p);
    await page.keyboard.press('Enter');
    await page.waitForSelector('#prompt-above');
    check((await page.textContent('#prompt-extra')).includes('Enter to skip'), 'the footprint top prompt does not say Enter skips');
    bad = await cut(['#prompt-text', '#prompt-extra', '#prompt-control', '.prompt-buttons'], '#prompt');
    check(bad.length === 0, `the footprint prompt is cut: ${bad.join('; ')}`);
    await page.screenshot({ path: SCREENSHOT.replace(/(\.png)?$/, '-prompt.png') });
    await page.keyboard.press('Escape');
    // ?: the keys, in an overlay that Escape closes.
    await page.keyboard.press('?');
    await page.waitForSelector('#keys-dialog[open]');
    const keys = await page.textContent('#keys-dialog');
    for (const k of ['Ctrl+Z', 'Enter', 'Escape', 'Delete', 'B', 'P', 'F', 'S']) check(keys.includes(k), `the keys overlay does not list ${k}`);
    await page.screenshot({ path: SCREENSHOT.replace(/(\.png)?$/, '-keys.png') });
    await page.keyboard.press('Escape');
    await page.waitForSelector('#keys-dialog:not([open])', { state: 'attached' });
    await page.click('#btn-keys');
    await page.waitForSelector('#keys-dialog[open]');
    await page.click('#keys-close');
    await page.waitForSelector('#keys-dialog:not([open])', { state: 'attached' });
    // F: the floor tool.
    await page.focus('#photo-canvas');
    await page.keyboard.press('f');
    await page.waitForSelector('#prompt[data-tool="floor"]');
    await page.keyboard.press('Escape');
    noProblems();
  });


  await step('12. planning you can read: bug colours, legend, fates, alternatives', async () => {
    await freshPage();
    await loadExample();
    await page.fill('#plan-start', '1.1, 1.7');
    await page.press('#plan-start', 'Tab');
    await page.fill('#plan-goal', PLAN_GOAL.join(', '));
    await page.press('#plan-goal', 'Tab');
    const s = await settle('planning', { plans: 1 }, { timeout: 60_000 });
    const mbpp = s.plan.results.find((r) => r.planner === 'mbpp');
    check(mbpp && mbpp.bugs.length >= 2 && mbpp.alternatives.length >= 1, `MBPP gave ${mbpp?.bugs.length} bugs, ${mbpp?.alternatives.length} alternatives`);
    // Bug tracks in colours no planner uses.
    const drawn = await page.evaluate(() => ({
      bugs: [...document.querySelectorAll('#plan-host svg .vp-bug')].map((e) => e.getAttribute('stroke')),
      planners: [...document.querySelectorAll('#plan-host svg .vp-path')].map((e) => e.getAttribute('stroke')),
    }));
    const rgb = (hex) => [1, 3, 5].map((i) => parseInt(hex.slice(i, i + 2), 16));
    for (const b of drawn.bugs) {
      for (const p of drawn.planners) {
        const d = Math.hypot(...rgb(b).map((v, i) => v - rgb(p)[i]));
        check(d > 80, `bug colour ${b} is close to planner colour ${p} (RGB distance ${d.toFixed(0)})`);
      }
    }
    // The legend names the marks; each bug's fate and each alternative's length are listed.
    const legend = await page.textContent('.layers');
    check(/hit/.test(legend) && /leave/.test(legend), `the legend does not explain hits and leave points: ${legend}`);
    const fates = await page.locator('#plan-bugs li').allTextContents();
    check(fates.length === mbpp.bugs.length, `${fates.length} bugs listed for ${mbpp.bugs.length}`);
    mbpp.bugs.forEach((b, i) => check(fates[i].includes(b.fate.replace('-', ' ')), `bug ${i + 1} is listed as "${fates[i]}", its fate is ${b.fate}`));
    const alts = await page.textContent('#plan-alternatives');
    for (const a of mbpp.alternatives) check(alts.includes(`${a.length_m.toFixed(2)} m`), `alternative of ${a.length_m.toFixed(2)} m not listed: "${alts}"`);
    await page.screenshot({ path: SCREENSHOT.replace(/(\.png)?$/, '-plan.png') });
    noProblems();
  });


  await step('13. the object that needs another corner says so beside it', async () => {
    await freshPage();
    await loadExample();
    const o = example.scene.objects[crate];
    const n = example.scene.objects.length;
    await page.keyboard.press('b');
    await clickImage(o.base.near);
    await clickImage(o.base.right);
    await page.keyboard.press('Enter');
    await page.waitForSelector('#prompt[data-tool="select"]');
    await page.waitForFunction(() => window.vpmap.status().buildError && !window.vpmap.status().pending && window.vpmap.status().busy.length === 0, null, { timeout: 30_000 });
    expectRefused(400);
    const s = await status();
    check(JSON.stringify(s.marked) === JSON.stringify(['objects', n]), `the new box is not marked: ${JSON.stringify(s.marked)} (${s.buildError})`);
    check(/add base\.left/.test(s.markedNote || ''), `no note beside the box: ${JSON.stringify(s.markedNote)}`);
    check(JSON.stringify(s.selection) === JSON.stringify({ type: 'object', index: n }), `the box is not selected: ${JSON.stringify(s.selection)}`);
    await page.screenshot({ path: SCREENSHOT.replace(/(\.png)?$/, '-needs-corner.png') });
    noProblems();
  });


  await step('14. a box corner clicked near its guide line goes on it (Alt: where clicked)', async () => {
    await freshPage();
    await loadExample();
    // The page's own snapping to guide lines and points, with the photo's out of the way
    // (snap.mjs tests that; it may move a point to the photo's corner, off the line).
    await page.uncheck('#snap-photo');
    const o = example.scene.objects[bookcase];
    const d = [o.base.right[0] - o.base.near[0], o.base.right[1] - o.base.near[1]];
    const len = Math.hypot(d[0], d[1]);
    const off = [o.base.right[0] - (4 * d[1]) / len, o.base.right[1] + (4 * d[0]) / len];
    const n = example.scene.objects.length;
    const info = () => page.locator(`#object-list li[data-index="${n}"] .obj-info`).textContent();
    for (const alt of [false, true]) {
      await page.focus('#photo-canvas');
      await page.keyboard.press('b');
      await clickImage(o.base.near);
      if (alt) await page.keyboard.down('Alt');
      await clickImage(off);
      if (alt) await page.keyboard.up('Alt');
      await page.keyboard.press('Enter');
      await page.waitForSelector('#prompt[data-tool="select"]');
      await page.waitForFunction(() => window.vpmap.status().buildError && !window.vpmap.status().pending && window.vpmap.status().busy.length === 0, null, { timeout: 30_000 });
      expectRefused(400);
      const text = await info();
      const right = (await sceneNow()).objects[n].base.right;
      if (alt) check(/base\.right is 4\.\d px off/.test(text) && Math.hypot(right[0] - off[0], right[1] - off[1]) < 1, `with Alt the corner was moved to ${right}: ${text}`);
      else check(!/px off/.test(text) && Math.hypot(right[0] - off[0], right[1] - off[1]) > 2, `the corner 4 px off its line was not put on it (${right}): ${text}`);
      await page.keyboard.press('Escape');
      await page.keyboard.press('Control+z');
    }
    noProblems();
  });


  await step('15. a point clicked near where two edges meet goes on the corner (Alt: where clicked)', async () => {
    await freshPage();
    await loadExample();
    // The page's own snapping to guide lines and points, with the photo's out of the way
    // (snap.mjs tests that; it may move a point to the photo's corner, off the line).
    await page.uncheck('#snap-photo');
    // The example's vanishing-point lines are its boxes' edges: they meet at the crate's near corner.
    const near = example.scene.objects[crate].base.near;
    const off = [near[0] + 3, near[1] + 3];
    for (const alt of [false, true]) {
      await page.focus('#photo-canvas');
      await page.keyboard.press('f');
      if (alt) await page.keyboard.down('Alt');
      await clickImage(off);
      if (alt) await page.keyboard.up('Alt');
      for (const p of [[200, 1150], [1500, 1150]]) await clickImage(p);
      await page.keyboard.press('Enter');
      await page.waitForSelector('#prompt[data-tool="select"]');
      const got = (await sceneNow()).floor[0];
      const want = alt ? off : near;
      check(Math.hypot(got[0] - want[0], got[1] - want[1]) < 0.6, `${alt ? 'with Alt' : 'without Alt'} the floor corner is at ${got}, not ${want}`);
      await page.keyboard.press('Control+z');
    }
    noProblems();
  });

  await step('16. a dragged corner snaps to its guide line and to line ends; Shift drags finely; Alt frees', async () => {
    await freshPage();
    await loadExample();
    // The page's own snapping to guide lines and points, with the photo's out of the way
    // (snap.mjs tests that; it may move a point to the photo's corner, off the line).
    await page.uncheck('#snap-photo');
    const scale = await page.evaluate(() => {
      const a = window.vpmap.imageToClient(0, 0), b = window.vpmap.imageToClient(1000, 0);
      return (b[0] - a[0]) / 1000;
    });
    const drag = async (from, to, { shift = false, alt = false } = {}) => {
      await settle('the builds before the drag', {});
      const [x0, y0] = await stableClient(from);
      const [x1, y1] = await client(to);
      await page.mouse.move(x0, y0);
      await page.mouse.down();
      if (shift) await page.keyboard.down('Shift');
      if (alt) await page.keyboard.down('Alt');
      for (let k = 1; k <= 8; k++) await page.mouse.move(x0 + ((x1 - x0) * k) / 8, y0 + ((y1 - y0) * k) / 8);
      await page.mouse.up();
      if (alt) await page.keyboard.up('Alt');
      if (shift) await page.keyboard.up('Shift');
    };
    // (a) The bookcase's right base corner dragged 4 px off the line from its near corner
    // towards its vanishing point stays on that line; with Alt it goes where dropped.
    const o = example.scene.objects[bookcase];
    const d = [o.base.right[0] - o.base.near[0], o.base.right[1] - o.base.near[1]];
    const len = Math.hypot(d[0], d[1]);
    const along = [o.base.right[0] - (30 * d[0]) / len, o.base.right[1] - (30 * d[1]) / len];
    const off = [along[0] - (4 * d[1]) / len, along[1] + (4 * d[0]) / len];
    const lineDist = (p) => Math.abs((p[0] - o.base.near[0]) * d[1] - (p[1] - o.base.near[1]) * d[0]) / len;
    for (const alt of [false, true]) {
      await drag(o.base.right, off, { alt });
      const got = (await sceneNow()).objects[bookcase].base.right;
      if (alt) check(Math.abs(lineDist(got) - 4) < 0.6, `with Alt the dragged corner is ${lineDist(got).toFixed(2)} px off its line, not 4`);
      else check(lineDist(got) < 0.05 && Math.hypot(got[0] - along[0], got[1] - along[1]) < 0.6 / scale + 0.6, `the dragged corner ended ${lineDist(got).toFixed(2)} px off its line at ${got} (want on it near ${along})`);
      await page.keyboard.press('Control+z');
    }
    // (b) Shift: a floor corner follows the pointer ten times slower, so it lands between the
    // image positions a pointer pixel can reach at this zoom.
    const f0 = (await sceneNow()).floor[0];
    const pointerPx = 1 / scale; // image px per screen px
    await drag(f0, [f0[0] + 37 * pointerPx, f0[1] + 23 * pointerPx], { shift: true });
    const f1 = (await sceneNow()).floor[0];
    const moved = [(f1[0] - f0[0]) / pointerPx, (f1[1] - f0[1]) / pointerPx];
    check(Math.abs(moved[0] - 3.7) < 0.35 && Math.abs(moved[1] - 2.3) < 0.35, `with Shift the corner moved ${moved.map((v) => v.toFixed(2))} screen px for a 37, 23 px drag (want a tenth)`);
    await page.keyboard.press('Control+z');
    // (c) Zoomed in, a floor corner clicked near the end of a line that meets no other line goes
    // on the end (at the fitted zoom ends attract nothing: e2e.mjs places corners there).
    const groups = example.scene.vanishing_points.map((vp) => vp.lines || []);
    const corners = segmentCorners(groups, 12);
    const ends = groups.flat().flatMap((s) => [[s[0], s[1]], [s[2], s[3]]]);
    const lonely = ends
      .map((e) => ({ e, gap: Math.min(...corners.map((c) => Math.hypot(c[0] - e[0], c[1] - e[1])), Infinity) }))
      .filter((x) => x.gap > 60 && x.e[1] > 700)
      .sort((a, b) => b.gap - a.gap)[0];
    check(!!lonely, 'the example has no line end away from every corner below the horizon to test with');
    const at = await client(lonely.e);
    await page.mouse.move(at[0], at[1]);
    for (let k = 0; k < 2; k++) await page.mouse.wheel(0, -600);
    const zoomed = await page.evaluate(() => {
      const a = window.vpmap.imageToClient(0, 0), b = window.vpmap.imageToClient(1000, 0);
      return (b[0] - a[0]) / 1000;
    });
    check(zoomed > 4 * scale, `two wheel turns zoomed only from ${scale} to ${zoomed}`);
    const near = [lonely.e[0] + 3 / zoomed, lonely.e[1] - 2 / zoomed];
    await page.focus('#photo-canvas');
    await page.keyboard.press('f');
    await clickImage(near);
    await page.keyboard.press('0'); // fit, to reach the other corners
    for (const p of [[200, 1150], [1500, 1150]]) await clickImage(p);
    await page.keyboard.press('Enter');
    await page.waitForSelector('#prompt[data-tool="select"]');
    const got = (await sceneNow()).floor[0];
    check(Math.hypot(got[0] - lonely.e[0], got[1] - lonely.e[1]) < 1e-6, `the floor corner clicked 2 px from a line end is at ${got}, not on the end ${lonely.e}`);
    noProblems();
  });

  await step('17. floor-plan labels are readable at the default zoom and do not overlap', async () => {
    for (const [w, h] of [[1366, 768], [1920, 1080]]) {
      await freshPage(w, h);
      await loadExample();
      const labels = () => page.evaluate(() => {
        const texts = [...document.querySelectorAll('#plan-svg [id="fp-labels"] text')];
        const boxes = [...document.querySelectorAll('#plan-svg [id="fp-labels"] rect')].map((r) => r.getBoundingClientRect());
        const ticks = [...document.querySelectorAll('#plan-svg [id="fp-axes"] text:not([font-size])')].map((t) => t.getBoundingClientRect().height);
        return {
          names: texts.filter((t) => t.getAttribute('font-weight') === 'bold').map((t) => ({ text: t.textContent, px: t.getBoundingClientRect().height })),
          boxes: boxes.map((r) => [r.left, r.top, r.width, r.height]),
          ticks,
        };
      });
      const got = await labels();
      check(got.names.length === example.scene.objects.length, `${got.names.length} object labels on the plan, ${example.scene.objects.length} objects`);
      // A 11.5 px name is about 13 px tall on screen (the glyph box).
      for (const n of got.names) check(n.px >= 11, `at ${w} x ${h} the label “${n.text}” is ${n.px.toFixed(1)} px tall on screen`);
      for (const t of got.ticks) check(t >= 9.5, `at ${w} x ${h} an axis tick label is ${t.toFixed(1)} px tall`);
      got.boxes.forEach((a, i) => got.boxes.slice(i + 1).forEach((b) => {
        const apart = a[0] >= b[0] + b[2] || b[0] >= a[0] + a[2] || a[1] >= b[1] + b[3] || b[1] >= a[1] + a[3];
        check(apart, `at ${w} x ${h} two object labels overlap: ${a.map(Math.round)} and ${b.map(Math.round)}`);
      }));
      await page.screenshot({ path: SCREENSHOT.replace(/(\.png)?$/, `-labels-${w}.png`) });
      // Zoomed in, the picture's own sizes come back (labels grow with the plan, not beyond).
      const before = got.names[0].px;
      const c = await planClient([0, 3]);
      await page.mouse.move(c[0], c[1]);
      for (let k = 0; k < 6; k++) await page.mouse.wheel(0, -400);
      const zoomed = await labels();
      check(zoomed.names[0].px > before * 1.5, `zoomed in, the label is ${zoomed.names[0].px.toFixed(1)} px (was ${before.toFixed(1)})`);
      // The downloaded plan keeps the server's label sizes.
      const exported = await page.evaluate(() => window.vpmap.planSvg());
      check(!/plan-label-box" transform=/.test(exported) && !/display: none/.test(exported), 'the downloaded plan carries the on-screen label scaling');
    }
    noProblems();
  });

  noProblems();
}

main()
  .then(pass)
  .catch((err) => fail(err.stack || String(err)));
