// Boxes by the corners the user can see (docs/scene-format.md): a box's `base` and `top` name
// any of its corners in one of two views. Corner view, a box seen across one of its vertical
// edges: `near` (the edge nearest the camera), `right`, `left` (the ends of the visible faces)
// and `far` (opposite `near`, usually hidden). Face view, a box seen face-on: `front_left`,
// `front_right` (the face towards the camera), `back_left`, `back_right`. `own_yaw: true`
// marks a box turned on the floor by its own angle. Pure: no DOM, so the unit tests
// (e2e/unit/box.test.mjs) run it in Node. The server decides whether the corners fix the box
// and names the corner to add when they do not.

import { distortPx, undistortPx } from './geometry.js';

/** The corner names of each view, in the order of the box's 2 x 2 grid of vertical edges. */
export const BOX_VIEWS = {
  corner: ['near', 'right', 'left', 'far'],
  face: ['front_left', 'front_right', 'back_left', 'back_right'],
};

/** Every corner name, corner view first (as the server lists them). */
export const BOX_CORNERS = [...BOX_VIEWS.corner, ...BOX_VIEWS.face];

/** Where each corner sits in the box's 2 x 2 grid of vertical edges: corners one step apart share an edge. */
const GRID = {
  near: [0, 0], right: [1, 0], left: [0, 1], far: [1, 1],
  front_left: [0, 0], front_right: [1, 0], back_left: [0, 1], back_right: [1, 1],
};

/** What to click for each corner, in words. */
export const CORNER_HELP = {
  near: 'where the two visible faces meet, nearest the camera',
  right: 'the right end of the visible faces',
  left: 'the left end of the visible faces',
  far: 'opposite the near corner, usually hidden',
  front_left: 'the left end of the face towards the camera',
  front_right: 'the right end of the face towards the camera',
  back_left: 'the left end of the face away from the camera',
  back_right: 'the right end of the face away from the camera',
};

/**
 * The order in which the box tool asks for the corners of a view. Corner view: the thesis's
 * base near, right, left and top near, left first (the old flow), then what is often hidden.
 * Face view: the front face, then the top's back edge, then the hidden back of the base.
 */
export const BOX_STEPS = {
  corner: [
    ['base', 'near'], ['base', 'right'], ['base', 'left'], ['top', 'near'], ['top', 'left'],
    ['top', 'right'], ['top', 'far'], ['base', 'far'],
  ],
  face: [
    ['base', 'front_left'], ['base', 'front_right'], ['top', 'front_left'], ['top', 'front_right'],
    ['top', 'back_left'], ['top', 'back_right'], ['base', 'back_left'], ['base', 'back_right'],
  ],
};

const isPoint = (p) => Array.isArray(p) && p.length === 2 && p.every(Number.isFinite);

/** `base.near`, `top.front_left`: a corner's name in messages and in `scale.edge`. */
export function cornerLabel(part, corner) {
  return `${part}.${corner}`;
}

/** The corner name in words: `front_left` -> `front left`. */
export function cornerWords(corner) {
  return corner.replace('_', ' ');
}

/** The view a box's corners are named in ('corner' or 'face'; 'corner' for a box with none). */
export function boxView(o) {
  for (const part of ['base', 'top']) {
    for (const c of BOX_CORNERS) if (isPoint(o?.[part]?.[c])) return BOX_VIEWS.face.includes(c) ? 'face' : 'corner';
  }
  return 'corner';
}

/** Every corner a box gives: `[{part, corner, p}]`, base first, in grid order. */
export function boxPoints(o) {
  const out = [];
  for (const part of ['base', 'top']) {
    for (const corner of BOX_CORNERS) {
      const p = o?.[part]?.[corner];
      if (isPoint(p)) out.push({ part, corner, p });
    }
  }
  return out;
}

/**
 * The box's edges between given corners, by name: `[{a, b, part}]` with `a`, `b` like
 * `base.near` (as `scale.edge` names them) and `part` 'base', 'top' or 'vertical'. Two
 * corners of one face share an edge when they are one grid step apart.
 */
export function boxEdgeNames(o) {
  const pts = boxPoints(o);
  const edges = [];
  for (let i = 0; i < pts.length; i++) {
    for (let j = i + 1; j < pts.length; j++) {
      const a = pts[i], b = pts[j];
      const [ai, aj] = GRID[a.corner], [bi, bj] = GRID[b.corner];
      const steps = Math.abs(ai - bi) + Math.abs(aj - bj);
      const part = a.part === b.part ? (steps === 1 ? a.part : null) : steps === 0 ? 'vertical' : null;
      if (part) edges.push({ a: cornerLabel(a.part, a.corner), b: cornerLabel(b.part, b.corner), part, pa: a.p, pb: b.p });
    }
  }
  return edges;
}

/** The box's edges between given corners, to draw: `[{a, b, part}]` with image points `a`, `b` (boxEdgeNames). */
export function boxEdges(o) {
  return boxEdgeNames(o).map((e) => ({ a: e.pa, b: e.pb, part: e.part }));
}

/** The value of a scale choice "this edge of the box" in the page's form, and back. */
export function edgeChoice(edge) {
  return `edge:${edge[0]},${edge[1]}`;
}

/** `[a, b]` of an `edgeChoice` value, or null for any other value. */
export function parseEdgeChoice(value) {
  const m = /^edge:((?:base|top)\.[a-z_]+),((?:base|top)\.[a-z_]+)$/.exec(value || '');
  return m ? [m[1], m[2]] : null;
}

/** The given corner one grid step from `corner` on the same part (base or top), or null. */
export function neighbourCorner(o, part, corner) {
  const [i, j] = GRID[corner];
  for (const c of BOX_CORNERS) {
    const [ci, cj] = GRID[c];
    if (Math.abs(ci - i) + Math.abs(cj - j) === 1 && isPoint(o?.[part]?.[c]) && (BOX_VIEWS.face.includes(c) === BOX_VIEWS.face.includes(corner))) return o[part][c];
  }
  return null;
}

/** A corner this far (image px) or more off its line is shown as off it. */
export const OFF_LINE_PX = 2;

/** The corner of each view that the edges to its grid neighbours start from (the thesis's near corner). */
export const BOX_ANCHOR = { corner: 'near', face: 'front_left' };

/** Distance (px) from `p` to the line through `a` and `b`, and the foot of the perpendicular; null when a = b. */
export function offLine(p, a, b) {
  const d = [b[0] - a[0], b[1] - a[1]];
  const n = Math.hypot(d[0], d[1]);
  if (!(n > 1e-9)) return null;
  const t = ((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / (n * n);
  const foot = [a[0] + t * d[0], a[1] + t * d[1]];
  return { px: Math.hypot(p[0] - foot[0], p[1] - foot[1]), foot };
}

/**
 * As `offLine` for a photo with a lens (`lensOf`; null: `offLine` itself): photo pixel `p` from
 * the line that runs from photo pixel `a` towards pinhole point `v` in the pinhole camera's
 * image, where such a line is straight. The foot is found there and taken back to its photo
 * pixel; `px` is the photo's pixels from `p` to it. Null when `a` is `v` or the foot lies beyond
 * the lens's reach.
 */
export function offLineThroughLens(p, a, v, lens) {
  if (!lens) return offLine(p, a, v);
  const r = offLine(undistortPx(p, lens), undistortPx(a, lens), v);
  const foot = r ? distortPx(r.foot, lens) : null;
  return foot ? { px: Math.hypot(p[0] - foot[0], p[1] - foot[1]), foot } : null;
}

/** The sine of the angle between the lines p->q and p->v (1 when either is empty), as the server's side view measures it. */
function misalignment(p, q, v) {
  const a = [q[0] - p[0], q[1] - p[1]], b = [v[0] - p[0], v[1] - p[1]];
  const n = Math.hypot(a[0], a[1]) * Math.hypot(b[0], b[1]);
  return n > 0 ? Math.abs(a[0] * b[1] - a[1] * b[0]) / n : 1;
}

/**
 * How far a box's corners are from the lines they should lie on (image pixels): each base
 * corner next to the anchor (BOX_ANCHOR) from the line from the anchor towards its horizontal
 * vanishing point, `vps[0]` or `vps[1]` (not for a box with its own yaw), and each
 * top corner from the vertical line through its base corner (towards `vps[2]`). A list of
 * `{part, corner, from, vp, px, foot}`: `from` the corner the line starts at, `vp` its index,
 * `foot` the nearest point on it. Vanishing points may be null (then no line is checked). With
 * `lens` (`lensOf`) the corners are photo pixels, the vanishing points the pinhole camera's
 * (`pinholeVp`), and the lines straight in the pinhole image (`offLineThroughLens`).
 */
export function guideOffsets(o, vps, lens = null) {
  const out = [];
  const base = o?.base || {};
  const view = boxView(o);
  const anchor = BOX_ANCHOR[view];
  const a = base[anchor];
  if (isPoint(a) && !o.own_yaw && isPoint(vps?.[0]) && isPoint(vps?.[1])) {
    // The anchor's two grid neighbours, each on an edge towards A or B: paired as the server
    // pairs them (the assignment with the smaller sum of misalignments), or the nearer line
    // for a corner alone.
    const [ai, aj] = GRID[anchor];
    const next = BOX_VIEWS[view].filter((c) => Math.abs(GRID[c][0] - ai) + Math.abs(GRID[c][1] - aj) === 1 && isPoint(base[c]));
    const mis = (c, k) => misalignment(undistortPx(a, lens), undistortPx(base[c], lens), vps[k]);
    let ks;
    if (next.length === 2) ks = mis(next[0], 0) + mis(next[1], 1) <= mis(next[0], 1) + mis(next[1], 0) ? [0, 1] : [1, 0];
    else ks = next.map((c) => (mis(c, 0) <= mis(c, 1) ? 0 : 1));
    next.forEach((c, i) => {
      const r = offLineThroughLens(base[c], a, vps[ks[i]], lens);
      if (r) out.push({ part: 'base', corner: c, from: anchor, vp: ks[i], ...r });
    });
  }
  const vv = vps?.[2];
  for (const [c, p] of Object.entries(o?.top || {})) {
    const b = base[c];
    const r = isPoint(p) && isPoint(b) && isPoint(vv) ? offLineThroughLens(p, b, vv, lens) : null;
    if (r) out.push({ part: 'top', corner: c, from: c, vp: 2, ...r });
  }
  return out;
}

/**
 * The lines a corner about to be clicked should lie on (for snapping): a base corner next to the
 * anchor, the lines from the anchor towards A and B (not with its own yaw); a top corner, the
 * vertical through its base corner. `[{from, vp}]` with `from` an image point, `vp` an index.
 */
export function guideLines(o, part, corner, vps, ownYaw = false) {
  const out = [];
  const view = BOX_VIEWS.face.includes(corner) ? 'face' : 'corner';
  const anchor = BOX_ANCHOR[view];
  if (part === 'base') {
    const a = o?.base?.[anchor];
    const [i, j] = GRID[corner], [ai, aj] = GRID[anchor];
    if (!ownYaw && isPoint(a) && Math.abs(i - ai) + Math.abs(j - aj) === 1) {
      for (const k of [0, 1]) if (isPoint(vps?.[k])) out.push({ from: a, vp: k });
    }
  } else if (isPoint(o?.base?.[corner]) && isPoint(vps?.[2])) {
    out.push({ from: o.base[corner], vp: 2 });
  }
  return out;
}

/** The base outline of a box in the image (for selection): four corners when three or more of the base are given (the fourth completes the parallelogram), else []. */
export function boxBaseOutline(o) {
  const view = boxView(o);
  const names = BOX_VIEWS[view];
  const base = o?.base || {};
  const given = names.map((c) => (isPoint(base[c]) ? base[c] : null));
  const missing = given.findIndex((p) => !p);
  if (given.filter(Boolean).length < 3) return [];
  if (missing >= 0) {
    // The missing corner is opposite the corner diagonal to it: p = a + b - opposite.
    const opposite = 3 - missing;
    const [a, b] = [0, 1, 2, 3].filter((k) => k !== missing && k !== opposite).map((k) => given[k]);
    const o2 = given[opposite];
    given[missing] = [a[0] + b[0] - o2[0], a[1] + b[1] - o2[1]];
  }
  // Grid order 00, 10, 01, 11 -> ring 00, 10, 11, 01.
  return [given[0], given[1], given[3], given[2]];
}

/** The convex hull of points (Andrew's monotone chain), counter-clockwise in image axes; [] below 3 distinct points. */
export function convexHull(points) {
  const pts = [...points].sort((a, b) => a[0] - b[0] || a[1] - b[1]);
  const cross = (o, a, b) => (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
  const half = (list) => {
    const out = [];
    for (const p of list) {
      while (out.length >= 2 && cross(out[out.length - 2], out[out.length - 1], p) <= 0) out.pop();
      out.push(p);
    }
    out.pop();
    return out;
  };
  const hull = [...half(pts), ...half([...pts].reverse())];
  return hull.length >= 3 ? hull : [];
}

/** The image outline of a box for selection: its base (boxBaseOutline), else the hull of every given corner. */
export function boxOutline(o) {
  const base = boxBaseOutline(o);
  return base.length ? base : convexHull(boxPoints(o).map((x) => x.p));
}

/** "3 base + 2 top corners (corner view)", for the object list. */
export function describeBox(o) {
  const pts = boxPoints(o);
  const nb = pts.filter((x) => x.part === 'base').length;
  const nt = pts.length - nb;
  const plural = (n, w) => `${n} ${w}${n === 1 ? '' : 's'}`;
  const corners = nt ? `${nb} base + ${plural(nt, 'top corner')}` : `${plural(nb, 'base corner')}, no top`;
  return `${corners}${boxView(o) === 'face' ? ' (face view)' : ''}${o?.own_yaw ? ', own yaw' : ''}`;
}

/**
 * The box tool's walk through the corners of one view: each step is clicked or skipped (a
 * hidden corner), undo takes back the last click or skip, and the box can be finished once
 * one corner is given. `object(name)` is the scene object.
 */
export class BoxAnnotation {
  constructor(view = 'corner') {
    this.setView(view);
    this.ownYaw = false;
  }

  /** Choose the view; only before the first click or skip (else returns false). */
  setView(view) {
    if (!BOX_STEPS[view]) throw new Error(`unknown box view ${JSON.stringify(view)}; use corner or face`);
    if (this.history?.length) return false;
    this.view = view;
    this.history = []; // [{part, corner, p}] with p null for a skipped corner
    return true;
  }

  /** The step being asked for, `{part, corner}`, or null when every corner has had its turn. */
  get current() {
    const s = BOX_STEPS[this.view][this.history.length];
    return s ? { part: s[0], corner: s[1] } : null;
  }

  /** How many corners were clicked (skips not counted). */
  get clicked() {
    return this.history.filter((x) => x.p).length;
  }

  get done() {
    return this.current === null;
  }

  /** The corners given so far, as a box object's `base` and `top` (no name). */
  get partial() {
    const o = {};
    for (const { part, corner, p } of this.history) {
      if (!p) continue;
      o[part] = o[part] || {};
      o[part][corner] = p;
    }
    return o;
  }

  /** Click the current corner at `p`. */
  click(p) {
    const c = this.current;
    if (!c || !isPoint(p)) return false;
    this.history.push({ ...c, p: [p[0], p[1]] });
    return true;
  }

  /** Skip the current corner (hidden, or not wanted). */
  skip() {
    const c = this.current;
    if (!c) return false;
    this.history.push({ ...c, p: null });
    return true;
  }

  undo() {
    return this.history.pop() !== undefined;
  }

  get canUndo() {
    return this.history.length > 0;
  }

  /** At least one corner is clicked (the server says whether they fix the box). */
  get canFinish() {
    return this.clicked > 0;
  }

  /** The scene object: `{name, base, top?, own_yaw?}` with the clicked corners. */
  object(name) {
    const { base, top } = this.partial;
    const o = { name, base: base || {} };
    if (top) o.top = top;
    if (this.ownYaw) o.own_yaw = true;
    return o;
  }
}
