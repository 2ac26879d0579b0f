// Small helpers shared by the page's modules.

/** `document.getElementById`, throwing when the element is missing (a broken page, not a user error). */
export function $(id) {
  const el = document.getElementById(id);
  if (!el) throw new Error(`missing element #${id}`);
  return el;
}

/** Create an element with attributes and children. `on*` keys are not supported on purpose (CSP, and clarity). */
export function h(tag, attrs = {}, ...children) {
  const el = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (v === undefined || v === null || v === false) continue;
    if (k === 'class') el.className = v;
    else if (k === 'text') el.textContent = v;
    else if (k === 'dataset') Object.assign(el.dataset, v);
    else el.setAttribute(k, v === true ? '' : String(v));
  }
  for (const c of children.flat()) {
    if (c === null || c === undefined || c === false) continue;
    el.append(c instanceof Node ? c : document.createTextNode(String(c)));
  }
  return el;
}

export const SVG_NS = 'http://www.w3.org/2000/svg';

/** Create an SVG element with attributes (presentation attributes only: no `style`, so the markup works under a strict CSP and in exported files). */
export function svgEl(tag, attrs = {}) {
  const el = document.createElementNS(SVG_NS, tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (v === undefined || v === null) continue;
    el.setAttribute(k, String(v));
  }
  return el;
}

/** A number with `d` decimals, or an en dash when missing or not finite. */
export function fmt(v, d = 2) {
  return typeof v === 'number' && Number.isFinite(v) ? v.toFixed(d) : '–';
}

/**
 * A standard deviation with `d` decimals; `<0.01` (one unit of the last decimal) when a
 * non-zero value would round to zero, so a small error bar is not shown as exactly 0.
 */
export function fmtSd(v, d = 2) {
  if (!(typeof v === 'number' && Number.isFinite(v))) return '–';
  const text = v.toFixed(d);
  return v > 0 && Number(text) === 0 ? `<${(10 ** -d).toFixed(d)}` : text;
}

/** Parse "x, y" (comma or whitespace separated) into [x, y], or null. */
export function parsePair(text) {
  if (typeof text !== 'string') return null;
  const parts = text.trim().split(/[\s,;]+/).filter(Boolean);
  if (parts.length !== 2) return null;
  const v = parts.map(Number);
  return v.every(Number.isFinite) ? v : null;
}

export function formatPair(p, d = 2) {
  return p ? `${p[0].toFixed(d)}, ${p[1].toFixed(d)}` : '';
}

export function base64ToBytes(b64) {
  const bin = atob(b64);
  const out = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; i++) out[i] = bin.charCodeAt(i);
  return out;
}

/** Offer `data` (Blob, bytes or text) as a download named `name`. */
export function download(name, data, type = 'application/octet-stream') {
  const blob = data instanceof Blob ? data : new Blob([data], { type });
  const url = URL.createObjectURL(blob);
  const a = h('a', { href: url, download: name });
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 30_000);
}

/** Read a File as text. */
export function readText(file) {
  return file.text();
}

export function clamp(v, lo, hi) {
  return Math.min(hi, Math.max(lo, v));
}

/** True when the keyboard event comes from a text field (so shortcuts stay out of its way). */
export function isTyping(ev) {
  const t = ev.target;
  if (!(t instanceof HTMLElement)) return false;
  if (t.isContentEditable) return true;
  if (t instanceof HTMLTextAreaElement || t instanceof HTMLSelectElement) return true;
  if (t instanceof HTMLInputElement) {
    return !['checkbox', 'radio', 'button', 'submit', 'file', 'range', 'color'].includes(t.type);
  }
  return false;
}
