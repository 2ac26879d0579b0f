// The floor plan: the SVG that /api/build returns, shown inline, with the planned paths drawn
// over it and clicks turned into map coordinates.
//
// Picture <-> map coordinates. The server writes the transform from map coordinates (map.json's
// frame: x right, y up) to the SVG's user units on the root element, as
// `data-svg-from-map="a b c d e f"` in SVG `matrix(a b c d e f)` order (x' = a x + c y + e,
// y' = b x + d y + f); the page reads it and never re-derives it from the drawing. A plan without
// it is refused with an error in the plan pane. A click is taken from screen to SVG user units
// with the SVG's getScreenCTM(), then to map coordinates with the inverse transform. The overlay
// is drawn in the same user units, inside the SVG, so it scales and exports with the plan.

import { SVG_NS, svgEl, base64ToBytes, fmt } from './util.js';
import { parseAffine, applyAffine, invertAffine, occupancyToSvg } from './geometry.js';
import { drawCameras } from './plan-cameras.js';
import { SMOOTH_COLOUR, drawSmooth, drawHeadingArrows, headingTowards, pathHeadings } from './smooth-view.js';

const ID_PREFIX = 'fp-';
/** Bug track colours: none near a planner's (purple, orange, teal) or the alternatives' grey. */
export const BUG_COLOURS = ['#1f5fd6', '#d62728', '#e377c2', '#8c564b', '#bcbd22', '#00b7eb', '#222222', '#ff9896'];
/** The drive on the true office: its track, the true objects, the re-planning points. */
export const DRIVE_COLOUR = '#111111';
export const DRIVE_TRUTH_COLOUR = '#d50000';
export const DRIVE_REPLAN_COLOUR = '#ff6f00';
export const PLANNER_STYLE = {
  mbpp: { label: 'MBPP', colour: '#6a3d9a', width: 3.2, dash: null },
  'astar-ps': { label: 'A* PS', colour: '#ef7d00', width: 2.4, dash: null },
  optimal: { label: 'optimal', colour: '#138a72', width: 2, dash: '7 5' },
  smooth: { label: 'smooth', colour: SMOOTH_COLOUR, width: 3, dash: null },
};

/** Two presses on a heading arrow this close (ms) free its heading. */
const DOUBLE_PRESS_MS = 450;

const finite = (p) => Array.isArray(p) && Number.isFinite(p[0]) && Number.isFinite(p[1]);

/** Object names on the plan are never drawn smaller than this on screen (px); the size lines in proportion. */
const LABEL_NAME_PX = 11.5;
/** Axis tick labels are never drawn smaller than this on screen (px). */
const TICK_PX = 10;

/**
 * The server's object labels (svg.rs `<g id="labels">`: per label an optional leader line and dot,
 * a rect, the name in bold, then size lines), each wrapped in its own group so the page can draw
 * it at screen size: `[{box, leader, rect, namePx}]` with `rect` in SVG user units.
 */
function groupLabels(svg) {
  const host = svg.querySelector(`[id="${ID_PREFIX}labels"]`);
  if (!host) return [];
  const labels = [];
  let cur = null;
  const start = (before) => {
    const g = svgEl('g', { class: 'plan-label' });
    const box = svgEl('g', { class: 'plan-label-box' });
    g.append(box);
    host.insertBefore(g, before);
    cur = { g, box, leader: null, rect: null, namePx: 0 };
    labels.push(cur);
  };
  for (const el of [...host.children]) {
    if (el.classList?.contains('plan-label')) continue;
    const kind = el.localName;
    if (kind === 'line' || (kind === 'rect' && (!cur || cur.rect)) || !cur) start(el);
    if (kind === 'line' || kind === 'circle') {
      cur.g.insertBefore(el, cur.box);
      if (kind === 'line') {
        cur.leader = el;
        cur.leaderEnd = [el.getAttribute('x2'), el.getAttribute('y2')];
      }
    } else {
      cur.box.append(el);
      if (kind === 'rect') {
        cur.rect = ['x', 'y', 'width', 'height'].map((a) => Number(el.getAttribute(a)));
        cur.rectEl = el;
      } else if (kind === 'text' && !cur.namePx) {
        cur.namePx = Number(el.getAttribute('font-size')) || 0;
        cur.nameEl = el;
      } else if (kind === 'text') {
        cur.sizeEls = [...(cur.sizeEls || []), el];
      }
    }
  }
  return labels.filter((l) => l.rect && l.rect.every(Number.isFinite) && l.namePx > 0);
}

/** Do rects `[x, y, w, h]` overlap (with a gap of `gap`)? */
const overlaps = (a, b, gap) => a[0] < b[0] + b[2] + gap && b[0] < a[0] + a[2] + gap && a[1] < b[1] + b[3] + gap && b[1] < a[1] + a[3] + gap;

/** The attribute of a floor-plan SVG's root element that holds its map-to-picture transform. */
export const SVG_FROM_MAP_ATTR = 'data-svg-from-map';

/** The map-to-picture transform of a parsed floor-plan SVG document; throws when it is missing or bad. */
export function svgFromMap(doc) {
  const root = doc.documentElement;
  if (!root.hasAttribute(SVG_FROM_MAP_ATTR)) {
    throw new Error(`the floor plan has no ${SVG_FROM_MAP_ATTR} attribute, so the page cannot relate it to map coordinates (is the server older than the page?)`);
  }
  const text = root.getAttribute(SVG_FROM_MAP_ATTR);
  const tf = parseAffine(text);
  if (!tf) throw new Error(`the floor plan's ${SVG_FROM_MAP_ATTR}="${text}" is not an invertible transform "a b c d e f"`);
  return tf;
}

/** The plot rectangle with room for the axis labels (svg.rs: labels left of and below it), or `full`. */
function plotBox(svg, full) {
  const rect = svg.querySelector(`[id="${ID_PREFIX}plot-clip"] rect`);
  if (!rect) return full;
  const x = Number(rect.getAttribute('x')), y = Number(rect.getAttribute('y'));
  const w = Number(rect.getAttribute('width')), h = Number(rect.getAttribute('height'));
  if (![x, y, w, h].every(Number.isFinite) || !(w > 0 && h > 0)) return full;
  const f = full.w / 1000;
  const left = Math.min(x - full.x, 58 * f), bottom = 40 * f, pad = 6 * f;
  return { x: x - left, y: y - pad, w: w + left + pad, h: h + pad + bottom };
}

/** Give every id in the SVG a prefix (and follow the references), so it cannot clash with the page's ids. */
function prefixIds(root) {
  for (const el of root.querySelectorAll('[id]')) el.id = ID_PREFIX + el.id;
  const attrs = ['clip-path', 'fill', 'stroke', 'mask', 'filter', 'marker-start', 'marker-mid', 'marker-end'];
  for (const el of root.querySelectorAll('*')) {
    for (const a of attrs) {
      const v = el.getAttribute(a);
      if (v && v.includes('url(#')) el.setAttribute(a, v.replace(/url\(#/g, `url(#${ID_PREFIX}`));
    }
    for (const a of ['href', 'xlink:href']) {
      const v = el.getAttribute(a);
      if (v && v.startsWith('#')) el.setAttribute(a, `#${ID_PREFIX}${v.slice(1)}`);
    }
  }
}

/** A PGM (P5, 8-bit) occupancy image as a data: URL: occupied dark, unknown grey, free clear. */
function pgmToDataUrl(bytes) {
  let pos = 0;
  const token = () => {
    for (;;) {
      while (pos < bytes.length && /\s/.test(String.fromCharCode(bytes[pos]))) pos++;
      if (bytes[pos] === 35) {
        while (pos < bytes.length && bytes[pos] !== 10) pos++;
      } else break;
    }
    let s = '';
    while (pos < bytes.length && !/\s/.test(String.fromCharCode(bytes[pos]))) s += String.fromCharCode(bytes[pos++]);
    return s;
  };
  if (token() !== 'P5') return null;
  const w = Number(token()), hgt = Number(token()), max = Number(token());
  pos++;
  if (!(w > 0 && hgt > 0 && max > 0 && max < 256) || bytes.length < pos + w * hgt) return null;
  const canvas = document.createElement('canvas');
  canvas.width = w;
  canvas.height = hgt;
  const ctx = canvas.getContext('2d');
  const img = ctx.createImageData(w, hgt);
  for (let i = 0; i < w * hgt; i++) {
    const v = bytes[pos + i];
    const o = i * 4;
    if (v <= 50) { img.data[o] = 30; img.data[o + 1] = 30; img.data[o + 2] = 40; img.data[o + 3] = 150; }
    else if (v < 250) { img.data[o] = 120; img.data[o + 1] = 120; img.data[o + 2] = 120; img.data[o + 3] = 70; }
  }
  ctx.putImageData(img, 0, 0);
  return canvas.toDataURL('image/png');
}

export class PlanView {
  /**
   * @param {HTMLElement} host
   * @param {{onPick: (p: number[]) => void, onCamera: (i: number) => void, onHeading: (which: string, deg: number|null) => void}} handlers
   *   `onPick` gets a click's map point, `onCamera` the photo whose camera (of a room) was
   *   clicked, `onHeading` a start or goal heading dragged (degrees) or freed (null).
   */
  constructor(host, { onPick, onCamera, onHeading }) {
    this.host = host;
    this.onPick = onPick;
    this.onHeading = onHeading;
    /** Heading arrows (the smooth planner on): the set headings, degrees, null when free. */
    this.headings = { on: false, start: null, goal: null };
    this.onCamera = onCamera;
    this.activeCamera = 0;
    this.svg = null;
    this.tf = null;
    this.map = null;
    this.occupancy = null;
    this.occupancyUrl = null;
    this.plan = null;
    this.drive = null;
    this.start = null;
    this.goal = null;
    this.layers = { bugs: true, alternatives: true, mbpp: true, 'astar-ps': true, optimal: true, smooth: true, occupancy: false };
    this.coords = document.createElement('div');
    this.coords.className = 'plan-coords';
    // Overlay sizes are in screen pixels: redraw when the plan's size changes.
    let lastW = 0;
    new ResizeObserver(() => {
      const w = this.host.clientWidth;
      if (this.svg && w !== lastW) this.draw();
      lastW = w;
    }).observe(host);
  }

  /**
   * Show a new plan picture for `map` (the map.json object); `occupancy` from the build;
   * `active` the photo shown (its camera highlighted when the map has the room's `cameras`).
   */
  setBuild(svgText, map, occupancy, active = 0) {
    this.activeCamera = active;
    const doc = new DOMParser().parseFromString(svgText, 'image/svg+xml');
    let tf;
    try {
      if (doc.querySelector('parsererror') || doc.documentElement.localName !== 'svg') {
        throw new Error('the server sent a floor plan that is not valid SVG');
      }
      tf = svgFromMap(doc);
    } catch (err) {
      this.showError(`Floor plan: ${err.message}`);
      throw err;
    }
    prefixIds(doc.documentElement);
    const svg = document.importNode(doc.documentElement, true);
    const vb = svg.viewBox.baseVal;
    if (!vb || !vb.width) {
      svg.setAttribute('viewBox', `0 0 ${svg.getAttribute('width')} ${svg.getAttribute('height')}`);
    }
    svg.removeAttribute('width');
    svg.removeAttribute('height');
    svg.setAttribute('aria-label', 'Floor plan. Click to set the start or the goal of a path.');
    svg.setAttribute('id', 'plan-svg');
    const overlay = svgEl('g', { id: `${ID_PREFIX}overlay`, class: 'vp-overlay' });
    if (svg.querySelector(`[id="${ID_PREFIX}plot-clip"]`)) overlay.setAttribute('clip-path', `url(#${ID_PREFIX}plot-clip)`);
    svg.append(overlay);
    this.host.replaceChildren(svg, this.coords);
    // Keep the user's zoom across rebuilds: remember it in map units.
    const prevMapBox = this.svg && this.box && !this.atHome ? this.boxToMap(this.box) : null;
    this.svg = svg;
    this.overlay = overlay;
    this.tf = tf;
    this.tfInverse = invertAffine(tf);
    this.map = map;
    const full = svg.viewBox.baseVal;
    this.fullBox = { x: full.x, y: full.y, w: full.width, h: full.height };
    this.homeBox = plotBox(svg, this.fullBox);
    if (prevMapBox) this.setBox(this.mapToBox(prevMapBox), false);
    else this.setBox(this.homeBox, true);
    this.listen(svg);
    this.labels = groupLabels(svg);
    this.axes = svg.querySelector(`[id="${ID_PREFIX}axes"]`);
    this.axesPx = Number(this.axes?.getAttribute('font-size')) || 0;
    if (occupancy !== this.occupancy) {
      this.occupancy = occupancy;
      this.occupancyUrl = null;
    }
    this.draw();
  }

  /** Pointer and keyboard input on the plan: click picks a point, drag pans, wheel zooms. */
  listen(svg) {
    svg.setAttribute('tabindex', '0');
    let press = null;
    let lastHandle = null;
    svg.addEventListener('pointerdown', (e) => {
      if (e.button !== 0 && e.button !== 1) return;
      const heading = e.button === 0 ? e.target.closest?.('.vp-heading-handle')?.getAttribute('data-heading') : null;
      // A second press on the same arrow within DOUBLE_PRESS_MS frees its heading (the pointer
      // capture makes the svg, not the arrow, the target of a dblclick).
      const last = lastHandle;
      lastHandle = heading ? { heading, t: e.timeStamp } : null;
      if (heading && last?.heading === heading && e.timeStamp - last.t < DOUBLE_PRESS_MS) {
        lastHandle = null;
        e.preventDefault();
        this.headings[heading] = null;
        this.onHeading?.(heading, null);
        return;
      }
      press = { id: e.pointerId, x: e.clientX, y: e.clientY, box: { ...this.box }, panning: e.button === 1, heading, turned: false };
      svg.setPointerCapture(e.pointerId);
      e.preventDefault();
    });
    svg.addEventListener('pointermove', (e) => {
      const m = this.clientToMap(e.clientX, e.clientY);
      const u = this.map?.units === 'm' ? 'm' : 'ch';
      this.coords.textContent = m ? `x ${fmt(m[0])} ${u}, y ${fmt(m[1])} ${u}` : '';
      if (!press || press.id !== e.pointerId) return;
      if (press.heading) {
        const from = this[press.heading];
        const deg = m && from ? headingTowards(from, m) : null;
        if (deg !== null) {
          this.headings[press.heading] = Math.round(deg);
          press.turned = true;
          this.draw();
        }
        return;
      }
      if (!press.panning && Math.hypot(e.clientX - press.x, e.clientY - press.y) > 4) press.panning = true;
      if (press.panning) {
        const k = this.unitsPerPx(press.box);
        this.setBox({ ...press.box, x: press.box.x - (e.clientX - press.x) * k, y: press.box.y - (e.clientY - press.y) * k }, false);
        svg.classList.add('panning');
      }
    });
    const end = (e, cancelled) => {
      if (!press || press.id !== e.pointerId) return;
      const wasPan = press.panning;
      const { heading, turned } = press;
      press = null;
      if (heading) {
        if (turned && !cancelled) this.onHeading?.(heading, this.headings[heading]);
        return;
      }
      svg.classList.remove('panning');
      if (wasPan) this.draw();
      else if (!cancelled && e.button === 0) {
        const m = this.clientToMap(e.clientX, e.clientY);
        if (m) this.onPick(m);
      }
    };
    svg.addEventListener('pointerup', (e) => end(e, false));
    svg.addEventListener('pointercancel', (e) => end(e, true));
    svg.addEventListener('pointerleave', () => {
      if (!press) this.coords.textContent = '';
    });
    svg.addEventListener('wheel', (e) => {
      e.preventDefault();
      const dy = e.deltaMode === 1 ? e.deltaY * 33 : e.deltaY;
      this.zoomAt(Math.exp(dy * 0.0015), e.clientX, e.clientY);
    }, { passive: false });
    svg.addEventListener('keydown', (e) => {
      const r = svg.getBoundingClientRect();
      const cx = r.left + r.width / 2, cy = r.top + r.height / 2;
      const k = this.unitsPerPx(this.box) * 40;
      const pan = { ArrowLeft: [-k, 0], ArrowRight: [k, 0], ArrowUp: [0, -k], ArrowDown: [0, k] }[e.key];
      if (e.key === '+' || e.key === '=') this.zoomAt(0.8, cx, cy);
      else if (e.key === '-' || e.key === '_') this.zoomAt(1.25, cx, cy);
      else if (e.key === '0') this.fit();
      else if (pan) this.setBox({ ...this.box, x: this.box.x + pan[0], y: this.box.y + pan[1] }, false, true);
      else return;
      e.preventDefault();
    });
  }

  /** SVG user units per screen pixel for a view box (the larger of the two axes: "meet"). */
  unitsPerPx(box) {
    const r = this.svg.getBoundingClientRect();
    if (r.width < 2 || r.height < 2) return box.w / 600; // hidden (a narrow screen's other tab)
    return Math.max(box.w / Math.max(1, r.width), box.h / Math.max(1, r.height));
  }

  setBox(box, atHome, redraw = true) {
    this.box = box;
    this.atHome = atHome;
    this.svg.setAttribute('viewBox', `${box.x} ${box.y} ${box.w} ${box.h}`);
    if (redraw && this.overlay) this.draw();
  }

  /** Zoom by `factor` (< 1 zooms in) about a client point. */
  zoomAt(factor, cx, cy) {
    const ctm = this.svg.getScreenCTM();
    if (!ctm) return;
    const p = new DOMPoint(cx, cy).matrixTransform(ctm.inverse());
    const b = this.box;
    const w = Math.min(this.fullBox.w * 4, Math.max(this.fullBox.w / 50, b.w * factor));
    const f = w / b.w;
    this.setBox({ x: p.x - (p.x - b.x) * f, y: p.y - (p.y - b.y) * f, w: b.w * f, h: b.h * f }, false);
  }

  /** Show the plot (the map area with its axes). */
  fit() {
    if (this.svg) this.setBox(this.homeBox, true);
  }

  /** Show the whole picture, with title and legend. */
  showAll() {
    if (this.svg) this.setBox(this.fullBox, false);
  }

  boxToMap(b) {
    return [this.svgToMap([b.x, b.y]), this.svgToMap([b.x + b.w, b.y + b.h])];
  }

  mapToBox([p, q]) {
    const a = this.mapToSvg(p), c = this.mapToSvg(q);
    return { x: a[0], y: a[1], w: c[0] - a[0], h: c[1] - a[1] };
  }

  clear() {
    this.svg = null;
    this.tf = null;
    this.overlay = null;
    this.host.replaceChildren(Object.assign(document.createElement('p'), { className: 'empty', textContent: 'The floor plan appears here once the scene builds.' }));
  }

  /** Show `message` in place of the plan (a plan that cannot be used). */
  showError(message) {
    this.svg = null;
    this.tf = null;
    this.overlay = null;
    this.host.replaceChildren(Object.assign(document.createElement('p'), { className: 'empty error', role: 'alert', textContent: message }));
  }

  markStale(stale) {
    this.host.classList.toggle('stale', stale);
  }

  mapToSvg(p) {
    return applyAffine(this.tf, p);
  }

  svgToMap(q) {
    return applyAffine(this.tfInverse, q);
  }

  clientToMap(cx, cy) {
    if (!this.svg || !this.tf) return null;
    const ctm = this.svg.getScreenCTM();
    if (!ctm) return null;
    const q = new DOMPoint(cx, cy).matrixTransform(ctm.inverse());
    return this.svgToMap([q.x, q.y]);
  }

  /** Viewport coordinates of a map point (used by the end-to-end test to click). */
  mapToClient(p) {
    if (!this.svg || !this.tf) return null;
    const q = this.mapToSvg(p);
    const r = new DOMPoint(q[0], q[1]).matrixTransform(this.svg.getScreenCTM());
    return [r.x, r.y];
  }

  /** Highlight the camera of photo `i` (a room's). */
  setActiveCamera(i) {
    this.activeCamera = i;
    this.draw();
  }

  setMarkers(start, goal) {
    this.start = start;
    this.goal = goal;
    this.draw();
  }

  /** The heading arrows: shown when `on` (the smooth planner asked for), the set headings in degrees (null: free). */
  setHeadings(on, start, goal) {
    this.headings = { on, start, goal };
    this.draw();
  }

  setPlan(plan) {
    this.plan = plan;
    this.draw();
  }

  /** Show a drive on the true map (an /api/navigate answer), or none. */
  setDrive(drive) {
    this.drive = drive;
    this.draw();
  }

  setLayer(name, on) {
    this.layers[name] = on;
    this.draw();
  }

  /** User units for `px` screen pixels at the current zoom (so the overlay keeps its size). */
  u(px) {
    return px * (this.svg && this.box ? this.unitsPerPx(this.box) : 1);
  }

  points(list) {
    return list.filter(finite).map((p) => this.mapToSvg(p).map((v) => v.toFixed(2)).join(',')).join(' ');
  }

  polyline(parent, pts, attrs) {
    if (!pts || pts.length < 2) return null;
    const el = svgEl('polyline', { points: this.points(pts), fill: 'none', 'stroke-linejoin': 'round', 'stroke-linecap': 'round', ...attrs });
    parent.append(el);
    return el;
  }

  /**
   * Object labels and axis ticks at a readable screen size: at the page's default zoom the
   * 1000-unit picture is shown at about a third of its size, so each label is scaled about its
   * centre until its name is LABEL_NAME_PX on screen, keeping only the name (the sizes are in
   * the object list and the object's tooltip; enlarged, they would cover the plan), then moved
   * down off the labels above it (top to bottom), its leader line following. Zoomed in far
   * enough, the picture's own labels come back whole.
   */
  fitLabels() {
    const k = this.unitsPerPx(this.box);
    if (this.axes && this.axesPx > 0) this.axes.setAttribute('font-size', Math.max(this.axesPx, TICK_PX * k).toFixed(2));
    const placed = [];
    const order = [...(this.labels || [])].sort((a, b) => a.rect[1] - b.rect[1]);
    for (const l of order) {
      const m = Math.max(1, (LABEL_NAME_PX * k) / l.namePx);
      const nameOnly = m > 1 && l.sizeEls?.length > 0 && l.nameEl;
      for (const el of l.sizeEls || []) el.style.display = nameOnly ? 'none' : '';
      const [x, y, , ] = l.rect;
      // Name only: the rect shrinks to the name's line, the name centred in it.
      const w = nameOnly ? Math.min(l.rect[2], l.nameEl.getComputedTextLength() + 0.6 * l.namePx) : l.rect[2];
      const h = nameOnly ? 1.5 * l.namePx : l.rect[3];
      const x0 = x + (l.rect[2] - w) / 2;
      l.rectEl.setAttribute('x', x0.toFixed(2));
      l.rectEl.setAttribute('width', w.toFixed(2));
      l.rectEl.setAttribute('height', h.toFixed(2));
      if (l.nameY === undefined) l.nameY = l.nameEl?.getAttribute('y');
      if (l.nameEl) l.nameEl.setAttribute('y', nameOnly ? (y + 1.12 * l.namePx).toFixed(2) : l.nameY);
      const cx = x0 + w / 2, cy = y + h / 2;
      const r = [cx - (w * m) / 2, cy - (h * m) / 2, w * m, h * m];
      const gap = 2 * k;
      for (let tries = 0; tries < 50; tries++) {
        const hit = placed.find((q) => overlaps(q, r, gap));
        if (!hit) break;
        r[1] = hit[1] + hit[3] + gap + 1e-6;
      }
      placed.push(r);
      const dy = r[1] + r[3] / 2 - cy;
      if (m === 1 && dy === 0) l.box.removeAttribute('transform');
      else l.box.setAttribute('transform', `translate(${cx.toFixed(2)} ${(cy + dy).toFixed(2)}) scale(${m.toFixed(4)}) translate(${(-cx).toFixed(2)} ${(-cy).toFixed(2)})`);
      if (l.leader) {
        const ax = Number(l.leader.getAttribute('x1')), ay = Number(l.leader.getAttribute('y1'));
        l.leader.setAttribute('x2', Math.min(Math.max(ax, r[0]), r[0] + r[2]).toFixed(2));
        l.leader.setAttribute('y2', Math.min(Math.max(ay, r[1]), r[1] + r[3]).toFixed(2));
      }
    }
  }

  /** The labels and ticks as the server drew them (for the downloaded picture). */
  resetLabels() {
    if (this.axes && this.axesPx > 0) this.axes.setAttribute('font-size', String(this.axesPx));
    for (const l of this.labels || []) {
      l.box.removeAttribute('transform');
      for (const el of l.sizeEls || []) el.style.display = '';
      l.rectEl.setAttribute('x', String(l.rect[0]));
      l.rectEl.setAttribute('width', String(l.rect[2]));
      l.rectEl.setAttribute('height', String(l.rect[3]));
      if (l.nameEl && l.nameY !== undefined) l.nameEl.setAttribute('y', l.nameY);
      if (l.leader) {
        l.leader.setAttribute('x2', l.leaderEnd[0]);
        l.leader.setAttribute('y2', l.leaderEnd[1]);
      }
    }
  }

  draw() {
    if (!this.overlay) return;
    this.fitLabels();
    const g = this.overlay;
    g.replaceChildren();
    if (this.layers.occupancy && this.occupancy) this.drawOccupancy(g);
    const results = (this.plan && this.plan.results) || [];
    const byName = Object.fromEntries(results.map((r) => [r.planner, r]));
    const mbpp = byName.mbpp;
    if (mbpp && this.layers.bugs) this.drawBugs(g, mbpp.bugs || []);
    if (mbpp && this.layers.alternatives) {
      const alt = svgEl('g', { class: 'vp-alternatives', stroke: '#8a8a8a', 'stroke-width': this.u(1.6), 'stroke-dasharray': `${this.u(5)} ${this.u(4)}`, 'stroke-opacity': 0.9 });
      for (const a of mbpp.alternatives || []) this.polyline(alt, a.waypoints, {});
      g.append(alt);
    }
    for (const name of ['astar-ps', 'mbpp', 'optimal']) {
      const r = byName[name];
      const st = PLANNER_STYLE[name];
      if (!r || !r.found || !this.layers[name]) continue;
      this.polyline(g, r.waypoints, {
        class: `vp-path vp-path-${name}`,
        'data-planner': name,
        stroke: st.colour,
        'stroke-width': this.u(st.width),
        'stroke-dasharray': st.dash ? st.dash.split(' ').map((v) => this.u(Number(v))).join(' ') : null,
      });
    }
    if (byName.smooth && this.layers.smooth) drawSmooth(this, g, byName.smooth);
    if (this.headings.on) {
      const shown = pathHeadings(byName.smooth);
      drawHeadingArrows(this, g, [
        { which: 'start', p: finite(this.start) ? this.start : null, heading: this.headings.start, shown: shown[0], colour: '#1b8a3a' },
        { which: 'goal', p: finite(this.goal) ? this.goal : null, heading: this.headings.goal, shown: shown[1], colour: '#c62828' },
      ]);
    }
    if (this.drive) this.drawDrive(g, this.drive);
    if (Array.isArray(this.map?.cameras) && this.map.cameras.length) drawCameras(this, g, this.map.cameras, this.activeCamera, this.onCamera);
    for (const [p, label, colour] of [[this.start, 'S', '#1b8a3a'], [this.goal, 'G', '#c62828']]) {
      if (!finite(p)) continue;
      const [x, y] = this.mapToSvg(p);
      const m = svgEl('g', { class: `vp-marker vp-marker-${label === 'S' ? 'start' : 'goal'}` });
      m.append(svgEl('circle', { cx: x, cy: y, r: this.u(9), fill: colour, stroke: '#fff', 'stroke-width': this.u(2) }));
      const t = svgEl('text', { x, y: y + this.u(4.5), 'text-anchor': 'middle', 'font-size': this.u(12), 'font-weight': 700, fill: '#fff' });
      t.textContent = label;
      m.append(t);
      g.append(m);
    }
  }

  /** The true objects (red dashed outlines), the driven track and where the robot re-planned. */
  drawDrive(g, d) {
    const wrap = svgEl('g', { class: 'vp-drive' });
    const truth = svgEl('g', { class: 'vp-truth', fill: 'none', stroke: DRIVE_TRUTH_COLOUR, 'stroke-width': this.u(1.6), 'stroke-dasharray': `${this.u(4)} ${this.u(3)}` });
    for (const o of d.truth_objects || []) {
      const ring = (o.footprint || []).filter(finite);
      if (ring.length < 3) continue;
      const el = svgEl('polygon', { points: this.points(ring) });
      const title = svgEl('title');
      title.textContent = `${o.name}: where it really is`;
      el.append(title);
      truth.append(el);
    }
    wrap.append(truth);
    this.polyline(wrap, d.waypoints || [], { class: 'vp-drive-track', stroke: DRIVE_COLOUR, 'stroke-width': this.u(2.6), 'stroke-opacity': 0.9 });
    const arm = this.u(5);
    for (const e of (d.events || []).slice(1)) {
      if (!finite(e.at)) continue;
      const [x, y] = this.mapToSvg(e.at);
      const m = svgEl('path', { class: 'vp-drive-replan', d: `M${x} ${y - arm}L${x + arm} ${y}L${x} ${y + arm}L${x - arm} ${y}Z`, fill: DRIVE_REPLAN_COLOUR, stroke: '#fff', 'stroke-width': this.u(1) });
      const title = svgEl('title');
      title.textContent = `re-planned here: ${e.reason === 'blocked' ? 'the path ahead was blocked' : 'a shorter way opened'} (${fmt(e.time_ms, 2)} ms)`;
      m.append(title);
      wrap.append(m);
    }
    g.append(wrap);
  }

  drawBugs(g, bugs) {
    // Bug tracks, hits and leave points are map points (the centres of the cells walked).
    const wrap = svgEl('g', { class: 'vp-bugs', fill: 'none', 'stroke-width': this.u(1.4), 'stroke-opacity': 0.75, 'stroke-linejoin': 'round', 'stroke-linecap': 'round' });
    const conv = (list) => (Array.isArray(list) ? list.filter(finite) : []);
    bugs.forEach((bug, i) => {
      const colour = BUG_COLOURS[i % BUG_COLOURS.length];
      const cells = conv(bug.cells);
      const line = this.polyline(wrap, cells.length === 1 ? [cells[0], cells[0]] : cells, { stroke: colour, class: 'vp-bug', 'data-bug': i });
      if (line) {
        const title = svgEl('title');
        title.textContent = `bug ${i + 1}${bug.fate ? `: ${bug.fate}` : ''}`;
        line.append(title);
      }
      const arm = this.u(3.5);
      for (const p of conv(bug.hits)) {
        const [x, y] = this.mapToSvg(p);
        wrap.append(svgEl('path', { d: `M${x - arm} ${y - arm}L${x + arm} ${y + arm}M${x - arm} ${y + arm}L${x + arm} ${y - arm}`, stroke: colour, 'stroke-width': this.u(1.6), 'stroke-opacity': 1 }));
      }
      for (const p of conv(bug.leaves)) {
        const [x, y] = this.mapToSvg(p);
        wrap.append(svgEl('circle', { cx: x, cy: y, r: this.u(3), fill: '#fff', stroke: colour, 'stroke-opacity': 1 }));
      }
    });
    g.append(wrap);
  }

  drawOccupancy(g) {
    const o = this.occupancy;
    if (!o || !o.pgm_base64) return;
    if (!this.occupancyUrl) this.occupancyUrl = pgmToDataUrl(base64ToBytes(o.pgm_base64));
    if (!this.occupancyUrl) return;
    const res = o.resolution, origin = o.origin;
    if (!(res > 0) || !Array.isArray(origin) || !(o.width > 0 && o.height > 0)) return;
    const m = occupancyToSvg(this.tf, o);
    g.append(svgEl('image', {
      class: 'vp-occupancy',
      href: this.occupancyUrl,
      x: 0, y: 0, width: o.width, height: o.height,
      transform: `matrix(${m.a} ${m.b} ${m.c} ${m.d} ${m.e} ${m.f})`,
      preserveAspectRatio: 'none',
      'image-rendering': 'optimizeSpeed',
    }));
  }

  /** The plan as a standalone SVG document (with the overlay), for download. */
  serialize() {
    if (!this.svg) return null;
    this.resetLabels();
    const clone = this.svg.cloneNode(true);
    this.fitLabels();
    const vb = this.fullBox;
    clone.setAttribute('viewBox', `${vb.x} ${vb.y} ${vb.w} ${vb.h}`);
    clone.setAttribute('width', String(vb.w));
    clone.setAttribute('height', String(vb.h));
    clone.removeAttribute('tabindex');
    clone.removeAttribute('class');
    clone.removeAttribute('aria-label');
    clone.setAttribute('xmlns', SVG_NS);
    return `<?xml version="1.0" encoding="UTF-8"?>\n${new XMLSerializer().serializeToString(clone)}`;
  }
}
