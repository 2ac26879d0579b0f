// Files in and out: opening a photo (into the active photo of the room) or adding photos to
// the room, opening a scene file (into the active photo) or a room file (the whole room),
// loading the example, saving the scene (one photo) or the room (several), and downloading the
// build's files and the floor plan picture.

import * as api from './api.js';
import { $, h, base64ToBytes, download } from './util.js';
import { emptyScene, normaliseScene } from './scene.js';
import { createSlot, roomScenes } from './state.js';
import { parseRoom, roomBody, roomFileName } from './room.js';

/** The file name to save the scene under: the photo's name with `.scene.json`. */
export function sceneFileName(photoName) {
  const base = (photoName || 'scene').replace(/\.[^.]+$/, '');
  return `${base}.scene.json`;
}

async function decodePhoto(blob) {
  try {
    return await createImageBitmap(blob, { imageOrientation: 'from-image' });
  } catch {
    throw new Error('cannot read this file as a JPEG or PNG image');
  }
}

/** Wire the page's file inputs, drop area, example button and downloads to `app`. */
export function installFiles(app) {
  const { state, photoView, planView } = app;

  // ---- photo and scene files ----------------------------------------------------------------

  /**
   * Show a photo in the active slot, or with `add` in a new slot of the room (made active).
   * Keeps the slot's scene when it was made for a photo of the same size (a scene or room file
   * opened before its photos).
   */
  async function openPhoto(blob, name, { add = false } = {}) {
    app.clearError();
    const bmp = await decodePhoto(blob);
    if (add && state.scene) {
      app.flushAutosave();
      app.cancelDetect();
      app.endTool();
      state.photos.push(createSlot());
      state.active = state.photos.length - 1;
    }
    state.photo?.close?.();
    if (state.photoUrl) URL.revokeObjectURL(state.photoUrl);
    state.photo = bmp;
    state.photoBlob = blob;
    state.photoUrl = URL.createObjectURL(blob);
    state.photoName = name || 'photo';
    state.truth = null;
    state.detection = null;
    // This photo's scene as the browser kept it (autosave.js), if it was opened before.
    const kept = app.photoOpened(state.photoName, bmp.width, bmp.height, new Uint8Array(await blob.arrayBuffer()));
    const restored = kept && !normaliseScene(kept.scene);
    const keep = !restored && state.scene && state.scene.image.width === bmp.width && state.scene.image.height === bmp.height;
    // Undo never crosses a change of photo: it would put one photo's annotations on another.
    app.history.clear();
    const room = state.photos.length > 1;
    if (restored || !keep) {
      state.scene = restored ? kept.scene : emptyScene(bmp.width, bmp.height);
      state.savedVpPoints = [null, null, null];
      state.selection = null;
      // A single photo's build is of this photo alone: forget it. A room's is of every photo.
      if (!room) app.clearBuild();
      app.syncForms();
    }
    photoView.setImage(bmp, bmp.width, bmp.height);
    $('drop-hint').hidden = true;
    app.photoShown();
    app.scheduleBuild();
    const which = room ? `Photo ${state.active + 1}, ${state.photoName}` : state.photoName;
    if (restored) {
      const when = new Date(kept.saved_at).toLocaleString();
      app.setStatus(`${which}: your annotations of ${when} are back (kept in this browser). New scene (keep photo) starts afresh.`);
    } else {
      app.setStatus(`${which}: ${bmp.width} × ${bmp.height} px${keep ? ' (the open scene is kept)' : ''}. Next: Detect.`);
    }
  }

  /** Add each photo file to the room (one slot each), the last one active. */
  async function addPhotos(files) {
    for (const file of files) {
      try {
        await openPhoto(file, file.name, { add: true });
      } catch (err) {
        app.showError(`${file.name}: ${err.message}`);
      }
    }
  }

  $('photo-input').addEventListener('change', async (e) => {
    const file = e.target.files[0];
    e.target.value = '';
    if (file) await openPhoto(file, file.name).catch((err) => app.showError(err.message));
  });

  for (const id of ['add-photo-input', 'add-photo-strip-input']) {
    $(id).addEventListener('change', async (e) => {
      const files = [...e.target.files];
      e.target.value = '';
      await addPhotos(files);
    });
  }

  /** A single scene: into the active photo (undoable). */
  function openScene(scene, fileName) {
    if (state.scene) app.pushUndo();
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
    const room = state.photos.length > 1;
    if (!room) app.clearBuild();
    app.photoShown();
    const which = room ? ` into photo ${state.active + 1}` : '';
    return `Opened ${fileName}${which}.${note}${state.photo ? '' : ' Open its photo to see it under the annotations.'}`;
  }

  /**
   * A room file: it replaces the room. Each photo already open stays with the room file's photo
   * of the same place in the list when it has that photo's size; the others are open with
   * Open photo… while their thumbnail is active.
   */
  function openRoom(scenes, fileName) {
    app.flushAutosave();
    app.cancelDetect();
    app.endTool();
    const old = state.photos;
    state.photos = scenes.map((scene, i) => {
      const prev = old[i];
      const fits = prev?.photo && prev.photo.width === scene.image.width && prev.photo.height === scene.image.height;
      const slot = createSlot({ scene });
      if (fits) Object.assign(slot, { photo: prev.photo, photoBlob: prev.photoBlob, photoName: prev.photoName, photoUrl: prev.photoUrl, photoKey: prev.photoKey });
      return slot;
    });
    for (const [i, prev] of old.entries()) {
      if (state.photos[i]?.photo === prev.photo) continue;
      prev.photo?.close?.();
      if (prev.photoUrl) URL.revokeObjectURL(prev.photoUrl);
    }
    state.active = 0;
    state.selection = null;
    state.handle = null;
    app.clearBuild();
    app.photoShown();
    const missing = state.photos.filter((s) => !s.photo).length;
    return `Opened ${fileName}: a room of ${scenes.length} photos.${missing ? ` ${missing} without their photo: click a thumbnail, then Open photo… to see it under its annotations.` : ''}`;
  }

  async function openSceneFile(file) {
    app.clearError();
    let value;
    try {
      value = JSON.parse(await file.text());
    } catch (err) {
      app.showError(`${file.name} is not valid JSON: ${err.message}`);
      return;
    }
    const parsed = parseRoom(value);
    if (parsed.error) {
      app.showError(`${file.name}: ${parsed.error}`);
      return;
    }
    const many = state.photos.filter((s) => s.scene).length;
    if (parsed.room && many > 1 && !window.confirm(`Replace the room of ${many} photos with ${file.name}?`)) return;
    const message = parsed.room ? openRoom(parsed.scenes, file.name) : openScene(parsed.scenes[0], file.name);
    $('drop-hint').hidden = true;
    app.syncForms();
    app.renderPanel();
    app.scheduleBuild();
    app.sceneChanged(); // kept for the open photos...
    app.sceneSaved(); // ...and in its file already
    app.setStatus(message);
  }

  $('scene-input').addEventListener('change', async (e) => {
    const file = e.target.files[0];
    e.target.value = '';
    if (file) await openSceneFile(file);
  });

  $('btn-save-scene').addEventListener('click', () => {
    if (!state.scene) return;
    const scenes = roomScenes(state);
    if (scenes.length > 1) {
      // A room: every photo's scene in one file.
      const name = roomFileName(state.photos[0].photoName);
      download(name, `${JSON.stringify(roomBody(scenes), null, 1)}\n`, 'application/json');
      app.sceneSaved();
      app.setStatus(`Saved ${name}: the room of ${scenes.length} photos.`);
      return;
    }
    const { width, height } = state.scene.image;
    // The file is named after the open photo only when it was made for a photo of its size.
    const forPhoto = !state.photo || (state.photo.width === width && state.photo.height === height);
    const name = forPhoto ? sceneFileName(state.photoName) : `scene-${width}x${height}.scene.json`;
    download(name, `${JSON.stringify(state.scene, null, 1)}\n`, 'application/json');
    app.sceneSaved();
    app.setStatus(forPhoto ? `Saved ${name}.` : `Saved ${name}: made for a ${width} × ${height} photo, not the open ${state.photo.width} × ${state.photo.height} one.`);
  });

  // Drag and drop onto the photo area: a scene or room file, a photo (into the active photo),
  // or several photos (each added to the room).
  const wrap = $('photo-wrap');
  wrap.addEventListener('dragover', (e) => {
    e.preventDefault();
    wrap.classList.add('dragover');
  });
  wrap.addEventListener('dragleave', () => wrap.classList.remove('dragover'));
  wrap.addEventListener('drop', async (e) => {
    e.preventDefault();
    wrap.classList.remove('dragover');
    const files = [...e.dataTransfer.files];
    const file = files[0];
    if (!file) return;
    if (file.type === 'application/json' || file.name.endsWith('.json')) await openSceneFile(file);
    else if (files.length > 1) await addPhotos(files);
    else await openPhoto(file, file.name).catch((err) => app.showError(err.message));
  });

  // ---- the example ----------------------------------------------------------------------------

  async function loadExample() {
    app.clearError();
    state.busy.example = true;
    app.setStatus('Loading the example…');
    try {
      const ex = await api.getExample();
      const problem = normaliseScene(ex.scene);
      if (problem) throw new Error(`the example scene: ${problem}`);
      const blob = new Blob([base64ToBytes(ex.photo_png_base64)], { type: 'image/png' });
      const bmp = await decodePhoto(blob);
      app.history.clear(); // another photo: see openPhoto
      app.photoOpened('example.png', bmp.width, bmp.height, null); // the example is not kept
      state.photo?.close?.();
      if (state.photoUrl) URL.revokeObjectURL(state.photoUrl);
      state.photo = bmp;
      state.photoBlob = blob;
      state.photoUrl = URL.createObjectURL(blob);
      state.photoName = 'example.png';
      state.truth = 'example';
      state.scene = ex.scene;
      state.detection = null;
      state.savedVpPoints = [null, null, null];
      state.selection = null;
      photoView.setImage(bmp, bmp.width, bmp.height);
      $('drop-hint').hidden = true;
      app.clearBuild();
      app.photoShown();
      state.busy.example = false;
      app.setStatus('Example loaded.');
      app.buildNow();
    } catch (err) {
      if (!api.isAbort(err)) app.showError(`Loading the example failed: ${err.message}`);
      app.setStatus('');
    } finally {
      state.busy.example = false;
      app.refreshBusy();
    }
  }

  $('btn-example').addEventListener('click', loadExample);

  // ---- downloads ------------------------------------------------------------------------------

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
        app.showError(`Download failed: ${err.message}`);
      }
    });
  }
}
