// The scene file (docs/scene-format.md) as the page edits it. The page keeps the scene in
// exactly the file's shape, so saving is `JSON.stringify` and unknown fields survive a round trip.

import { lensOf, pinholeVp, vpPoint } from './geometry.js';
import { boxOutline, boxPoints, convexHull } from './box.js';

export const VP_NAMES = ['Horizontal A', 'Horizontal B', 'Vertical'];
export const VP_COLOURS = ['#e53935', '#2e9d3a', '#1e73d8'];

/** A new scene for a photo of `width` x `height` pixels. */
export function emptyScene(width, height) {
  return {
    version: 1,
    image: { width, height },
    vanishing_points: [{ lines: [] }, { lines: [] }],
    objects: [],
    floor: [],
  };
}

/**
 * Check a parsed JSON value is plausibly a scene, and fill in the lists the page relies on.
 * Returns an error message or null. The server does the real validation.
 */
export function normaliseScene(scene) {
  if (!scene || typeof scene !== 'object' || Array.isArray(scene)) return 'the file is not a JSON object';
  if (scene.version !== 1) return `unsupported scene version ${JSON.stringify(scene.version)} (expected 1)`;
  const img = scene.image;
  if (!img || !(img.width > 0) || !(img.height > 0)) return 'the scene has no valid `image` {width, height}';
  if (!Array.isArray(scene.vanishing_points)) scene.vanishing_points = [];
  while (scene.vanishing_points.length < 2) scene.vanishing_points.push({ lines: [] });
  for (const vp of scene.vanishing_points) {
    if (vp.lines !== undefined && !Array.isArray(vp.lines)) return '`vanishing_points[].lines` must be a list';
  }
  if (!Array.isArray(scene.objects)) scene.objects = [];
  if (!Array.isArray(scene.floor)) scene.floor = [];
  return null;
}

/** The vanishing point entry can be resolved (a point, a direction at infinity, or two or more lines). */
export function vpUsable(vp) {
  if (!vp) return false;
  if (Array.isArray(vp.point) && vp.point.length === 2) return true;
  if (Array.isArray(vp.direction) && vp.direction.length === 2) return true;
  return Array.isArray(vp.lines) && vp.lines.length >= 2;
}

/** Why the scene cannot be built yet, or null when it can be sent to /api/build. */
export function buildBlocker(scene) {
  if (!scene) return 'open a photo or a scene';
  const vps = scene.vanishing_points || [];
  for (let i = 0; i < Math.min(vps.length, 3); i++) {
    if (!vpUsable(vps[i])) {
      return `${VP_NAMES[i]} vanishing point needs a point or at least two lines`;
    }
  }
  if (vps.length < 2) return 'two horizontal vanishing points are needed';
  if (scene.floor && scene.floor.length > 0 && scene.floor.length < 3) return 'the floor needs at least 3 corners';
  return null;
}

/** A name like `base 2` not used by any object yet. */
export function uniqueName(scene, base) {
  const used = new Set(scene.objects.map((o) => o.name));
  for (let i = 1; ; i++) {
    const n = `${base} ${i}`;
    if (!used.has(n)) return n;
  }
}

/** Get the value at `path` (a list of keys) in `obj`. */
export function getAt(obj, path) {
  let v = obj;
  for (const k of path) {
    if (v == null) return undefined;
    v = v[k];
  }
  return v;
}

/** Set the value at `path` in `obj`. */
export function setAt(obj, path, value) {
  let v = obj;
  for (const k of path.slice(0, -1)) v = v[k];
  v[path[path.length - 1]] = value;
}

/**
 * Every draggable point of the scene: `{path, p, kind, owner}` where `path` locates the point
 * (`p` is `[x, y]`) or, for segment ends, the segment and `end` 0 or 1.
 */
export function handles(scene) {
  const out = [];
  if (!scene) return out;
  scene.objects.forEach((o, i) => {
    if (o.base) {
      // A box: every corner it names, base then top (box.js).
      for (const { part, corner, p } of boxPoints(o)) out.push({ path: ['objects', i, part, corner], p, kind: 'object', owner: i });
    }
    if (Array.isArray(o.footprint)) {
      o.footprint.forEach((p, j) => out.push({ path: ['objects', i, 'footprint', j], p, kind: 'object', owner: i }));
      if (o.top && Array.isArray(o.top.point)) out.push({ path: ['objects', i, 'top', 'point'], p: o.top.point, kind: 'object', owner: i });
    }
  });
  (scene.floor || []).forEach((p, j) => out.push({ path: ['floor', j], p, kind: 'floor' }));
  const fd = scene.scale && scene.scale.floor_distance;
  if (fd) {
    for (const k of ['from', 'to']) if (fd[k]) out.push({ path: ['scale', 'floor_distance', k], p: fd[k], kind: 'scale' });
  }
  (scene.vanishing_points || []).forEach((vp, k) => {
    (vp.lines || []).forEach((s, j) => {
      out.push({ path: ['vanishing_points', k, 'lines', j], end: 0, p: [s[0], s[1]], kind: 'vp', owner: k });
      out.push({ path: ['vanishing_points', k, 'lines', j], end: 1, p: [s[2], s[3]], kind: 'vp', owner: k });
    });
  });
  return out;
}

/** The image outline of an object (for selection): its base polygon; a box's base completed to four corners, or the hull of its corners. */
export function objectOutline(o) {
  if (Array.isArray(o.footprint)) return o.footprint;
  if (o.base) return boxOutline(o);
  return [];
}

/**
 * The image area of an object for a click to select it: the convex hull of its outline and its
 * top points (a box's faces and a footprint's prism, not only its base).
 */
export function objectHull(o) {
  const pts = [...objectOutline(o)];
  if (o.base) pts.push(...boxPoints(o).map((x) => x.p));
  if (Array.isArray(o.top?.point)) pts.push(o.top.point);
  return convexHull(pts);
}

/** Area of a polygon (absolute, in its units squared). */
export function polygonArea(ring) {
  let a = 0;
  for (let i = 0, j = ring.length - 1; i < ring.length; j = i++) a += ring[j][0] * ring[i][1] - ring[i][0] * ring[j][1];
  return Math.abs(a) / 2;
}

/**
 * The resolved vanishing points of the scene (null entries where unknown), in the pinhole
 * camera's image: with a lens (`lens_distortion`) a `lines` entry's segments are taken through
 * it before they are intersected, as the server reads them (`pinholeVp`).
 */
export function resolvedVps(scene) {
  const lens = lensOf(scene);
  return (scene?.vanishing_points || []).map((vp) => pinholeVp(vp, lens));
}

/**
 * For each detected segment, the index of the scene's vanishing point it supports (-1 for
 * none). The detector lists its vanishing points in its own order with a `vertical` flag;
 * each is matched to the scene entry whose direction from the principal point is closest.
 */
export function segmentOwners(res, scene) {
  const owners = new Array((res.segments || []).length).fill(-1);
  const pp = scene.principal_point || [scene.image.width / 2, scene.image.height / 2];
  const scenePts = scene.vanishing_points.map(vpPoint);
  const dir = (p) => {
    const d = [p[0] - pp[0], p[1] - pp[1]];
    const n = Math.hypot(d[0], d[1]) || 1;
    return [d[0] / n, d[1] / n];
  };
  let nextHorizontal = 0;
  for (const v of res.vanishing_points || []) {
    let k = v.vertical ? 2 : nextHorizontal++;
    if (v.point && !v.vertical) {
      let best = -1;
      for (let j = 0; j < Math.min(2, scenePts.length); j++) {
        if (!scenePts[j]) continue;
        const a = dir(v.point), b = dir(scenePts[j]);
        const c = Math.abs(a[0] * b[0] + a[1] * b[1]);
        if (best < 0 || c > best) {
          best = c;
          k = j;
        }
      }
    }
    for (const i of v.segments || []) if (i >= 0 && i < owners.length) owners[i] = k;
  }
  return owners;
}

/**
 * The scene point a server message is about: its first field name in backquotes
 * (`floor[2]`, `objects[0].base.right`, `objects[1].footprint[3]`, `objects[1].top.point`)
 * as `{path, p, note}` with `p` the point, or `{path, object, note}` for an object or a part
 * of it that is not one point (`objects[1]`, `objects[1].base`), or null when the message names
 * no point of this scene. `note` is what the message says to add (`add base.left`), or null.
 */
export function messagePoint(message, scene) {
  const m = /`((?:floor|objects)\[\d+\][^`]*)`/.exec(String(message || ''));
  if (!m || !scene) return null;
  const path = [];
  for (const part of m[1].matchAll(/([a-z_]+)|\[(\d+)\]/g)) path.push(part[1] !== undefined ? part[1] : Number(part[2]));
  const v = getAt(scene, path);
  // What the message says to add (`add \`base.left\``), to show beside the object.
  const add = /add `([a-z_.]+)`/.exec(String(message));
  const note = add ? `add ${add[1]}` : null;
  if (Array.isArray(v) && v.length === 2 && v.every(Number.isFinite)) return { path, p: v, note };
  if (path[0] === 'objects' && v !== undefined && scene.objects?.[path[1]]) return { path: ['objects', path[1]], object: path[1], note };
  return null;
}

/** A deep copy (the scene is plain JSON). */
export function cloneScene(scene) {
  return scene ? JSON.parse(JSON.stringify(scene)) : null;
}
