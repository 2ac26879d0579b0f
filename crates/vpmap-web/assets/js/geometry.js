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

/**
 * Fit the floor plan's map-to-picture transform `px = a + s x`, `py = b - s y` (one scale,
 * +y up the page) to corresponding points by least squares. `pairs` is a list of
 * `[[x, y] map, [px, py] picture]`. Returns `{a, b, s, rms, n}` or null.
 */
export function fitPlanTransform(pairs) {
  // Unknowns (a, b, s). Residuals: a + s x - px and b - s y - py.
  let n = 0, sx = 0, sy = 0, spx = 0, spy = 0, sxx = 0, syy = 0, sxpx = 0, sypy = 0;
  for (const [[x, y], [px, py]] of pairs) {
    if (![x, y, px, py].every(Number.isFinite)) continue;
    n++;
    sx += x; sy += y; spx += px; spy += py;
    sxx += x * x; syy += y * y; sxpx += x * px; sypy += y * py;
  }
  if (n < 2) return null;
  // Normal equations: eliminate a = (spx - s sx)/n, b = (spy + s sy)/n.
  const num = sxpx - (sx * spx) / n - (sypy - (sy * spy) / n);
  const den = sxx - (sx * sx) / n + (syy - (sy * sy) / n);
  if (!(den > 1e-12)) return null;
  const s = num / den;
  if (!(s > 0)) return null;
  const a = (spx - s * sx) / n;
  const b = (spy + s * sy) / n;
  let e = 0;
  for (const [[x, y], [px, py]] of pairs) {
    if (![x, y, px, py].every(Number.isFinite)) continue;
    e += (a + s * x - px) ** 2 + (b - s * y - py) ** 2;
  }
  return { a, b, s, rms: Math.sqrt(e / n), n };
}

/** Points of SVG path data made only of M/L/Z commands with absolute coordinates, one list per sub-path. */
export function parsePathRings(d) {
  const rings = [];
  let cur = null;
  const re = /([MLZmlz])|(-?\d*\.?\d+(?:e[-+]?\d+)?)/g;
  let cmd = null;
  const nums = [];
  const flush = () => {
    while (nums.length >= 2) {
      const x = nums.shift(), y = nums.shift();
      if (cmd === 'M' || !cur) {
        cur = [];
        rings.push(cur);
        cmd = 'L';
      }
      cur.push([x, y]);
    }
  };
  let m;
  while ((m = re.exec(d)) !== null) {
    if (m[1]) {
      flush();
      const c = m[1];
      if (c === 'm' || c === 'l') return null; // relative commands: not what vpmap writes
      if (c === 'Z' || c === 'z') {
        cur = null;
        cmd = null;
      } else cmd = c;
    } else nums.push(Number(m[2]));
  }
  flush();
  return rings;
}
