// Clicks that snap to the photo (docs/snapping.md): a placed point goes where the user clicked
// at once; the server (/api/snap) then looks at the photo around it for the corner where two
// straight edges meet and, if the point is still where it was put, moves it there and records
// its covariance (covariances.js). The snapped point and the edges that fixed it are drawn for
// FLASH_MS; a click that stays (flat wall, a single edge) shows the server's note briefly.
// Snapping is on unless the toolbar's toggle is off; Alt places a point where clicked. The
// photo is sent once per photo (/api/photo) and named by its id afterwards.

import { proposeBoxes, snapClick, uploadPhoto } from './api.js';
import { resolvedVps } from './scene.js';
import { lensOf } from './geometry.js';
import { $ } from './util.js';
import { pathKey, setCovariance } from './covariances.js';

/** How long the snapped point and its edges are drawn, ms. */
export const FLASH_MS = 1000;
/** How long a note on a click that stayed is shown, ms. */
const NOTE_MS = 3000;

/** The scene's vanishing points as the API takes them: the known ones up to the first unknown. */
export function knownVps(scene) {
  const out = [];
  for (const p of resolvedVps(scene).slice(0, 3)) {
    if (!p) break;
    out.push([p[0], p[1]]);
  }
  return out;
}

/**
 * The `/api/snap` body for a click at `raw` on photo `id` of `scene`: its known vanishing points
 * (the pinhole camera's) and, for a photo with a lens, the lens and its centre, so that the
 * server looks along the edges as the photo bows them.
 */
export function snapRequest(scene, id, raw, clickSigma) {
  return withLens(scene, { photo: id, click: raw, vanishing_points: knownVps(scene), click_sigma: clickSigma ?? undefined });
}

/** `body` with the scene's lens and its centre when it has one (/api/snap, /api/propose). */
export function withLens(scene, body) {
  const lens = lensOf(scene);
  if (lens) {
    body.lens_distortion = { k: lens.k };
    body.principal_point = lens.centre;
  }
  return body;
}

/** Install the toggle and `app.photoSnap` (enabled, flash, pending, and whether a build
 * waits for the pending answers). */
export function installPhotoSnap(app) {
  const snap = { enabled: true, flash: null, pending: 0, noteTimer: 0, buildWaiting: false };
  app.photoSnap = snap;
  const toggle = $('snap-photo');
  if (toggle) {
    toggle.checked = true;
    toggle.addEventListener('change', () => {
      snap.enabled = toggle.checked;
      app.setStatus(snap.enabled ? 'Clicks snap to the photo’s corners (Alt: where clicked).' : 'Clicks go where clicked (snapping to the photo is off).');
    });
  }
}

/** The id of the active photo on the server (sent once; again after the server forgot it). */
async function photoId(app, slot, again = false) {
  // A photo opened into the same slot replaces the one the server keeps for it.
  if (again || slot.snapPhotoOf !== slot.photoBlob) slot.snapPhoto = null;
  if (!slot.snapPhoto) {
    if (!slot.photoBlob) throw new Error('the photo’s bytes are not open in this page (open the photo)');
    slot.snapPhotoOf = slot.photoBlob;
    slot.snapPhoto = uploadPhoto(slot.photoBlob).then((a) => a.id);
    slot.snapPhoto.catch(() => {
      slot.snapPhoto = null;
    });
  }
  return slot.snapPhoto;
}

/** Call `fn(id)` with the photo's id, sending the photo again once when the server has forgotten it (404). */
async function withPhoto(app, slot, fn) {
  try {
    return await fn(await photoId(app, slot));
  } catch (err) {
    if (err?.status !== 404) throw err;
    return fn(await photoId(app, slot, true));
  }
}

function showNote(app, text) {
  const snap = app.photoSnap;
  app.setStatus(text);
  clearTimeout(snap.noteTimer);
  snap.noteTimer = setTimeout(() => {
    if (typeof document !== 'undefined' && document.getElementById('status')?.textContent === text) app.setStatus('');
  }, NOTE_MS);
}

/** Whether a click with event `e` should snap to the photo. */
export function snapWanted(app, e) {
  return !!(app.photoSnap?.enabled && !e?.altKey && app.state.photoBlob && app.state.scene);
}

const same = (a, b) => Array.isArray(a) && Array.isArray(b) && a[0] === b[0] && a[1] === b[1];

/**
 * Snap the point just placed at `raw`: when the answer comes and `get()` still gives `raw`
 * (the user has not taken it back or moved it), `set(point, covariance)` moves it. Returns
 * the request's promise (resolves to the answer, or null).
 */
export async function snapPlaced(app, raw, { get, set }) {
  const st = app.state;
  const slot = st.photos[st.active];
  const snap = app.photoSnap;
  if (snap.failed === slot) return null;
  snap.pending++;
  try {
    const request = (id) => snapClick(snapRequest(st.scene, id, raw, st.settings.click_sigma));
    const ans = await withPhoto(app, slot, request);
    st.counters.snaps = (st.counters.snaps || 0) + 1;
    snap.last = ans;
    if (st.photos[st.active] !== slot) return null;
    snap.flash = { click: raw, point: ans.point, edges: ans.edges || [], snapped: ans.snapped, until: performance.now() + FLASH_MS };
    app.requestRender();
    setTimeout(() => app.requestRender(), FLASH_MS + 30);
    if (!ans.snapped) {
      showNote(app, `Kept where clicked: ${ans.note}.`);
      return ans;
    }
    if (same(get(), raw)) {
      set(ans.point, ans.covariance_px2);
      showNote(app, `Snapped ${ans.moved_px.toFixed(1)} px to the corner of two edges (Alt-click to place a point where clicked).`);
    }
    return ans;
  } catch (err) {
    // A photo the server cannot read: say so once and stop trying for this photo.
    if (err?.status === 400 && /photo|JPEG|PNG|decode|empty/i.test(err.message) && !/outside/.test(err.message)) snap.failed = slot;
    app.showError(`Snapping to the photo: ${err.message}. The point stays where clicked.`);
    return null;
  } finally {
    snap.pending--;
    // The build put off while clicks were snapping (requests.js).
    if (!snap.pending && snap.buildWaiting) {
      snap.buildWaiting = false;
      app.scheduleBuild();
    }
  }
}

/** The active photo's box proposals (/api/propose): `[{corners: {base, top}, score}]`. */
export async function fetchProposals(app) {
  const st = app.state;
  const slot = st.photos[st.active];
  const vps = knownVps(st.scene);
  if (vps.length < 2) throw new Error('box proposals need the two horizontal vanishing points: detect them or draw their lines first');
  const ans = await withPhoto(app, slot, (id) => proposeBoxes(withLens(st.scene, { photo: id, vanishing_points: vps })));
  return ans.proposals || [];
}

/** Draw the last snap's edges and point while it is fresh. */
export function drawSnapFlash(view, app) {
  const f = app.photoSnap?.flash;
  if (!f || performance.now() > f.until) return;
  for (const e of f.edges) {
    view.path([[e[0], e[1]], [e[2], e[3]]]);
    view.strokeHalo('#ffee58', 2);
  }
  if (f.snapped) {
    view.path([f.click, f.point]);
    view.strokeHalo('#ffffff', 1, [2, 2]);
    view.dot(f.point, 5, '#ffee58');
  } else {
    const q = view.imageToScreen(f.click);
    view.ctx.beginPath();
    view.ctx.arc(q[0], q[1], 9, 0, Math.PI * 2);
    view.strokeHalo('#ff9e80', 1.5, [3, 3]);
  }
}

/**
 * Where a point a placement tool put lives, for snapPlaced: in the tool's draft (`tool.draft()`
 * an object like the one it will add, `tool.draftSet(rel, p)`) until the tool commits it, then
 * in the scene at `tool.committed.prefix` + `rel` (`committed.name`: the object must still be
 * there under that name). A snap on the draft is kept in `tool.covs` (PendingCovariances) and
 * written with the object; a snap after the commit edits the scene (no undo step of its own:
 * undo takes the point back with the object).
 */
export function placedTarget(app, tool, rel) {
  const scenePath = () => {
    const c = tool.committed;
    const scene = app.state.scene;
    if (!c || !scene) return null;
    if (c.name !== undefined && scene.objects?.[c.prefix[1]]?.name !== c.name) return null;
    return [...c.prefix, ...rel];
  };
  const at = (v, path) => path.reduce((o, k) => o?.[k], v);
  return {
    get: () => {
      if (!tool.committed) return at(tool.draft(), rel);
      const path = scenePath();
      return path ? at(app.state.scene, path) : null;
    },
    set: (p, cov) => {
      if (!tool.committed) {
        tool.draftSet(rel, p);
        tool.covs.set(rel, p, cov);
        app.requestRender();
        return;
      }
      const path = scenePath();
      if (!path) return;
      app.edit((scene) => {
        let v = scene;
        for (const k of path.slice(0, -1)) v = v[k];
        v[path[path.length - 1]] = [p[0], p[1]];
        setCovariance(scene, pathKey(path), cov);
      }, { undo: false });
    },
  };
}
