// The page's state and its undo history. The scene is kept in the scene file's own shape
// (scene.js); everything else the page shows is derived from `state` by the panels and views.
// Pure: no DOM, so the unit tests (e2e/unit/state.test.mjs) run it in Node.

/** How many scene versions undo keeps. */
export const UNDO_LIMIT = 200;

/** The state of a page that has nothing open yet. */
export function createState() {
  return {
    scene: null,
    photo: null, // ImageBitmap
    photoBlob: null, // the photo's original bytes, sent to /api/detect
    photoName: '',
    detection: null, // {segments, segmentVp, warnings}
    camera: null, // camera of the last build
    build: null, // last successful /api/build answer
    buildError: null,
    marked: null, // {path, p} of the point the build error is about (scene.messagePoint)
    selection: null, // {type: 'object', index} | {type: 'vpline', vp, line}
    handle: null, // last grabbed point, for keyboard nudging
    showSegments: true,
    savedVpPoints: [null, null, null],
    // method null: the server's default (the build answer's map.method says which it is);
    // click_sigma null: estimated by the fit.
    // hidden_free: hidden floor counts as free (map and plan); unknown_passable: the planners
    // may cross unknown cells (plan only).
    settings: { method: null, resolution: 0.05, robot_radius: 0.2, click_sigma: null, hidden_free: false },
    plan: { start: null, goal: null, result: null, error: null, unknown_passable: false },
    // The true map the server knows for this photo ('example': the bundled office), and the
    // last drive on it (/api/navigate).
    truth: null,
    drive: { result: null, error: null },
    counters: { builds: 0, plans: 0, detects: 0, drives: 0 },
    busy: { build: false, plan: false, detect: false, example: false, drive: false },
  };
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
