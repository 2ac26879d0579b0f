// A synthetic photo of the bundled example (examples/office.json), for the mock server: the
// truth's objects (examples/office.truth.json) as prisms on a tiled floor, with three walls
// along the room's floor edges, ray-cast through the example's camera (k_matrix,
// rotation_map_from_camera and position of its map.json). 2 x 2 supersampling, PNG output.
// Node built-ins only.

import { deflateSync } from 'node:zlib';

const WALL_HEIGHT = 2.6;
const TILE = 0.5;

const CRC_TABLE = (() => {
  const t = new Uint32Array(256);
  for (let n = 0; n < 256; n++) {
    let c = n;
    for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
    t[n] = c >>> 0;
  }
  return t;
})();

function crc32(buf) {
  let c = 0xffffffff;
  for (const b of buf) c = CRC_TABLE[(c ^ b) & 255] ^ (c >>> 8);
  return (c ^ 0xffffffff) >>> 0;
}

function chunk(type, data) {
  const out = Buffer.alloc(12 + data.length);
  out.writeUInt32BE(data.length, 0);
  out.write(type, 4, 'latin1');
  data.copy(out, 8);
  out.writeUInt32BE(crc32(out.subarray(4, 8 + data.length)), 8 + data.length);
  return out;
}

/** Encode 8-bit RGB pixels as a PNG. */
export function encodePng(width, height, rgb) {
  const raw = Buffer.alloc((width * 3 + 1) * height);
  for (let y = 0; y < height; y++) {
    raw[y * (width * 3 + 1)] = 0;
    rgb.copy(raw, y * (width * 3 + 1) + 1, y * width * 3, (y + 1) * width * 3);
  }
  const ihdr = Buffer.alloc(13);
  ihdr.writeUInt32BE(width, 0);
  ihdr.writeUInt32BE(height, 4);
  ihdr[8] = 8;
  ihdr[9] = 2;
  return Buffer.concat([
    Buffer.from([0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a]),
    chunk('IHDR', ihdr),
    chunk('IDAT', deflateSync(raw, { level: 6 })),
    chunk('IEND', Buffer.alloc(0)),
  ]);
}

const norm = (v) => {
  const n = Math.hypot(...v);
  return v.map((x) => x / n);
};

/**
 * Render the room. `camera` is map.json's camera; `truth` is office.truth.json.
 * Returns PNG bytes.
 */
export function renderExample(camera, truth) {
  const { width, height } = camera.image;
  const K = camera.k_matrix;
  const f = K[0][0], cx = K[0][2], cy = K[1][2];
  const R = camera.rotation_map_from_camera;
  const o = camera.position;
  // Room axes from the first box's near -> right edge.
  const fp0 = truth.objects[0].footprint;
  const a = norm([fp0[1][0] - fp0[0][0], fp0[1][1] - fp0[0][1]]);
  const b = [-a[1], a[0]];
  const light = norm([0.35, -0.55, 0.75]);
  const palette = [[176, 112, 64], [150, 150, 160], [120, 160, 90], [200, 180, 140], [200, 70, 60], [90, 120, 190]];

  // Faces: vertical quads (edge p -> q, z from 0 to h) and horizontal polygons (tops).
  const sides = [];
  const tops = [];
  truth.objects.forEach((obj, i) => {
    const fp = obj.footprint;
    const hgt = obj.height;
    const colour = palette[i % palette.length];
    for (let j = 0; j < fp.length; j++) sides.push({ p: fp[j], q: fp[(j + 1) % fp.length], z0: 0, z1: hgt, colour, kind: 'object' });
    tops.push({ ring: fp, z: hgt, colour });
  });
  // Walls along the room's three far floor edges (the floor's other edges are the image border).
  const fl = truth.floor;
  for (let j = 0; j < 3; j++) {
    const p = fl[j], q = fl[j + 1];
    const d = norm([q[0] - p[0], q[1] - p[1]]);
    const ext = 0.3;
    sides.push({ p: [p[0] - d[0] * ext, p[1] - d[1] * ext], q: [q[0] + d[0] * ext, q[1] + d[1] * ext], z0: 0, z1: WALL_HEIGHT, colour: [222, 218, 205], kind: 'wall' });
  }
  for (const s of sides) {
    const d = [s.q[0] - s.p[0], s.q[1] - s.p[1]];
    s.len = Math.hypot(d[0], d[1]);
    s.u = [d[0] / s.len, d[1] / s.len];
    s.n = [-s.u[1], s.u[0]]; // one of the two normals
  }

  const inside = (p, ring) => {
    let c = false;
    for (let i = 0, j = ring.length - 1; i < ring.length; j = i++) {
      const [xi, yi] = ring[i], [xj, yj] = ring[j];
      if ((yi > p[1]) !== (yj > p[1]) && p[0] < ((xj - xi) * (p[1] - yi)) / (yj - yi) + xi) c = !c;
    }
    return c;
  };

  const shade = (colour, normal, k = 1) => {
    const l = 0.5 + 0.5 * Math.abs(normal[0] * light[0] + normal[1] * light[1] + normal[2] * light[2]);
    return colour.map((c) => c * l * k);
  };

  const trace = (u, v) => {
    const dc = [(u - cx) / f, (v - cy) / f, 1];
    const d = [
      R[0][0] * dc[0] + R[0][1] * dc[1] + R[0][2] * dc[2],
      R[1][0] * dc[0] + R[1][1] * dc[1] + R[1][2] * dc[2],
      R[2][0] * dc[0] + R[2][1] * dc[1] + R[2][2] * dc[2],
    ];
    let best = Infinity;
    let col = null;
    for (const s of sides) {
      const den = s.n[0] * d[0] + s.n[1] * d[1];
      if (Math.abs(den) < 1e-12) continue;
      const t = (s.n[0] * (s.p[0] - o[0]) + s.n[1] * (s.p[1] - o[1])) / den;
      if (!(t > 1e-6 && t < best)) continue;
      const x = o[0] + t * d[0], y = o[1] + t * d[1], z = o[2] + t * d[2];
      const along = (x - s.p[0]) * s.u[0] + (y - s.p[1]) * s.u[1];
      if (along < 0 || along > s.len || z < s.z0 || z > s.z1) continue;
      best = t;
      let k = 1;
      if (s.kind === 'wall') {
        // Panels: vertical joints every metre along the wall, a skirting board and a rail.
        const w = along - Math.floor(along);
        if (w < 0.02 || z < 0.1 || Math.abs(z - 1.0) < 0.025) k = 0.72;
      }
      col = shade(s.colour, [s.n[0], s.n[1], 0], k);
    }
    for (const tp of tops) {
      if (Math.abs(d[2]) < 1e-12) continue;
      const t = (tp.z - o[2]) / d[2];
      if (!(t > 1e-6 && t < best)) continue;
      const p = [o[0] + t * d[0], o[1] + t * d[1]];
      if (!inside(p, tp.ring)) continue;
      best = t;
      col = shade(tp.colour, [0, 0, 1], 1.08);
    }
    if (d[2] < 0) {
      const t = -o[2] / d[2];
      if (t < best) {
        const x = o[0] + t * d[0], y = o[1] + t * d[1];
        const pu = x * a[0] + y * a[1], pv = x * b[0] + y * b[1];
        const odd = (Math.floor(pu / TILE) + Math.floor(pv / TILE)) & 1;
        const base = odd ? [186, 178, 160] : [120, 112, 100];
        const fade = Math.exp(-t / 14);
        col = base.map((c) => (c * fade + 150 * (1 - fade)));
        best = t;
      }
    }
    if (!col) {
      const g = Math.max(0, Math.min(1, 0.5 - d[2]));
      col = [200 - 60 * g, 215 - 40 * g, 235];
    }
    return col;
  };

  const rgb = Buffer.alloc(width * height * 3);
  const offs = [0.25, 0.75];
  let seed = 12345;
  const noise = () => {
    seed = (seed * 1103515245 + 12345) & 0x7fffffff;
    return (seed / 0x7fffffff - 0.5) * 3;
  };
  for (let y = 0; y < height; y++) {
    for (let x = 0; x < width; x++) {
      let r = 0, g = 0, bl = 0;
      for (const oy of offs) {
        for (const ox of offs) {
          const c = trace(x + ox, y + oy);
          r += c[0]; g += c[1]; bl += c[2];
        }
      }
      const i = (y * width + x) * 3;
      const n = noise();
      rgb[i] = Math.max(0, Math.min(255, Math.round(r / 4 + n)));
      rgb[i + 1] = Math.max(0, Math.min(255, Math.round(g / 4 + n)));
      rgb[i + 2] = Math.max(0, Math.min(255, Math.round(bl / 4 + n)));
    }
  }
  return encodePng(width, height, rgb);
}
