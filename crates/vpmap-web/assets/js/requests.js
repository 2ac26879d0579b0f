// The three requests the page makes while it is used: build (after every edit, debounced),
// plan (after a build or a new start/goal, debounced) and detect (on a click). Each is a
// `latestRequest` (latest.js): a newer request aborts the older one and only the latest
// answer reaches the views.

import * as api from './api.js';
import { $, h, fmt, parsePair, formatPair, base64ToBytes } from './util.js';
import { segmentOwners } from './scene.js';
import { roomBody, roomBlocker, roomProblem, cameraOf } from './room.js';
import { roomScenes } from './state.js';
import { PLANNER_STYLE } from './plan-view.js';
import { latestRequest } from './latest.js';
import { parseHeading, parseTurningRadius, smoothRequest } from './smooth-view.js';

const PLANNERS = ['mbpp', 'astar-ps', 'optimal'];
/** Debounce of build and plan: wait this long after the last change (ms)... */
const DEBOUNCE_MS = 100;
/** ...but no longer than this while changes keep coming (a drag), ms. */
const DEBOUNCE_MAX_MS = 400;

/** The server's API names of the plan pane's options, and the pane's labels for them. */
const OPTION_LABELS = [
  [/\bset unknown_passable or hidden_free\b/g, 'tick “unknown as passable” or “hidden floor as free” under the floor plan'],
  [/\bunknown_passable\b/g, '“unknown as passable”'],
  [/\bhidden_free\b/g, '“hidden floor as free”'],
  [/\brobot_radius\b/g, '“Robot radius”'],
];

/**
 * A planning error as the page words it: the options by the labels the page gives them, and
 * numbers to the centimetre (the server prints them in full).
 */
export function planMessage(text) {
  let out = String(text);
  for (const [re, label] of OPTION_LABELS) out = out.replace(re, label);
  return out.replace(/-?\d+\.\d{3,}/g, (m) => String(Number(Number(m).toFixed(2))));
}

/** Add build, plan and detect to `app` and wire their buttons and inputs. */
export function installRequests(app) {
  const { state, planView, modelView } = app;
  /** What is sent as the scene: the active photo's scene for one photo, else the room file (room.js). */
  const body = () => roomBody(roomScenes(state));
  const blocker = () => roomBlocker(roomScenes(state));

  // ---- build --------------------------------------------------------------------------------

  let buildStarted = 0;
  const build = latestRequest({
    ready: () => !blocker(),
    run(signal) {
      app.setStatus('Building…');
      buildStarted = performance.now();
      return api.build(body(), state.settings, signal);
    },
    busy(on) {
      state.busy.build = on;
      if (!on) app.refreshBusy();
    },
    done(res) {
      applyBuild(res);
      state.counters.builds++;
      app.setStatus(`Built in ${Math.round(performance.now() - buildStarted)} ms.`);
    },
    fail(err) {
      state.buildError = err.message;
      markStale(true);
      // The photo and point the message is about: the point ringed on the photo (its object
      // selected) when that photo is the one shown, the photo's thumbnail badged.
      setProblem(roomProblem(err.message, roomScenes(state)) || { photo: null, message: err.message });
      if (state.marked?.path?.[0] === 'objects') app.select({ type: 'object', index: state.marked.path[1] });
      app.photoView.requestRender();
      app.renderPlacements?.();
      const other = state.problem.photo !== null && state.problem.photo !== state.active;
      app.showError(`Cannot build the map: ${err.message}${state.marked?.p ? ' (ringed in red on the photo)' : other ? ` (photo ${state.problem.photo + 1}: click its thumbnail)` : ''}`);
      app.setStatus('Build failed: see the message at the bottom.');
    },
    wait: DEBOUNCE_MS,
    maxWait: DEBOUNCE_MAX_MS,
  });

  /**
   * What the last build error or the build blocker is about (room.js roomProblem: `{photo,
   * message, ...}`, or null): kept in `state.problem`, its point in `state.marked` when it is on
   * the active photo.
   */
  function setProblem(problem) {
    state.problem = problem;
    const here = problem && problem.photo === state.active && (problem.p || problem.object !== undefined);
    state.marked = here ? problem : null;
    app.renderProblems?.();
  }

  function scheduleBuild() {
    const why = blocker();
    if (why) {
      build.cancel();
      state.busy.build = false;
      markStale(true);
      if (state.problem?.message !== why.message) setProblem(state.scene ? why : null);
      $('status').textContent = state.scene ? `To build: ${why.message}.` : '';
      app.refreshBusy();
      return;
    }
    // A blocker that is gone is no problem any more (a build error stays until the next answer).
    if (state.problem && !state.buildError) setProblem(null);
    // Clicks still snapping to the photo are about to move: build once they have (the last
    // answer schedules it; photo-snap.js).
    const snap = app.photoSnap;
    if (snap?.pending) {
      build.cancel();
      state.busy.build = false;
      snap.buildWaiting = true;
      markStale(true);
      return;
    }
    build.schedule();
  }

  function buildNow() {
    scheduleBuild();
    build.flush();
  }

  function markStale(stale) {
    planView.markStale(stale && !!state.build);
    modelView.markStale(stale && !!state.build);
    document.querySelector('.camera-bar').classList.toggle('stale', stale && !!state.build);
  }

  function clearBuild() {
    // Forget the build and the plan, including any still on their way.
    build.cancel();
    plan.cancel();
    state.busy.build = false;
    state.busy.plan = false;
    app.refreshBusy();
    state.build = null;
    state.camera = null;
    state.buildError = null;
    setProblem(null);
    state.plan.result = null;
    planView.clear();
    clearDrive();
    app.renderCamera();
    app.renderWarnings([]);
    app.renderPlacements?.();
    app.renderDownloads();
    app.renderPlanResults();
  }

  function applyBuild(res) {
    state.build = res;
    state.camera = cameraOf(res, state.active);
    state.buildError = null;
    setProblem(null);
    app.clearError();
    app.renderCamera();
    app.renderMethod();
    try {
      planView.setBuild(res.svg, res.map, res.occupancy, state.active);
      planView.setMarkers(state.plan.start, state.plan.goal);
      planView.setPlan(state.plan.result);
    } catch (err) {
      app.showError(`Floor plan: ${err.message}`);
    }
    markStale(false);
    app.renderWarnings([...(res.warnings || []), ...((res.map && res.map.warnings) || [])]);
    app.renderPlacements?.();
    app.renderDownloads();
    app.renderObjectList();
    if (res.glb_base64) {
      modelView
        .setModel(base64ToBytes(res.glb_base64), { content: (res.map?.objects || []).length + ((res.map?.floor || []).length ? 1 : 0) })
        .then(() => {
          modelView.setCameras(res.map?.cameras || [], state.active);
          update3dPaths();
        })
        .catch((err) => {
          $('model-host').replaceChildren(h('p', { class: 'empty', text: `3D view: ${err.message}` }));
        });
    }
    app.photoView.requestRender();
    if (state.plan.start && state.plan.goal) schedulePlan();
  }

  // ---- path planning ------------------------------------------------------------------------

  const plan = latestRequest({
    ready: () => !!(state.plan.start && state.plan.goal && !blocker()),
    run(signal) {
      const status = $('plan-status');
      status.classList.remove('error');
      status.textContent = 'Planning…';
      return api.plan(
        {
          scene: body(),
          // The method the map was built with (the server's default when none is chosen).
          method: state.settings.method ?? state.build?.map?.method ?? null,
          resolution: state.settings.resolution,
          robot_radius: state.settings.robot_radius,
          click_sigma: state.settings.click_sigma,
          hidden_free: state.settings.hidden_free,
          unknown_passable: state.plan.unknown_passable,
          start: state.plan.start,
          goal: state.plan.goal,
          // With a turning radius the smooth planner too, and its headings when set.
          ...smoothRequest(state.plan, PLANNERS),
        },
        signal,
      );
    },
    busy(on) {
      state.busy.plan = on;
      app.refreshBusy();
    },
    done(res) {
      state.plan.result = res;
      state.plan.error = null;
      state.counters.plans++;
      const found = (res.results || []).filter((r) => r.found).length;
      const notes = (res.results || []).filter((r) => r.note).map((r) => `${PLANNER_STYLE[r.planner]?.label || r.planner}: ${r.note}`);
      $('plan-status').textContent = [found ? '' : 'No path: start and goal are not connected through known free floor.', ...notes].filter(Boolean).join(' ');
    },
    fail(err) {
      const status = $('plan-status');
      state.plan.result = null;
      state.plan.error = err.message;
      status.textContent = planMessage(err.message);
      status.classList.add('error');
    },
    always() {
      planView.setPlan(state.plan.result);
      app.renderPlanResults();
      update3dPaths();
    },
    wait: DEBOUNCE_MS,
    maxWait: DEBOUNCE_MAX_MS,
  });

  function pickPlanPoint(q) {
    // To the millimetre: a click is not more precise, and messages then show short numbers.
    const p = q.map((v) => Math.round(v * 1000) / 1000);
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
    clearDrive();
    planView.setMarkers(state.plan.start, state.plan.goal);
    update3dPaths();
    app.renderPlanButtons();
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

  $('btn-plan').addEventListener('click', () => plan.now());

  // ---- the smooth planner: turning radius and headings -----------------------------------------

  /** Show the heading arrows and fields as the plan state has them. */
  function renderHeadings() {
    const on = Number.isFinite(state.plan.turning_radius);
    planView.setHeadings(on, state.plan.start_heading, state.plan.goal_heading);
    for (const [id, key] of [['plan-start-heading', 'start_heading'], ['plan-goal-heading', 'goal_heading']]) {
      const v = state.plan[key];
      if (document.activeElement !== $(id)) $(id).value = Number.isFinite(v) ? String(v) : '';
    }
  }

  /** Set a heading (`which`: start or goal; degrees, or null: free) and plan again. */
  function setHeading(which, deg) {
    state.plan[`${which}_heading`] = Number.isFinite(deg) ? deg : null;
    renderHeadings();
    schedulePlan();
  }

  function badField(text) {
    $('plan-status').textContent = text;
    $('plan-status').classList.add('error');
  }

  $('plan-turning-radius').addEventListener('change', (e) => {
    const r = parseTurningRadius(e.target.value);
    if (r === undefined) return badField('Write the turning radius as a positive number of metres, or leave it empty for no smooth path.');
    state.plan.turning_radius = r;
    renderHeadings();
    schedulePlan();
  });
  $('plan-reverse').addEventListener('change', (e) => {
    state.plan.reverse = e.target.checked;
    // Only the smooth planner drives in reverse: without a turning radius nothing changes.
    if (Number.isFinite(state.plan.turning_radius)) schedulePlan();
  });
  for (const [id, which] of [['plan-start-heading', 'start'], ['plan-goal-heading', 'goal']]) {
    $(id).addEventListener('change', (e) => {
      const d = parseHeading(e.target.value);
      if (d === undefined) return badField('Write a heading in degrees (0 along x, 90 along y), or leave it empty to keep it free.');
      setHeading(which, d);
    });
  }
  $('btn-free-headings').addEventListener('click', () => {
    state.plan.start_heading = null;
    state.plan.goal_heading = null;
    renderHeadings();
    schedulePlan();
  });

  // Where paths may go: hidden floor as free (the map changes: build again, then plan) and
  // unknown cells as passable (the planners only).
  $('opt-hidden-free').addEventListener('change', (e) => {
    state.settings.hidden_free = e.target.checked;
    app.scheduleBuild();
  });
  $('opt-unknown-passable').addEventListener('change', (e) => {
    state.plan.unknown_passable = e.target.checked;
    schedulePlan();
  });

  $('btn-clear-path').addEventListener('click', () => {
    plan.cancel();
    state.plan = { ...state.plan, start: null, goal: null, result: null, error: null };
    $('plan-start').value = '';
    $('plan-goal').value = '';
    $('pick-start').checked = true;
    planView.setMarkers(null, null);
    planView.setPlan(null);
    app.renderPlanResults();
    update3dPaths();
    app.renderPlanButtons();
  });

  // ---- a drive on the true office (/api/navigate) ----------------------------------------------

  let driveAbort = null;

  /** Forget the last drive (the map, the start or the goal changed), and any on its way. */
  function clearDrive() {
    driveAbort?.abort();
    driveAbort = null;
    state.drive = { result: null, error: null };
    state.busy.drive = false;
    planView.setDrive(null);
    renderDrive();
  }

  function renderDrive() {
    $('drive').hidden = state.truth !== 'example';
    $('btn-drive').disabled = state.busy.drive || !(state.plan.start && state.plan.goal && state.build);
    const out = $('drive-result');
    const r = state.drive.result;
    out.classList.toggle('error', !!state.drive.error);
    if (state.drive.error) out.textContent = planMessage(state.drive.error);
    else if (state.busy.drive) out.textContent = 'Driving…';
    else if (!r) out.textContent = 'Set a start and a goal, then Drive: the track, the true objects (red) and where the robot re-planned appear on the floor plan.';
    else {
      const count = (why) => r.events.filter((e) => e.reason === why).length;
      const replans = `${r.replans} re-plan${r.replans === 1 ? '' : 's'} (${count('blocked')} on a blocked path, ${count('opened')} on an opening)`;
      const timing = `planning ${fmt(r.planning_time_ms, r.planning_time_ms < 10 ? 2 : 1)} ms in all`;
      if (r.reached && r.optimum_any_angle > 0) {
        const excess = (100 * (r.length - r.optimum_any_angle)) / r.optimum_any_angle;
        out.textContent = `Reached the goal after ${fmt(r.length, 2)} m; the true room's shortest path is ${fmt(r.optimum_any_angle, 2)} m (${excess < 0.05 ? 'no detour' : `+${fmt(excess, 1)} %`}). ${replans}, ${timing}.`;
      } else {
        out.textContent = `Stopped: ${r.outcome}, after ${fmt(r.length, 2)} m and ${replans}.`;
      }
    }
  }

  async function drive() {
    driveAbort?.abort();
    const ctl = new AbortController();
    driveAbort = ctl;
    state.drive = { result: null, error: null };
    state.busy.drive = true;
    renderDrive();
    try {
      const res = await api.navigate(
        {
          scene: body(),
          method: state.settings.method ?? state.build?.map?.method ?? null,
          resolution: state.settings.resolution,
          robot_radius: state.settings.robot_radius,
          click_sigma: state.settings.click_sigma,
          hidden_free: state.settings.hidden_free,
          start: state.plan.start,
          goal: state.plan.goal,
          truth: state.truth,
          planner: $('drive-planner').value,
          sensor_range: Number($('drive-range').value) || null,
        },
        ctl.signal,
      );
      if (driveAbort !== ctl) return;
      state.drive.result = res;
      state.counters.drives++;
    } catch (err) {
      if (api.isAbort(err) || driveAbort !== ctl) return;
      state.drive.error = err.message;
    }
    driveAbort = null;
    state.busy.drive = false;
    planView.setDrive(state.drive.result);
    renderDrive();
  }

  $('btn-drive').addEventListener('click', drive);
  app.renderDrive = renderDrive;

  function schedulePlan() {
    if (state.plan.start && state.plan.goal && state.build) plan.schedule();
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

  // ---- detection ----------------------------------------------------------------------------

  let detectStarted = 0;
  const detect = latestRequest({
    run(signal, options) {
      app.setStatus(state.photos.length > 1 ? `Photo ${state.active + 1}: detecting edges and vanishing points…` : 'Detecting edges and vanishing points…');
      detectStarted = performance.now();
      return api.detect(state.photoBlob, options, signal);
    },
    busy(on) {
      state.busy.detect = on;
      if (!on) app.refreshBusy();
    },
    done(res) {
      const d = res.scene || {};
      app.edit((s) => {
        if (d.image) s.image = d.image;
        s.vanishing_points = d.vanishing_points || [];
        while (s.vanishing_points.length < 2) s.vanishing_points.push({ lines: [] });
        for (const k of ['principal_point', 'principal_point_sd_px', 'focal_px', 'focal_sd_px', 'lens_distortion', 'perspective']) {
          if (d[k] !== undefined && d[k] !== null) s[k] = d[k];
          else delete s[k];
        }
      });
      state.savedVpPoints = [null, null, null];
      state.detection = { segments: res.segments || [], segmentVp: segmentOwners(res, state.scene), warnings: res.warnings || [] };
      app.renderWarnings(state.build ? state.build.warnings || [] : []);
      state.counters.detects++;
      const n = state.scene.vanishing_points.length;
      const f = res.focal_px ?? d.focal_px;
      const lens = d.lens_distortion ? `, lens k ${fmt(d.lens_distortion.k, 3)}${Number.isFinite(d.lens_distortion.k_sd) ? ` ± ${fmt(d.lens_distortion.k_sd, 3)}` : ''}` : '';
      app.setStatus(`Detected ${n} vanishing points (${res.perspective || d.perspective || `${n}pp`}), ${(res.segments || []).length} segments, focal ${fmt(f, 0)} px${lens}, in ${Math.round(performance.now() - detectStarted)} ms.`);
      app.syncForms();
      app.renderPanel();
    },
    fail(err) {
      app.showError(`Detection failed: ${err.message}`);
      app.setStatus('');
    },
  });

  $('btn-detect').addEventListener('click', () => {
    if (!state.photoBlob) return;
    app.clearError();
    const focal = Number($('det-focal').value);
    const ppText = $('det-pp').value.trim();
    const pp = ppText ? parsePair(ppText) : null;
    if (ppText && !pp) {
      app.showError('Principal point for detection: write it as “x, y” in pixels, or leave it empty.');
      return;
    }
    detect.now({ focal_px: focal > 0 ? focal : undefined, principal_point: pp });
  });

  $('show-segments').addEventListener('change', (e) => {
    state.showSegments = e.target.checked;
    if (!state.showSegments && state.selection?.type === 'vpline') app.select(null);
    app.photoView.requestRender();
  });
  $('btn-fit').addEventListener('click', () => app.photoView.fit());

  /** Another photo became the active one: its camera of the last build, its point of the problem, its camera highlighted. */
  function cameraChanged() {
    state.camera = cameraOf(state.build, state.active);
    setProblem(state.problem);
    planView.setActiveCamera(state.active);
    modelView.setCameras(state.build?.map?.cameras || [], state.active);
  }

  Object.assign(app, {
    cameraChanged,
    scheduleBuild,
    buildNow,
    clearBuild,
    setProblem,
    /** Forget a detection on its way (another photo became the active one). */
    cancelDetect: () => detect.cancel(),
    pickPlanPoint,
    setHeading,
    /** A build or plan is scheduled and not started yet. */
    requestsPending: () => build.pending || plan.pending || !!app.photoSnap?.buildWaiting,
  });
}
