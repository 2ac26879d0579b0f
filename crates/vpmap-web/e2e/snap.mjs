// Browser test of clicks that snap to the photo (issue 31), in headless Chromium against
// `vpmap serve` (the real server: snapping needs it):
//
//   1. Load example (a photo rendered from the example's truth; its box corners are exact);
//   2. Add box, a click 2.5 px off a box's base near corner: the corner lands within 1 px of
//      it when the answer comes (the edges flash: screenshot `-snap-flash.png`); Backspace
//      takes it back; an Alt-click puts it where clicked;
//   3. three snapped base corners and Done: the box's corners carry covariances in the
//      scene's click_covariances_px2; dragging one by hand drops its entry; undo brings it
//      back; undo again takes the box and its entries away;
//   4. Propose boxes lists at least one candidate (outlined on the photo: `-snap-proposals.png`);
//      Accept adds a box with its corners; undo takes it back; opening another photo forgets
//      the candidates.
//
// No console error or warning is allowed. Environment as e2e.mjs (VPMAP_BIN, VPMAP_URL,
// VPMAP_E2E_CHROMIUM, VPMAP_E2E_SCREENSHOT, VPMAP_E2E_HEADED). Prints `SNAP PASSED`.

import { launchChromium, startServer, testRun } from './harness.mjs';

const TOTAL_MS = 150_000;
const SHOT = (what) => (process.env.VPMAP_E2E_SCREENSHOT || '/tmp/vpmap-e2e.png').replace(/(\.png)?$/, `-snap-${what}.png`);

let server = null;
let browser = null;
let page = null;
const problems = [];
const { log, check, step, fail, pass } = testRun({
  label: 'SNAP',
  totalMs: TOTAL_MS,
  failureShot: SHOT('failed'),
  resources: () => ({ server, browser, page }),
});

const noProblems = () => check(problems.length === 0, problems.join('\n'));
const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1]);
const fmtP = (p) => (p ? `(${p[0].toFixed(2)}, ${p[1].toFixed(2)})` : 'none');
const sceneNow = () => page.evaluate(() => window.vpmap.scene());
const toolPoints = () => page.evaluate(() => window.vpmap.toolPoints());
const snapAnswers = () => page.evaluate(() => window.vpmap.snap().answers);

async function settle(what) {
  await page.waitForFunction(() => {
    const s = window.vpmap.status();
    return !s.pending && s.busy.length === 0 && window.vpmap.snap().pending === 0;
  }, null, { timeout: 60_000, polling: 50 }).catch(() => {
    throw new Error(`${what} did not settle`);
  });
}

async function clickImage(p, modifiers = []) {
  const [x, y] = await page.evaluate(([a, b]) => window.vpmap.imageToClient(a, b), p);
  await page.mouse.move(x, y);
  for (const m of modifiers) await page.keyboard.down(m);
  await page.mouse.click(x, y);
  for (const m of modifiers) await page.keyboard.up(m);
}

/** Click `p` and wait for its snap answer. */
async function snapAt(p) {
  const before = await snapAnswers();
  await clickImage(p);
  await page.waitForFunction((b) => window.vpmap.snap().answers > b && window.vpmap.snap().pending === 0, before, { timeout: 30_000, polling: 20 });
}

async function main() {
  const url = await step('start the server', async () => {
    const s = await startServer({ log });
    server = s.server;
    return s.url;
  });
  await step('launch Chromium', async () => {
    browser = await launchChromium();
    page = await browser.newPage({ viewport: { width: 1400, height: 900 } });
    page.on('console', (m) => {
      if (m.type() === 'error' || m.type() === 'warning') problems.push(`console ${m.type()}: ${m.text()}`);
    });
    page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
    const res = await page.goto(url, { waitUntil: 'load' });
    check(res && res.ok(), `GET ${url} answered ${res && res.status()}`);
    await page.waitForFunction(() => !!window.vpmap, null, { timeout: 10_000 });
  });

  let example;
  await step('load the example', async () => {
    await page.click('#btn-example');
    await page.waitForFunction(() => window.vpmap.status().builds >= 1, null, { timeout: 60_000 });
    await settle('the example');
    example = await sceneNow();
    check(example.objects.some((o) => o.base?.near), 'the example has no box');
    check(await page.isChecked('#snap-photo'), 'snapping to the photo is not on by default');
    noProblems();
  });

  await step('Propose boxes lists candidates; Accept adds one; undo takes it back', async () => {
    await page.click('#btn-propose');
    await page.waitForSelector('#proposal-list li[data-index]', { timeout: 60_000 });
    const n = await page.locator('#proposal-list li[data-index]').count();
    log(`  ${n} candidates`);
    check(n >= 1, 'no candidate listed');
    await page.hover('#proposal-list li[data-index="0"]');
    await page.screenshot({ path: SHOT('proposals') });
    const before = (await sceneNow()).objects.length;
    await page.click('#proposal-list li[data-index="0"] button');
    await settle('the accepted box');
    const s = await sceneNow();
    check(s.objects.length === before + 1 && s.objects[before].base, 'Accept added no box');
    log(`  accepted: ${JSON.stringify(s.objects[before])}`);
    const err = await page.evaluate(() => window.vpmap.status().buildError);
    if (err) log(`  its build: ${err}`);
    // A candidate of too few corners is refused by the build, naming the corner to add: expected.
    for (let i = problems.length - 1; i >= 0; i--) if (problems[i].includes('status of 400')) problems.splice(i, 1);
    await page.click('#btn-undo');
    check((await sceneNow()).objects.length === before, 'undo did not take the accepted box back');
    await settle('undo');
    // Listed again, for the next step: another photo forgets them.
    await page.click('#btn-propose');
    await page.waitForSelector('#proposal-list li[data-index]', { timeout: 60_000 });
    noProblems();
  });

  // A photo drawn here: a dark box face on a light wall, its corners known exactly.
  const box = { base: { near: [100, 220], right: [300, 185], left: [88, 80] } };
  await step('open a drawn photo with known corners', async () => {
    const bytes = await page.evaluate(async () => {
      const c = new OffscreenCanvas(400, 300);
      const g = c.getContext('2d');
      g.fillStyle = '#d8d4cc';
      g.fillRect(0, 0, 400, 300);
      g.fillStyle = '#4a5560';
      // A little blur, as a lens gives every photo (a step one pixel wide has no profile
      // to fit an edge to).
      g.filter = 'blur(1.2px)';
      // A quadrilateral whose sides run at about 10 and 95 degrees (not along the pixel grid).
      g.beginPath();
      g.moveTo(100, 220);
      g.lineTo(300, 185);
      g.lineTo(312, 45);
      g.lineTo(88, 80);
      g.closePath();
      g.fill();
      const blob = await c.convertToBlob({ type: 'image/png' });
      return Array.from(new Uint8Array(await blob.arrayBuffer()));
    });
    await page.setInputFiles('#photo-input', { name: 'drawn.png', mimeType: 'image/png', buffer: Buffer.from(bytes) });
    await page.waitForFunction(() => window.vpmap.scene()?.image?.width === 400 && window.vpmap.scene().objects.length === 0, null, { timeout: 10_000 });
    check((await page.locator('#proposal-list li[data-index]').count()) === 0, "the example photo's box candidates are still listed for the new photo");
    check(await page.isHidden('#proposal-list'), 'the candidate list is still shown for the new photo');
    // Its vanishing points, as a person would give them: where the quadrilateral's opposite
    // sides meet (the near-right side and the top side; the two near-vertical sides), and a
    // second horizontal one orthogonal to both for a principal point at the image centre.
    const scene = {
      version: 1,
      image: { width: 400, height: 300 },
      vanishing_points: [
        { point: [7666.6667, -1104.1667] },
        { point: [-218.5723, -1113.8683] },
        { point: [198.5, 1369.1667] },
      ],
      objects: [],
    };
    await page.setInputFiles('#scene-input', { name: 'drawn.json', mimeType: 'application/json', buffer: Buffer.from(JSON.stringify(scene)) });
    await page.waitForFunction(() => window.vpmap.scene()?.vanishing_points?.length === 3, null, { timeout: 10_000 });
    await settle('the drawn photo\'s vanishing points');
  });
  const corner = box.base.near;
  const off = [corner[0] + 2.0, corner[1] - 1.5];

  await step('a click near a corner snaps onto it; the edges flash', async () => {
    await page.click('#btn-add-box');
    await page.waitForSelector('#prompt:not([data-tool="select"])');
    await snapAt(off);
    log(`  answer: ${JSON.stringify(await page.evaluate(() => window.vpmap.snap().last))}`);
    const got = (await toolPoints())?.base?.near;
    log(`  clicked ${fmtP(off)}, ${dist(off, corner).toFixed(2)} px off ${fmtP(corner)}: now at ${fmtP(got)}, ${got ? dist(got, corner).toFixed(2) : '-'} px off`);
    check(got && dist(got, corner) < 1.0, `the corner went to ${fmtP(got)}, not within 1 px of ${fmtP(corner)}`);
    await page.screenshot({ path: SHOT('flash') });
    noProblems();
  });

  await step('Backspace takes it back; Alt-click puts it where clicked', async () => {
    await page.keyboard.press('Backspace');
    check(!(await toolPoints())?.base?.near, 'Backspace left the snapped corner');
    const before = await snapAnswers();
    await clickImage(off, ['Alt']);
    await page.waitForTimeout(400);
    const got = (await toolPoints())?.base?.near;
    check(got && dist(got, off) < 0.6, `the Alt-click's corner is at ${fmtP(got)}, not where clicked ${fmtP(off)}`);
    check((await snapAnswers()) === before, 'an Alt-click asked the server to snap');
    await page.keyboard.press('Backspace');
  });

  let index;
  await step('snapped corners carry covariances into the scene; a drag drops one; undo', async () => {
    for (const name of ['near', 'right', 'left']) {
      const c = box.base[name];
      await snapAt([c[0] + 1.5, c[1] + 1.5]);
      const last = await page.evaluate(() => window.vpmap.snap().last);
      log(`  base ${name}: ${last.snapped ? `snapped ${last.moved_px.toFixed(2)} px` : `kept: ${last.note}`}`);
    }
    const draft = await toolPoints();
    const snapped = ['near', 'right', 'left'].filter((n) => dist(draft.base[n], box.base[n]) < 1.0);
    log(`  ${snapped.length} of 3 base corners within 1 px of the example's: ${snapped.join(', ')}`);
    check(snapped.includes('near'), 'the near corner did not snap');
    await page.keyboard.press('Enter');
    await settle('the box with snapped corners');
    const s = await sceneNow();
    index = s.objects.length - 1;
    const table = s.click_covariances_px2 || {};
    for (const n of snapped) check(table[`objects[${index}].base.${n}`], `no covariance for objects[${index}].base.${n}: ${JSON.stringify(table)}`);
    check(!(await page.evaluate(() => window.vpmap.status().buildError)), 'the box with covariances did not build');
    // Drag its near corner by hand (Alt: not snapped) 6 px to the right.
    const p = s.objects[index].base.near;
    const [x, y] = await page.evaluate(([a, b]) => window.vpmap.imageToClient(a, b), p);
    await page.mouse.move(x, y);
    await page.keyboard.down('Alt');
    await page.mouse.down();
    await page.mouse.move(x + 3, y, { steps: 3 });
    await page.mouse.move(x + 6, y, { steps: 3 });
    await page.mouse.up();
    await page.keyboard.up('Alt');
    await settle('the drag');
    const moved = await sceneNow();
    check(dist(moved.objects[index].base.near, p) > 1, 'the drag did not move the corner');
    check(!moved.click_covariances_px2?.[`objects[${index}].base.near`], 'the dragged corner kept its covariance');
    await page.click('#btn-undo');
    const back = await sceneNow();
    check(dist(back.objects[index].base.near, p) < 1e-9 && back.click_covariances_px2?.[`objects[${index}].base.near`], 'undo did not bring back the corner and its covariance');
    await page.click('#btn-undo');
    const gone = await sceneNow();
    check(gone.objects.length === index && !Object.keys(gone.click_covariances_px2 || {}).some((k) => k.startsWith(`objects[${index}]`)), 'undo did not take the box and its covariances away');
    await settle('undo');
    noProblems();
  });

}

main()
  .then(pass)
  .catch((err) => fail(err?.message || String(err)));
