// The room's photos as a strip of thumbnails above the photo (shown once the room has two or
// more photos): click one to make it the active photo, × to remove it (after asking); a red
// badge marks the photo the last build error or build blocker is about, and the same message
// shows beside the photo (`#photo-note`) while that photo is the active one. Adding photos is
// files.js's (Add photo…); the room's state is state.js's.

import { $, h } from './util.js';
import { createSlot } from './state.js';

/** Wire the strip to `app`: adds `switchPhoto`, `removePhoto`, `renderStrip`, `renderProblems`. */
export function installPhotoStrip(app) {
  const { state } = app;
  const strip = $('photo-strip');
  const list = $('photo-thumbs');

  /** The label of photo `i` on its thumbnail and in messages. */
  const label = (i) => `${i + 1}`;

  function renderStrip() {
    const n = state.photos.length;
    const room = n > 1;
    strip.hidden = !room;
    document.body.classList.toggle('room', room);
    $('btn-save-scene').textContent = room ? 'Save room' : 'Save scene';
    $('btn-save-scene').title = room ? `Save the room file: the annotations of all ${n} photos` : '';
    list.replaceChildren(
      ...state.photos.map((slot, i) => {
        const active = i === state.active;
        const size = slot.scene ? `${slot.scene.image.width} × ${slot.scene.image.height}` : '';
        const name = slot.photoName || (slot.scene ? `no photo (${size})` : 'empty');
        const pic = slot.photoUrl
          ? h('img', { src: slot.photoUrl, alt: '', draggable: 'false' })
          : h('span', { class: 'thumb-blank', text: size || '—' });
        const pick = h('button', {
          type: 'button',
          class: 'thumb-pick',
          'aria-pressed': String(active),
          'aria-label': `Photo ${label(i)}: ${name}`,
          title: `Photo ${label(i)}: ${name}${slot.photo ? '' : ' (open its photo with Open photo… while it is active)'}`,
        }, pic, h('span', { class: 'thumb-num', text: label(i) }), h('span', { class: 'thumb-name', text: name }));
        pick.addEventListener('click', () => switchPhoto(i));
        const badge = h('span', { class: 'thumb-badge', text: '!', hidden: true, role: 'img' });
        const remove = h('button', { type: 'button', class: 'thumb-remove small', text: '×', 'aria-label': `Remove photo ${label(i)}`, title: `Remove photo ${label(i)} from the room` });
        remove.addEventListener('click', () => removePhoto(i));
        return h('li', { class: active ? 'thumb active' : 'thumb', dataset: { photo: i } }, pick, badge, remove);
      }),
    );
    renderProblems();
  }

  /** The badge on the photo the problem is about, and the message beside the active photo. */
  function renderProblems() {
    const p = state.problem;
    for (const li of list.children) {
      const i = Number(li.dataset.photo);
      const badge = li.querySelector('.thumb-badge');
      const on = !!p && p.photo === i;
      badge.hidden = !on;
      li.classList.toggle('has-problem', on);
      if (on) {
        badge.title = p.message;
        badge.setAttribute('aria-label', `Photo ${label(i)}: ${p.message}`);
      } else {
        badge.removeAttribute('title');
        badge.removeAttribute('aria-label');
      }
    }
    const note = $('photo-note');
    const here = !!p && state.photos.length > 1 && p.photo === state.active;
    note.hidden = !here;
    note.textContent = here ? `Photo ${label(state.active)}: ${p.message}` : '';
  }

  /** Make photo `i` the one shown and edited. */
  function switchPhoto(i) {
    if (i === state.active || !state.photos[i]) return;
    app.flushAutosave?.();
    app.cancelDetect?.();
    app.endTool();
    state.active = i;
    state.selection = null;
    state.handle = null;
    photoShown();
    const slot = state.photos[i];
    app.setStatus(`Photo ${label(i)}${slot.photoName ? ` (${slot.photoName})` : ''}${slot.photo ? '' : ': no photo open for it; Open photo… puts one under its annotations'}.`);
  }

  /** Show the active photo: its picture, its annotations, its camera of the last build. */
  function photoShown() {
    const { scene, photo } = state;
    app.photoView.setImage(photo || null, photo?.width || scene?.image.width || 0, photo?.height || scene?.image.height || 0);
    $('drop-hint').hidden = !!scene;
    app.cameraChanged();
    app.syncForms();
    app.renderPanel();
    app.renderCamera();
    app.renderWarnings(state.build ? [...(state.build.warnings || []), ...(state.build.map?.warnings || [])] : []);
    app.proposalsForPhoto?.();
    renderStrip();
  }

  /** Remove photo `i` from the room, after asking when it has annotations. */
  function removePhoto(i) {
    const slot = state.photos[i];
    if (!slot) return;
    const s = slot.scene;
    const work = s && (s.objects.length || s.floor.length || s.vanishing_points.some((vp) => vp.point || vp.lines?.length));
    if (work && !window.confirm(`Remove photo ${label(i)}${slot.photoName ? ` (${slot.photoName})` : ''} and its annotations from the room? This cannot be undone (they stay kept in this browser for its photo).`)) return;
    app.flushAutosave?.();
    app.cancelDetect?.();
    app.endTool();
    slot.photo?.close?.();
    if (slot.photoUrl) URL.revokeObjectURL(slot.photoUrl);
    state.photos.splice(i, 1);
    if (!state.photos.length) state.photos.push(createSlot());
    if (state.active > i || state.active >= state.photos.length) state.active = Math.max(0, state.active - 1);
    state.selection = null;
    state.handle = null;
    app.setProblem(null);
    app.sceneChanged();
    photoShown();
    app.scheduleBuild();
    app.setStatus(`Removed photo ${label(i)}; ${state.photos.length} photo${state.photos.length === 1 ? '' : 's'} left.`);
  }

  Object.assign(app, { switchPhoto, removePhoto, renderStrip, renderProblems, photoShown });
}
