// The photo canvas: the photo with zoom and pan, and over it the detected segments, the
// vanishing-point lines, the horizon and principal point of the last build, the annotations
// and the active tool's preview. Pointer input goes to the active tool (select-tool.js and
// the placement tools, placement-tool.js); what a tool does not take pans the view, and a
// press without movement is a click.

import { VP_COLOURS, objectOutline, resolvedVps } from './scene.js';
import { OFF_LINE_PX, boxEdges, boxPoints, guideOffsets } from './box.js';
import { clipLine, distortPx, lensOf, segmentThroughLens, vpPoint } from './geometry.js';
import { clamp } from './util.js';

/** Points of the polyline the pinhole horizon is drawn as through a lens. */
const HORIZON_CURVE_SAMPLES = 128;

const CLICK_SLOP_PX = 4;
const MIN_SCALE = 0.01;
const MAX_SCALE = 40;

export class PhotoView {
  /**
   * @param {HTMLCanvasElement} canvas
   * @param {object} app  `state` (scene, detection, camera, selection, showSegments, ...),
   *   `tool` (the active tool) and `photoViewChanged()`.
   */
  constructor(canvas, app) {
    this.canvas = canvas;
    this.ctx = canvas.getContext('2d');
    this.app = app;
    this.photo = null;
    this.imgW = 0;
    this.imgH = 0;
    this.s = 1; // screen (CSS) pixels per image pixel
    this.tx = 0;
    this.ty = 0;
    this.fitted = true; // re-fit on resize until the user zooms or pans
    this.cursor = null; // image point under the pointer
    this.cursorScreen = null;
    this.gesture = null;
    this.frame = 0;
    this.cssW = 1;
    this.cssH = 1;

    new ResizeObserver(() => this.resize()).observe(canvas);
    canvas.addEventListener('pointerdown', (e) => this.onDown(e));
    canvas.addEventListener('pointermove', (e) => this.onMove(e));
    canvas.addEventListener('pointerup', (e) => this.onUp(e));
    canvas.addEventListener('pointercancel', (e) => this.onUp(e, true));
    canvas.addEventListener('pointerleave', () => {
      if (!this.gesture) {
        this.cursor = null;
        this.cursorScreen = null;
        this.requestRender();
      }
    });
    canvas.addEventListener('wheel', (e) => this.onWheel(e), { passive: false });
    canvas.addEventListener('keydown', (e) => this.onKey(e));
    canvas.addEventListener('contextmenu', (e) => e.preventDefault());
    this.resize();
  }

  /** Show `photo` (an ImageBitmap, or null for a blank board) of `w` x `h` image pixels. */
  setImage(photo, w, h) {
    this.photo = photo;
    this.imgW = w;
    this.imgH = h;
    this.fit();
  }

  get hasImage() {
    return this.imgW > 0 && this.imgH > 0;
  }

  resize() {
    const r = this.canvas.getBoundingClientRect();
    this.cssW = Math.max(1, r.width);
    this.cssH = Math.max(1, r.height);
    const dpr = window.devicePixelRatio || 1;
    this.canvas.width = Math.round(this.cssW * dpr);
    this.canvas.height = Math.round(this.cssH * dpr);
    if (this.fitted) this.fit();
    // Setting the size cleared the canvas: draw now, not a frame later (no blank frame while
    // the layout around the photo changes, e.g. a room's message above it).
    if (this.frame) cancelAnimationFrame(this.frame);
    this.frame = 0;
    this.render();
  }

  fit() {
    this.fitted = true;
    if (!this.hasImage) {
      this.s = 1;
      this.tx = this.ty = 0;
    } else {
      const pad = 12;
      this.s = Math.max(MIN_SCALE, Math.min((this.cssW - 2 * pad) / this.imgW, (this.cssH - 2 * pad) / this.imgH));
      this.tx = (this.cssW - this.imgW * this.s) / 2;
      this.ty = (this.cssH - this.imgH * this.s) / 2;
    }
    this.requestRender();
  }

  zoomAt(factor, sx, sy) {
    const s = clamp(this.s * factor, MIN_SCALE, MAX_SCALE);
    const k = s / this.s;
    this.tx = sx - (sx - this.tx) * k;
    this.ty = sy - (sy - this.ty) * k;
    this.s = s;
    this.fitted = false;
    this.requestRender();
  }

  imageToScreen(p) {
    return [p[0] * this.s + this.tx, p[1] * this.s + this.ty];
  }

  screenToImage(q) {
    return [(q[0] - this.tx) / this.s, (q[1] - this.ty) / this.s];
  }

  /** Viewport (client) coordinates of an image point: for tests and tooltips. */
  imageToClient(p) {
    const r = this.canvas.getBoundingClientRect();
    const q = this.imageToScreen(p);
    return [r.left + q[0], r.top + q[1]];
  }

  /** Image pixels per screen pixel, for hit radii. */
  get px() {
    return 1 / this.s;
  }

  eventScreen(e) {
    const r = this.canvas.getBoundingClientRect();
    return [e.clientX - r.left, e.clientY - r.top];
  }

  onDown(e) {
    if (!this.hasImage) return;
    this.canvas.focus({ preventScroll: true });
    const q = this.eventScreen(e);
    const p = this.screenToImage(q);
    const tool = this.app.tool;
    const panOnly = e.button === 1 || e.button === 2 || (e.button === 0 && e.shiftKey && e.altKey);
    if (!panOnly && e.button === 0 && tool.pointerDown && tool.pointerDown(p, e, this)) {
      this.gesture = { kind: 'tool', id: e.pointerId };
    } else {
      this.gesture = { kind: panOnly ? 'pan' : 'maybe-click', id: e.pointerId, start: q, tx: this.tx, ty: this.ty, p };
    }
    this.canvas.setPointerCapture(e.pointerId);
    e.preventDefault();
  }

  onMove(e) {
    const q = this.eventScreen(e);
    const p = this.screenToImage(q);
    this.cursor = p;
    this.cursorScreen = q;
    const g = this.gesture;
    if (g && g.id === e.pointerId) {
      if (g.kind === 'tool') {
        this.app.tool.pointerMove?.(p, e, this);
      } else {
        const moved = Math.hypot(q[0] - g.start[0], q[1] - g.start[1]);
        if (g.kind === 'maybe-click' && moved > CLICK_SLOP_PX) g.kind = 'pan';
        if (g.kind === 'pan') {
          this.tx = g.tx + q[0] - g.start[0];
          this.ty = g.ty + q[1] - g.start[1];
          this.fitted = false;
          this.canvas.classList.add('pan');
        }
      }
    } else {
      this.app.tool.hover?.(p, this);
      this.canvas.classList.toggle('grab', !!this.app.tool.wantsGrab?.(p, this));
    }
    this.requestRender();
  }

  onUp(e, cancelled = false) {
    const g = this.gesture;
    if (!g || g.id !== e.pointerId) return;
    this.gesture = null;
    this.canvas.classList.remove('pan');
    if (this.canvas.hasPointerCapture(e.pointerId)) this.canvas.releasePointerCapture(e.pointerId);
    const p = this.screenToImage(this.eventScreen(e));
    if (g.kind === 'tool') this.app.tool.pointerUp?.(p, e, this, cancelled);
    else if (g.kind === 'maybe-click' && !cancelled) this.app.tool.click?.(g.p, e, this);
    this.requestRender();
  }

  onWheel(e) {
    if (!this.hasImage) return;
    e.preventDefault();
    const q = this.eventScreen(e);
    const dy = e.deltaMode === 1 ? e.deltaY * 33 : e.deltaY;
    this.zoomAt(Math.exp(-dy * 0.0015), q[0], q[1]);
  }

  onKey(e) {
    if (e.ctrlKey || e.metaKey || e.altKey) return;
    const c = [this.cssW / 2, this.cssH / 2];
    if (e.key === '+' || e.key === '=') this.zoomAt(1.25, ...c);
    else if (e.key === '-' || e.key === '_') this.zoomAt(0.8, ...c);
    else if (e.key === '0') this.fit();
    else if (e.key.startsWith('Arrow')) {
      const step = e.shiftKey ? 10 : 1;
      const d = { ArrowLeft: [-1, 0], ArrowRight: [1, 0], ArrowUp: [0, -1], ArrowDown: [0, 1] }[e.key];
      if (!this.app.nudge(d[0] * step, d[1] * step)) {
        this.tx -= d[0] * step * 4;
        this.ty -= d[1] * step * 4;
        this.fitted = false;
        this.requestRender();
      }
    } else return;
    e.preventDefault();
    e.stopPropagation();
  }

  requestRender() {
    if (this.frame) return;
    this.frame = requestAnimationFrame(() => {
      this.frame = 0;
      this.render();
    });
  }

  // ---- drawing -------------------------------------------------------------------------

  render() {
    const { ctx } = this;
    const dpr = this.canvas.width / this.cssW;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.clearRect(0, 0, this.canvas.width, this.canvas.height);
    if (!this.hasImage) return;
    // Photo (or a blank board when a scene is open without its photo).
    ctx.setTransform(dpr * this.s, 0, 0, dpr * this.s, dpr * this.tx, dpr * this.ty);
    if (this.photo) {
      ctx.imageSmoothingEnabled = this.s < 2;
      ctx.imageSmoothingQuality = 'high';
      ctx.drawImage(this.photo, 0, 0, this.imgW, this.imgH);
    } else {
      ctx.fillStyle = '#50545c';
      ctx.fillRect(0, 0, this.imgW, this.imgH);
    }
    // Overlays in CSS pixels, so line widths do not change with the zoom.
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    const st = this.app.state;
    ctx.lineCap = 'round';
    ctx.lineJoin = 'round';
    if (st.showSegments) this.drawSegments(st);
    this.drawVpLines(st);
    this.drawCamera(st);
    if (st.scene) {
      this.drawFloor(st);
      this.drawObjects(st);
      this.drawScaleLine(st);
    }
    this.drawMarked(st);
    this.app.tool.draw?.(ctx, this);
    for (const draw of this.app.overlays || []) draw(this);
    if (this.app.tool.loupe && this.cursorScreen && !(this.gesture && this.gesture.kind === 'pan')) this.drawLoupe();
  }

  /** A polyline through image points. */
  path(pts, close = false) {
    const { ctx } = this;
    ctx.beginPath();
    pts.forEach((p, i) => {
      const q = this.imageToScreen(p);
      if (i === 0) ctx.moveTo(q[0], q[1]);
      else ctx.lineTo(q[0], q[1]);
    });
    if (close) ctx.closePath();
  }

  /** A line with a dark halo so it reads on any photo. */
  strokeHalo(colour, width, dash = []) {
    const { ctx } = this;
    ctx.setLineDash([]);
    ctx.strokeStyle = 'rgba(0,0,0,0.55)';
    ctx.lineWidth = width + 2;
    ctx.stroke();
    ctx.setLineDash(dash);
    ctx.strokeStyle = colour;
    ctx.lineWidth = width;
    ctx.stroke();
    ctx.setLineDash([]);
  }

  dot(p, r, fill, stroke = '#000') {
    const { ctx } = this;
    const q = this.imageToScreen(p);
    ctx.beginPath();
    ctx.arc(q[0], q[1], r, 0, Math.PI * 2);
    ctx.fillStyle = fill;
    ctx.fill();
    ctx.lineWidth = 1.2;
    ctx.strokeStyle = stroke;
    ctx.stroke();
  }

  label(p, text, colour, dx = 6, dy = -6) {
    const { ctx } = this;
    const q = this.imageToScreen(p);
    ctx.font = '600 12px system-ui, sans-serif';
    ctx.lineWidth = 3;
    ctx.strokeStyle = 'rgba(0,0,0,0.75)';
    ctx.strokeText(text, q[0] + dx, q[1] + dy);
    ctx.fillStyle = colour;
    ctx.fillText(text, q[0] + dx, q[1] + dy);
  }

  drawSegments(st) {
    const det = st.detection;
    if (!det || !Array.isArray(det.segments)) return;
    const { ctx } = this;
    const owner = det.segmentVp || [];
    ctx.lineWidth = 1;
    for (let i = 0; i < det.segments.length; i++) {
      const s = det.segments[i];
      const k = owner[i];
      ctx.strokeStyle = k === undefined || k < 0 ? 'rgba(220,220,220,0.45)' : hexAlpha(VP_COLOURS[k], 0.45);
      const a = this.imageToScreen([s[0], s[1]]);
      const b = this.imageToScreen([s[2], s[3]]);
      ctx.beginPath();
      ctx.moveTo(a[0], a[1]);
      ctx.lineTo(b[0], b[1]);
      ctx.stroke();
    }
  }

  drawVpLines(st) {
    const vps = st.scene?.vanishing_points || [];
    const sel = st.selection;
    const active = this.app.tool.vpIndex;
    // A vanishing `point` is the pinhole camera's (docs/scene-format.md): through a lens it is
    // drawn where the photo shows it; one found from the drawn lines is in the photo already.
    const lens = lensOf(st.scene);
    vps.forEach((vp, k) => {
      const colour = VP_COLOURS[k] || '#fff';
      const point = Array.isArray(vp.point) && lens ? distortPx(vp.point, lens) : vpPoint(vp);
      const lines = vp.lines || [];
      const focus = active === k || (sel && sel.type === 'vpline' && sel.vp === k);
      // Extensions towards the vanishing point for the VP being edited.
      if (focus && point) {
        for (const s of lines) {
          const mid = [(s[0] + s[2]) / 2, (s[1] + s[3]) / 2];
          this.path([mid, point]);
          this.ctx.strokeStyle = hexAlpha(colour, 0.5);
          this.ctx.lineWidth = 1;
          this.ctx.setLineDash([4, 4]);
          this.ctx.stroke();
          this.ctx.setLineDash([]);
        }
      }
      // Handles only on the selected line (the only one whose ends can be dragged) and on the
      // lines of the direction being drawn; hidden segments are drawn thin, without handles.
      lines.forEach((s, j) => {
        const selected = sel && sel.type === 'vpline' && sel.vp === k && sel.line === j;
        this.path([[s[0], s[1]], [s[2], s[3]]]);
        if (!st.showSegments) {
          this.ctx.strokeStyle = hexAlpha(colour, 0.6);
          this.ctx.lineWidth = 1;
          this.ctx.stroke();
          return;
        }
        this.strokeHalo(colour, selected ? 3.5 : 2);
        if (selected || active === k) {
          const r = selected ? 4.5 : 3;
          this.dot([s[0], s[1]], r, '#fff', colour);
          this.dot([s[2], s[3]], r, '#fff', colour);
        }
      });
      if (point) {
        const q = this.imageToScreen(point);
        if (q[0] > -20 && q[1] > -20 && q[0] < this.cssW + 20 && q[1] < this.cssH + 20) {
          this.dot(point, 6, colour, '#fff');
          this.label(point, ['A', 'B', 'V'][k] || '?', colour, 8, 4);
        }
      }
    });
  }

  drawCamera(st) {
    const cam = st.camera;
    if (!cam) return;
    const { ctx } = this;
    const lens = lensOf(st.scene);
    if (Array.isArray(cam.horizon) && cam.horizon.length === 2 && lens) {
      // The pinhole horizon through the photo's lens: a curve, drawn as a polyline of points
      // on the pinhole line across twice the photo's extent, each taken to its photo pixel.
      const w = st.scene.image.width, h = st.scene.image.height;
      const seg = clipLine(cam.horizon[0], cam.horizon[1], [-w / 2, -h / 2, 1.5 * w, 1.5 * h]);
      const pts = seg ? segmentThroughLens(seg[0], seg[1], lens, HORIZON_CURVE_SAMPLES) : [];
      if (pts.length >= 2) {
        this.path(pts);
        this.strokeHalo('#ffd400', 2, [10, 6]);
        const inView = pts.filter((q) => { const r = this.imageToScreen(q); return r[0] >= 0 && r[0] <= this.cssW && r[1] >= 0 && r[1] <= this.cssH; });
        if (inView.length) {
          const left = inView.reduce((a, b) => (b[0] < a[0] ? b : a));
          const q = this.imageToScreen(left);
          this.label(this.screenToImage([Math.max(q[0], 4) + 4, q[1]]), 'horizon', '#ffd400', 0, -6);
        }
      }
    } else if (Array.isArray(cam.horizon) && cam.horizon.length === 2) {
      const view = [this.screenToImage([0, 0]), this.screenToImage([this.cssW, this.cssH])];
      const seg = clipLine(cam.horizon[0], cam.horizon[1], [view[0][0], view[0][1], view[1][0], view[1][1]]);
      if (seg) {
        this.path(seg);
        this.strokeHalo('#ffd400', 2, [10, 6]);
        const left = seg[0][0] < seg[1][0] ? seg[0] : seg[1];
        const q = this.imageToScreen(left);
        this.label(this.screenToImage([Math.max(q[0], 4) + 4, q[1]]), 'horizon', '#ffd400', 0, -6);
      }
    }
    const pp = cam.principal_point;
    if (Array.isArray(pp)) {
      const q = this.imageToScreen(pp);
      ctx.beginPath();
      ctx.moveTo(q[0] - 9, q[1]);
      ctx.lineTo(q[0] + 9, q[1]);
      ctx.moveTo(q[0], q[1] - 9);
      ctx.lineTo(q[0], q[1] + 9);
      this.strokeHalo('#ff3df2', 2);
      ctx.beginPath();
      ctx.arc(q[0], q[1], 5, 0, Math.PI * 2);
      this.strokeHalo('#ff3df2', 1.5);
    }
  }

  drawFloor(st) {
    const floor = st.scene.floor || [];
    if (floor.length === 0) return;
    const { ctx } = this;
    this.path(floor, floor.length >= 3);
    if (floor.length >= 3) {
      ctx.fillStyle = 'rgba(90, 200, 120, 0.13)';
      ctx.fill();
    }
    this.strokeHalo('#7ee08f', 2, [7, 4]);
    floor.forEach((p, i) => {
      this.dot(p, 3.5, '#7ee08f');
      if (i === 0) this.label(p, 'floor', '#7ee08f');
    });
  }

  drawObjects(st) {
    const sel = st.selection;
    st.scene.objects.forEach((o, i) => {
      const selected = sel && sel.type === 'object' && sel.index === i;
      const colour = o.footprint ? '#ffb74d' : '#5ec8ff';
      const w = selected ? 3 : 2;
      const { ctx } = this;
      if (o.base) {
        if (selected) {
          const ring = objectOutline(o);
          if (ring.length >= 3) {
            this.path(ring, true);
            ctx.fillStyle = hexAlpha(colour, 0.2);
            ctx.fill();
          }
        }
        for (const e of boxEdges(o)) {
          this.path([e.a, e.b]);
          this.strokeHalo(colour, w, e.part === 'top' ? [5, 4] : []);
        }
        const pts = boxPoints(o);
        for (const { p } of pts) this.dot(p, selected ? 4.5 : 3.5, colour);
        // A corner off the line it should lie on: the line, and by how much (the object list says it too).
        for (const g of guideOffsets(o, resolvedVps(st.scene), lensOf(st.scene))) {
          if (g.px < OFF_LINE_PX) continue;
          const p = o[g.part][g.corner];
          this.path([g.part === 'top' ? o.base[g.from] : o.base[g.from], g.foot, p]);
          this.strokeHalo('#ff9100', 1.5, [3, 3]);
          this.label(p, `${g.px.toFixed(1)} px off its line`, '#ff9100', 8, -8);
        }
        if (pts.length) this.label(pts[0].p, o.name || '(unnamed)', selected ? '#fff' : colour, 7, 16);
      } else if (Array.isArray(o.footprint)) {
        const fp = o.footprint;
        this.path(fp, true);
        if (selected) {
          ctx.fillStyle = hexAlpha(colour, 0.2);
          ctx.fill();
        }
        this.strokeHalo(colour, w);
        const t = o.top;
        if (t && Array.isArray(t.point) && fp[t.above]) {
          this.path([fp[t.above], t.point]);
          this.strokeHalo(colour, w);
          this.dot(t.point, selected ? 4.5 : 3.5, colour);
        }
        fp.forEach((p) => this.dot(p, selected ? 4.5 : 3.5, colour));
        if (fp[0]) this.label(fp[0], o.name || '(unnamed)', selected ? '#fff' : colour, 7, 16);
      }
    });
  }

  drawScaleLine(st) {
    const fd = st.scene.scale && st.scene.scale.floor_distance;
    if (!fd || !fd.from || !fd.to) return;
    this.path([fd.from, fd.to]);
    this.strokeHalo('#ffffff', 2, [3, 3]);
    this.dot(fd.from, 3.5, '#fff');
    this.dot(fd.to, 3.5, '#fff');
    const mid = [(fd.from[0] + fd.to[0]) / 2, (fd.from[1] + fd.to[1]) / 2];
    this.label(mid, `${fd.meters} m`, '#fff');
  }

  /** A red ring round the point the last build error is about. */
  drawMarked(st) {
    const m = st.marked;
    if (m && m.object !== undefined) {
      // The object the error is about: the note beside it (what to add).
      const o = st.scene?.objects?.[m.object];
      const at = o ? (o.base ? boxPoints(o)[0]?.p : o.footprint?.[0]) : null;
      if (at) this.label(at, `⚠ ${m.note || 'see the error below'}`, '#ff5252', 8, 34);
      return;
    }
    const p = m?.p;
    if (!p) return;
    const { ctx } = this;
    const q = this.imageToScreen(p);
    ctx.beginPath();
    ctx.arc(q[0], q[1], 11, 0, Math.PI * 2);
    this.strokeHalo('#ff1744', 3);
    this.label(p, m.note ? `the error is about this point: ${m.note}` : 'the error is about this point', '#ff5252', 14, 4);
  }

  /** A magnified view of the photo around the pointer, for placing corners precisely. */
  drawLoupe() {
    if (!this.photo || !this.cursor) return;
    const { ctx } = this;
    const size = 136;
    const mag = clamp(this.s * 4, 2, 24);
    const [cx, cy] = this.cursorScreen;
    // Put the loupe away from the pointer: top-right, or top-left when near the right edge.
    const x = cx + size + 30 < this.cssW ? cx + 24 : cx - size - 24;
    const y = clamp(cy - size - 24, 4, this.cssH - size - 4);
    const half = size / 2 / mag;
    ctx.save();
    ctx.beginPath();
    ctx.rect(x, y, size, size);
    ctx.clip();
    ctx.fillStyle = '#222';
    ctx.fillRect(x, y, size, size);
    ctx.imageSmoothingEnabled = false;
    ctx.drawImage(this.photo, this.cursor[0] - half, this.cursor[1] - half, 2 * half, 2 * half, x, y, size, size);
    ctx.strokeStyle = 'rgba(255,255,255,0.9)';
    ctx.lineWidth = 1;
    ctx.beginPath();
    ctx.moveTo(x + size / 2, y);
    ctx.lineTo(x + size / 2, y + size / 2 - 4);
    ctx.moveTo(x + size / 2, y + size / 2 + 4);
    ctx.lineTo(x + size / 2, y + size);
    ctx.moveTo(x, y + size / 2);
    ctx.lineTo(x + size / 2 - 4, y + size / 2);
    ctx.moveTo(x + size / 2 + 4, y + size / 2);
    ctx.lineTo(x + size, y + size / 2);
    ctx.stroke();
    ctx.restore();
    ctx.strokeStyle = '#fff';
    ctx.lineWidth = 2;
    ctx.strokeRect(x, y, size, size);
  }
}

/** `#rrggbb` with an alpha, as an rgba() string. */
export function hexAlpha(hex, a) {
  const n = parseInt(hex.slice(1), 16);
  return `rgba(${(n >> 16) & 255},${(n >> 8) & 255},${n & 255},${a})`;
}
