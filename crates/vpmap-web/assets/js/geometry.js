// Plane geometry for drawing and hit testing (pixels or metres; nothing here is part of the
// reconstruction, which the server does).

/**
 * The point nearest to all the lines through the segments `[x1, y1, x2, y2]`, in the
 * least-squares sense (what vpmap does for a vanishing point given as `lines`), or null when
 * there are fewer than two usable segments or they are (nearly) parallel.
 */
export function intersectSegments(segs) {
  let a11 = 0, a12 = 0, a22 = 0, b1 = 0, b2 = 0, n = 0;
  for (const s of segs) {
    const dx = s[2] - s[0], dy = s[3] - s[1];
    const len = Math.hypot(dx, dy);
    if (!(len > 1e-9)) continue;
    const nx = -dy / len, ny = dx / len; // unit normal
    const c = nx * s[0] + ny * s[1];
    a11 += nx * nx; a12 += nx * ny; a22 += ny * ny;
    b1 += nx * c; b2 += ny * c;
    n++;
  }
  if (n < 2) return null;
  const det = a11 * a22 - a12 * a12;
  if (Math.abs(det) < 1e-10 * n * n) return null;
  const p = [(b1 * a22 - b2 * a12) / det, (a11 * b2 - a12 * b1) / det];
  return p.every(Number.isFinite) ? p : null;
}

/**
 * A scene entry's vanishing point in the pinhole camera's image, as the server reads it: its
 * `point` as given (a point is the pinhole camera's), else its lines' intersection after each
 * segment's ends are taken through `lens` (`lensOf`; segments are photo pixels). Without a lens
 * the same as `vpPoint`.
 */
export function pinholeVp(vp, lens) {
  if (!lens || !Array.isArray(vp?.lines)) return vpPoint(vp);
  return intersectSegments(vp.lines.map((s) => {
    const a = undistortPx([s[0], s[1]], lens), b = undistortPx([s[2], s[3]], lens);
    return [a[0], a[1], b[0], b[1]];
  }));
}

/**
 * The photo pixels of the straight line that runs from photo pixel `from` towards pinhole point
 * `vp` in the pinhole camera's image (`lens`, see `lensOf`), `reach` pinhole pixels either side
 * of `from` (not past `vp` when it is nearer): `samples + 1` points of the pinhole line, each taken
 * to its photo pixel (points beyond the lens's reach are left out). Without a lens the two ends.
 * Null when `from` is `vp`.
 */
export function lineThroughLens(from, vp, lens, reach, samples = 64) {
  const a = undistortPx(from, lens);
  const d = [vp[0] - a[0], vp[1] - a[1]];
  const len = Math.hypot(d[0], d[1]);
  if (!(len > 1e-9)) return null;
  const u = [d[0] / len, d[1] / len];
  const t0 = -reach, t1 = Math.min(reach, len);
  return segmentThroughLens([a[0] + u[0] * t0, a[1] + u[1] * t0], [a[0] + u[0] * t1, a[1] + u[1] * t1], lens, samples);
}

/**
 * The photo pixels of the pinhole segment from `p` to `q` through `lens` (`lensOf`): `samples + 1`
 * evenly spaced points of it, each taken to its photo pixel (those beyond the lens's reach left
 * out); without a lens, its two ends.
 */
export function segmentThroughLens(p, q, lens, samples = 64) {
  if (!lens) return [p, q];
  const out = [];
  for (let i = 0; i <= samples; i += 1) {
    const t = i / samples;
    const r = distortPx([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])], lens);
    if (r) out.push(r);
  }
  return out;
}

/** The resolved vanishing point of a scene entry: its `point`, else its lines' intersection. */
export function vpPoint(vp) {
  if (!vp) return null;
  if (Array.isArray(vp.point) && vp.point.length === 2) return vp.point;
  if (Array.isArray(vp.lines)) return intersectSegments(vp.lines);
  return null;
}

/**
 * The part of the infinite line through `p` and `q` inside the rectangle
 * `[x0, y0, x1, y1]`, as `[[x, y], [x, y]]`, or null when it misses it.
 */
export function clipLine(p, q, rect) {
  const [x0, y0, x1, y1] = rect;
  const dx = q[0] - p[0], dy = q[1] - p[1];
  if (!(Math.hypot(dx, dy) > 0)) return null;
  let t0 = -Infinity, t1 = Infinity;
  const clip = (den, num) => {
    // Keep t with den * t <= num.
    if (Math.abs(den) < 1e-12) return num >= 0;
    const t = num / den;
    if (den > 0) t1 = Math.min(t1, t);
    else t0 = Math.max(t0, t);
    return true;
  };
  if (!clip(-dx, p[0] - x0) || !clip(dx, x1 - p[0]) || !clip(-dy, p[1] - y0) || !clip(dy, y1 - p[1])) return null;
  if (t0 > t1) return null;
  return [[p[0] + t0 * dx, p[1] + t0 * dy], [p[0] + t1 * dx, p[1] + t1 * dy]];
}

/**
 * The lens of a photo's scene as docs/scene-format.md defines `lens_distortion` (the division
 * model: photo pixel `p` to pinhole `c + (p - c) / (1 + k r^2)`, `r = |p - c| / h`, `c` the
 * scene's `principal_point` or the image centre, `h` half the image diagonal), as
 * `{k, centre, unit}`; null for a pinhole photo (no lens, or `k` 0).
 */
export function lensOf(scene) {
  const l = scene?.lens_distortion;
  const w = scene?.image?.width, h = scene?.image?.height;
  if (!l || !Number.isFinite(l.k) || l.k === 0 || !(w > 0 && h > 0)) return null;
  const pp = scene.principal_point;
  const centre = Array.isArray(pp) && pp.every(Number.isFinite) ? pp : [w / 2, h / 2];
  return { k: l.k, centre, unit: Math.hypot(w, h) / 2 };
}

/** Photo pixel `p` taken to the pinhole camera's image by `lens` (`lensOf`; null: unchanged). */
export function undistortPx(p, lens) {
  if (!lens) return p;
  const d = [p[0] - lens.centre[0], p[1] - lens.centre[1]];
  const s = 1 + lens.k * (d[0] * d[0] + d[1] * d[1]) / (lens.unit * lens.unit);
  return [lens.centre[0] + d[0] / s, lens.centre[1] + d[1] / s];
}

/**
 * The photo pixel of pinhole pixel `p` through `lens` (the inverse of `undistortPx`, the root
 * nearer the pinhole radius), or null beyond the lens's reach; `p` itself without a lens.
 */
export function distortPx(p, lens) {
  if (!lens) return p;
  const d = [p[0] - lens.centre[0], p[1] - lens.centre[1]];
  const ru = Math.hypot(d[0], d[1]) / lens.unit;
  if (ru === 0) return p;
  const disc = 1 - 4 * lens.k * ru * ru;
  if (!(disc >= 0)) return null;
  const rd = (2 * ru) / (1 + Math.sqrt(disc));
  return [lens.centre[0] + d[0] * (rd / ru), lens.centre[1] + d[1] * (rd / ru)];
}

/**
 * How far (px) `p` lies above the horizon through `a` and `b` (image points, y down): positive
 * above it, negative below, "above" being the side away from the bottom of the image (for any
 * roll under 90 degrees). Null when `a` = `b`.
 */
export function aboveHorizon(p, a, b) {
  const d = [b[0] - a[0], b[1] - a[1]];
  const n = Math.hypot(d[0], d[1]);
  if (!(n > 0)) return null;
  // The unit normal pointing down the image.
  let nx = -d[1] / n, ny = d[0] / n;
  if (ny < 0) { nx = -nx; ny = -ny; }
  return -((p[0] - a[0]) * nx + (p[1] - a[1]) * ny);
}

/**
 * Corners where edges of different directions meet: for every two segments `[x1, y1, x2, y2]`
 * from different lists of `groups` (the lines towards each vanishing point), the crossing of
 * their lines when it lies within `reach` of an end of each (an L-shaped meeting, as at a box's
 * corner). Image pixels.
 */
export function segmentCorners(groups, reach) {
  const out = [];
  const nearEnd = (p, s) => Math.min(Math.hypot(p[0] - s[0], p[1] - s[1]), Math.hypot(p[0] - s[2], p[1] - s[3])) <= reach;
  for (let a = 0; a < groups.length; a++) {
    for (let b = a + 1; b < groups.length; b++) {
      for (const s of groups[a] || []) {
        for (const t of groups[b] || []) {
          const d1 = [s[2] - s[0], s[3] - s[1]], d2 = [t[2] - t[0], t[3] - t[1]];
          const den = d1[0] * d2[1] - d1[1] * d2[0];
          if (Math.abs(den) < 1e-9 * Math.hypot(...d1) * Math.hypot(...d2)) continue;
          const u = ((t[0] - s[0]) * d2[1] - (t[1] - s[1]) * d2[0]) / den;
          const p = [s[0] + u * d1[0], s[1] + u * d1[1]];
          if (nearEnd(p, s) && nearEnd(p, t)) out.push(p);
        }
      }
    }
  }
  return out;
}

/** Distance from point `p` to the segment `a`-`b`. */
export function distToSegment(p, a, b) {
  const dx = b[0] - a[0], dy = b[1] - a[1];
  const l2 = dx * dx + dy * dy;
  let t = l2 > 0 ? ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2 : 0;
  t = Math.max(0, Math.min(1, t));
  return Math.hypot(p[0] - a[0] - t * dx, p[1] - a[1] - t * dy);
}

/** Even-odd point-in-polygon test. */
export function pointInPolygon(p, ring) {
  let inside = false;
  for (let i = 0, j = ring.length - 1; i < ring.length; j = i++) {
    const [xi, yi] = ring[i], [xj, yj] = ring[j];
    if ((yi > p[1]) !== (yj > p[1]) && p[0] < ((xj - xi) * (p[1] - yi)) / (yj - yi) + xi) inside = !inside;
  }
  return inside;
}

// Affine transforms in SVG's `matrix(a b c d e f)` order, as `{a, b, c, d, e, f}`:
// x' = a x + c y + e, y' = b x + d y + f.

/**
 * The transform written in a floor-plan SVG's `data-svg-from-map` attribute ("a b c d e f",
 * map coordinates to SVG user units), or null when the text is not six finite numbers or the
 * transform cannot be inverted.
 */
export function parseAffine(text) {
  if (typeof text !== 'string') return null;
  const parts = text.trim().split(/[\s,]+/);
  if (parts.length !== 6 || parts.some((p) => p === '')) return null;
  const v = parts.map(Number);
  if (!v.every(Number.isFinite)) return null;
  const [a, b, c, d, e, f] = v;
  const m = { a, b, c, d, e, f };
  return invertAffine(m) ? m : null;
}

/** `m` applied to the point `p`. */
export function applyAffine(m, p) {
  return [m.a * p[0] + m.c * p[1] + m.e, m.b * p[0] + m.d * p[1] + m.f];
}

/** The inverse of `m`, or null when it is singular. */
export function invertAffine(m) {
  const det = m.a * m.d - m.b * m.c;
  if (!(Math.abs(det) > 1e-12) || !Number.isFinite(det)) return null;
  return {
    a: m.d / det,
    b: -m.b / det,
    c: -m.c / det,
    d: m.a / det,
    e: (m.c * m.f - m.d * m.e) / det,
    f: (m.b * m.e - m.a * m.f) / det,
  };
}

/** `m` after `n`: the transform that applies `n` first, then `m`. */
export function composeAffine(m, n) {
  return {
    a: m.a * n.a + m.c * n.b,
    b: m.b * n.a + m.d * n.b,
    c: m.a * n.c + m.c * n.d,
    d: m.b * n.c + m.d * n.d,
    e: m.a * n.e + m.c * n.f + m.e,
    f: m.b * n.e + m.d * n.f + m.f,
  };
}

/**
 * Where the occupancy grid's image goes in the picture: the transform from image pixels
 * (column u right, row v down; row 0 is the grid's top row, at the largest map y, as in the
 * PGM file) to SVG user units, given the map-to-picture transform `svgFromMap` and the grid's
 * `width` and `height` (cells), `resolution` (map units per cell) and `origin` (map point of
 * the bottom-left corner of the bottom-left cell).
 */
export function occupancyToSvg(svgFromMap, { height, resolution, origin }) {
  const mapFromPixel = { a: resolution, b: 0, c: 0, d: -resolution, e: origin[0], f: origin[1] + height * resolution };
  return composeAffine(svgFromMap, mapFromPixel);
}
