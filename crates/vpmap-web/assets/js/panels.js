// The step panel (vanishing points, objects, floor, scale, settings, plan results), the step
// prompt above the photo, the camera bar, the status line, the error banner and the tabs of
// narrow screens. Everything here is drawn from `app.state`; edits go through `app.edit`.

import { $, h, fmt, fmtSd, parsePair, formatPair } from './util.js';
import { VP_NAMES, resolvedVps, vpUsable } from './scene.js';
import { OFF_LINE_PX, boxEdgeNames, describeBox, edgeChoice, guideOffsets, parseEdgeChoice } from './box.js';
import { lensOf, vpPoint } from './geometry.js';
import { VpLineTool } from './vp-line-tool.js';
import { BUG_COLOURS, PLANNER_STYLE } from './plan-view.js';
import { smoothDetail } from './smooth-view.js';
import { busyNames, roomScenes } from './state.js';
import { linkCandidates, sharedWith, photoList } from './room.js';

/** ` · ±X° (95 %)`, the 95 % ellipse's major semi-axis of a vanishing point's covariance (degrees²), or ''. */
function vpSpread(vp) {
  const c = vp.covariance_deg2;
  if (!Array.isArray(c) || c.length !== 2) return '';
  const [[a, b], [, d]] = c;
  const major = (a + d) / 2 + Math.sqrt(((a - d) / 2) ** 2 + b * b);
  if (!(major > 0)) return '';
  return ` · ±${Math.sqrt(5.991 * major).toFixed(1)}° (95 %)`;
}

const IDLE_PROMPT = 'Drag a corner to move it · click an object or a line to select it (then drag the line\'s ends; Delete removes it) · scroll to zoom · drag to pan · ? for keys';
const TABS = ['photo', 'plan', 'model'];

/** Add the panel's functions to `app` and wire its inputs. */
export function installPanels(app) {
  const { state } = app;

  // ---- status and errors ----------------------------------------------------------------

  function setStatus(text) {
    const el = $('status');
    el.textContent = text;
    refreshBusy();
  }

  function refreshBusy() {
    const busy = Object.values(state.busy).some(Boolean);
    $('status').classList.toggle('busy', busy);
    document.body.dataset.busy = busyNames(state.busy).join(' ');
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

  // ---- the step prompt and the tool buttons ----------------------------------------------

  function renderPrompt() {
    const box = $('prompt');
    const extra = $('prompt-extra');
    extra.replaceChildren();
    $('prompt-control').replaceChildren();
    const placing = app.tool !== app.selectTool && !!app.tool.prompt;
    box.dataset.tool = placing ? app.tool.kind : 'select';
    $('prompt-cancel').hidden = !placing;
    if (!placing) {
      $('prompt-text').textContent = state.scene ? IDLE_PROMPT : '';
      $('prompt-text').title = '';
      $('prompt-undo').hidden = true;
      $('prompt-finish').hidden = true;
      return;
    }
    const p = app.tool.prompt();
    $('prompt-text').textContent = p.text;
    $('prompt-text').title = p.help || '';
    if (p.extra) $('prompt-control').append(p.extra);
    if (p.help) extra.textContent = `(${p.help})`;
    $('prompt-undo').hidden = false;
    $('prompt-undo').disabled = !p.canUndo;
    const fin = $('prompt-finish');
    fin.hidden = !p.finish;
    fin.textContent = p.finish || 'Done';
    app.photoView.requestRender();
  }

  function renderToolButtons() {
    const kind = app.tool.kind;
    for (const [id, k] of [['btn-add-box', 'box'], ['btn-add-footprint', 'footprint'], ['btn-floor', 'floor'], ['btn-floor-distance', 'floor-distance']]) {
      $(id).setAttribute('aria-pressed', String(kind === k));
    }
    renderVpList();
  }

  // ---- the panel --------------------------------------------------------------------------

  function renderPanel() {
    const has = !!state.scene;
    if (app.tool === app.selectTool) renderPrompt();
    for (const id of ['btn-add-box', 'btn-add-footprint', 'btn-floor', 'btn-floor-distance', 'btn-new-scene', 'btn-save-scene']) $(id).disabled = !has;
    $('btn-detect').disabled = !state.photoBlob;
    $('btn-propose').disabled = !has || !state.photoBlob;
    $('btn-clear-floor').disabled = !has || !(state.scene.floor || []).length;
    $('btn-undo').disabled = !app.history?.canUndo;
    $('btn-redo').disabled = !app.history?.canRedo;
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
          // The detector's `perspective` describes the old count; the count decides.
          app.edit((s) => { s.vanishing_points.push({ lines: [] }); delete s.perspective; });
          app.setTool(new VpLineTool(app, 2));
        });
        actions.append(add);
      } else {
        const lines = vp.lines || [];
        const p = vpPoint(vp);
        let info;
        if (Array.isArray(vp.point)) info = `point ${formatPair(vp.point, 0)}${vpSpread(vp)}${lines.length ? ` · ${lines.length} lines as evidence` : ''}`;
        else if (p) info = `from ${lines.length} lines: ${formatPair(p, 0)}`;
        else info = lines.length >= 2 ? `${lines.length} lines (parallel: no point)` : `draw ${2 - lines.length} more line${lines.length === 1 ? '' : 's'}`;
        li.append(h('div', { class: 'vp-info', text: info }));
        if (!vpUsable(vp)) li.classList.add('incomplete');
        const draw = h('button', { type: 'button', class: 'small', text: 'Draw lines', 'aria-pressed': String(app.tool.kind === 'vp-line' && app.tool.vpIndex === k) });
        draw.addEventListener('click', () => app.setTool(new VpLineTool(app, k)));
        actions.append(draw);
        if (lines.length) {
          const clear = h('button', { type: 'button', class: 'small', text: 'Clear lines' });
          clear.addEventListener('click', () =>
            app.edit((s) => {
              s.vanishing_points[k].lines = [];
              app.detachVpPoint(k, s);
            }),
          );
          actions.append(clear);
        }
        if (!vp.point && state.savedVpPoints[k]) {
          const restore = h('button', { type: 'button', class: 'small', text: 'Use detected point', title: 'Use the point found by detection instead of the lines' });
          restore.addEventListener('click', () => app.edit((s) => {
            s.vanishing_points[k].point = state.savedVpPoints[k];
            const cov = state.savedVpCovariances?.[k];
            if (cov) s.vanishing_points[k].covariance_deg2 = cov;
          }));
          actions.append(restore);
        }
        if (k === 2) {
          const rm = h('button', { type: 'button', class: 'small', text: 'Remove', title: 'Two-point perspective: no vertical vanishing point' });
          rm.addEventListener('click', () => app.edit((s) => { s.vanishing_points.length = 2; delete s.perspective; }));
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
    if (o.base) parts.push(describeBox(o));
    else parts.push(`${(o.footprint || []).length} corners${o.top ? ' + top' : ', no top'}`);
    const lines = [parts.join(' · ')];
    if (m) lines.push(...objectMeasures(m, map.units === 'm' ? 'm' : 'ch', !!o.own_yaw));
    // Corners off the lines they should lie on: the map's box cannot pass through them, so
    // its sizes differ from distances measured on the clicked points. Said with the distance.
    if (o.base) {
      for (const g of guideOffsets(o, resolvedVps(state.scene), lensOf(state.scene))) {
        if (g.px < OFF_LINE_PX) continue;
        const towards = g.part === 'top' ? `the vertical through base.${g.corner}` : `the line from base.${g.from} towards ${['A', 'B'][g.vp]}`;
        lines.push(`⚠ ${g.part}.${g.corner} is ${g.px.toFixed(1)} px off ${towards}`);
      }
    }
    return { kind, text: lines.join('\n') };
  }

  /**
   * The object's sizes, height and position as the build measured them, one line each, with
   * ± 1 sigma when the map has error bars (method fit), and then its outline's least certain
   * corner (1 sigma along that corner's least certain direction); a box with its own yaw also
   * gets its yaw.
   */
  function objectMeasures(m, u, ownYaw) {
    const unc = m.uncertainty || null;
    const pm = (v, sd, d = 2) => (unc && Number.isFinite(sd) ? `${fmt(v, d)} ± ${fmtSd(sd, d)}` : fmt(v, d));
    const size = m.size ? `${pm(m.size.length, unc?.length_sd)} × ${pm(m.size.breadth, unc?.breadth_sd)} ${u}` : `area ${fmt(m.area)} ${u}²`;
    let height = `height ${m.height === null || m.height === undefined ? 'unknown' : `${pm(m.height, unc?.height_sd)} ${u}`}`;
    if (ownYaw && unc && Number.isFinite(unc.yaw_deg)) height += `, yaw ${pm(unc.yaw_deg, unc.yaw_sd_deg, 1)}°`;
    if (!unc) return [`${size}, ${height}`];
    const lines = [size, height];
    if (Array.isArray(m.centroid)) {
      const cov = unc.centroid_covariance;
      const sx = cov ? Math.sqrt(cov[0][0]) : undefined, sy = cov ? Math.sqrt(cov[1][1]) : undefined;
      lines.push(`at (${pm(m.centroid[0], sx)}, ${pm(m.centroid[1], sy)}) ${u}`);
    }
    // The least certain footprint corner (what the warning of objects placed poorly reads).
    if (Number.isFinite(unc.corner_sd)) lines.push(`outline ± ${fmtSd(unc.corner_sd, 2)} ${u} at its least certain corner`);
    return lines;
  }

  /**
   * The room's names for linking: the names the other photos use and this one does not (the
   * name inputs' suggestions, `#room-names`), and for each name of this photo the other photos
   * that use it too (shown as "also in photo 2").
   */
  function roomNames() {
    const scenes = roomScenes(state);
    const candidates = scenes.length > 1 ? linkCandidates(scenes, state.active) : [];
    const list = $('room-names');
    const key = candidates.map((c) => c.name).join('\n');
    if (list.dataset.key !== key) {
      list.dataset.key = key;
      list.replaceChildren(...candidates.map((c) => h('option', { value: c.name, text: `in ${photoList(c.photos)}` })));
    }
    return { candidates, shared: scenes.length > 1 ? sharedWith(scenes, state.active) : new Map() };
  }

  /** The "also in photo 2" line of an object, or ''. */
  const sharedText = (shared, name) => (shared.get(name)?.length ? `⇄ same object in ${photoList(shared.get(name))}` : '');

  /** Offer `candidates` in an object's "same as…" select; hidden when there is none or the object is linked already. */
  function fillLinkSelect(sel, candidates, linked) {
    sel.hidden = !candidates.length || linked;
    const key = candidates.map((c) => `${c.name}:${c.photos}`).join('\n');
    if (sel.dataset.key === key) return;
    sel.dataset.key = key;
    sel.replaceChildren(
      h('option', { value: '', text: 'same as…' }),
      ...candidates.map((c) => h('option', { value: c.name, text: `${c.name} (${photoList(c.photos)})` })));
  }

  /** A select offering the other photos' names: one choice links the object to theirs. */
  function linkSelect(i, candidates, linked) {
    const sel = h('select', { class: 'obj-link small', 'aria-label': `Same object as one in another photo (object ${i + 1})`, title: 'The same object as one named in another photo: choose its name' });
    fillLinkSelect(sel, candidates, linked);
    sel.addEventListener('change', () => {
      if (!sel.value) return;
      renameObject(i, sel.value);
      const others = sharedWith(roomScenes(state), state.active).get(sel.value) || [];
      app.setStatus(`Linked: “${sel.value}” of photo ${state.active + 1} is the same object as in ${photoList(others)}.`);
      renderObjectList(true);
    });
    return sel;
  }

  function renderObjectList(force = false) {
    const ul = $('object-list');
    const objs = state.scene?.objects || [];
    const { candidates, shared } = roomNames();
    // Rebuilt when the photo or the objects' kinds change; else updated in place.
    const key = `${state.active}|${objs.map((o) => (o.footprint ? 'f' : 'b')).join('')}`;
    const sel = state.selection?.type === 'object' ? state.selection.index : -1;
    if (!force && key === objectListKey && ul.children.length === objs.length) {
      // Update in place, so that a name being typed keeps its focus.
      objs.forEach((o, i) => {
        const li = ul.children[i];
        li.classList.toggle('selected', i === sel);
        const input = li.querySelector('.obj-name');
        if (document.activeElement !== input && input.value !== o.name) input.value = o.name;
        li.querySelector('.obj-info').textContent = objectInfo(o).text;
        li.querySelector('.obj-shared').textContent = sharedText(shared, o.name);
        if (candidates.length) input.setAttribute('list', 'room-names');
        else input.removeAttribute('list');
        fillLinkSelect(li.querySelector('.obj-link'), candidates, !!shared.get(o.name)?.length);
      });
      return;
    }
    objectListKey = key;
    ul.replaceChildren(
      ...objs.map((o, i) => {
        const info = objectInfo(o);
        const input = h('input', { type: 'text', class: 'obj-name', value: o.name, 'aria-label': `Name of object ${i + 1}`, spellcheck: 'false', list: candidates.length ? 'room-names' : null });
        input.addEventListener('focus', () => {
          if (state.selection?.index !== i) app.select({ type: 'object', index: i });
        });
        input.addEventListener('input', () => renameObject(i, input.value));
        const del = h('button', { type: 'button', class: 'small', text: 'Delete', 'aria-label': `Delete ${o.name}` });
        del.addEventListener('click', () => app.removeObject(i));
        const li = h('li', { dataset: { index: i }, class: i === sel ? 'selected' : '' },
          input,
          h('span', {}, h('span', { class: 'obj-kind', text: info.kind }), ' ', del),
          linkSelect(i, candidates, !!shared.get(o.name)?.length),
          h('span', { class: 'obj-shared', text: sharedText(shared, o.name) }),
          h('span', { class: 'obj-info', text: info.text }));
        return li;
      }),
    );
  }

  function renameObject(i, name) {
    const old = state.scene.objects[i].name;
    if (old === name) return;
    app.edit(
      (s) => {
        s.objects[i].name = name;
        if (s.scale && s.scale.object === old) s.scale.object = name;
      },
      { live: true, undo: true },
    );
    renderScaleObjects();
    renderObjectList(); // in place: the names offered and which objects are shared
  }

  // ---- scale, intrinsics and build settings ---------------------------------------------

  function renderScaleObjects() {
    const sel = $('scale-object-name');
    const names = (state.scene?.objects || []).map((o) => o.name);
    const want = state.scene?.scale?.object ?? sel.value;
    const current = [...sel.options].map((o) => o.value).join('\n');
    if (current !== names.join('\n')) {
      sel.replaceChildren(...names.map((n) => h('option', { value: n, text: n })));
    }
    if (names.includes(want)) sel.value = want;
    renderScaleDims();
  }

  /**
   * The choices of the known dimension: the object's length, breadth (its longer and shorter
   * side as reconstructed) or height, or, for a box, one of its edges between given corners
   * (`scale.edge`, which does not depend on the reconstruction).
   */
  function renderScaleDims() {
    const dim = $('scale-object-dim');
    const o = (state.scene?.objects || []).find((x) => x.name === $('scale-object-name').value);
    const edges = o?.base ? boxEdgeNames(o).map((e) => [e.a, e.b]) : [];
    const sc = state.scene?.scale;
    if (sc?.edge && sc.object === o?.name && !edges.some((e) => edgeChoice(e) === edgeChoice(sc.edge))) edges.push(sc.edge);
    const want = dim.value;
    const key = edges.map(edgeChoice).join('\n');
    if (dim.dataset.edges !== key) {
      dim.dataset.edges = key;
      const fixed = ['length', 'breadth', 'height'].map((v) => h('option', { value: v, text: v }));
      const group = edges.length ? [h('optgroup', { label: 'box edge' }, ...edges.map((e) => h('option', { value: edgeChoice(e), text: `${e[0]} – ${e[1]}` })))] : [];
      dim.replaceChildren(...fixed, ...group);
    }
    if ([...dim.options].some((x) => x.value === want)) dim.value = want;
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
      renderScaleDims();
      $('scale-object-dim').value = sc.edge ? edgeChoice(sc.edge) : sc.dimension || 'length';
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
      const dim = $('scale-object-dim').value;
      const edge = parseEdgeChoice(dim);
      if (edge) scale = m > 0 && name ? { object: name, edge, meters: m } : null;
      else scale = m > 0 && name ? { object: name, dimension: dim, meters: m } : null;
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
    app.edit((s) => {
      if (scale) s.scale = scale;
      else delete s.scale;
    });
  }

  $('scale-object-name').addEventListener('change', renderScaleDims);
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
    app.edit((s) => {
      if (p) s.principal_point = p;
      else delete s.principal_point;
    });
  });

  $('scene-focal').addEventListener('change', (e) => {
    const f = Number(e.target.value);
    app.edit((s) => {
      if (e.target.value.trim() && f > 0) s.focal_px = f;
      else delete s.focal_px;
    });
  });

  $('set-method').addEventListener('change', (e) => {
    // The empty choice is the server's default.
    state.settings.method = e.target.value || null;
    app.scheduleBuild();
  });

  /** Name the server's default method (known from the last build made with it). */
  function renderMethod() {
    const map = state.build?.map;
    if (state.settings.method === null && map?.method) $('set-method-default').textContent = `server's default (${map.method})`;
  }

  $('set-click-sigma').addEventListener('input', (e) => {
    // Empty: the fit estimates the noise. Anything else goes to the server, which checks the
    // range (0 < σ ≤ 100 px) and says what is wrong.
    const text = e.target.value.trim();
    const v = Number(text);
    const next = text === '' || !Number.isFinite(v) ? null : v;
    if (next === state.settings.click_sigma) return;
    state.settings.click_sigma = next;
    app.scheduleBuild();
  });
  for (const [id, key] of [['set-resolution', 'resolution'], ['set-radius', 'robot_radius']]) {
    $(id).addEventListener('input', (e) => {
      const v = Number(e.target.value);
      if (!(v >= 0) || (key === 'resolution' && !(v > 0))) return;
      state.settings[key] = v;
      app.scheduleBuild();
    });
  }

  // ---- the build's results: camera, warnings, plan table, downloads ----------------------

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
    const lens = c?.lens_distortion;
    const lensText = lens ? `${fmt(lens.k, 3)}${Number.isFinite(lens.k_sd) ? ` ± ${fmtSd(lens.k_sd, 3)}` : ''}` : 'none';
    set('cam-lens', c ? lensText : '–', lens?.k);
    // The fit's error bars (1 sigma) after each value, and its report.
    const map = state.build?.map;
    const cu = c?.uncertainty ?? null;
    const sd = (id, v, d, suffix) => {
      const el = $(id);
      const ok = cu && Number.isFinite(v) && !(id === 'cam-height-sd' && v === 0);
      el.textContent = ok ? ` ± ${fmtSd(v, d)}${suffix}` : '';
      if (ok) el.dataset.value = String(v);
      else delete el.dataset.value;
    };
    sd('cam-pitch-sd', cu?.pitch_deg_sd, 2, '°');
    sd('cam-roll-sd', cu?.roll_deg_sd, 2, '°');
    sd('cam-focal-sd', cu?.focal_px_sd, 1, ' px');
    sd('cam-height-sd', cu?.height_sd, 3, ` ${units}`);
    const fit = c ? map?.fit : null;
    $('fit-report').hidden = !fit;
    const source = { given: 'given', residuals: 'estimated from the residuals', default: 'the default' };
    $('fit-click-sigma').textContent = fit ? `${fmt(fit.click_sigma_px, 2)} px (${source[fit.click_sigma_source] || fit.click_sigma_source})` : '–';
    $('fit-rms').textContent = fit ? `${fmt(fit.rms_residual_px, 2)} px` : '–';
    $('fit-dof').textContent = fit ? String(fit.degrees_of_freedom) : '–';
  }

  function renderWarnings(list) {
    const ul = $('warnings');
    const det = (state.detection?.warnings || []).map((w) => `Detection: ${w}`);
    // A warning the placements panel already says (a pinned photo) is said there only.
    ul.replaceChildren(...[...new Set([...det, ...list])].filter((w) => !app.saidByPlacements?.(w)).map((w) => h('li', { text: w })));
  }

  function renderPlanButtons() {
    $('btn-plan').disabled = !(state.plan.start && state.plan.goal && state.scene && state.build);
    app.renderDrive?.();
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
        const name = h('td', {}, h('i', { class: `sw ${{ mbpp: 'sw-mbpp', 'astar-ps': 'sw-astar', optimal: 'sw-opt', smooth: 'sw-smooth' }[r.planner] || ''}` }), ' ', st ? st.label : r.planner);
        const lengthCell = r.found
          ? h('td', { text: `${fmt(r.length_m, 2)} ${units}` })
          : h('td', { class: 'notfound', text: r.skipped ? 'skipped' : 'no path', title: r.note || null });
        return h('tr', { dataset: { planner: r.planner }, title: r.note || null },
          name,
          lengthCell,
          h('td', { text: `${fmt(r.time_ms, r.time_ms < 10 ? 2 : 1)} ms` }),
          h('td', { text: r.planner === 'mbpp' ? `${(r.alternatives || []).length} alternatives` : r.planner === 'smooth' ? smoothDetail(r.smooth, units) : '' }));
      }),
    );
    renderPlanDetails(rows.find((r) => r.planner === 'mbpp'), units);
  }

  /** MBPP's alternatives by length and each bug with its colour on the plan and its fate. */
  function renderPlanDetails(mbpp, units) {
    const alts = (mbpp?.found && mbpp.alternatives) || [];
    $('plan-alternatives').hidden = alts.length === 0;
    $('plan-alternatives').textContent = alts.length ? `MBPP's alternatives (grey, dashed): ${alts.map((a) => `${fmt(a.length_m, 2)} ${units}`).join(', ')}` : '';
    const bugs = (mbpp && mbpp.bugs) || [];
    const fate = {
      'reached-goal': 'reached goal',
      waiting: 'waiting (stopped on a cell another bug had walked straight on)',
      looped: 'looped (walked round an obstacle without meeting its line again)',
      stuck: 'stuck (could not move)',
    };
    $('plan-bugs').hidden = bugs.length === 0;
    $('plan-bugs').replaceChildren(...bugs.map((b, i) => {
      const sw = h('i', { class: 'sw', 'data-colour': BUG_COLOURS[i % BUG_COLOURS.length] });
      sw.style.background = BUG_COLOURS[i % BUG_COLOURS.length];
      const from = Number.isInteger(b.parent) ? `, split from bug ${b.parent + 1}` : '';
      return h('li', {}, sw, `bug ${i + 1}: ${fate[b.fate] || b.fate}, ${b.steps} steps${from}`);
    }));
  }

  function renderDownloads() {
    for (const b of document.querySelectorAll('[data-download]')) b.disabled = !state.build;
  }

  // ---- tabs (narrow screens) --------------------------------------------------------------

  function showPane(name) {
    for (const t of TABS) {
      const on = t === name;
      const tab = $(`tab-${t}`);
      tab.setAttribute('aria-selected', String(on));
      tab.tabIndex = on ? 0 : -1;
      $(`pane-${t}`).classList.toggle('active', on);
    }
  }

  TABS.forEach((t, i) => {
    const tab = $(`tab-${t}`);
    tab.addEventListener('click', () => showPane(t));
    tab.addEventListener('keydown', (e) => {
      const d = e.key === 'ArrowRight' ? 1 : e.key === 'ArrowLeft' ? -1 : 0;
      if (!d) return;
      const next = TABS[(i + d + TABS.length) % TABS.length];
      showPane(next);
      $(`tab-${next}`).focus();
      e.preventDefault();
    });
  });

  Object.assign(app, {
    setStatus,
    refreshBusy,
    showError,
    clearError,
    renderPrompt,
    renderToolButtons,
    renderPanel,
    renderVpList,
    renderObjectList,
    renderScaleObjects,
    syncForms,
    renderCamera,
    renderMethod,
    renderWarnings,
    renderPlanButtons,
    renderPlanResults,
    renderDownloads,
    showPane,
  });
}
