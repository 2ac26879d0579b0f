// A room's placements the clicks leave open: the map's `alternatives` (docs/map-format.md: a
// photo that fits about as well turned otherwise and that no physical check rules out) and the
// photos pinned to one by their scene's `placement_turn_deg` (docs/scene-format.md, "A room of
// several photos"). The panel under the warnings lists each with one button: **Swap** writes
// the alternative's `placement_turn_deg` into that photo's scene (one undoable edit of that
// photo), so the next build places the photo so turned and the map, the plan and everything
// drawn follow it; **Unpin** removes the field and lets the fit choose again. With several
// alternatives each has a check box, and **Swap checked together** pins every checked photo in
// one rebuild (an undoable edit of each). A pinned photo is said once: its row, not also the
// map's warning that it is pinned (`saidByPlacements`). So is a tie: an alternative's row
// carries the advice of the map's tie warning for that photo ("photo N is tied to the room
// only by ...; to be sure, name one more object ..."), and the warnings list leaves that
// warning out (issue 39). A tie warning with no alternative (the physical checks decided it)
// stays in the list.
//
// placementRows, pinnedWarningPhoto, tieWarning and the scene edits are pure (no DOM), so the unit tests
// (e2e/unit/placement.test.mjs) run them in Node.

import { $, h, fmt } from './util.js';

/**
 * What the panel lists for a build answer's `map` and the room's `scenes` (0-based photos):
 * `[{kind: 'alternative', photo, turn_deg, placement_turn_deg, cost_px2, chosen_cost_px2, text, warning}]`
 * for each alternative (none while `stale`, i.e. the last build failed; `warning` the map's tie
 * warning for that photo whose advice `text` repeats, or null when there is none), then
 * `[{kind: 'pinned', photo, placement_turn_deg, text}]` for each pinned photo (photo 2..n).
 * A room of one photo has none.
 */
export function placementRows(map, scenes, { stale = false } = {}) {
  if (!Array.isArray(scenes) || scenes.length < 2) return [];
  const rows = [];
  const alternatives = !stale && Array.isArray(map?.alternatives) ? map.alternatives : [];
  const warnings = Array.isArray(map?.warnings) ? map.warnings : [];
  for (const a of alternatives) {
    const photo = Number(a.photo) - 1;
    if (!(photo >= 1 && photo < scenes.length) || ![0, 90, 180, 270].includes(a.placement_turn_deg)) continue;
    // A photo already pinned to this very placement is listed as pinned, below.
    if (scenes[photo]?.placement_turn_deg === a.placement_turn_deg) continue;
    const tie = warnings.map(tieWarning).find((t) => t && t.photo === photo) ?? null;
    const advice = tie ? ` Photo ${photo + 1} is tied to the room only by ${tie.by}: ${tie.advice}.` : '';
    rows.push({
      kind: 'alternative',
      photo,
      turn_deg: a.turn_deg,
      placement_turn_deg: a.placement_turn_deg,
      cost_px2: a.cost_px2,
      chosen_cost_px2: a.chosen_cost_px2,
      text: `Photo ${photo + 1} fits about as well turned by ${a.turn_deg}° (cost ${costText(a.cost_px2)} against the map's ${costText(a.chosen_cost_px2)} px²): the clicks and the room's walls cannot tell which is right.${advice}`,
      warning: tie ? tie.warning : null,
    });
  }
  scenes.forEach((scene, photo) => {
    const v = scene?.placement_turn_deg;
    if (photo === 0 || v === undefined || v === null) return;
    rows.push({
      kind: 'pinned',
      photo,
      placement_turn_deg: v,
      text: `Photo ${photo + 1}'s placement is pinned (placement_turn_deg ${v}°): the fit tries no other turn of it.`,
    });
  });
  return rows;
}

/** A cost for the panel: three decimals below 1000 px², else whole. */
function costText(v) {
  if (!Number.isFinite(v)) return '?';
  return Math.abs(v) < 1000 ? fmt(v, 3) : String(Math.round(v));
}

/** Pin `scene` to the alternative's placement (its `placement_turn_deg`). */
export function pinPlacement(scene, placementTurnDeg) {
  scene.placement_turn_deg = placementTurnDeg;
}

/**
 * The photo (0-based) whose pin a map warning reports ("photo N's placement is pinned by its
 * `placement_turn_deg` ...", vpmap-metrology's room fit), or null for any other warning.
 */
export function pinnedWarningPhoto(warning) {
  const m = /^photo (\d+)'s placement is pinned by its `placement_turn_deg`/.exec(String(warning));
  return m ? Number(m[1]) - 1 : null;
}

/**
 * A map warning that a photo is tied to the room by few objects (vpmap-metrology's room fit,
 * room/choose.rs: "photo N is tied to the room only by "a", which fits about as well with
 * photo N turned by T degrees (...): ...; to be sure, name one more object seen in photo N
 * and another photo"), read as `{ photo (0-based), by, advice, warning }`, or null for any
 * other warning (or one worded otherwise: then the list keeps saying it).
 */
export function tieWarning(warning) {
  const w = String(warning);
  const m = /^photo (\d+) is tied to the room only by (.+?), which fits? about as well with photo \1 turned by .*; (to be sure, name one more object .+)$/.exec(w);
  return m ? { photo: Number(m[1]) - 1, by: m[2], advice: m[3], warning: w } : null;
}

/** Let the fit choose the photo's placement again. */
export function unpinPlacement(scene) {
  delete scene.placement_turn_deg;
}

/**
 * Add `renderPlacements` to `app` (the panel `#placements`, redrawn after every build) and
 * `saidByPlacements(warning)` (whether the panel already says a warning).
 */
export function installPlacements(app) {
  const { state } = app;

  /** The slots holding a scene, in the order the room file lists them (room.js roomBody). */
  const sceneSlots = () => state.photos.filter((s) => s.scene);

  /** Change photo `photo`'s scene (0-based in the room file) in one undoable edit of that photo. */
  function editPhoto(photo, fn) {
    const slot = sceneSlots()[photo];
    if (!slot) return;
    if (slot === state.photos[state.active]) {
      app.edit(fn);
    } else {
      slot.history?.record(slot.scene);
      fn(slot.scene);
      app.scheduleBuild();
      app.sceneChanged();
    }
    renderPlacements();
  }

  /** Pin every photo of `picks` (alternative rows) at once: an undoable edit of each photo, one rebuild. */
  function swapTogether(picks) {
    if (picks.length === 0) return;
    // Each edit schedules the build; the schedule's debounce makes it one build of them all.
    for (const r of picks) editPhoto(r.photo, (s) => pinPlacement(s, r.placement_turn_deg));
    app.setStatus(`Photos ${picks.map((r) => r.photo + 1).join(', ')} placed as their alternatives turn them: rebuilding…`);
  }

  /** The rows for the current build and scenes. */
  const currentRows = () => placementRows(state.build?.map, sceneSlots().map((s) => s.scene), { stale: !!state.buildError });

  /**
   * Whether `warning` says what a row of the panel says: a pinned photo, and a tie whose
   * alternative's row carries its advice, are said once (in the row).
   */
  function saidByPlacements(warning) {
    const rows = currentRows();
    if (rows.some((r) => r.kind === 'alternative' && r.warning === warning)) return true;
    const photo = pinnedWarningPhoto(warning);
    return photo !== null && rows.some((r) => r.kind === 'pinned' && r.photo === photo);
  }

  function renderPlacements() {
    const host = $('placements');
    if (!host) return;
    const rows = currentRows();
    const alternatives = rows.filter((r) => r.kind === 'alternative');
    const together = alternatives.length >= 2;
    host.hidden = rows.length === 0;
    const all = together
      ? h('button', { type: 'button', class: 'swap-together', text: 'Swap checked together', disabled: true, title: 'Place every checked photo as its alternative turns it, in one rebuild (each photo\'s Undo takes its own back)' })
      : null;
    const picks = [];
    const items = rows.map((r) => {
      const button = r.kind === 'alternative'
        ? h('button', { type: 'button', class: 'swap', text: 'Swap', title: `Place photo ${r.photo + 1} turned by ${r.turn_deg}° and rebuild (photo ${r.photo + 1}'s Undo takes it back)` })
        : h('button', { type: 'button', class: 'unpin', text: 'Unpin', title: `Let the fit choose photo ${r.photo + 1}'s placement again` });
      button.dataset.photo = String(r.photo);
      button.addEventListener('click', () => {
        if (r.kind === 'alternative') {
          editPhoto(r.photo, (s) => pinPlacement(s, r.placement_turn_deg));
          app.setStatus(`Photo ${r.photo + 1} placed turned by ${r.turn_deg}°: rebuilding…`);
        } else {
          editPhoto(r.photo, unpinPlacement);
          app.setStatus(`Photo ${r.photo + 1}'s placement is the fit's choice again: rebuilding…`);
        }
      });
      let pick = null;
      if (all && r.kind === 'alternative') {
        pick = h('input', { type: 'checkbox', class: 'swap-pick', title: `Swap photo ${r.photo + 1} together with the other checked photos`, 'aria-label': `Swap photo ${r.photo + 1} together with the other checked photos`, dataset: { photo: String(r.photo) } });
        pick.addEventListener('change', () => {
          all.disabled = !picks.some(([box]) => box.checked);
        });
        picks.push([pick, r]);
      }
      return h('li', { class: r.kind, dataset: { photo: String(r.photo), kind: r.kind } }, pick, pick ? ' ' : null, h('span', { text: r.text }), ' ', button);
    });
    if (all) {
      all.addEventListener('click', () => swapTogether(picks.filter(([box]) => box.checked).map(([, r]) => r)));
      items.push(h('li', { class: 'together' }, h('span', { text: `${alternatives.length} photos are tied: check the ones to swap at once (one at a time, each swap re-fits the room and may change what the others' alternatives are).` }), ' ', all));
    }
    host.replaceChildren(...items);
  }

  Object.assign(app, { renderPlacements, saidByPlacements });
}
