// The scene's `click_covariances_px2` table (docs/scene-format.md): how well each snapped click
// is known, a 2 x 2 covariance in px², keyed by the click's field path (`objects[0].base.near`,
// `objects[1].footprint[2]`, `objects[1].top.point`, `floor[3]`). The fit weighs each such
// click by its own covariance. An entry describes the point as it was snapped: moving the
// point by hand drops it, removing an object or the floor drops theirs and renumbers the
// objects after it, so the table never names a click that is not there (the server refuses
// such a scene). Pure: no DOM, so the unit tests (e2e/unit/covariances.test.mjs) run it in Node.

export const COV_FIELD = 'click_covariances_px2';

/** The field path of a point's path in the scene: `['objects', 0, 'base', 'near']` -> `objects[0].base.near`. */
export function pathKey(path) {
  let out = '';
  for (const k of path) {
    if (typeof k === 'number') out += `[${k}]`;
    else out += out ? `.${k}` : k;
  }
  return out;
}

const isCov = (m) => Array.isArray(m) && m.length === 2 && m.every((r) => Array.isArray(r) && r.length === 2 && r.every(Number.isFinite));

/** Record the covariance of the point at `key` (pathKey); a non-matrix drops the entry. */
export function setCovariance(scene, key, cov) {
  if (!isCov(cov)) {
    dropCovariance(scene, key);
    return;
  }
  if (!scene[COV_FIELD] || typeof scene[COV_FIELD] !== 'object') scene[COV_FIELD] = {};
  // Exactly symmetric, as the server checks it.
  const b = (cov[0][1] + cov[1][0]) / 2;
  scene[COV_FIELD][key] = [[cov[0][0], b], [b, cov[1][1]]];
}

/** The covariance recorded for `key`, or null. */
export function covarianceAt(scene, key) {
  return scene?.[COV_FIELD]?.[key] ?? null;
}

/** Drop the entries whose keys `drop(key)` says; the table goes when empty. Returns how many went. */
function dropWhere(scene, drop) {
  const t = scene?.[COV_FIELD];
  if (!t || typeof t !== 'object') return 0;
  let n = 0;
  for (const k of Object.keys(t)) {
    if (drop(k)) {
      delete t[k];
      n++;
    }
  }
  if (!Object.keys(t).length) delete scene[COV_FIELD];
  return n;
}

/** The point at `key` was moved by hand: its entry no longer describes it. */
export function dropCovariance(scene, key) {
  return dropWhere(scene, (k) => k === key);
}

/** `objects[i]...`: the object index of a key, or -1. */
function objectOf(key) {
  const m = /^objects\[(\d+)\]/.exec(key);
  return m ? Number(m[1]) : -1;
}

/** Object `i` was removed (spliced out): drop its entries and renumber those of the objects after it. */
export function objectRemoved(scene, i) {
  const t = scene?.[COV_FIELD];
  if (!t) return;
  const moved = {};
  for (const [k, v] of Object.entries(t)) {
    const j = objectOf(k);
    if (j === i) continue;
    moved[j > i ? k.replace(/^objects\[\d+\]/, `objects[${j - 1}]`) : k] = v;
  }
  if (Object.keys(moved).length) scene[COV_FIELD] = moved;
  else delete scene[COV_FIELD];
}

/** Every entry of object `i`'s points (it was replaced or its points changed wholesale). */
export function dropObject(scene, i) {
  return dropWhere(scene, (k) => objectOf(k) === i);
}

/** The floor outline was replaced or cleared: drop its entries. */
export function dropFloor(scene) {
  return dropWhere(scene, (k) => k.startsWith('floor['));
}

/**
 * Snapped points of a tool not yet in the scene: each kept with the point it describes,
 * by its path relative to where the tool's result goes (`['base', 'near']` for a box corner,
 * `['footprint', 2]`, `['floor', 3]`). `commit(scene, prefix, draft)` writes the entries whose
 * point in `draft` is still the snapped one (a corner taken back by undo, or clicked again
 * elsewhere, has none) under `prefix` (`['objects', 4]`, or `[]` for the floor).
 */
export class PendingCovariances {
  constructor() {
    this.entries = new Map();
  }

  set(rel, point, cov) {
    this.entries.set(pathKey(rel), { rel, point: [point[0], point[1]], cov });
  }

  /** The entries still describing their points in `draft` (an object or `{floor}`). */
  valid(draft) {
    const out = [];
    for (const e of this.entries.values()) {
      let v = draft;
      for (const k of e.rel) v = v?.[k];
      if (Array.isArray(v) && v[0] === e.point[0] && v[1] === e.point[1]) out.push(e);
    }
    return out;
  }

  commit(scene, prefix, draft) {
    for (const e of this.valid(draft)) setCovariance(scene, pathKey([...prefix, ...e.rel]), e.cov);
  }
}
