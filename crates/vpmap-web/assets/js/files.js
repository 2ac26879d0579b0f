// Files in and out: opening a photo or a scene file (buttons and drag and drop), loading the
// example, saving the scene and downloading the build's files and the floor plan picture.

import * as api from './api.js';
import { $, h, base64ToBytes, download } from './util.js';
import { emptyScene, normaliseScene } from './scene.js';

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

  /** Show a photo. Keeps the scene when it was made for a photo of the same size. */
  async function openPhoto(blob, name) {
    app.clearError();
    const bmp = await decodePhoto(blob);
    state.photo?.close?.();
    state.photo = bmp;
    state.photoBlob = blob;
    state.photoName = name || 'photo';
    state.truth = null;
    state.detection = null;
    // This photo's scene as the browser kept it (autosave.js), if it was opened before.
    const kept = app.photoOpened(state.photoName, bmp.width, bmp.height, new Uint8Array(await blob.arrayBuffer()));
    const restored = kept && !normaliseScene(kept.scene);
    const keep = !restored && state.scene && state.scene.image.width === bmp.width && state.scene.image.height === bmp.height;
    // Undo never crosses a change of photo: it would put one photo's annotations on another.
    app.history.clear();
    if (restored) {
      state.scene = kept.scene;
      state.savedVpPoints = [null, null, null];
      state.selection = null;
      app.clearBuild();
      app.syncForms();
    } else if (!keep) {
      state.scene = emptyScene(bmp.width, bmp.height);
      state.savedVpPoints = [null, null, null];
      state.selection = null;
      app.clearBuild();
      app.syncForms();
    }
    photoView.setImage(bmp, bmp.width, bmp.height);
    $('drop-hint').hidden = true;
    app.renderPanel();
    app.scheduleBuild();
    if (restored) {
      const when = new Date(kept.saved_at).toLocaleString();
      app.setStatus(`${state.photoName}: your annotations of ${when} are back (kept in this browser). New scene (keep photo) starts afresh.`);
    } else {
      app.setStatus(`${state.photoName}: ${bmp.width} × ${bmp.height} px${keep ? ' (the open scene is kept)' : ''}. Next: Detect.`);
    }
  }

  $('photo-input').addEventListener('change', async (e) => {
    const file = e.target.files[0];
    e.target.value = '';
    if (file) await openPhoto(file, file.name).catch((err) => app.showError(err.message));
  });

  async function openSceneFile(file) {
    app.clearError();
    let scene;
    try {
      scene = JSON.parse(await file.text());
    } catch (err) {
      app.showError(`${file.name} is not valid JSON: ${err.message}`);
      return;
    }
    const problem = normaliseScene(scene);
    if (problem) {
      app.showError(`${file.name}: ${problem}`);
      return;
    }
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
    $('drop-hint').hidden = true;
    app.clearBuild();
    app.syncForms();
    app.renderPanel();
    app.scheduleBuild();
    app.sceneChanged(); // kept for the open photo...
    app.sceneSaved(); // ...and in its file already
    app.setStatus(`Opened ${file.name}.${note}${state.photo ? '' : ' Open its photo to see it under the annotations.'}`);
  }

  $('scene-input').addEventListener('change', async (e) => {
    const file = e.target.files[0];
    e.target.value = '';
    if (file) await openSceneFile(file);
  });

  $('btn-save-scene').addEventListener('click', () => {
    if (!state.scene) return;
    const { width, height } = state.scene.image;
    // The file is named after the open photo only when it was made for a photo of its size.
    const forPhoto = !state.photo || (state.photo.width === width && state.photo.height === height);
    const name = forPhoto ? sceneFileName(state.photoName) : `scene-${width}x${height}.scene.json`;
    download(name, `${JSON.stringify(state.scene, null, 1)}\n`, 'application/json');
    app.sceneSaved();
    app.setStatus(forPhoto ? `Saved ${name}.` : `Saved ${name}: made for a ${width} × ${height} photo, not the open ${state.photo.width} × ${state.photo.height} one.`);
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
      state.photo = bmp;
      state.photoBlob = blob;
      state.photoName = 'example.png';
      state.truth = 'example';
      state.scene = ex.scene;
      state.detection = null;
      state.savedVpPoints = [null, null, null];
      state.selection = null;
      photoView.setImage(bmp, bmp.width, bmp.height);
      $('drop-hint').hidden = true;
      app.clearBuild();
      app.syncForms();
      app.renderPanel();
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
