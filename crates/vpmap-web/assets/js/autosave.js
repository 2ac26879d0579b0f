// No lost work: the scene of each photo the user opens is kept in the browser (localStorage)
// a moment after every change and comes back when the same photo is opened again, alone or as
// one photo of a room (each photo of the room is kept under its own key, so reopening the
// room's photos brings the whole room back); leaving the page with changes to any photo that
// were not saved to a file asks first. A photo is known by its name,
// size in pixels and a hash of its bytes. The example is not kept (it comes back on its own).
// The store functions take the storage as an argument, so the unit tests run them in Node.

/** Prefix of the keys the page writes in localStorage. */
export const KEY_PREFIX = 'vpmap.autosave.v1:';
/** How many photos' scenes are kept; the oldest goes first. */
export const KEEP = 20;
/** Wait this long after the last change before writing (ms). */
const DELAY_MS = 400;

/** FNV-1a (32 bit) of the bytes, as 8 hex digits: enough to tell two photos of one name apart. */
export function hashBytes(bytes) {
  let h = 0x811c9dc5;
  for (let i = 0; i < bytes.length; i++) {
    h ^= bytes[i];
    h = Math.imul(h, 0x01000193) >>> 0;
  }
  return h.toString(16).padStart(8, '0');
}

/** The key of a photo: name, size and the hash of its bytes. */
export function photoKey(name, width, height, bytes) {
  return `${KEY_PREFIX}${name}|${width}x${height}|${bytes.length}|${hashBytes(bytes)}`;
}

/** Keep `scene` under `key` (with the time, ms), dropping the oldest beyond `keep`; false when the storage refuses. */
export function storeScene(storage, key, scene, now, keep = KEEP) {
  try {
    storage.setItem(key, JSON.stringify({ saved_at: now, scene }));
  } catch {
    return false;
  }
  const entries = [];
  for (let i = 0; i < storage.length; i++) {
    const k = storage.key(i);
    if (!k || !k.startsWith(KEY_PREFIX)) continue;
    let at = 0;
    try {
      at = JSON.parse(storage.getItem(k)).saved_at || 0;
    } catch {
      // A broken entry goes first.
    }
    entries.push([at, k]);
  }
  entries.sort((a, b) => a[0] - b[0]);
  while (entries.length > keep) storage.removeItem(entries.shift()[1]);
  return true;
}

/** `{saved_at, scene}` kept under `key`, or null. */
export function loadScene(storage, key) {
  try {
    const v = JSON.parse(storage.getItem(key) || 'null');
    return v && v.scene && typeof v.scene === 'object' ? v : null;
  } catch {
    return null;
  }
}

/** Wire autosave and the warning before leaving to `app`. */
export function installAutosave(app) {
  const { state } = app;
  let storage = null;
  try {
    storage = window.localStorage;
  } catch {
    // Storage switched off: no autosave, the warning before leaving still works.
  }
  let timer = 0;
  state.dirty = false;
  // The scene last written for each key, so that a flush writes only what changed.
  const written = new Map();

  /** Keep every photo of the room that has a key (the active one is the one edited). */
  function flush() {
    clearTimeout(timer);
    timer = 0;
    if (!storage) return;
    for (const slot of state.photos) {
      if (!slot.photoKey || !slot.scene) continue;
      const text = JSON.stringify(slot.scene);
      if (written.get(slot.photoKey) === text) continue;
      if (storeScene(storage, slot.photoKey, slot.scene, Date.now())) written.set(slot.photoKey, text);
    }
  }

  /** The scene was edited: remember it (soon) and warn before leaving. */
  function sceneChanged() {
    state.dirty = true;
    if (!storage || !state.photos.some((s) => s.photoKey)) return;
    clearTimeout(timer);
    timer = setTimeout(flush, DELAY_MS);
  }

  /** A photo was opened (`bytes` its file): its key, and its kept scene if any (`{saved_at, scene}`). */
  function photoOpened(name, width, height, bytes) {
    flush();
    state.photoKey = bytes ? photoKey(name, width, height, bytes) : null;
    // A photo of a room is one more photo: the room's other changes are still unsaved.
    if (state.photos.length <= 1) state.dirty = false;
    const kept = storage && state.photoKey ? loadScene(storage, state.photoKey) : null;
    return kept && kept.scene.image?.width === width && kept.scene.image?.height === height ? kept : null;
  }

  window.addEventListener('beforeunload', (e) => {
    flush();
    if (!state.dirty) return;
    e.preventDefault();
    e.returnValue = '';
  });
  window.addEventListener('pagehide', flush);

  Object.assign(app, {
    sceneChanged,
    flushAutosave: flush,
    photoOpened,
    /** The scene was written to a file: nothing to lose on leaving. */
    sceneSaved: () => {
      state.dirty = false;
    },
  });
}
