// The page's state and its undo history. The state holds a room: a list of photos, one of them
// active; each photo's scene is kept in the scene file's own shape (scene.js), and everything
// else the page shows is derived from `state` by the panels and views. Undo is per photo: each
// photo has its own history and Undo acts on the active photo (adding or removing a photo is
// not an edit of a scene and is not undone).
// Pure: no DOM, so the unit tests (e2e/unit/state.test.mjs) run it in Node.

/** How many scene versions undo keeps. */
export const UNDO_LIMIT = 200;

/**
 * One photo of the room: its picture (if open), its scene (the scene file's shape, scene.js),
 * and what belongs to that photo alone: the detected segments, the vanishing points detection
 * found before the user's lines replaced them, the key its scene is kept under in the browser
 * (autosave.js) and its own undo history. `truth` names the true map the server knows for it
 * ('example': the bundled office).
 */
export function createSlot({ scene = null, photo = null, photoBlob = null, photoName = '', photoUrl = null } = {}) {
  return {
    scene,
    photo, // ImageBitmap
    photoBlob, // the photo's original bytes, sent to /api/detect
    photoName,
    photoUrl, // an object URL of photoBlob, for its thumbnail
    detection: null, // {segments, segmentVp, warnings}
    savedVpPoints: [null, null, null],
    photoKey: null,
    truth: null,
    history: new History(),
  };
}

/** The fields of `state` that are the active photo's own (`state.scene` is `state.photos[state.active].scene`). */
export const SLOT_FIELDS = ['scene', 'photo', 'photoBlob', 'photoName', 'photoUrl', 'detection', 'savedVpPoints', 'photoKey', 'history'];

/**
 * The state of a page that has nothing open yet. The room is `photos` (a list of slots,
 * createSlot) and `active`, the index of the photo being edited; every tool works on the
 * active photo through `state.scene`, `state.photo`, ... which read and write its slot (a
 * page with no photo yet gets its first slot on the first write).
 */
export function createState() {
  const state = {
    photos: [createSlot()],
    active: 0,
    camera: null, // the active photo's camera in the last build (room.js cameraOf)
    build: null, // last successful /api/build answer
    buildError: null,
    // The photo and point the last build error or build blocker is about:
    // {photo, message, path?, p?, object?, note?} (room.js roomProblem), and its point on the
    // active photo (`marked`, what photo-view.js rings: null when the problem is on another photo).
    problem: null,
    marked: null,
    selection: null, // {type: 'object', index} | {type: 'vpline', vp, line}
    handle: null, // last grabbed point, for keyboard nudging
    showSegments: true,
    // method null: the server's default (the build answer's map.method says which it is);
    // click_sigma null: estimated by the fit.
    // hidden_free: hidden floor counts as free (map and plan); unknown_passable: the planners
    // may cross unknown cells (plan only).
    settings: { method: null, resolution: 0.05, robot_radius: 0.2, click_sigma: null, hidden_free: false },
    // turning_radius (map units) turns the smooth planner on; start_heading / goal_heading:
    // its headings in degrees, atan2(dy, dx) in map coordinates, null when free; reverse:
    // whether it may drive backwards (cusps).
    plan: { start: null, goal: null, result: null, error: null, unknown_passable: false, turning_radius: null, start_heading: null, goal_heading: null, reverse: false },
    // The last drive on the true map (/api/navigate).
    drive: { result: null, error: null },
    counters: { builds: 0, plans: 0, detects: 0, drives: 0 },
    busy: { build: false, plan: false, detect: false, example: false, drive: false },
  };
  for (const k of SLOT_FIELDS) {
    Object.defineProperty(state, k, {
      enumerable: true,
      get() {
        const slot = state.photos[state.active];
        return slot ? slot[k] : k === 'history' ? null : k === 'savedVpPoints' ? [null, null, null] : null;
      },
      set(v) {
        if (!state.photos[state.active]) {
          state.photos.push(createSlot());
          state.active = state.photos.length - 1;
        }
        state.photos[state.active][k] = v;
      },
    });
  }
  // The true map the server knows: only for a page of one photo (a drive needs one camera's map).
  Object.defineProperty(state, 'truth', {
    enumerable: true,
    get: () => (state.photos.length === 1 ? state.photos[0].truth : null),
    set(v) {
      if (state.photos[state.active]) state.photos[state.active].truth = v;
    },
  });
  return state;
}

/** The scenes of the room's photos, in order (photos without a scene left out). */
export function roomScenes(state) {
  return state.photos.map((s) => s.scene).filter(Boolean);
}

/** The names of the requests on their way (`busy` flags that are set), in order. */
export function busyNames(busy) {
  return Object.entries(busy).filter(([, v]) => v).map(([k]) => k);
}

/**
 * Undo and redo of the scene, kept as JSON text (so no later edit can reach a saved version).
 * `dragging` is set during a drag, which records one undo step at its start only.
 */
export class History {
  constructor(limit = UNDO_LIMIT) {
    this.limit = limit;
    this.undoStack = [];
    this.redoStack = [];
    this.dragging = false;
  }

  get canUndo() {
    return this.undoStack.length > 0;
  }

  get canRedo() {
    return this.redoStack.length > 0;
  }

  /** Forget every step (a new photo: no undo may bring back another photo's annotations). */
  clear() {
    this.undoStack = [];
    this.redoStack = [];
    this.dragging = false;
  }

  /** Remember `scene` (before an edit) as the next undo step; clears redo. Null is not recorded. */
  record(scene) {
    if (!scene) return;
    this.undoStack.push(JSON.stringify(scene));
    if (this.undoStack.length > this.limit) this.undoStack.shift();
    this.redoStack = [];
  }

  /** Step back from `current`: the scene to show, or null when there is nothing to undo. */
  undo(current) {
    if (!this.undoStack.length) return null;
    this.redoStack.push(JSON.stringify(current));
    return JSON.parse(this.undoStack.pop());
  }

  /** Step forward from `current`: the scene to show, or null when there is nothing to redo. */
  redo(current) {
    if (!this.redoStack.length) return null;
    this.undoStack.push(JSON.stringify(current));
    return JSON.parse(this.redoStack.pop());
  }
}
