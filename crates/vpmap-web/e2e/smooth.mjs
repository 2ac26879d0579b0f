// Browser test of the smooth planner on the page (issue 41, item 5), in headless Chromium
// against `vpmap serve`:
//
//   1. Load example; set a start and a goal by clicking the floor plan;
//   2. type a turning radius: the plan request carries the smooth planner, the smooth path is
//      drawn as a curve with its tightest turn marked, its row gives max curvature, min
//      clearance and cusps, and dashed (free) heading arrows show at start and goal
//      (screenshot `-smooth-path.png`);
//   3. drag the start's heading arrow to point up the map (+y): the page plans again and the
//      answer's first pose leaves at the dragged heading (screenshot `-smooth-dragged.png`);
//   4. double-click the arrow: the heading is free again and the path re-planned without it;
//   5. with the start heading up the map, a goal 2 m up heading down and a radius of 0.5 m,
//      tick "reverse allowed": the request carries `reverse: true`, the path backs up (a
//      shorter one than forward only), each cusp is marked on the plan where the answer's
//      segments change direction and the row counts them (screenshots `-smooth-reverse.png`
//      and, the plan zoomed in, `-smooth-reverse-zoom.png`);
//      unticked, the request has no `reverse` and no cusp is marked.
//
// No console error or warning is allowed. Environment as e2e.mjs (VPMAP_BIN, VPMAP_URL,
// VPMAP_E2E_CHROMIUM, VPMAP_E2E_SCREENSHOT, VPMAP_E2E_HEADED). Prints `SMOOTH PASSED`.

import { launchChromium, startServer, testRun } from './harness.mjs';

const TOTAL_MS = 150_000;
const SHOT = (what) => (process.env.VPMAP_E2E_SCREENSHOT || '/tmp/vpmap-e2e.png').replace(/(\.png)?$/, `-smooth-${what}.png`);
/** Start and goal on the example's map, metres: across the office. */
const START = [-1.5, 2.0];
const GOAL = [2.0, 7.5];
const RADIUS_M = 0.2;
/** Step 5: from START heading up the map to 2 m further up heading down, radius 0.5 m. */
const REVERSE = { goal: [-1.5, 4.0], radius: 0.5 };

let server = null;
let browser = null;
let page = null;
const problems = [];
const { log, check, step, fail, pass } = testRun({
  label: 'SMOOTH',
  totalMs: TOTAL_MS,
  failureShot: SHOT('failed'),
  resources: () => ({ server, browser, page }),
});

const noProblems = () => check(problems.length === 0, problems.join('\n'));
const status = () => page.evaluate(() => window.vpmap.status());
const wrap = (d) => ((d + 540) % 360) - 180;

async function settle(what, before) {
  try {
    await page.waitForFunction((b) => {
      const s = window.vpmap.status();
      return !s.pending && s.busy.length === 0 && (s.plans > b || s.planError);
    }, before, { timeout: 60_000, polling: 50 });
  } catch {
    const s = await status();
    throw new Error(`${what} did not finish: ${JSON.stringify({ busy: s.busy, plans: s.plans, planError: s.planError })}`);
  }
  const s = await status();
  check(!s.planError, `${what}: ${s.planError}`);
  return s;
}

const toClient = (p) => page.evaluate(([x, y]) => window.vpmap.planMapToClient(x, y), p);
const smoothOf = (s) => s.plan?.results?.find((r) => r.planner === 'smooth');

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

  await step('1. load the example, click a start and a goal', async () => {
    await page.click('#btn-example');
    await page.waitForFunction(() => {
      const s = window.vpmap.status();
      return s.builds >= 1 && !s.pending && s.busy.length === 0;
    }, null, { timeout: 60_000, polling: 50 });
    await page.waitForSelector('#plan-host svg', { timeout: 10_000 });
    const before = (await status()).plans;
    for (const p of [START, GOAL]) {
      const q = await toClient(p);
      await page.mouse.click(q[0], q[1]);
    }
    const s = await settle('the first plan', before);
    check(!smoothOf(s), 'the smooth planner ran without a turning radius');
    check((await page.locator('.vp-heading').count()) === 0, 'heading arrows shown without a turning radius');
    noProblems();
  });

  let free;
  await step('2. a turning radius draws the smooth path and its tightest turn', async () => {
    const before = (await status()).plans;
    await page.fill('#plan-turning-radius', String(RADIUS_M));
    await page.press('#plan-turning-radius', 'Enter');
    await page.locator('#plan-turning-radius').blur();
    const s = await settle('planning with a turning radius', before);
    const r = smoothOf(s);
    check(r && r.found, `no smooth path: ${JSON.stringify(r?.note ?? r)}`);
    free = r.smooth;
    check(free.max_curvature <= 1 / RADIUS_M + 1e-9, `max curvature ${free.max_curvature} > 1/${RADIUS_M}`);
    check(Math.hypot(free.poses[0][0] - START[0], free.poses[0][1] - START[1]) < 0.05, `the path starts at ${free.poses[0]}`);
    check(s.headings[0] === null && s.headings[1] === null, `headings ${JSON.stringify(s.headings)} are not free`);
    const curve = page.locator('#plan-host svg .vp-path-smooth');
    check((await curve.count()) === 1, 'no smooth path drawn');
    const d = await curve.getAttribute('d');
    check((d.match(/L/g) || []).length === free.poses.length - 1, 'the drawn curve does not go through every pose');
    check((await page.locator('#plan-host svg .vp-tightest').count()) === 1, 'the tightest turn is not marked');
    check((await page.locator('#plan-host svg .vp-heading.free').count()) === 2, 'the free heading arrows are not shown');
    const row = await page.locator('#plan-table tbody tr[data-planner="smooth"]').textContent();
    check(/max curvature [\d.]+ \/m/.test(row) && /min clearance [\d.]+ m/.test(row) && /\d+ cusps?/.test(row), `the smooth row says ${row}`);
    log(`  smooth: ${free.length.toFixed(3)} m, leaves at ${free.poses[0][2].toFixed(1)} deg, max curvature ${free.max_curvature.toFixed(3)} /m, ${free.poses.length} poses; row: ${row}`);
    await page.screenshot({ path: SHOT('path') });
    noProblems();
  });

  await step('3. drag the start heading arrow up the map: the path leaves that way', async () => {
    const before = (await status()).plans;
    const handle = await page.locator('.vp-heading-handle[data-heading="start"]').boundingBox();
    check(handle, 'no start heading handle');
    const [hx, hy] = [handle.x + handle.width / 2, handle.y + handle.height / 2];
    const target = await toClient([START[0], START[1] + 0.8]);
    await page.mouse.move(hx, hy);
    await page.mouse.down();
    await page.mouse.move((hx + target[0]) / 2, (hy + target[1]) / 2, { steps: 4 });
    await page.mouse.move(target[0], target[1], { steps: 4 });
    await page.mouse.up();
    const s = await settle('planning with the dragged heading', before);
    const heading = s.headings[0];
    check(Number.isFinite(heading) && Math.abs(wrap(heading - 90)) <= 3, `the dragged start heading is ${heading}, not about 90`);
    check(s.headings[1] === null, 'the goal heading changed');
    check(Math.hypot(s.start[0] - START[0], s.start[1] - START[1]) < 1e-9, `the drag moved the start to ${s.start}`);
    const r = smoothOf(s);
    check(r && r.found, `no smooth path after the drag: ${r?.note}`);
    const first = r.smooth.poses[0];
    check(Math.abs(wrap(first[2] - heading)) < 1e-6, `the path leaves at ${first[2]}, asked ${heading}`);
    check(Math.abs(wrap(free.poses[0][2] - heading)) > 30, 'the free path already left at that heading: the test shows nothing');
    check((await page.locator('.vp-heading-start:not(.free)').count()) === 1, 'the start arrow is not shown as set');
    check((await page.inputValue('#plan-start-heading')) === String(heading), 'the start heading field does not show the dragged heading');
    log(`  dragged to ${heading} deg: the path leaves at ${first[2].toFixed(3)} deg, ${r.smooth.length.toFixed(3)} m`);
    await page.screenshot({ path: SHOT('dragged') });
    noProblems();
  });

  await step('4. double-click the arrow: the heading is free again', async () => {
    const before = (await status()).plans;
    const handle = await page.locator('.vp-heading-handle[data-heading="start"]').boundingBox();
    await page.mouse.dblclick(handle.x + handle.width / 2, handle.y + handle.height / 2);
    const s = await settle('planning with the heading freed', before);
    check(s.headings[0] === null, `the start heading is ${s.headings[0]} after a double-click`);
    check(Math.abs(s.start[0] - START[0]) < 1e-9 && Math.abs(s.start[1] - START[1]) < 1e-9, `the double-click moved the start to ${s.start}`);
    const r = smoothOf(s);
    check(r && r.found && Math.abs(wrap(r.smooth.poses[0][2] - free.poses[0][2])) < 1e-6, 'the freed path does not leave as the first free one did');
    noProblems();
  });

  await step('5. reverse allowed: the path backs up and its cusps are marked and counted', async () => {
    const bodies = [];
    const onRequest = (req) => {
      if (req.url().endsWith('/api/plan') && req.method() === 'POST') bodies.push(JSON.parse(req.postData() || '{}'));
    };
    page.on('request', onRequest);
    const replan = async (what, act) => {
      const before = (await status()).plans;
      await act();
      return settle(what, before);
    };
    const setField = (id, text) => replan(`typing ${text} into #${id}`, async () => {
      await page.fill(`#${id}`, text);
      await page.press(`#${id}`, 'Enter');
      await page.locator(`#${id}`).blur();
    });
    // The goal first: every plan on the way is a short one.
    const moved = await setField('plan-goal', REVERSE.goal.join(', '));
    check(Math.hypot(moved.goal[0] - REVERSE.goal[0], moved.goal[1] - REVERSE.goal[1]) < 1e-9, `the goal is ${moved.goal}`);
    await setField('plan-turning-radius', String(REVERSE.radius));
    await setField('plan-start-heading', '90');
    const forward = await setField('plan-goal-heading', '-90');
    const f = smoothOf(forward);
    check(f && f.found, `no forward smooth path: ${f?.note}`);
    check(f.smooth.cusps === 0 && (await page.locator('#plan-host svg .vp-cusp').count()) === 0, 'cusps without reverse');
    check(!('reverse' in bodies[bodies.length - 1]), 'the request asked for reverse before the box was ticked');
    const s = await replan('ticking reverse allowed', () => page.check('#plan-reverse'));
    check(s.reverse === true, 'the page state did not take reverse');
    const body = bodies[bodies.length - 1];
    check(body.reverse === true && body.turning_radius === REVERSE.radius, `the request was ${JSON.stringify({ reverse: body.reverse, turning_radius: body.turning_radius })}`);
    const r = smoothOf(s);
    check(r && r.found, `no smooth path with reverse: ${r?.note}`);
    const segs = r.smooth.segments;
    const changes = segs.filter((g, i) => i > 0 && g.direction !== segs[i - 1].direction);
    check(r.smooth.cusps >= 1 && changes.length === r.smooth.cusps, `cusps ${r.smooth.cusps}, direction changes ${changes.length}`);
    check(r.smooth.length < f.smooth.length, `backing up (${r.smooth.length} m) is not shorter than forward only (${f.smooth.length} m)`);
    const marks = page.locator('#plan-host svg .vp-cusp');
    check((await marks.count()) === r.smooth.cusps, `${await marks.count()} cusp marks for ${r.smooth.cusps} cusps`);
    // Each mark sits where its segment starts (the ring's centre in the plan's SVG units).
    for (let i = 0; i < changes.length; i++) {
      const ring = marks.nth(i).locator('circle').first();
      const [cx, cy] = [Number(await ring.getAttribute('cx')), Number(await ring.getAttribute('cy'))];
      const [ex, ey] = await page.evaluate(([x, y]) => window.vpmap.planMapToSvg(x, y), changes[i].start);
      check(Math.hypot(cx - ex, cy - ey) < 1e-6, `cusp mark ${i} at ${cx}, ${cy}, its segment starts at ${ex}, ${ey}`);
    }
    const row = await page.locator('#plan-table tbody tr[data-planner="smooth"]').textContent();
    const counted = `${r.smooth.cusps} cusp${r.smooth.cusps === 1 ? '' : 's'} (`;
    check(row.includes(counted) && /[\d.]+ m in reverse\)/.test(row), `the smooth row says ${row}`);
    log(`  reverse: ${r.smooth.length.toFixed(3)} m with ${r.smooth.cusps} cusp(s) vs ${f.smooth.length.toFixed(3)} m forward only; row: ${row}`);
    await page.screenshot({ path: SHOT('reverse') });
    // A closer look (for a person reading the screenshots): the plan zoomed in on the path.
    const centre = await toClient([(START[0] + REVERSE.goal[0]) / 2 - 0.3, (START[1] + REVERSE.goal[1]) / 2]);
    await page.mouse.move(centre[0], centre[1]);
    for (let i = 0; i < 3; i++) await page.mouse.wheel(0, -240);
    await page.mouse.move(5, 5); // no hover label over the path
    await page.locator('#plan-host').screenshot({ path: SHOT('reverse-zoom') });
    const off = await replan('unticking reverse allowed', () => page.uncheck('#plan-reverse'));
    check(!('reverse' in bodies[bodies.length - 1]), 'the request still asked for reverse');
    check(smoothOf(off).smooth.cusps === 0 && (await page.locator('#plan-host svg .vp-cusp').count()) === 0, 'cusps after unticking reverse');
    page.off('request', onRequest);
    noProblems();
  });
}

main()
  .then(pass)
  .catch((err) => fail(err?.message || String(err)));
