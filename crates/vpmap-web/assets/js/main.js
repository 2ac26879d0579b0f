// vpmap's web page: wiring of the photo canvas, the step panel, the floor plan and the 3D
// view to the server's API. State lives in `state`; the scene is kept in the scene file's
// own shape (scene.js). Every edit goes through `app.edit`, which records undo, redraws and
// schedules a rebuild (debounced 100 ms, stale requests aborted).

import * as api from './api.js';
import { $, h, debouncer, fmt, parsePair, formatPair, base64ToBytes, download, isTyping } from './util.js';
import { emptyScene, normaliseScene, buildBlocker, cloneScene, VP_NAMES, vpUsable } from './scene.js';
import { vpPoint } from './geometry.js';
import { PhotoView } from './photo-view.js';
import { SelectTool, BoxTool, FootprintTool, FloorTool, FloorDistanceTool, VpLineTool, moveHandle } from './tools.js';
import { PlanView, PLANNER_STYLE } from './plan-view.js';
import { ModelView } from './model-view.js';

const PLANNERS = ['mbpp', 'astar-ps', 'optimal'];
const UNDO_LIMIT = 200;

const state = {
  scene: null,
  photo: null, // ImageBitmap
  photoBlob: null, // the photo's original bytes, sent to /api/detect
  photoName: '',
  detection: null, // {segments, segmentVp, warnings}
  camera: null, // camera of the last build
  build: null, // last successful /api/build answer
  buildError: null,
  selection: null, // {type: 'object', index} | {type: 'vpline', vp, line}
  handle: null, // last grabbed point, for keyboard nudging
  showSegments: true,
  savedVpPoints: [null, null, null],
  settings: { method: 'sideview', resolution: 0.05, robot_radius: 0.2 },
  plan: { start: null, goal: null, result: null, error: null },
  counters: { builds: 0, plans: 0, detects: 0 },
  busy: { build: false, plan: false, detect: false, example: false },
};

const history = { undo: [], redo: [], dragging: false };

// ---- the app object the views and tools talk to ----------------------------------------

const app = {
  state,
  tool: null,
  edit,
  beginDrag() {
    pushUndo();
    history.dragging = true;
  },
  endDrag() {
    history.dragging = false;
    renderPanel();
  },
  select(sel) {
    state.selection = sel;
    renderObjectList();
    photoView.requestRender();
  },
  addObject(obj) {
    edit((scene) => scene.objects.push(obj));
    const i = state.scene.objects.length - 1;
    endTool();
    app.select({ type: 'object', index: i });
    const input = document.querySelector(`#object-list li[data-index="${i}"] .obj-name`);
    if (input) {
      input.focus();
      input.select();
    }
    setStatus(`Added “${obj.name}”: type a name, then add the next object or press Escape.`);
  },
  /** Lines of vanishing point `k` were edited: drop its `point`, so the lines decide. */
  detachVpPoint(k, scene) {
    const vp = scene.vanishing_points[k];
    if (vp && vp.point) {
      state.savedVpPoints[k] = vp.point;
      delete vp.point;
    }
  },
  endTool,
  promptChanged: renderPrompt,
  requestRender: () => photoView.requestRender(),
  nudge(dx, dy) {
    const hd = state.handle;
    if (!hd || !state.scene || app.tool !== selectTool) return false;
    let p;
    let v = state.scene;
    for (const k of hd.path) v = v?.[k];
    if (!v) return false;
    if (hd.end === undefined) p = [v[0] + dx, v[1] + dy];
    else p = hd.end === 0 ? [v[0] + dx, v[1] + dy] : [v[2] + dx, v[3] + dy];
    moveHandle(app, { ...hd, kind: hd.path[0] === 'vanishing_points' ? 'vp' : 'other' }, p, false);
    return true;
  },
};

const photoView = new PhotoView($('photo-canvas'), app);
const selectTool = new SelectTool(app);
app.tool = selectTool;
const planView = new PlanView($('plan-host'), { onPick: pickPlanPoint });
const modelView = new ModelView($('model-host'));

// ---- status and errors ------------------------------------------------------------------

function setStatus(text) {
  const el = $('status');
  el.textContent = text;
  refreshBusy();
}

function refreshBusy() {
  const busy = Object.values(state.busy).some(Boolean);
  $('status').classList.toggle('busy', busy);
  document.body.dataset.busy = Object.entries(state.busy).filter(([, v]) => v).map(([k]) => k).join(' ');
}

function showError(msg) {
  $('error-text').textContent = msg;
  $('error-banner').hidden = false;
}

function clearError() {
  $('error-banner').hidden = true;
  $('error-text').textContent = '';
}

$('error-close').addEventListener('click', clearError);

// ---- editing and undo -------------------------------------------------------------------

function pushUndo() {
  if (!state.scene) return;
  history.undo.push(JSON.stringify(state.scene));
  if (history.undo.length > UNDO_LIMIT) history.undo.shift();
  history.redo = [];
}

/** Change the scene: `fn(scene)` mutates it. `live`: part of a drag (no panel refresh). */
function edit(fn, { live = false, undo = true } = {}) {
  if (!state.scene) return;
  if (undo && !history.dragging) pushUndo();
  fn(state.scene);
  photoView.requestRender();
  if (!live) renderPanel();
  scheduleBuild();
}

function restore(json) {
  state.scene = JSON.parse(json);
  state.selection = null;
  state.handle = null;
  syncForms();
  renderPanel();
  photoView.requestRender();
  scheduleBuild();
}

function undo() {
  if (app.tool !== selectTool && app.tool.canUndo?.()) {
    app.tool.undo();
    return;
  }
  if (!history.undo.length) return;
  history.redo.push(JSON.stringify(state.scene));
  restore(history.undo.pop());
}

function redo() {
  if (!history.redo.length) return;
  history.undo.push(JSON.stringify(state.scene));
  restore(history.redo.pop());
}

$('btn-undo').addEventListener('click', undo);
$('btn-redo').addEventListener('click', redo);

// ---- tools and the step prompt ----------------------------------------------------------

function setTool(tool) {
  if (!state.scene) return;
  app.tool = tool;
  state.selection = null;
  renderPrompt();
  renderToolButtons();
  photoView.requestRender();
  $('photo-canvas').focus({ preventScroll: true });
  showPane('photo');
}

function endTool() {
  app.tool = selectTool;
  renderPrompt();
  renderToolButtons();
  photoView.requestRender();
}

const IDLE_PROMPT = 'Drag a point to move it · click an object or a line to select it (Delete removes it) · scroll to zoom · drag the background to pan';

function renderPrompt() {
  const box = $('prompt');
  const extra = $('prompt-extra');
  extra.replaceChildren();
  $('prompt-control').replaceChildren();
  const placing = app.tool !== selectTool && !!app.tool.prompt;
  box.dataset.tool = placing ? app.tool.kind : 'select';
  $('prompt-cancel').hidden = !placing;
  if (!placing) {
    $('prompt-text').textContent = state.scene ? IDLE_PROMPT : '';
    $('prompt-undo').hidden = true;
    $('prompt-finish').hidden = true;
    return;
  }
  const p = app.tool.prompt();
  $('prompt-text').textContent = p.text;
  if (p.extra) $('prompt-control').append(p.extra);
  if (p.help) extra.textContent = `(${p.help})`;
  $('prompt-undo').hidden = false;
  $('prompt-undo').disabled = !p.canUndo;
  const fin = $('prompt-finish');
  fin.hidden = !p.finish;
  fin.textContent = p.finish || 'Done';
  photoView.requestRender();
}

$('prompt-undo').addEventListener('click', () => app.tool.undo?.());
$('prompt-finish').addEventListener('click', () => app.tool.finish?.());
$('prompt-cancel').addEventListener('click', endTool);

function renderToolButtons() {
  const kind = app.tool.kind;
  for (const [id, k] of [['btn-add-box', 'box'], ['btn-add-footprint', 'footprint'], ['btn-floor', 'floor'], ['btn-floor-distance', 'floor-distance']]) {
    $(id).setAttribute('aria-pressed', String(kind === k));
  }
  renderVpList();
}

$('btn-add-box').addEventListener('click', () => setTool(new BoxTool(app)));
$('btn-add-footprint').addEventListener('click', () => setTool(new FootprintTool(app)));
$('btn-floor').addEventListener('click', () => setTool(new FloorTool(app)));
$('btn-floor-distance').addEventListener('click', () => {
  const m = Number($('scale-floor-m').value);
  if (!(m > 0)) {
    showError('Enter the distance between the two floor points (metres) first.');
    return;
  }
  $('scale-floor').checked = true;
  setTool(new FloorDistanceTool(app, m));
});
$('btn-clear-floor').addEventListener('click', () => edit((s) => { s.floor = []; }));
$('btn-new-scene').addEventListener('click', () => {
  if (!state.scene) return;
  pushUndo();
  state.scene = emptyScene(state.scene.image.width, state.scene.image.height);
  state.savedVpPoints = [null, null, null];
  state.selection = null;
  syncForms();
  renderPanel();
  clearBuild();
  photoView.requestRender();
  scheduleBuild();
  setStatus('New scene: detect or draw the vanishing points.');
});

// ---- keyboard ---------------------------------------------------------------------------

document.addEventListener('keydown', (e) => {
  const mod = e.ctrlKey || e.metaKey;
  if (mod && (e.key === 'z' || e.key === 'Z') && !isTyping(e)) {
    e.preventDefault();
    if (e.shiftKey) redo();
    else undo();
    return;
  }
  if (mod && (e.key === 'y' || e.key === 'Y') && !isTyping(e)) {
    e.preventDefault();
    redo();
    return;
  }
  if (isTyping(e) && e.key !== 'Escape') {
    if (e.key === 'Enter' && e.target.classList?.contains('obj-name')) e.target.blur();
    return;
  }
  const onButton = e.target instanceof HTMLButtonElement || e.target instanceof HTMLAnchorElement || e.target?.getAttribute?.('role') === 'tab';
  const placing = app.tool !== selectTool;
  if (e.key === 'Escape') {
    if (isTyping(e)) e.target.blur();
    if (placing) endTool();
    else app.select(null);
  } else if (e.key === 'Enter' && placing && !onButton) {
    app.tool.finish?.();
  } else if (e.key === 'Backspace' && placing) {
    if (app.tool.canUndo?.()) app.tool.undo();
  } else if ((e.key === 'Delete' || e.key === 'Backspace') && !placing && state.selection) {
    deleteSelection();
  } else return;
  e.preventDefault();
});

function deleteSelection() {
  const sel = state.selection;
  if (!sel) return;
  if (sel.type === 'object') removeObject(sel.index);
  else if (sel.type === 'vpline') {
    edit((s) => {
      s.vanishing_points[sel.vp].lines.splice(sel.line, 1);
      app.detachVpPoint(sel.vp, s);
    });
    state.selection = null;
    state.handle = null;
  }
}

function removeObject(i) {
  const name = state.scene.objects[i]?.name;
  edit((s) => {
    s.objects.splice(i, 1);
    if (s.scale && s.scale.object === name) delete s.scale;
  });
  state.selection = null;
  state.handle = null;
  syncForms();
  renderPanel();
}

// ---- photo and scene files -----------------------------------------------------------------

async function decodePhoto(blob) {
  try {
    return await createImageBitmap(blob, { imageOrientation: 'from-image' });
  } catch {
    throw new Error('cannot read this file as a JPEG or PNG image');
  }
}

/** Show a photo. Keeps the scene when it was made for a photo of the same size. */
async function openPhoto(blob, name) {
  clearError();
  const bmp = await decodePhoto(blob);
  state.photo?.close?.();
  state.photo = bmp;
  state.photoBlob = blob;
  state.photoName = name || 'photo';
  state.detection = null;
  const keep = state.scene && state.scene.image.width === bmp.width && state.scene.image.height === bmp.height;
  if (!keep) {
    if (state.scene) pushUndo();
    state.scene = emptyScene(bmp.width, bmp.height);
    state.savedVpPoints = [null, null, null];
    state.selection = null;
    clearBuild();
    syncForms();
  }
  photoView.setImage(bmp, bmp.width, bmp.height);
  $('drop-hint').hidden = true;
  renderPanel();
  scheduleBuild();
  setStatus(`${state.photoName}: ${bmp.width} × ${bmp.height} px${keep ? ' (the open scene is kept)' : ''}. Next: Detect.`);
}

$('photo-input').addEventListener('change', async (e) => {
  const file = e.target.files[0];
  e.target.value = '';
  if (file) await openPhoto(file, file.name).catch((err) => showError(err.message));
});

async function openSceneFile(file) {
  clearError();
  let scene;
  try {
    scene = JSON.parse(await file.text());
  } catch (err) {
    showError(`${file.name} is not valid JSON: ${err.message}`);
    return;
  }
  const problem = normaliseScene(scene);
  if (problem) {
    showError(`${file.name}: ${problem}`);
    return;
  }
  if (state.scene) pushUndo();
  state.scene = scene;
  state.savedVpPoints = [null, null, null];
  state.selection = null;
  state.detection = null;
  const { width, height } = scene.image;
  let note = '';
  if (state.photo && (state.photo.width !== width || state.photo.height !== height)) {
    note = ` It was made for a ${width} × ${height} photo, but the open photo is ${state.photo.width} × ${state.photo.height}.`;
  }
  if (!state.photo) photoView.setImage(null, width, height);
  else photoView.requestRender();
  $('drop-hint').hidden = true;
  clearBuild();
  syncForms();
  renderPanel();
  scheduleBuild();
  setStatus(`Opened ${file.name}.${note}${state.photo ? '' : ' Open its photo to see it under the annotations.'}`);
}

$('scene-input').addEventListener('change', async (e) => {
  const file = e.target.files[0];
  e.target.value = '';
  if (file) await openSceneFile(file);
});

function sceneFileName() {
  const base = (state.photoName || 'scene').replace(/\.[^.]+$/, '');
  return `${base}.scene.json`;
}

$('btn-save-scene').addEventListener('click', () => {
  if (!state.scene) return;
  download(sceneFileName(), `${JSON.stringify(state.scene, null, 1)}\n`, 'application/json');
});

// Drag and drop: a photo or a scene file onto the photo area.
const wrap = $('photo-wrap');
wrap.addEventListener('dragover', (e) => {
  e.preventDefault();
  wrap.classList.add('dragover');
});
wrap.addEventListener('dragleave', () => wrap.classList.remove('dragover'));
wrap.addEventListener('drop', async (e) => {
  e.preventDefault();
  wrap.classList.remove('dragover');
  const file = e.dataTransfer.files[0];
  if (!file) return;
  if (file.type === 'application/json' || file.name.endsWith('.json')) await openSceneFile(file);
  else await openPhoto(file, file.name).catch((err) => showError(err.message));
});

// ---- example and detection ---------------------------------------------------------------

$('btn-example').addEventListener('click', loadExample);

async function loadExample() {
  clearError();
  state.busy.example = true;
  setStatus('Loading the example…');
  try {
    const ex = await api.getExample();
    const problem = normaliseScene(ex.scene);
    if (problem) throw new Error(`the example scene: ${problem}`);
    const blob = new Blob([base64ToBytes(ex.photo_png_base64)], { type: 'image/png' });
    const bmp = await decodePhoto(blob);
    if (state.scene) pushUndo();
    state.photo?.close?.();
    state.photo = bmp;
    state.photoBlob = blob;
    state.photoName = 'example.png';
    state.scene = ex.scene;
    state.detection = null;
    state.savedVpPoints = [null, null, null];
    state.selection = null;
    photoView.setImage(bmp, bmp.width, bmp.height);
    $('drop-hint').hidden = true;
    clearBuild();
    syncForms();
    renderPanel();
    state.busy.example = false;
    setStatus('Example loaded.');
    buildNow();
  } catch (err) {
    if (!api.isAbort(err)) showError(`Loading the example failed: ${err.message}`);
    setStatus('');
  } finally {
    state.busy.example = false;
    refreshBusy();
  }
}

let detectCtl = null;
$('btn-detect').addEventListener('click', runDetect);

async function runDetect() {
  if (!state.photoBlob) return;
  clearError();
  const focal = Number($('det-focal').value);
  const ppText = $('det-pp').value.trim();
  const pp = ppText ? parsePair(ppText) : null;
  if (ppText && !pp) {
    showError('Principal point for detection: write it as “x, y” in pixels, or leave it empty.');
    return;
  }
  detectCtl?.abort();
  const ctl = (detectCtl = new AbortController());
  state.busy.detect = true;
  setStatus('Detecting edges and vanishing points…');
  const t0 = performance.now();
  try {
    const res = await api.detect(state.photoBlob, { focal_px: focal > 0 ? focal : undefined, principal_point: pp }, ctl.signal);
    const d = res.scene || {};
    edit((s) => {
      if (d.image) s.image = d.image;
      s.vanishing_points = d.vanishing_points || [];
      while (s.vanishing_points.length < 2) s.vanishing_points.push({ lines: [] });
      for (const k of ['principal_point', 'focal_px', 'perspective']) {
        if (d[k] !== undefined && d[k] !== null) s[k] = d[k];
        else delete s[k];
      }
    });
    state.savedVpPoints = [null, null, null];
    state.detection = { segments: res.segments || [], segmentVp: segmentOwners(res, state.scene), warnings: res.warnings || [] };
    renderWarnings(state.build ? state.build.warnings || [] : []);
    state.counters.detects++;
    const n = state.scene.vanishing_points.length;
    const f = res.focal_px ?? d.focal_px;
    setStatus(`Detected ${n} vanishing points (${res.perspective || d.perspective || `${n}pp`}), ${(res.segments || []).length} segments, focal ${fmt(f, 0)} px, in ${Math.round(performance.now() - t0)} ms.`);
    syncForms();
    renderPanel();
  } catch (err) {
    if (!api.isAbort(err)) {
      showError(`Detection failed: ${err.message}`);
      setStatus('');
    }
  } finally {
    if (detectCtl === ctl) {
      state.busy.detect = false;
      refreshBusy();
    }
  }
}

/**
 * For each detected segment, the index of the scene's vanishing point it supports (-1 for
 * none). The detector lists its vanishing points in its own order with a `vertical` flag;
 * each is matched to the scene entry whose direction from the principal point is closest.
 */
function segmentOwners(res, scene) {
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

$('show-segments').addEventListener('change', (e) => {
  state.showSegments = e.target.checked;
  photoView.requestRender();
});
$('btn-fit').addEventListener('click', () => photoView.fit());

// ---- build --------------------------------------------------------------------------------

let buildCtl = null;
let buildSeq = 0;
const buildDebounce = debouncer(runBuild, 100, 400);

function scheduleBuild() {
  const blocker = buildBlocker(state.scene);
  if (blocker) {
    buildDebounce.cancel();
    buildCtl?.abort();
    state.busy.build = false;
    markStale(true);
    $('status').textContent = state.scene ? `To build: ${blocker}.` : '';
    refreshBusy();
    return;
  }
  buildDebounce.schedule();
}

function buildNow() {
  scheduleBuild();
  buildDebounce.flush();
}

function markStale(stale) {
  planView.markStale(stale && !!state.build);
  modelView.markStale(stale && !!state.build);
  document.querySelector('.camera-bar').classList.toggle('stale', stale && !!state.build);
}

async function runBuild() {
  if (buildBlocker(state.scene)) return;
  buildCtl?.abort();
  const ctl = (buildCtl = new AbortController());
  const seq = ++buildSeq;
  state.busy.build = true;
  setStatus('Building…');
  const t0 = performance.now();
  try {
    const res = await api.build(state.scene, state.settings, ctl.signal);
    if (seq !== buildSeq) return;
    applyBuild(res);
    state.counters.builds++;
    setStatus(`Built in ${Math.round(performance.now() - t0)} ms.`);
  } catch (err) {
    if (api.isAbort(err) || seq !== buildSeq) return;
    state.buildError = err.message;
    markStale(true);
    showError(`Cannot build the map: ${err.message}`);
    setStatus('Build failed: see the message at the bottom.');
  } finally {
    if (seq === buildSeq) {
      state.busy.build = false;
      refreshBusy();
    }
  }
}

function clearBuild() {
  // Forget the build and the plan, including any still on their way.
  buildDebounce.cancel();
  buildCtl?.abort();
  buildSeq++;
  planDebounce.cancel();
  planCtl?.abort();
  planSeq++;
  state.busy.build = false;
  state.busy.plan = false;
  refreshBusy();
  state.build = null;
  state.camera = null;
  state.plan.result = null;
  planView.clear();
  renderCamera();
  renderWarnings([]);
  renderDownloads();
  renderPlanResults();
}

function applyBuild(res) {
  state.build = res;
  state.camera = res.camera || null;
  state.buildError = null;
  clearError();
  renderCamera();
  try {
    planView.setBuild(res.svg, res.map, res.occupancy);
    planView.setMarkers(state.plan.start, state.plan.goal);
    planView.setPlan(state.plan.result);
  } catch (err) {
    showError(`Floor plan: ${err.message}`);
  }
  markStale(false);
  renderWarnings([...(res.warnings || []), ...((res.map && res.map.warnings) || [])]);
  renderDownloads();
  renderObjectList();
  if (res.glb_base64) {
    modelView
      .setModel(base64ToBytes(res.glb_base64))
      .then(() => update3dPaths())
      .catch((err) => {
        $('model-host').replaceChildren(h('p', { class: 'empty', text: `3D view: ${err.message}` }));
      });
  }
  photoView.requestRender();
  if (state.plan.start && state.plan.goal) schedulePlan();
}

function renderCamera() {
  const c = state.camera;
  const units = state.build?.map?.units === 'camera_heights' ? 'ch' : 'm';
  const set = (id, text, value) => {
    const el = $(id);
    el.textContent = text;
    if (value === undefined || value === null || !Number.isFinite(value)) delete el.dataset.value;
    else el.dataset.value = String(value);
  };
  set('cam-pitch', c ? `${fmt(c.pitch_deg, 2)}°` : '–', c?.pitch_deg);
  set('cam-roll', c ? `${fmt(c.roll_deg, 2)}°` : '–', c?.roll_deg);
  set('cam-focal', c ? `${fmt(c.focal_px, 1)} px` : '–', c?.focal_px);
  set('cam-height', c && Number.isFinite(c.height) ? `${fmt(c.height, 3)} ${units}` : '–', c?.height);
  set('cam-pp', c?.principal_point ? `${fmt(c.principal_point[0], 1)}, ${fmt(c.principal_point[1], 1)}` : '–');
}

function renderWarnings(list) {
  const ul = $('warnings');
  const det = (state.detection?.warnings || []).map((w) => `Detection: ${w}`);
  ul.replaceChildren(...[...new Set([...det, ...list])].map((w) => h('li', { text: w })));
}

// ---- the panel ------------------------------------------------------------------------------

function renderPanel() {
  const has = !!state.scene;
  if (app.tool === selectTool) renderPrompt();
  for (const id of ['btn-add-box', 'btn-add-footprint', 'btn-floor', 'btn-floor-distance', 'btn-new-scene', 'btn-save-scene']) $(id).disabled = !has;
  $('btn-detect').disabled = !state.photoBlob;
  $('btn-clear-floor').disabled = !has || !(state.scene.floor || []).length;
  $('btn-undo').disabled = !history.undo.length;
  $('btn-redo').disabled = !history.redo.length;
  renderVpList();
  renderObjectList();
  renderScaleObjects();
  const n = has ? (state.scene.floor || []).length : 0;
  $('floor-info').textContent = !has ? '' : n ? `Floor: ${n} corners.` : 'Floor: not marked (optional; the free space needs it).';
  renderPlanButtons();
}

function renderVpList() {
  const ul = $('vp-list');
  ul.replaceChildren();
  if (!state.scene) return;
  const vps = state.scene.vanishing_points;
  for (let k = 0; k < 3; k++) {
    const vp = vps[k];
    const li = h('li', { dataset: { vp: k } });
    const head = h('div', { class: 'vp-head' }, h('span', { class: 'vp-title', text: VP_NAMES[k] }));
    li.append(head);
    const actions = h('div', { class: 'vp-actions' });
    if (!vp) {
      li.append(h('div', { class: 'vp-info', text: 'none: two-point perspective (pitch 0)' }));
      const add = h('button', { type: 'button', class: 'small', text: 'Add vertical', disabled: k === 2 && vps.length < 2 });
      add.addEventListener('click', () => {
        edit((s) => s.vanishing_points.push({ lines: [] }));
        setTool(new VpLineTool(app, 2));
      });
      actions.append(add);
    } else {
      const lines = vp.lines || [];
      const p = vpPoint(vp);
      let info;
      if (Array.isArray(vp.point)) info = `point ${formatPair(vp.point, 0)}${lines.length ? ` · ${lines.length} lines as evidence` : ''}`;
      else if (p) info = `from ${lines.length} lines: ${formatPair(p, 0)}`;
      else info = lines.length >= 2 ? `${lines.length} lines (parallel: no point)` : `draw ${2 - lines.length} more line${lines.length === 1 ? '' : 's'}`;
      li.append(h('div', { class: 'vp-info', text: info }));
      if (!vpUsable(vp)) li.classList.add('incomplete');
      const draw = h('button', { type: 'button', class: 'small', text: 'Draw lines', 'aria-pressed': String(app.tool.kind === 'vp-line' && app.tool.vpIndex === k) });
      draw.addEventListener('click', () => setTool(new VpLineTool(app, k)));
      actions.append(draw);
      if (lines.length) {
        const clear = h('button', { type: 'button', class: 'small', text: 'Clear lines' });
        clear.addEventListener('click', () =>
          edit((s) => {
            s.vanishing_points[k].lines = [];
            app.detachVpPoint(k, s);
          }),
        );
        actions.append(clear);
      }
      if (!vp.point && state.savedVpPoints[k]) {
        const restore = h('button', { type: 'button', class: 'small', text: 'Use detected point', title: 'Use the point found by detection instead of the lines' });
        restore.addEventListener('click', () => edit((s) => { s.vanishing_points[k].point = state.savedVpPoints[k]; }));
        actions.append(restore);
      }
      if (k === 2) {
        const rm = h('button', { type: 'button', class: 'small', text: 'Remove', title: 'Two-point perspective: no vertical vanishing point' });
        rm.addEventListener('click', () => edit((s) => { s.vanishing_points.length = 2; }));
        actions.append(rm);
      }
    }
    li.append(actions);
    ul.append(li);
  }
}

let objectListKey = '';

function objectInfo(o) {
  const map = state.build?.map;
  const m = map?.objects?.find((x) => x.name === o.name);
  const kind = o.footprint ? 'footprint' : 'box';
  const parts = [];
  if (o.base) parts.push(o.top?.near ? (o.top.left ? '3 base + 2 top corners' : '3 base + 1 top corner') : '3 base corners, no top');
  else parts.push(`${(o.footprint || []).length} corners${o.top ? ' + top' : ', no top'}`);
  if (m) {
    const u = map.units === 'm' ? 'm' : 'ch';
    const size = m.size ? `${fmt(m.size.length)} × ${fmt(m.size.breadth)} ${u}` : `area ${fmt(m.area)} ${u}²`;
    parts.push(`${size}, height ${m.height === null || m.height === undefined ? 'unknown' : `${fmt(m.height)} ${u}`}`);
  }
  return { kind, text: parts.join(' · ') };
}

function renderObjectList() {
  const ul = $('object-list');
  const objs = state.scene?.objects || [];
  const key = objs.map((o) => (o.footprint ? 'f' : 'b')).join('');
  const sel = state.selection?.type === 'object' ? state.selection.index : -1;
  if (key === objectListKey && ul.children.length === objs.length) {
    // Update in place, so that a name being typed keeps its focus.
    objs.forEach((o, i) => {
      const li = ul.children[i];
      li.classList.toggle('selected', i === sel);
      const input = li.querySelector('.obj-name');
      if (document.activeElement !== input && input.value !== o.name) input.value = o.name;
      li.querySelector('.obj-info').textContent = objectInfo(o).text;
    });
    return;
  }
  objectListKey = key;
  ul.replaceChildren(
    ...objs.map((o, i) => {
      const info = objectInfo(o);
      const input = h('input', { type: 'text', class: 'obj-name', value: o.name, 'aria-label': `Name of object ${i + 1}`, spellcheck: 'false' });
      input.addEventListener('focus', () => {
        if (state.selection?.index !== i) app.select({ type: 'object', index: i });
      });
      input.addEventListener('input', () => renameObject(i, input.value));
      const del = h('button', { type: 'button', class: 'small', text: 'Delete', 'aria-label': `Delete ${o.name}` });
      del.addEventListener('click', () => removeObject(i));
      const li = h('li', { dataset: { index: i }, class: i === sel ? 'selected' : '' },
        input,
        h('span', {}, h('span', { class: 'obj-kind', text: info.kind }), ' ', del),
        h('span', { class: 'obj-info', text: info.text }));
      return li;
    }),
  );
}

function renameObject(i, name) {
  const old = state.scene.objects[i].name;
  if (old === name) return;
  edit(
    (s) => {
      s.objects[i].name = name;
      if (s.scale && s.scale.object === old) s.scale.object = name;
    },
    { live: true, undo: true },
  );
  renderScaleObjects();
}

// ---- scale, intrinsics and build settings -----------------------------------------------

function renderScaleObjects() {
  const sel = $('scale-object-name');
  const names = (state.scene?.objects || []).map((o) => o.name);
  const want = state.scene?.scale?.object ?? sel.value;
  const current = [...sel.options].map((o) => o.value).join('\n');
  if (current !== names.join('\n')) {
    sel.replaceChildren(...names.map((n) => h('option', { value: n, text: n })));
  }
  if (names.includes(want)) sel.value = want;
}

/** Put the scene's scale, principal point and focal length into the form. */
function syncForms() {
  const sc = state.scene?.scale;
  renderScaleObjects();
  if (!sc) $('scale-none').checked = true;
  else if (sc.camera_height_m !== undefined) {
    $('scale-camera').checked = true;
    $('scale-camera-m').value = sc.camera_height_m;
  } else if (sc.object !== undefined) {
    $('scale-object').checked = true;
    $('scale-object-name').value = sc.object;
    $('scale-object-dim').value = sc.dimension || 'length';
    $('scale-object-m').value = sc.meters;
  } else if (sc.floor_distance) {
    $('scale-floor').checked = true;
    $('scale-floor-m').value = sc.floor_distance.meters;
  }
  $('scene-pp').value = state.scene?.principal_point ? formatPair(state.scene.principal_point, 1) : '';
  $('scene-focal').value = state.scene?.focal_px ?? '';
}

function scaleFromForm() {
  if (!state.scene) return;
  const mode = document.querySelector('input[name="scale"]:checked')?.value;
  const old = state.scene.scale;
  let scale;
  if (mode === 'camera') {
    const m = Number($('scale-camera-m').value);
    scale = m > 0 ? { camera_height_m: m } : null;
  } else if (mode === 'object') {
    const m = Number($('scale-object-m').value);
    const name = $('scale-object-name').value;
    scale = m > 0 && name ? { object: name, dimension: $('scale-object-dim').value, meters: m } : null;
  } else if (mode === 'floor') {
    const m = Number($('scale-floor-m').value);
    const fd = old?.floor_distance;
    scale = m > 0 && fd ? { floor_distance: { ...fd, meters: m } } : null;
    if (!fd) {
      setStatus('Click “Pick 2 points” and click two floor points that far apart.');
      return;
    }
  } else scale = null;
  if (JSON.stringify(scale) === JSON.stringify(old ?? null)) return;
  edit((s) => {
    if (scale) s.scale = scale;
    else delete s.scale;
  });
}

for (const el of document.querySelectorAll('#scale-fieldset input, #scale-fieldset select')) {
  el.addEventListener(el.tagName === 'SELECT' || el.type === 'radio' ? 'change' : 'input', scaleFromForm);
}

$('scene-pp').addEventListener('change', (e) => {
  const text = e.target.value.trim();
  const p = parsePair(text);
  if (text && !p) {
    showError('Principal point: write it as “x, y” in pixels, or leave it empty for the default.');
    return;
  }
  edit((s) => {
    if (p) s.principal_point = p;
    else delete s.principal_point;
  });
});

$('scene-focal').addEventListener('change', (e) => {
  const f = Number(e.target.value);
  edit((s) => {
    if (e.target.value.trim() && f > 0) s.focal_px = f;
    else delete s.focal_px;
  });
});

$('set-method').addEventListener('change', (e) => {
  state.settings.method = e.target.value;
  scheduleBuild();
});
for (const [id, key] of [['set-resolution', 'resolution'], ['set-radius', 'robot_radius']]) {
  $(id).addEventListener('input', (e) => {
    const v = Number(e.target.value);
    if (!(v >= 0) || (key === 'resolution' && !(v > 0))) return;
    state.settings[key] = v;
    scheduleBuild();
  });
}

// ---- path planning --------------------------------------------------------------------------

let planCtl = null;
let planSeq = 0;
const planDebounce = debouncer(runPlan, 100, 400);

function pickPlanPoint(p) {
  const which = document.querySelector('input[name="pick"]:checked')?.value || 'start';
  if (which === 'start') {
    state.plan.start = p;
    $('pick-goal').checked = true;
  } else state.plan.goal = p;
  $('plan-start').value = formatPair(state.plan.start);
  $('plan-goal').value = formatPair(state.plan.goal);
  planMarkersChanged();
}

function planMarkersChanged() {
  planView.setMarkers(state.plan.start, state.plan.goal);
  update3dPaths();
  renderPlanButtons();
  if (state.plan.start && state.plan.goal) schedulePlan();
}

for (const [id, key] of [['plan-start', 'start'], ['plan-goal', 'goal']]) {
  $(id).addEventListener('change', (e) => {
    const text = e.target.value.trim();
    const p = parsePair(text);
    if (text && !p) {
      $('plan-status').textContent = 'Write a point as “x, y” in metres.';
      $('plan-status').classList.add('error');
      return;
    }
    state.plan[key] = p;
    planMarkersChanged();
  });
}

function renderPlanButtons() {
  $('btn-plan').disabled = !(state.plan.start && state.plan.goal && state.scene && state.build);
}

$('btn-plan').addEventListener('click', () => {
  planDebounce.cancel();
  runPlan();
});

$('btn-clear-path').addEventListener('click', () => {
  planCtl?.abort();
  planDebounce.cancel();
  state.plan = { start: null, goal: null, result: null, error: null };
  $('plan-start').value = '';
  $('plan-goal').value = '';
  $('pick-start').checked = true;
  planView.setMarkers(null, null);
  planView.setPlan(null);
  renderPlanResults();
  update3dPaths();
  renderPlanButtons();
});

function schedulePlan() {
  if (state.plan.start && state.plan.goal && state.build) planDebounce.schedule();
}

async function runPlan() {
  const { start, goal } = state.plan;
  if (!start || !goal || buildBlocker(state.scene)) return;
  planCtl?.abort();
  const ctl = (planCtl = new AbortController());
  const seq = ++planSeq;
  state.busy.plan = true;
  refreshBusy();
  const status = $('plan-status');
  status.classList.remove('error');
  status.textContent = 'Planning…';
  try {
    const res = await api.plan(
      {
        scene: state.scene,
        method: state.settings.method,
        resolution: state.settings.resolution,
        robot_radius: state.settings.robot_radius,
        start,
        goal,
        planners: PLANNERS,
      },
      ctl.signal,
    );
    if (seq !== planSeq) return;
    state.plan.result = res;
    state.plan.error = null;
    state.counters.plans++;
    const found = (res.results || []).filter((r) => r.found).length;
    const notes = (res.results || []).filter((r) => r.note).map((r) => `${PLANNER_STYLE[r.planner]?.label || r.planner}: ${r.note}`);
    status.textContent = [found ? '' : 'No path: start and goal are not connected through known free floor.', ...notes].filter(Boolean).join(' ');
  } catch (err) {
    if (api.isAbort(err) || seq !== planSeq) return;
    state.plan.result = null;
    state.plan.error = err.message;
    status.textContent = err.message;
    status.classList.add('error');
  } finally {
    if (seq === planSeq) {
      state.busy.plan = false;
      refreshBusy();
      planView.setPlan(state.plan.result);
      renderPlanResults();
      update3dPaths();
    }
  }
}

function renderPlanResults() {
  const table = $('plan-table');
  const res = state.plan.result;
  const rows = (res && res.results) || [];
  table.hidden = rows.length === 0;
  const units = state.build?.map?.units === 'camera_heights' ? 'ch' : 'm';
  table.tBodies[0].replaceChildren(
    ...rows.map((r) => {
      const st = PLANNER_STYLE[r.planner];
      const name = h('td', {}, h('i', { class: `sw ${{ mbpp: 'sw-mbpp', 'astar-ps': 'sw-astar', optimal: 'sw-opt' }[r.planner] || ''}` }), ' ', st ? st.label : r.planner);
      const lengthCell = r.found
        ? h('td', { text: `${fmt(r.length_m, 2)} ${units}` })
        : h('td', { class: 'notfound', text: r.skipped ? 'skipped' : 'no path', title: r.note || null });
      return h('tr', { dataset: { planner: r.planner }, title: r.note || null },
        name,
        lengthCell,
        h('td', { text: `${fmt(r.time_ms, r.time_ms < 10 ? 2 : 1)} ms` }),
        h('td', { text: r.planner === 'mbpp' ? String((r.alternatives || []).length) : '' }));
    }),
  );
}

function update3dPaths() {
  const res = state.plan.result;
  const paths = [];
  for (const r of (res && res.results) || []) {
    if (!r.found || !planView.layers[r.planner]) continue;
    const st = PLANNER_STYLE[r.planner];
    if (st) paths.push({ points: r.waypoints, colour: st.colour, dashed: !!st.dash });
  }
  modelView.setPaths(paths, [
    { p: state.plan.start, colour: '#1b8a3a' },
    { p: state.plan.goal, colour: '#c62828' },
  ]);
}

for (const el of document.querySelectorAll('.layers input[data-layer]')) {
  el.addEventListener('change', () => {
    planView.setLayer(el.dataset.layer, el.checked);
    update3dPaths();
  });
}

$('btn-reset-3d').addEventListener('click', () => modelView.resetView());
$('btn-plan-fit').addEventListener('click', () => planView.fit());
$('btn-plan-all').addEventListener('click', () => planView.showAll());

// ---- downloads ------------------------------------------------------------------------------

function renderDownloads() {
  for (const b of document.querySelectorAll('[data-download]')) b.disabled = !state.build;
}

async function planPng() {
  const text = planView.serialize();
  if (!text) return null;
  const vb = planView.fullBox;
  const url = URL.createObjectURL(new Blob([text], { type: 'image/svg+xml' }));
  try {
    const img = new Image();
    img.src = url;
    await img.decode();
    const scale = 2;
    const canvas = h('canvas', { width: Math.round(vb.w * scale), height: Math.round(vb.h * scale) });
    const ctx = canvas.getContext('2d');
    ctx.fillStyle = '#fff';
    ctx.fillRect(0, 0, canvas.width, canvas.height);
    ctx.drawImage(img, 0, 0, canvas.width, canvas.height);
    return await new Promise((resolve) => canvas.toBlob(resolve, 'image/png'));
  } finally {
    URL.revokeObjectURL(url);
  }
}

for (const b of document.querySelectorAll('[data-download]')) {
  b.addEventListener('click', async () => {
    const r = state.build;
    if (!r) return;
    try {
      switch (b.dataset.download) {
        case 'map-json':
          download('map.json', `${JSON.stringify(r.map, null, 2)}\n`, 'application/json');
          break;
        case 'occupancy-yaml':
          download('occupancy.yaml', r.occupancy.yaml, 'text/yaml');
          break;
        case 'occupancy-pgm':
          download('occupancy.pgm', base64ToBytes(r.occupancy.pgm_base64), 'image/x-portable-graymap');
          break;
        case 'glb':
          download('model.glb', base64ToBytes(r.glb_base64), 'model/gltf-binary');
          break;
        case 'svg':
          download('floor-plan.svg', planView.serialize() || r.svg, 'image/svg+xml');
          break;
        case 'png': {
          const png = await planPng();
          if (png) download('floor-plan.png', png, 'image/png');
          break;
        }
        default:
      }
    } catch (err) {
      showError(`Download failed: ${err.message}`);
    }
  });
}

// ---- tabs (narrow screens) ------------------------------------------------------------------

const tabs = ['photo', 'plan', 'model'];

function showPane(name) {
  for (const t of tabs) {
    const on = t === name;
    const tab = $(`tab-${t}`);
    tab.setAttribute('aria-selected', String(on));
    tab.tabIndex = on ? 0 : -1;
    $(`pane-${t}`).classList.toggle('active', on);
  }
}

tabs.forEach((t, i) => {
  const tab = $(`tab-${t}`);
  tab.addEventListener('click', () => showPane(t));
  tab.addEventListener('keydown', (e) => {
    const d = e.key === 'ArrowRight' ? 1 : e.key === 'ArrowLeft' ? -1 : 0;
    if (!d) return;
    const next = tabs[(i + d + tabs.length) % tabs.length];
    showPane(next);
    $(`tab-${next}`).focus();
    e.preventDefault();
  });
});

// ---- CSP violations are bugs: make them loud -----------------------------------------------

document.addEventListener('securitypolicyviolation', (e) => {
  console.error(`CSP violation: ${e.violatedDirective} blocked ${e.blockedURI || 'inline code'}`);
});

// ---- hooks for the end-to-end test and for debugging ----------------------------------------

window.vpmap = Object.freeze({
  /** Viewport coordinates of an image pixel on the photo canvas. */
  imageToClient: (x, y) => photoView.imageToClient([x, y]),
  /** Viewport coordinates of a map point on the floor plan (null before a build). */
  planMapToClient: (x, y) => planView.mapToClient([x, y]),
  /** A copy of the scene being edited. */
  scene: () => cloneScene(state.scene),
  /** Counters and errors, to wait for the page to settle. */
  status: () => ({
    busy: Object.entries(state.busy).filter(([, v]) => v).map(([k]) => k),
    pending: buildDebounce.pending || planDebounce.pending,
    ...state.counters,
    buildError: state.buildError,
    planError: state.plan.error,
    camera: state.camera,
    plan: state.plan.result,
    start: state.plan.start,
    goal: state.plan.goal,
  }),
});

renderPanel();
renderCamera();
renderDownloads();
setStatus('Open a photo or load the example.');
