// The room's cameras on the floor plan (map.json `cameras`, one per photo, docs/map-format.md):
// each as a numbered disc at its station point with its viewing direction and the edges of its
// field of view, the active photo's camera highlighted with the floor it shows. A click on a
// camera makes its photo the active one. The geometry (cameraOnFloor) is pure, for the unit
// tests; drawCameras draws into the plan's overlay in SVG user units.

import { svgEl } from './util.js';

export const CAMERA_COLOUR = '#37474f';
export const ACTIVE_CAMERA_COLOUR = '#e65100';

const finite = (v) => typeof v === 'number' && Number.isFinite(v);

/** A unit direction on the floor `deg` degrees counter-clockwise from the map's +y. */
export function floorDirection(deg) {
  const t = (deg * Math.PI) / 180;
  return [-Math.sin(t), Math.cos(t)];
}

/**
 * A camera of map.json on the floor: `{at, heading_deg, forward, left, right}` with `at` its
 * station point `[x, y]`, `forward` its horizontal viewing direction and `left`, `right` the
 * directions of its image's left and right edges (unit vectors, map frame), or null when the
 * camera has no position. The heading is `heading_deg` (counter-clockwise from +y), else the
 * optical axis of `rotation_map_from_camera`; the edges are `horizontal_fov_deg` (degrees from
 * the viewing direction, negative to the left) turned by the heading.
 */
export function cameraOnFloor(cam) {
  const pos = cam?.position;
  if (!Array.isArray(pos) || !finite(pos[0]) || !finite(pos[1])) return null;
  let heading = cam.heading_deg;
  const r = cam.rotation_map_from_camera;
  if (!finite(heading) && Array.isArray(r) && r.length === 3 && finite(r[0]?.[2]) && finite(r[1]?.[2]) && Math.hypot(r[0][2], r[1][2]) > 1e-9) {
    // The optical axis (camera z) in the map frame is R's third column.
    heading = (Math.atan2(-r[0][2], r[1][2]) * 180) / Math.PI;
  }
  if (!finite(heading)) heading = 0;
  const fov = Array.isArray(cam.horizontal_fov_deg) && cam.horizontal_fov_deg.every(finite) ? cam.horizontal_fov_deg : null;
  return {
    at: [pos[0], pos[1]],
    heading_deg: heading,
    forward: floorDirection(heading),
    left: fov ? floorDirection(heading - fov[0]) : null,
    right: fov ? floorDirection(heading - fov[1]) : null,
  };
}

/**
 * Draw `cameras` into `g` for the plan view `view` (its mapToSvg and u: user units for screen
 * pixels); `onCamera(i)` is called when camera `i` is clicked.
 */
export function drawCameras(view, g, cameras, active, onCamera) {
  const wrap = svgEl('g', { class: 'vp-cameras' });
  const ends = (at, dir, px) => {
    const a = view.mapToSvg(at);
    const b = view.mapToSvg([at[0] + dir[0], at[1] + dir[1]]);
    const n = Math.hypot(b[0] - a[0], b[1] - a[1]) || 1;
    return [a, [a[0] + ((b[0] - a[0]) / n) * view.u(px), a[1] + ((b[1] - a[1]) / n) * view.u(px)]];
  };
  // The floor the active photo shows, under every camera, taking no clicks (a camera inside it
  // must stay clickable).
  const shown = cameras[active];
  const ring = Array.isArray(shown?.view_on_floor) ? shown.view_on_floor.filter((p) => Array.isArray(p) && finite(p[0]) && finite(p[1])) : [];
  if (ring.length >= 3) {
    wrap.append(svgEl('polygon', {
      class: 'vp-camera-view',
      points: ring.map((p) => view.mapToSvg(p).map((v) => v.toFixed(2)).join(',')).join(' '),
      fill: ACTIVE_CAMERA_COLOUR, 'fill-opacity': 0.07, stroke: ACTIVE_CAMERA_COLOUR, 'stroke-opacity': 0.6,
      'stroke-width': view.u(1.2), 'stroke-dasharray': `${view.u(5)} ${view.u(4)}`, 'pointer-events': 'none',
    }));
  }
  // The active camera last, on top.
  const order = cameras.map((c, i) => i).sort((a, b) => (a === active) - (b === active));
  for (const i of order) {
    const cam = cameras[i];
    const f = cameraOnFloor(cam);
    if (!f) continue;
    const on = i === active;
    const colour = on ? ACTIVE_CAMERA_COLOUR : CAMERA_COLOUR;
    const c = svgEl('g', { class: `vp-camera${on ? ' active' : ''}`, 'data-photo': i, cursor: 'pointer' });
    for (const dir of [f.left, f.right]) {
      if (!dir) continue;
      const [a, b] = ends(f.at, dir, 48);
      c.append(svgEl('line', { class: 'vp-camera-fov', x1: a[0], y1: a[1], x2: b[0], y2: b[1], stroke: colour, 'stroke-width': view.u(1.4), 'stroke-dasharray': `${view.u(4)} ${view.u(3)}`, 'pointer-events': 'none' }));
    }
    const [a, b] = ends(f.at, f.forward, 30);
    c.append(svgEl('line', { class: 'vp-camera-heading', x1: a[0], y1: a[1], x2: b[0], y2: b[1], stroke: colour, 'stroke-width': view.u(2.4), 'stroke-linecap': 'round' }));
    c.append(svgEl('circle', { cx: a[0], cy: a[1], r: view.u(9), fill: colour, stroke: '#fff', 'stroke-width': view.u(1.8) }));
    const t = svgEl('text', { x: a[0], y: a[1] + view.u(4.2), 'text-anchor': 'middle', 'font-size': view.u(11.5), 'font-weight': 700, fill: '#fff' });
    t.textContent = String(i + 1);
    c.append(t);
    const title = svgEl('title');
    title.textContent = `camera of photo ${i + 1}${on ? ' (the photo shown)' : ': click to show its photo'}`;
    c.append(title);
    // Not a start or goal: the plan's own pointer handling never sees the press.
    c.addEventListener('pointerdown', (e) => e.stopPropagation());
    c.addEventListener('click', (e) => {
      e.stopPropagation();
      onCamera?.(i);
    });
    wrap.append(c);
  }
  g.append(wrap);
}
