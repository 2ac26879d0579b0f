// vpmap's web page: the wiring. The page is split by concern:
//   state.js     the state and the undo history
//   latest.js    "latest request wins, debounced", for build, plan and detect
//   requests.js  build, plan and detect: the requests and what their answers change
//   panels.js    the step panel, the status line, the error banner and the tabs
//   files.js     opening photos and scene files, the example, saving and downloads
//   autosave.js  each photo's scene kept in the browser, and the warning before leaving
//   room.js      the room of several photos: its file, per-photo messages, linked names
//   photo-strip.js  the room's thumbnails: switch, remove, which photo a problem is about
//   placement.js the room's placements the clicks leave open: swap to one, unpin
// and the views (photo-view.js, plan-view.js, model-view.js) and photo tools (select-tool.js;
// placement-tool.js and the tools on it, box-tool.js, outline-tools.js, floor-distance-tool.js,
// vp-line-tool.js; where points snap, snap.js; a box's corners by name, corner or face view, in
// box.js).
// Every module talks to the others through `app`, the object this file builds. Every edit
// goes through `app.edit`, which records undo, redraws and schedules a rebuild (debounced
// 100 ms, stale requests aborted).

import { $, isTyping } from './util.js';
import { emptyScene, cloneScene } from './scene.js';
import { createState, busyNames } from './state.js';
import { PhotoView } from './photo-view.js';
import { SelectTool, moveHandle } from './select-tool.js';
import { BoxTool } from './box-tool.js';
import { FootprintTool, FloorTool } from './outline-tools.js';
import { FloorDistanceTool } from './floor-distance-tool.js';
import { PlanView } from './plan-view.js';
import { ModelView } from './model-view.js';
import { installPanels } from './panels.js';
import { installFiles } from './files.js';
import { installRequests } from './requests.js';
import { installAutosave } from './autosave.js';
import { installPhotoStrip } from './photo-strip.js';
import { installPlacements } from './placement.js';
import { roomBody } from './room.js';
import { roomScenes } from './state.js';
import { dropFloor, objectRemoved } from './covariances.js';
import { drawSnapFlash, installPhotoSnap } from './photo-snap.js';
import { drawProposals, installProposals } from './proposals.js';

const state = createState();

// ---- the app object the views, tools and modules talk to --------------------------------

const app = {
  state,
  /** The active photo's undo history (each photo has its own: state.js). */
  get history() {
    return state.history;
  },
  tool: null,
  edit,
  pushUndo,
  beginDrag() {
    pushUndo();
    app.history.dragging = true;
  },
  endDrag() {
    app.history.dragging = false;
    app.renderPanel();
  },
  select(sel) {
    state.selection = sel;
    app.renderObjectList();
    app.photoView.requestRender();
  },
  /** Add `obj` in one undoable edit; `also(scene, index)` may add to the same edit (its covariances). */
  addObject(obj, also = null) {
    edit((scene) => {
      scene.objects.push(obj);
      also?.(scene, scene.objects.length - 1);
    });
    const i = state.scene.objects.length - 1;
    endTool();
    app.select({ type: 'object', index: i });
    const input = document.querySelector(`#object-list li[data-index="${i}"] .obj-name`);
    if (input) {
      input.focus();
      input.select();
    }
    app.setStatus(`Added “${obj.name}”: type a name, then add the next object or press Escape.`);
  },
  /** Lines of vanishing point `k` were edited: drop its `point`, so the lines decide. */
  detachVpPoint(k, scene) {
    const vp = scene.vanishing_points[k];
    if (vp && vp.point) {
      state.savedVpPoints[k] = vp.point;
      delete vp.point;
    }
    // A covariance belongs to the point: lines alone carry their own spread.
    if (vp && vp.covariance_deg2) {
      state.savedVpCovariances = state.savedVpCovariances || [null, null, null];
      state.savedVpCovariances[k] = vp.covariance_deg2;
      delete vp.covariance_deg2;
    }
  },
  setTool,
  endTool,
  promptChanged: () => app.renderPrompt(),
  requestRender: () => app.photoView.requestRender(),
  removeObject,
  nudge(dx, dy) {
    const hd = state.handle;
    if (!hd || !state.scene || app.tool !== app.selectTool) return false;
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

app.photoView = new PhotoView($('photo-canvas'), app);
app.selectTool = new SelectTool(app);
app.tool = app.selectTool;
app.planView = new PlanView($('plan-host'), { onPick: (p) => app.pickPlanPoint(p), onCamera: (i) => app.switchPhoto(i), onHeading: (which, deg) => app.setHeading(which, deg) });
app.modelView = new ModelView($('model-host'));

app.overlays = [(view) => drawProposals(view, app), (view) => drawSnapFlash(view, app)];

installPanels(app);
installPhotoSnap(app);
installProposals(app);
installRequests(app);
installPhotoStrip(app);
installPlacements(app);
installAutosave(app);
installFiles(app);

// ---- editing and undo -------------------------------------------------------------------

function pushUndo() {
  app.history?.record(state.scene);
}

/** Change the scene: `fn(scene)` mutates it. `live`: part of a drag (no panel refresh). */
function edit(fn, { live = false, undo = true } = {}) {
  if (!state.scene) return;
  if (undo && !app.history.dragging) pushUndo();
  fn(state.scene);
  app.photoView.requestRender();
  if (!live) app.renderPanel();
  app.scheduleBuild();
  app.sceneChanged();
}

function restore(scene) {
  state.scene = scene;
  state.selection = null;
  state.handle = null;
  app.syncForms();
  app.renderPanel();
  app.photoView.requestRender();
  app.scheduleBuild();
  app.sceneChanged();
}

function undo() {
  if (app.tool !== app.selectTool && app.tool.canUndo?.()) {
    app.tool.undo();
    return;
  }
  const scene = app.history.undo(state.scene);
  if (scene) restore(scene);
}

function redo() {
  const scene = app.history.redo(state.scene);
  if (scene) restore(scene);
}

$('btn-undo').addEventListener('click', undo);
$('btn-redo').addEventListener('click', redo);

// ---- tools -------------------------------------------------------------------------------

function setTool(tool) {
  if (!state.scene) return;
  app.tool = tool;
  state.selection = null;
  app.renderPrompt();
  app.renderToolButtons();
  app.photoView.requestRender();
  $('photo-canvas').focus({ preventScroll: true });
  app.showPane('photo');
}

function endTool() {
  app.tool = app.selectTool;
  app.renderPrompt();
  app.renderToolButtons();
  app.photoView.requestRender();
}

$('prompt-undo').addEventListener('click', () => app.tool.undo?.());
$('prompt-finish').addEventListener('click', () => app.tool.finish?.());
$('prompt-cancel').addEventListener('click', endTool);

$('btn-add-box').addEventListener('click', () => setTool(new BoxTool(app)));
$('btn-add-footprint').addEventListener('click', () => setTool(new FootprintTool(app)));
$('btn-floor').addEventListener('click', () => setTool(new FloorTool(app)));
$('btn-floor-distance').addEventListener('click', () => {
  const m = Number($('scale-floor-m').value);
  if (!(m > 0)) {
    app.showError('Enter the distance between the two floor points (metres) first.');
    return;
  }
  $('scale-floor').checked = true;
  setTool(new FloorDistanceTool(app, m));
});
$('btn-clear-floor').addEventListener('click', () => edit((s) => {
  s.floor = [];
  dropFloor(s);
}));
$('btn-new-scene').addEventListener('click', () => {
  if (!state.scene) return;
  pushUndo();
  state.scene = emptyScene(state.scene.image.width, state.scene.image.height);
  state.savedVpPoints = [null, null, null];
  state.selection = null;
  app.syncForms();
  app.renderPanel();
  app.clearBuild();
  app.photoView.requestRender();
  app.scheduleBuild();
  app.sceneChanged();
  app.setStatus('New scene: detect or draw the vanishing points.');
});

// ---- keyboard ---------------------------------------------------------------------------

document.addEventListener('keydown', (e) => {
  if ($('keys-dialog').open) return; // the list's own keys (Escape closes it)
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
  // The keys list, and the tools by their letters (not while placing: S, Enter are the tool's).
  if (e.key === '?' && !mod) {
    e.preventDefault();
    showKeys();
    return;
  }
  const tools = { b: 'btn-add-box', p: 'btn-add-footprint', f: 'btn-floor' };
  if (!mod && !e.altKey && tools[e.key.toLowerCase()] && app.tool === app.selectTool && state.scene) {
    e.preventDefault();
    $(tools[e.key.toLowerCase()]).click();
    return;
  }
  // A room's photos: the previous and next one (not while placing: a half-made object is this photo's).
  if (!mod && !e.altKey && (e.key === '[' || e.key === ']') && state.photos.length > 1 && app.tool === app.selectTool) {
    e.preventDefault();
    const n = state.photos.length;
    app.switchPhoto((state.active + (e.key === ']' ? 1 : n - 1)) % n);
    return;
  }
  const onButton = e.target instanceof HTMLButtonElement || e.target instanceof HTMLAnchorElement || e.target?.getAttribute?.('role') === 'tab';
  const placing = app.tool !== app.selectTool;
  if (e.key === 'Escape') {
    if (isTyping(e)) e.target.blur();
    if (placing) endTool();
    else app.select(null);
  } else if (e.key === 'Enter' && placing && !onButton) {
    app.tool.finish?.();
  } else if ((e.key === 's' || e.key === 'S') && placing && !mod && app.tool.skip) {
    app.tool.skip();
  } else if (e.key === 'Backspace' && placing) {
    if (app.tool.canUndo?.()) app.tool.undo();
  } else if ((e.key === 'Delete' || e.key === 'Backspace') && !placing && state.selection) {
    deleteSelection();
  } else return;
  e.preventDefault();
});

function showKeys() {
  const d = $('keys-dialog');
  if (!d.open) d.showModal();
}
$('btn-keys').addEventListener('click', showKeys);

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
    objectRemoved(s, i);
    if (s.scale && s.scale.object === name) delete s.scale;
  });
  state.selection = null;
  state.handle = null;
  app.syncForms();
  app.renderPanel();
}

// ---- CSP violations are bugs: make them loud -----------------------------------------------

document.addEventListener('securitypolicyviolation', (e) => {
  console.error(`CSP violation: ${e.violatedDirective} blocked ${e.blockedURI || 'inline code'}`);
});

// ---- hooks for the end-to-end test and for debugging ----------------------------------------

window.vpmap = Object.freeze({
  /** Viewport coordinates of an image pixel on the photo canvas. */
  imageToClient: (x, y) => app.photoView.imageToClient([x, y]),
  /** Viewport coordinates of a map point on the floor plan (null before a build). */
  planMapToClient: (x, y) => app.planView.mapToClient([x, y]),
  /** The floor plan's SVG coordinates of a map point (where its marks are drawn). */
  planMapToSvg: (x, y) => app.planView.mapToSvg([x, y]),
  /** The floor plan as downloaded (SVG text, with the overlay), or null. */
  planSvg: () => app.planView.serialize(),
  /** A copy of the last build's map (map.json), or null. */
  map: () => cloneScene(state.build?.map ?? null),
  /** A copy of the scene being edited (the active photo's). */
  scene: () => cloneScene(state.scene),
  /** A copy of what Save writes and a build sends: the scene for one photo, else the room file. */
  room: () => cloneScene(state.scene ? roomBody(roomScenes(state)) : null),
  /** The 3D view's framing (ModelView.framing), or null before its first model. */
  view3d: () => app.modelView.framing(),
  /** A copy of the active placement tool's points so far (a box tool's `{base, top}`), or null. */
  toolPoints: () => cloneScene(app.tool.draft?.() ?? null),
  /** Snapping to the photo: requests on their way, answers so far, the toggle. */
  snap: () => ({ pending: app.photoSnap.pending, answers: state.counters.snaps || 0, enabled: app.photoSnap.enabled, last: cloneScene(app.photoSnap.last ?? null) }),
  /** Counters and errors, to wait for the page to settle. */
  status: () => ({
    busy: busyNames(state.busy),
    pending: app.requestsPending(),
    ...state.counters,
    buildError: state.buildError,
    marked: state.marked?.path ?? null,
    photos: state.photos.length,
    active: state.active,
    problemPhoto: state.problem?.photo ?? null,
    problem: state.problem?.message ?? null,
    markedNote: state.marked?.note ?? null,
    unsaved: !!state.dirty,
    selection: state.selection,
    planError: state.plan.error,
    camera: state.camera,
    plan: state.plan.result,
    start: state.plan.start,
    goal: state.plan.goal,
    turningRadius: state.plan.turning_radius,
    headings: [state.plan.start_heading, state.plan.goal_heading],
    reverse: state.plan.reverse,
    drive: state.drive.result,
    driveError: state.drive.error,
  }),
});

app.renderPanel();
app.renderCamera();
app.renderDownloads();
app.renderStrip();
app.setStatus('Open a photo or load the example.');
