// End-to-end test of the page served by `vpmap serve`, in headless Chromium.
//
//   cd crates/vpmap-web/e2e && npm ci && node e2e.mjs
//
// Starts `target/release/vpmap serve --port 0` (or uses VPMAP_URL), loads the page, loads the
// example, opens a new scene on the example photo, runs detection, places the example's
// corners with the guided tools (mouse clicks on the photo), checks the floor plan, the 3D view
// and the pitch (within 0.5 degrees of the example's), plans a path by clicking a start and a
// goal on the floor plan, checks a path is drawn, saves the scene and the PNG plan, and takes
// a screenshot. Exits 0 on success, 1 with a message naming the failed step otherwise; the
// whole run is limited to 2 minutes.
//
// Environment:
//   VPMAP_URL             test a running server at this URL instead of starting one
//   VPMAP_BIN             the vpmap binary (default: <repo>/target/release/vpmap)
//   VPMAP_E2E_MOCK=1      start mock-server.mjs instead of `vpmap serve`
//   VPMAP_E2E_CHROMIUM    Chromium executable (default: /usr/bin/chromium)
//   VPMAP_E2E_SCREENSHOT  screenshot path (default: /tmp/vpmap-e2e.png)
//   VPMAP_E2E_HEADED=1    show the browser window

import { readFile } from 'node:fs/promises';
import { launchChromium, startServer, testRun } from './harness.mjs';

const TOTAL_MS = 120_000;
const SCREENSHOT = process.env.VPMAP_E2E_SCREENSHOT || '/tmp/vpmap-e2e.png';
const PITCH_TOLERANCE_DEG = 0.5;
// Start and goal on the example's free floor (map metres, at least 0.4 m from any obstacle
// with the default 0.2 m robot radius): right of the crate, and behind it to the right of the
// bookcase, so that MBPP has to go round the crate and the floor it hides (4 bugs).
const PLAN_START = [1.1, 1.7];
const PLAN_GOAL = [0.2, 5.0];

let server = null;
let browser = null;
let page = null;
const { log, check, step, fail, pass } = testRun({
  label: 'E2E',
  totalMs: TOTAL_MS,
  failureShot: SCREENSHOT.replace(/(\.png)?$/, '-failed.png'),
  resources: () => ({ server, browser, page }),
});

async function main() {
  const url = await step('start the server', async () => {
    const started = await startServer({ mock: true, log });
    server = started.server;
    return started.url;
  });
  log(`server at ${url}`);

  await step('launch Chromium', async () => {
    browser = await launchChromium();
  });
  page = await browser.newPage({ viewport: { width: 1600, height: 1000 }, acceptDownloads: true });
  const problems = [];
  page.on('console', (m) => {
    if (m.type() === 'error') problems.push(`console error: ${m.text()}`);
  });
  page.on('pageerror', (e) => problems.push(`uncaught exception: ${e.message}`));
  page.on('requestfailed', (r) => {
    const why = r.failure()?.errorText || '';
    if (!why.includes('ERR_ABORTED')) problems.push(`request failed: ${r.url()} (${why})`);
  });
  page.on('request', (r) => {
    const u = r.url();
    if (!u.startsWith(url) && !u.startsWith('data:') && !u.startsWith('blob:')) problems.push(`external request: ${u}`);
  });
  const noProblems = () => check(problems.length === 0, problems.join('\n'));

  const status = () => page.evaluate(() => window.vpmap.status());
  /** Wait until at least `n` builds succeeded and nothing is pending or running. */
  const settle = async (what, counters, timeout = 30_000) => {
    try {
      await page.waitForFunction(
        (want) => {
          const s = window.vpmap.status();
          return !s.pending && s.busy.length === 0 && Object.entries(want).every(([k, v]) => s[k] >= v);
        },
        counters,
        { timeout, polling: 50 },
      );
    } catch {
      const s = await status();
      throw new Error(`${what} did not finish: ${JSON.stringify({ busy: s.busy, builds: s.builds, plans: s.plans, detects: s.detects, buildError: s.buildError, planError: s.planError })}`);
    }
    const s = await status();
    if (s.buildError) throw new Error(`the build failed: ${s.buildError}`);
    return s;
  };
  const clickImage = async (p) => {
    const [x, y] = await page.evaluate(([px, py]) => window.vpmap.imageToClient(px, py), p);
    await page.mouse.click(x, y);
  };
  /** The pitch the page shows: its value, checked against the text on screen (2 decimals). */
  const displayedPitch = async () => {
    const v = await page.locator('#cam-pitch').getAttribute('data-value');
    const text = await page.textContent('#cam-pitch');
    check(v !== null && /^-?\d+\.\d\d°$/.test(text), `no pitch is displayed (the page shows "${text}")`);
    check(Math.abs(Number(v) - parseFloat(text)) <= 0.0051, `the page shows pitch "${text}" for ${v}`);
    return Number(v);
  };

  await step('load the page', async () => {
    const res = await page.goto(url, { waitUntil: 'load' });
    check(res && res.ok(), `GET ${url} answered ${res && res.status()}`);
    await page.waitForFunction(() => !!window.vpmap, null, { timeout: 10_000 });
    noProblems();
  });

  let example;
  let examplePitch;
  await step('load the example', async () => {
    await page.click('#btn-example');
    const s = await settle('building the example', { builds: 1 }, 60_000);
    example = await page.evaluate(() => window.vpmap.scene());
    check(example && example.objects.length > 0, 'the example scene has no objects');
    examplePitch = await displayedPitch();
    check(Math.abs(examplePitch - s.camera.pitch_deg) < 0.01, 'the displayed pitch is not the build answer\'s');
    await page.waitForSelector('#plan-host svg', { timeout: 10_000 });
    log(`  example: ${example.objects.length} objects, ${example.floor.length} floor corners, pitch ${examplePitch.toFixed(3)} deg`);
  });

  await step('new scene and detection on the example photo', async () => {
    const before = (await status()).detects;
    await page.click('#btn-new-scene');
    const blank = await page.evaluate(() => window.vpmap.scene());
    check(blank.objects.length === 0 && blank.floor.length === 0, 'New scene did not clear the annotations');
    await page.click('#btn-detect');
    const s = await settle('detection', { detects: before + 1 }, 30_000);
    const scene = await page.evaluate(() => window.vpmap.scene());
    const vps = scene.vanishing_points.filter((v) => v.point || (v.lines && v.lines.length >= 2));
    check(vps.length === example.vanishing_points.length, `detection found ${vps.length} vanishing points, the example has ${example.vanishing_points.length}`);
    log(`  detected ${scene.vanishing_points.length} vanishing points, focal ${scene.focal_px}, ${s.builds} builds so far`);
  });

  await step('the detection\'s error bars on the page', async () => {
    // Each detected vanishing point's 95 % spread in the list, from its covariance as the scene
    // states it, and the lens's k and sd in the camera bar, as the map reports them.
    const scene = await page.evaluate(() => window.vpmap.scene());
    const infos = await page.locator('#vp-list .vp-info').allTextContents();
    let shown = 0;
    for (const [k, vp] of scene.vanishing_points.entries()) {
      check(Array.isArray(vp.covariance_deg2), `detected vanishing point ${k + 1} has no covariance: ${JSON.stringify(vp)}`);
      const [[a, b], [, d]] = vp.covariance_deg2;
      const major = (a + d) / 2 + Math.sqrt(((a - d) / 2) ** 2 + b * b);
      const want = `±${Math.sqrt(5.991 * major).toFixed(1)}° (95 %)`;
      check(infos[k]?.includes(want), `vanishing point ${k + 1}'s row shows "${infos[k]}", not its ${want}`);
      shown += 1;
    }
    check(shown >= 2, `only ${shown} vanishing points with a spread`);
    const lens = scene.lens_distortion;
    check(lens && Number.isFinite(lens.k) && lens.k_sd > 0, `detection wrote no lens with its sd: ${JSON.stringify(lens)}`);
    await page.waitForFunction(() => Number.isFinite(window.vpmap.map()?.camera?.lens_distortion?.k_sd), null, { timeout: 30_000 });
    const camLens = (await page.evaluate(() => window.vpmap.map())).camera.lens_distortion;
    const text = (await page.textContent('#cam-lens')).trim();
    const m = text.match(/^(-?\d+\.\d{3}) ± (<?\d+\.\d{3})$/);
    check(m, `the camera bar's lens shows "${text}", not "k ± sd"`);
    check(Math.abs(Number(m[1]) - camLens.k) <= 0.0005, `the camera bar's lens k ${m[1]} is not the map's ${camLens.k}`);
    const sdShown = m[2].startsWith('<') ? 0 : Number(m[2]);
    check(Math.abs(sdShown - camLens.k_sd) <= 0.0005, `the camera bar's lens sd ${m[2]} is not the map's ${camLens.k_sd}`);
    log(`  ${shown} spreads in the list (${infos.map((t) => t.split(' · ')[1]).join(', ')}); lens ${text}`);
  });

  await step('place the example\'s corners', async () => {
    // The example's corners exactly as its scene gives them: not moved to the photo (snap.mjs tests that).
    await page.uncheck('#snap-photo');
    const points = [];
    for (const [i, o] of example.objects.entries()) {
      if (o.base) {
        await page.click('#btn-add-box');
        await page.waitForSelector('#prompt:not([data-tool="select"])');
        const text = await page.textContent('#prompt-text');
        check(/near base corner/.test(text), `the box prompt reads "${text}"`);
        const seq = [o.base.near, o.base.right, o.base.left];
        if (o.top?.near) seq.push(o.top.near);
        if (o.top?.near && o.top?.left) seq.push(o.top.left);
        for (const p of seq) {
          await clickImage(p);
          points.push([p, ['objects', i]]);
        }
        await page.keyboard.press('Enter'); // Done: the other corners are not needed
      } else {
        await page.click('#btn-add-footprint');
        await page.waitForSelector('#prompt:not([data-tool="select"])');
        for (const p of o.footprint) {
          await clickImage(p);
          points.push([p, ['objects', i]]);
        }
        await page.keyboard.press('Enter'); // polygon done
        if (o.top) {
          await page.selectOption('#prompt-above', String(o.top.above));
          await clickImage(o.top.point);
        } else await page.keyboard.press('Enter');
      }
      await page.waitForSelector('#prompt[data-tool="select"]');
      const input = page.locator(`#object-list li[data-index="${i}"] .obj-name`);
      await input.fill(o.name);
      await input.press('Enter');
    }
    if (example.floor.length) {
      await page.click('#btn-floor');
      for (const p of example.floor) await clickImage(p);
      await page.keyboard.press('Enter');
      await page.waitForSelector('#prompt[data-tool="select"]');
    }
    const sc = example.scale;
    if (sc?.camera_height_m !== undefined) {
      await page.check('#scale-camera');
      await page.fill('#scale-camera-m', String(sc.camera_height_m));
    } else if (sc?.object !== undefined) {
      await page.check('#scale-object');
      await page.selectOption('#scale-object-name', sc.object);
      await page.selectOption('#scale-object-dim', sc.dimension);
      await page.fill('#scale-object-m', String(sc.meters));
    } else if (sc) {
      throw new Error(`the test cannot enter a scale of the form ${JSON.stringify(sc)}`);
    }
    // Compare what the page recorded with the example's corners.
    const placed = await page.evaluate(() => window.vpmap.scene());
    check(placed.objects.length === example.objects.length, `${placed.objects.length} objects placed, expected ${example.objects.length}`);
    const flat = (o) => [
      ...(o.base ? [o.base.near, o.base.right, o.base.left] : o.footprint),
      ...(o.top ? [o.top.near, o.top.left, o.top.point].filter(Boolean) : []),
    ];
    let worst = 0;
    example.objects.forEach((o, i) => {
      const a = flat(o), b = flat(placed.objects[i]);
      check(placed.objects[i].name === o.name, `object ${i} is named "${placed.objects[i].name}", expected "${o.name}"`);
      check(a.length === b.length, `object ${o.name}: ${b.length} points placed, expected ${a.length}`);
      a.forEach((p, j) => (worst = Math.max(worst, Math.hypot(p[0] - b[j][0], p[1] - b[j][1]))));
    });
    example.floor.forEach((p, j) => (worst = Math.max(worst, Math.hypot(p[0] - placed.floor[j][0], p[1] - placed.floor[j][1]))));
    check(worst < 3, `a placed corner is ${worst.toFixed(2)} px from the example's`);
    check(JSON.stringify(placed.scale) === JSON.stringify(example.scale), `scale ${JSON.stringify(placed.scale)}, expected ${JSON.stringify(example.scale)}`);
    log(`  placed ${points.length} object corners and ${example.floor.length} floor corners, worst ${worst.toFixed(2)} px off`);
  });

  await step('floor plan, 3D view and pitch', async () => {
    const before = (await status()).builds;
    await page.waitForTimeout(150); // let the last edit's debounce start
    const s = await settle('the build after the corners', { builds: Math.max(before, 1) });
    check(s.camera, 'no camera after the build');
    const svg = page.locator('#plan-host svg');
    check((await svg.count()) === 1, 'no floor plan SVG');
    const box = await svg.boundingBox();
    check(box && box.width > 100 && box.height > 100, `the floor plan is ${JSON.stringify(box)}`);
    // The page places the overlay with the server's data-svg-from-map transform: it must put
    // the map's floor corners on the corners of the floor outline the server drew (1 px).
    const floorOff = await page.evaluate(() => {
      const map = window.vpmap.map();
      const svg = document.querySelector('#plan-host svg');
      const path = svg.querySelector('[id="fp-floor"]');
      if (!map || !path || !(map.floor || []).length) return { error: `map ${!!map}, floor path ${!!path}` };
      const drawn = [...path.getAttribute('d').matchAll(/(-?[\d.]+)[ ,](-?[\d.]+)/g)].map((m) => [Number(m[1]), Number(m[2])]);
      const ctm = svg.getScreenCTM();
      let worst = 0;
      map.floor.forEach((corner, i) => {
        const q = new DOMPoint(drawn[i][0], drawn[i][1]).matrixTransform(ctm);
        const c = window.vpmap.planMapToClient(corner[0], corner[1]);
        worst = Math.max(worst, Math.hypot(q.x - c[0], q.y - c[1]));
      });
      return { attr: svg.getAttribute('data-svg-from-map'), corners: map.floor.length, drawn: drawn.length, worst };
    });
    check(!floorOff.error, `cannot compare the floor outline: ${floorOff.error}`);
    check(floorOff.drawn >= floorOff.corners, `the floor outline has ${floorOff.drawn} points for ${floorOff.corners} corners`);
    check(floorOff.worst <= 1, `map floor corners land ${floorOff.worst.toFixed(2)} px from the drawn outline (data-svg-from-map="${floorOff.attr}")`);
    log(`  data-svg-from-map="${floorOff.attr}": ${floorOff.corners} floor corners within ${floorOff.worst.toFixed(3)} px of the outline`);
    const objects = await page.locator('#plan-host svg [id^="fp-object-"]').count();
    check(objects === example.objects.length, `the floor plan shows ${objects} objects, expected ${example.objects.length}`);
    await page.waitForFunction(() => Number(document.getElementById('model-host').dataset.meshes) > 0, null, { timeout: 30_000 });
    const canvas = await page.locator('#model-host canvas').boundingBox();
    check(canvas && canvas.width > 100 && canvas.height > 100, `the 3D canvas is ${JSON.stringify(canvas)}`);
    const pitch = await displayedPitch();
    log(`  pitch ${pitch.toFixed(3)} deg (example ${examplePitch.toFixed(3)}), roll ${await page.textContent('#cam-roll')}, focal ${await page.textContent('#cam-focal')}`);
    check(Math.abs(pitch - examplePitch) <= PITCH_TOLERANCE_DEG, `pitch ${pitch.toFixed(3)} deg differs from the example's ${examplePitch.toFixed(3)} deg by more than ${PITCH_TOLERANCE_DEG}`);
    noProblems();
  });

  await step('plan a path', async () => {
    const before = (await status()).plans;
    for (const p of [PLAN_START, PLAN_GOAL]) {
      const q = await page.evaluate(([x, y]) => window.vpmap.planMapToClient(x, y), p);
      check(q, 'the floor plan has no coordinate transform');
      const box = await page.locator('#plan-host svg').boundingBox();
      check(q[0] > box.x && q[0] < box.x + box.width && q[1] > box.y && q[1] < box.y + box.height, `map point ${p} is outside the visible floor plan`);
      await page.mouse.click(q[0], q[1]);
    }
    const s = await settle('planning', { plans: before + 1 }, 60_000);
    check(s.planError === null, `planning failed: ${s.planError}`);
    for (const [got, want, name] of [[s.start, PLAN_START, 'start'], [s.goal, PLAN_GOAL, 'goal']]) {
      check(got && Math.hypot(got[0] - want[0], got[1] - want[1]) < 0.05, `the ${name} is ${JSON.stringify(got)}, clicked at ${JSON.stringify(want)}`);
    }
    const mbpp = s.plan.results.find((r) => r.planner === 'mbpp');
    check(mbpp && mbpp.found, 'MBPP found no path');
    const line = page.locator('#plan-host svg .vp-path-mbpp');
    check((await line.count()) === 1, 'no MBPP path is drawn on the floor plan');
    const pts = (await line.getAttribute('points')).trim().split(/\s+/);
    check(pts.length >= 2, 'the drawn MBPP path has fewer than 2 points');
    const rows = await page.locator('#plan-table tbody tr').count();
    check(rows === s.plan.results.length, `the results table has ${rows} rows for ${s.plan.results.length} planners`);
    for (const r of s.plan.results) log(`  ${r.planner}: ${r.found ? `${r.length_m.toFixed(3)} m` : 'no path'}, ${r.time_ms.toFixed(2)} ms${r.planner === 'mbpp' ? `, ${(r.bugs || []).length} bugs, ${(r.alternatives || []).length} alternatives` : ''}`);
  });

  await step('drive the true office', async () => {
    // The example's photo is open (with the scene placed above), so its true room is known.
    check(await page.isVisible('#drive'), 'the drive panel is hidden with the example open');
    if (process.env.VPMAP_E2E_MOCK === '1') {
      log('  skipped: the mock server has no /api/navigate');
      return;
    }
    const before = (await status()).drives;
    await page.selectOption('#drive-planner', 'dstar-lite');
    await page.click('#btn-drive');
    const s = await settle('driving', { drives: before + 1 }, 60_000);
    check(s.driveError === null, `the drive failed: ${s.driveError}`);
    const d = s.drive;
    check(d.reached, `the robot did not reach the goal: ${d.outcome}`);
    check(d.length >= d.optimum_any_angle - 1e-9, `the drive (${d.length} m) is shorter than the true room's shortest path (${d.optimum_any_angle} m)`);
    // Independently of the server's grids: the track keeps the robot's radius (less a cell and
    // a half of discretisation) from every true object.
    const radius = 0.2, cell = 0.05;
    const segDist = (p, a, b) => {
      const d2 = (b[0] - a[0]) ** 2 + (b[1] - a[1]) ** 2;
      const t = d2 > 0 ? Math.max(0, Math.min(1, ((p[0] - a[0]) * (b[0] - a[0]) + (p[1] - a[1]) * (b[1] - a[1])) / d2)) : 0;
      return Math.hypot(p[0] - a[0] - t * (b[0] - a[0]), p[1] - a[1] - t * (b[1] - a[1]));
    };
    const crosses = (a, b, c, e) => {
      const o = (p, q, r) => Math.sign((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]));
      return o(a, b, c) !== o(a, b, e) && o(c, e, a) !== o(c, e, b);
    };
    let nearest = Infinity;
    for (const o of d.truth_objects) {
      const ring = o.footprint;
      for (let i = 0; i + 1 < d.waypoints.length; i++) {
        const [a, b] = [d.waypoints[i], d.waypoints[i + 1]];
        for (let j = 0; j < ring.length; j++) {
          const [c, e] = [ring[j], ring[(j + 1) % ring.length]];
          check(!crosses(a, b, c, e), `the track crosses the true ${o.name}`);
          nearest = Math.min(nearest, segDist(c, a, b), segDist(a, c, e), segDist(b, c, e));
        }
      }
    }
    check(nearest >= radius - 1.5 * cell, `the track comes ${nearest.toFixed(3)} m from a true object (robot radius ${radius} m)`);
    check((await page.locator('#plan-host svg .vp-drive-track').count()) === 1, 'the driven track is not drawn');
    check((await page.locator('#plan-host svg .vp-truth polygon').count()) === d.truth_objects.length, 'the true objects are not all drawn');
    check((await page.locator('#plan-host svg .vp-drive-replan').count()) === d.events.length - 1, 'the re-planning points are not all drawn');
    const text = await page.textContent('#drive-result');
    check(/^Reached the goal after \d+\.\d\d m; the true room's shortest path is \d+\.\d\d m/.test(text), `the drive result reads "${text}"`);
    log(`  drive: ${d.length.toFixed(3)} m against ${d.optimum_any_angle.toFixed(3)} m, ${d.replans} re-plans, nearest true object ${nearest.toFixed(3)} m`);
    await page.screenshot({ path: SCREENSHOT.replace(/(\.png)?$/, '-drive.png') });
    noProblems();
  });

  await step('error bars with the joint fit', async () => {
    const before = (await status()).builds;
    await page.selectOption('#set-method', 'fit');
    await page.fill('#set-click-sigma', '1');
    const s = await settle('the build with method fit', { builds: before + 1 });
    const map = await page.evaluate(() => window.vpmap.map());
    check(map.method === 'fit', `the map was built with ${map.method}, not fit`);
    check(map.fit && map.fit.click_sigma_px === 1 && map.fit.click_sigma_source === 'given', `fit report ${JSON.stringify(map.fit)}`);
    // One 95 % ellipse per object on the floor plan, where the map puts its centre.
    const ellipses = await page.evaluate(() => [...document.querySelectorAll('#plan-host svg .centroid-ellipse')].map((e) => {
      const r = e.getBoundingClientRect();
      return { id: e.id, cx: r.x + r.width / 2, cy: r.y + r.height / 2 };
    }));
    check(ellipses.length === map.objects.length, `the floor plan shows ${ellipses.length} ellipses for ${map.objects.length} objects`);
    for (const [i, o] of map.objects.entries()) {
      const c = o.uncertainty.centroid_ellipse_95.centre;
      const q = await page.evaluate(([x, y]) => window.vpmap.planMapToClient(x, y), c);
      const e = ellipses.find((x) => x.id === `fp-ellipse-${i}`);
      check(e && Math.hypot(e.cx - q[0], e.cy - q[1]) <= 1.5, `the ellipse of ${o.name} is not centred on its centroid: ${JSON.stringify(e)} vs ${q}`);
    }
    // ± values in the object list, the floor plan's labels and the camera bar.
    const info = await page.locator('#object-list .obj-info').allTextContents();
    const boxes = map.objects.filter((o) => o.size);
    for (const o of boxes) {
      const line = info.find((t) => t.includes(`${o.size.length.toFixed(2)} ± `));
      check(line && /height \d+\.\d\d ± [<\d]/.test(line) && /at \(-?\d+\.\d\d ± [<\d.]+, -?\d+\.\d\d ± /.test(line), `no ± sizes, height and position for ${o.name} in the object list: ${JSON.stringify(info)}`);
      check(line && /outline ± [<\d][\d.]* m at its least certain corner/.test(line), `no outline ± for ${o.name} in the object list: ${JSON.stringify(info)}`);
    }
    const labels = await page.locator('#plan-host svg [id="fp-labels"] text').allTextContents();
    check(labels.filter((t) => t.includes(' ± ')).length >= boxes.length * 2, `the floor plan's labels have no ± values: ${JSON.stringify(labels)}`);
    for (const id of ['cam-pitch-sd', 'cam-roll-sd', 'cam-focal-sd']) {
      const text = await page.textContent(`#${id}`);
      check(/^ ± [<\d]/.test(text), `#${id} shows "${text}"`);
    }
    const report = await page.textContent('#fit-report');
    check(await page.isVisible('#fit-report') && report.includes('1.00 px (given)') && /RMS residual \d+\.\d\d px/.test(report), `the fit report reads "${report}"`);
    log(`  ${ellipses.length} ellipses; camera pitch ${await page.textContent('#cam-pitch')}${await page.textContent('#cam-pitch-sd')}; ${report.trim().split('. ')[0]}; ${s.builds} builds`);
    await page.screenshot({ path: SCREENSHOT.replace(/(\.png)?$/, '-fit.png') });
    noProblems();
  });

  await step('a box by the corners one can see', async () => {
    // Two base corners only do not fix a box: the server's message names the corner to add.
    let before = (await status()).builds;
    const crate = example.objects.findIndex((o) => o.base && o.top?.near && o.top?.left);
    check(crate >= 0, 'the example has no box with two top corners');
    const o = example.objects[crate];
    await page.click('#btn-add-box');
    await page.waitForSelector('#prompt-box-view');
    await clickImage(o.base.near);
    await clickImage(o.base.right);
    await page.keyboard.press('Enter');
    await page.waitForSelector('#prompt[data-tool="select"]');
    await page.waitForFunction((n) => window.vpmap.status().buildError && !window.vpmap.status().pending && window.vpmap.status().busy.length === 0, before, { timeout: 30_000 });
    const err = (await status()).buildError;
    check(/add `base\.left`/.test(err), `the error does not name the corner to add: ${err}`);
    check(await page.isVisible('#error-banner') && (await page.textContent('#error-text')).includes(err), 'the error is not shown');
    // The browser logs the refused build (400) as a console error: expected here.
    const refused = problems.findIndex((m) => m.includes('status of 400'));
    check(refused >= 0, 'the refused build left no trace in the console');
    problems.splice(refused, 1);
    // Undo the box (Escape first: the new box's name field has the focus).
    await page.keyboard.press('Escape');
    await page.keyboard.press('Control+z');
    check((await page.evaluate(() => window.vpmap.scene())).objects.length === example.objects.length, 'undo did not remove the box');
    // The box again, its base left corner skipped as if hidden, with its two top corners: the
    // fit measures it as from all five.
    before = (await status()).builds;
    const want = (await page.evaluate(() => window.vpmap.map())).objects[crate];
    await page.click('#btn-add-box');
    await page.waitForSelector('#prompt-box-view');
    await clickImage(o.base.near);
    await clickImage(o.base.right);
    await page.click('#prompt-skip');
    check(/near top corner/.test(await page.textContent('#prompt-text')), 'after skipping base left the tool does not ask for the near top corner');
    await clickImage(o.top.near);
    await clickImage(o.top.left);
    await page.keyboard.press('Enter');
    await page.waitForSelector('#prompt[data-tool="select"]');
    const added = (await page.evaluate(() => window.vpmap.scene())).objects.at(-1);
    check(JSON.stringify(Object.keys(added.base)) === '["near","right"]' && JSON.stringify(Object.keys(added.top)) === '["near","left"]', `the box is ${JSON.stringify(added)}`);
    await page.waitForTimeout(150);
    await settle('the build with the hidden corner', { builds: before + 1 });
    // A build may start while the box is still being clicked (two base corners, then the top
    // ones): the server refuses that half-drawn box (400), expected as above. How many such
    // builds finish before the next edit cancels them depends on how long a build takes, so
    // every 400 of this step goes; the step's own build above succeeded.
    for (let k = problems.length - 1; k >= 0; k--) {
      if (problems[k].includes('status of 400')) problems.splice(k, 1);
    }
    const got = (await page.evaluate(() => window.vpmap.map())).objects.at(-1);
    for (const k of ['length', 'breadth']) {
      check(Math.abs(got.size[k] - want.size[k]) <= 0.05 * want.size[k], `the box without base.left is ${got.size[k].toFixed(3)} ${k}, with it ${want.size[k].toFixed(3)}`);
    }
    check(Math.abs(got.height - want.height) <= 0.05 * want.height, `height ${got.height} vs ${want.height}`);
    log(`  without base.left: ${got.size.length.toFixed(3)} x ${got.size.breadth.toFixed(3)} x ${got.height.toFixed(3)}, with it ${want.size.length.toFixed(3)} x ${want.size.breadth.toFixed(3)} x ${want.height.toFixed(3)}`);
    await page.keyboard.press('Escape');
    await page.keyboard.press('Control+z');
    check((await page.evaluate(() => window.vpmap.scene())).objects.length === example.objects.length, 'undo did not remove the box');
    noProblems();
  });

  await step('scale from a named box edge', async () => {
    // The first box's vertical edge above its near corner, as long as the map measures it:
    // the camera height must come out as before. "Before" is the map of this scene: the last
    // step's undo rebuilds without its extra box, and the clicks refine the camera (the
    // detected vanishing points carry their uncertainty), so wait for that build.
    await page.waitForFunction(() => {
      const st = window.vpmap.status();
      const m = window.vpmap.map();
      return !st.pending && st.busy.length === 0 && m && m.objects.length === window.vpmap.scene().objects.length;
    }, null, { timeout: 30_000 });
    const before = (await status()).builds;
    const map = await page.evaluate(() => window.vpmap.map());
    const i = example.objects.findIndex((o) => o.base && o.top?.near);
    const o = map.objects[i];
    // The object, the edge and the length first, then the choice: one edit, one build. (Chosen
    // first, each field's change would build a scale of its own on the way, e.g. the old length
    // on another dimension, and the page's re-plan with the earlier start and goal may then be
    // refused as off the floor, a 400 in the console, depending on how fast the builds are.)
    await page.selectOption('#scale-object-name', o.name);
    await page.selectOption('#scale-object-dim', 'edge:base.near,top.near');
    await page.fill('#scale-object-m', o.height.toFixed(4));
    await page.check('#scale-object');
    const s = await settle('the build with an edge scale', { builds: before + 1 });
    const scale = (await page.evaluate(() => window.vpmap.scene())).scale;
    check(JSON.stringify(scale.edge) === '["base.near","top.near"]' && scale.object === o.name, `the scale is ${JSON.stringify(scale)}`);
    check(Math.abs(s.camera.height - map.camera.height) <= 0.001 * map.camera.height, `camera height ${s.camera.height} with the edge scale, ${map.camera.height} before`);
    log(`  ${o.name} base.near-top.near = ${o.height.toFixed(4)} m: camera height ${s.camera.height.toFixed(4)} m (was ${map.camera.height.toFixed(4)})`);
    noProblems();
  });

  await step('save the scene and the PNG plan', async () => {
    const [dl] = await Promise.all([page.waitForEvent('download'), page.click('#btn-save-scene')]);
    const saved = JSON.parse(await readFile(await dl.path(), 'utf8'));
    check(saved.objects.length === example.objects.length && saved.version === 1, 'the saved scene does not hold the objects');
    const [png] = await Promise.all([page.waitForEvent('download'), page.click('[data-download="png"]')]);
    const bytes = await readFile(await png.path());
    check(bytes.length > 1000 && bytes.subarray(1, 4).toString() === 'PNG', 'the floor-plan PNG download is not a PNG');
    noProblems();
  });

  await step('screenshot', async () => {
    await page.screenshot({ path: SCREENSHOT });
    log(`  screenshot: ${SCREENSHOT}`);
  });
  noProblems();
}

main()
  .then(pass)
  .catch((err) => fail(err.stack || String(err)));
