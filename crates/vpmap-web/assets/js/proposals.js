// "Propose boxes": cuboid candidates from the photo's line segments (/api/propose: edges along
// the three directions that close into box corners). They are listed under the objects and
// outlined on the photo (the hovered or focused one bright); accepting one adds a box with
// its corners in one undoable edit, each corner still editable like a clicked one.

import { boxEdges, boxPoints } from './box.js';
import { uniqueName } from './scene.js';
import { $, h } from './util.js';
import { fetchProposals } from './photo-snap.js';

const COLOUR = '#e1a3ff';

/** A proposal's corners as a box object (no name). */
export function proposalObject(p) {
  const o = { base: { ...(p.corners?.base || {}) } };
  if (p.corners?.top && Object.keys(p.corners.top).length) o.top = { ...p.corners.top };
  return o;
}

export function installProposals(app) {
  const st = app.state;
  // The candidates, with the photo slot and picture they were found in.
  const ui = { list: [], hover: -1, slot: null, photo: null };
  app.proposals = ui;
  const button = $('btn-propose');
  const host = $('proposal-list');

  function clear() {
    ui.list = [];
    ui.hover = -1;
    ui.slot = null;
    ui.photo = null;
    render();
    app.requestRender();
  }
  app.clearProposals = clear;
  // Called whenever a photo is shown: the candidates of another photo (or of the picture this
  // slot showed before) are forgotten.
  app.proposalsForPhoto = () => {
    if (ui.list.length && (ui.slot !== st.photos[st.active] || ui.photo !== st.photo)) clear();
  };

  function render() {
    host.replaceChildren();
    host.hidden = !ui.list.length;
    ui.list.forEach((p, i) => {
      const corners = boxPoints(proposalObject(p)).length;
      const accept = h('button', { type: 'button', class: 'small', text: 'Accept', title: 'Add this box (undo takes it back)' });
      accept.addEventListener('click', () => acceptProposal(i));
      const li = h('li', { 'data-index': i, tabindex: '-1' }, h('span', { text: `candidate ${i + 1}: ${corners} corners, score ${Math.round(p.score)}` }), accept);
      const on = () => {
        ui.hover = i;
        app.requestRender();
      };
      const off = () => {
        if (ui.hover === i) ui.hover = -1;
        app.requestRender();
      };
      li.addEventListener('mouseenter', on);
      li.addEventListener('mouseleave', off);
      accept.addEventListener('focus', on);
      accept.addEventListener('blur', off);
      host.append(li);
    });
    const dismiss = h('button', { type: 'button', class: 'small link', text: 'Dismiss the candidates' });
    dismiss.addEventListener('click', clear);
    if (ui.list.length) host.append(h('li', { class: 'proposal-dismiss' }, dismiss));
  }

  function acceptProposal(i) {
    const p = ui.list[i];
    if (!p || !st.scene) return;
    ui.list.splice(i, 1);
    ui.hover = -1;
    render();
    app.addObject({ name: uniqueName(st.scene, 'box'), ...proposalObject(p) });
  }

  button.addEventListener('click', async () => {
    if (!st.scene) return;
    button.disabled = true;
    app.setStatus('Looking for boxes in the photo’s segments…');
    try {
      const slot = st.photos[st.active];
      const photo = st.photo;
      const list = await fetchProposals(app);
      if (st.photos[st.active] !== slot || st.photo !== photo) return;
      ui.list = list;
      ui.slot = slot;
      ui.photo = photo;
      render();
      app.requestRender();
      app.setStatus(list.length ? `${list.length} box candidates: hover one to see it, Accept to add it.` : 'No box candidates found in the photo’s segments.');
    } catch (err) {
      app.showError(`Propose boxes: ${err.message}`);
      app.setStatus('');
    } finally {
      button.disabled = !st.scene || !st.photoBlob;
    }
  });
}

/** The listed candidates on the photo: faint, the hovered one bright. */
export function drawProposals(view, app) {
  const ui = app.proposals;
  if (!ui?.list.length || ui.slot !== app.state.photos[app.state.active] || ui.photo !== app.state.photo) return;
  ui.list.forEach((p, i) => {
    const o = proposalObject(p);
    const hot = i === ui.hover;
    for (const e of boxEdges(o)) {
      view.path([e.a, e.b]);
      if (hot) view.strokeHalo(COLOUR, 2.5);
      else {
        view.ctx.strokeStyle = 'rgba(225,163,255,0.55)';
        view.ctx.lineWidth = 1.2;
        view.ctx.setLineDash([4, 3]);
        view.ctx.stroke();
        view.ctx.setLineDash([]);
      }
    }
    if (hot) for (const { p: q } of boxPoints(o)) view.dot(q, 3.5, COLOUR);
  });
}
