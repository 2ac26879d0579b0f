// The smooth planner on the page: what the plan request adds for it (a turning radius turns it
// on; start and goal headings, free when not set), its path drawn as a curve over the plan with
// its tightest turn marked, the heading arrows at start and goal (dragged to turn them), and
// its row's measures. Headings are degrees, atan2(dy, dx) in the map's coordinates (y up), as
// /api/plan takes them (docs/web-api.md).

import { svgEl, fmt } from './util.js';

/** The smooth path's colour (also `--smooth` in the page's CSS). */
export const SMOOTH_COLOUR = '#1565c0';
/** The tightest turn's mark. */
export const TIGHTEST_COLOUR = '#d81b60';
/** A cusp's mark (a change between forward and reverse). */
export const CUSP_COLOUR = '#ef6c00';
/** Length of a heading arrow on screen, px. */
const ARROW_PX = 34;

/** A heading in degrees wrapped into (-180, 180], to a tenth of a degree. */
export function wrapHeading(deg) {
  let d = ((deg + 180) % 360 + 360) % 360 - 180;
  if (d === -180) d = 180;
  return Math.round(d * 10) / 10 + 0;
}

/**
 * A heading typed by the user: empty is free (`null`), a finite number of degrees is wrapped
 * ([`wrapHeading`]); anything else is `undefined` (refused).
 */
export function parseHeading(text) {
  const t = String(text ?? '').trim().replace(/°$/, '').trim();
  if (t === '') return null;
  const v = Number(t);
  return Number.isFinite(v) ? wrapHeading(v) : undefined;
}

/**
 * A turning radius typed by the user: empty turns the smooth planner off (`null`); a positive
 * finite number is the radius; anything else is `undefined` (refused, the server's message
 * would name it too).
 */
export function parseTurningRadius(text) {
  const t = String(text ?? '').trim();
  if (t === '') return null;
  const v = Number(t);
  return Number.isFinite(v) && v > 0 ? v : undefined;
}

/** The heading from map point `from` towards `to`, degrees (wrapped), or null when they coincide. */
export function headingTowards(from, to) {
  const dx = to[0] - from[0], dy = to[1] - from[1];
  if (!(Math.hypot(dx, dy) > 0)) return null;
  return wrapHeading((Math.atan2(dy, dx) * 180) / Math.PI);
}

/**
 * The planners and fields a plan request adds for the smooth planner, from the plan state
 * (`turning_radius`, `start_heading`, `goal_heading`, `reverse`): none without a turning
 * radius; `reverse: true` only when reverse driving is allowed.
 */
export function smoothRequest(plan, planners) {
  if (!(plan && Number.isFinite(plan.turning_radius) && plan.turning_radius > 0)) return { planners: [...planners] };
  const out = { planners: [...planners, 'smooth'], turning_radius: plan.turning_radius };
  if (Number.isFinite(plan.start_heading)) out.start_heading_deg = plan.start_heading;
  if (Number.isFinite(plan.goal_heading)) out.goal_heading_deg = plan.goal_heading;
  if (plan.reverse === true) out.reverse = true;
  return out;
}

/**
 * The cusps of a smooth answer: where one segment's `direction` (forward or reverse) differs
 * from the one before it, `{ at: [x, y], from, to }` with `at` the later segment's start.
 */
export function cuspPoints(smooth) {
  const segs = Array.isArray(smooth?.segments) ? smooth.segments : [];
  const out = [];
  for (let i = 1; i < segs.length; i++) {
    const [a, b] = [segs[i - 1], segs[i]];
    if (a?.direction && b?.direction && a.direction !== b.direction && Array.isArray(b.start)) {
      out.push({ at: [b.start[0], b.start[1]], from: a.direction, to: b.direction });
    }
  }
  return out;
}

/** The length a smooth answer drives in reverse (sum of its reverse segments), map units. */
export function reverseLength(smooth) {
  const segs = Array.isArray(smooth?.segments) ? smooth.segments : [];
  return segs.filter((s) => s?.direction === 'reverse').reduce((sum, s) => sum + (Number.isFinite(s.length) ? s.length : 0), 0);
}

/**
 * The middle of an arc segment of the smooth answer (`centre`, `radius`, `start`, `length`,
 * `turn`): its start point turned about the centre by half the arc's angle. The point turns
 * with the heading, forward or in reverse: anticlockwise for a `left` turn (the heading grows),
 * clockwise for a `right` one.
 */
export function arcMidpoint(seg) {
  const [cx, cy] = seg.centre, [sx, sy] = seg.start;
  const sign = seg.turn === 'left' ? 1 : -1;
  const a = (sign * seg.length) / seg.radius / 2;
  const dx = sx - cx, dy = sy - cy;
  return [cx + dx * Math.cos(a) - dy * Math.sin(a), cy + dx * Math.sin(a) + dy * Math.cos(a)];
}

/** The tightest turn of a smooth answer: `{ centre, mid, radius }`, or null (a straight path). */
export function tightestTurn(smooth) {
  const seg = smooth?.segments?.[smooth.tightest_turn];
  if (!seg || seg.type !== 'arc' || !Array.isArray(seg.centre) || !(seg.radius > 0)) return null;
  return { centre: seg.centre, mid: arcMidpoint(seg), radius: seg.radius };
}

/** The smooth row's measures in words: tightest radius (max curvature), clearance, cusps. */
export function smoothDetail(smooth, units) {
  if (!smooth?.found) return '';
  const k = smooth.max_curvature;
  const turn = k > 0 ? `max curvature ${fmt(k, 2)} /${units} (radius ${fmt(1 / k, 2)} ${units})` : 'straight';
  const back = reverseLength(smooth);
  const reversing = back > 0 ? ` (${fmt(back, 2)} ${units} in reverse)` : '';
  return `${turn}, min clearance ${fmt(smooth.min_clearance, 2)} ${units}, ${smooth.cusps} cusp${smooth.cusps === 1 ? '' : 's'}${reversing}`;
}

/** The path's poses as an SVG path through their points (the curve at a quarter cell). */
function curvePath(v, poses) {
  return poses
    .filter((p) => Array.isArray(p) && Number.isFinite(p[0]) && Number.isFinite(p[1]))
    .map((p, i) => {
      const [x, y] = v.mapToSvg(p);
      return `${i ? 'L' : 'M'}${x.toFixed(2)} ${y.toFixed(2)}`;
    })
    .join('');
}

/** Draw the smooth result `r` of a plan answer on the plan view `v` into `g`. */
export function drawSmooth(v, g, r) {
  const s = r?.smooth;
  if (!s?.found || !Array.isArray(s.poses) || s.poses.length < 2) return;
  const wrap = svgEl('g', { class: 'vp-smooth' });
  wrap.append(svgEl('path', {
    class: 'vp-path vp-path-smooth',
    'data-planner': 'smooth',
    d: curvePath(v, s.poses),
    fill: 'none',
    stroke: SMOOTH_COLOUR,
    'stroke-width': v.u(3),
    'stroke-linejoin': 'round',
    'stroke-linecap': 'round',
  }));
  const t = tightestTurn(s);
  if (t) {
    const [mx, my] = v.mapToSvg(t.mid), [cx, cy] = v.mapToSvg(t.centre);
    const mark = svgEl('g', { class: 'vp-tightest' });
    mark.append(svgEl('line', { x1: cx, y1: cy, x2: mx, y2: my, stroke: TIGHTEST_COLOUR, 'stroke-width': v.u(1.4), 'stroke-dasharray': `${v.u(3)} ${v.u(2)}` }));
    mark.append(svgEl('circle', { cx: mx, cy: my, r: v.u(5), fill: 'none', stroke: TIGHTEST_COLOUR, 'stroke-width': v.u(2) }));
    const title = svgEl('title');
    title.textContent = `tightest turn: radius ${fmt(t.radius, 2)}`;
    mark.append(title);
    wrap.append(mark);
  }
  // Each cusp (the robot stops and changes between forward and reverse): a bar across the
  // path with a ring, its title saying which way it changes.
  for (const c of cuspPoints(s)) {
    const [x, y] = v.mapToSvg(c.at);
    const mark = svgEl('g', { class: 'vp-cusp', 'data-from': c.from, 'data-to': c.to });
    mark.append(svgEl('circle', { cx: x, cy: y, r: v.u(6), fill: '#fff', stroke: CUSP_COLOUR, 'stroke-width': v.u(2) }));
    mark.append(svgEl('circle', { cx: x, cy: y, r: v.u(2.2), fill: CUSP_COLOUR, stroke: 'none' }));
    const title = svgEl('title');
    title.textContent = `cusp: the robot stops and changes from ${c.from} to ${c.to}`;
    mark.append(title);
    wrap.append(mark);
  }
  g.append(wrap);
}

/** The screen direction (SVG units, unit length) of map heading `deg` at map point `p`. */
function screenDirection(v, p, deg) {
  const a = (deg * Math.PI) / 180;
  const q0 = v.mapToSvg(p), q1 = v.mapToSvg([p[0] + Math.cos(a), p[1] + Math.sin(a)]);
  const n = Math.hypot(q1[0] - q0[0], q1[1] - q0[1]) || 1;
  return [(q1[0] - q0[0]) / n, (q1[1] - q0[1]) / n];
}

/**
 * Heading arrows at start and goal (`ends`: `[{ which, p, heading, shown, colour }]`): a set
 * heading solid, a free one dashed along the heading the path took (`shown`), or to the right
 * when there is no path yet. Each arrow's tip has a handle (`data-heading` its end) the plan
 * view drags.
 */
export function drawHeadingArrows(v, g, ends) {
  for (const e of ends) {
    if (!e.p) continue;
    const free = !Number.isFinite(e.heading);
    const deg = free ? (Number.isFinite(e.shown) ? e.shown : 0) : e.heading;
    const [x, y] = v.mapToSvg(e.p);
    const [dx, dy] = screenDirection(v, e.p, deg);
    const len = v.u(ARROW_PX), head = v.u(7);
    const tx = x + dx * len, ty = y + dy * len;
    const arrow = svgEl('g', { class: `vp-heading vp-heading-${e.which}${free ? ' free' : ''}`, 'data-heading': e.which });
    arrow.append(svgEl('line', { x1: x, y1: y, x2: tx, y2: ty, stroke: e.colour, 'stroke-width': v.u(2.2), 'stroke-dasharray': free ? `${v.u(4)} ${v.u(3)}` : null, 'stroke-opacity': free ? 0.7 : 1 }));
    const [px, py] = [-dy, dx];
    arrow.append(svgEl('path', {
      d: `M${tx + dx * head} ${ty + dy * head}L${tx + px * head * 0.6} ${ty + py * head * 0.6}L${tx - px * head * 0.6} ${ty - py * head * 0.6}Z`,
      fill: free ? '#fff' : e.colour,
      stroke: e.colour,
      'stroke-width': v.u(1.2),
    }));
    const handle = svgEl('circle', { class: 'vp-heading-handle', 'data-heading': e.which, cx: tx, cy: ty, r: v.u(9), fill: 'transparent', stroke: 'none' });
    const title = svgEl('title');
    title.textContent = free
      ? `${e.which} heading free${Number.isFinite(e.shown) ? ` (the path leaves at ${fmt(e.shown, 0)}°)` : ''}: drag to set it`
      : `${e.which} heading ${fmt(e.heading, 0)}°: drag to turn it, double-click to free it`;
    handle.append(title);
    arrow.append(handle);
    g.append(arrow);
  }
}

/** The headings a smooth answer's path has at its ends, degrees, or nulls. */
export function pathHeadings(r) {
  const poses = r?.smooth?.found ? r.smooth.poses : null;
  if (!Array.isArray(poses) || poses.length === 0) return [null, null];
  return [poses[0][2], poses[poses.length - 1][2]].map((d) => (Number.isFinite(d) ? wrapHeading(d) : null));
}
