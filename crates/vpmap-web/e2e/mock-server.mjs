// A stand-in for `vpmap serve`, for working on the page (and running e2e.mjs) without the
// Rust server: serves crates/vpmap-web/assets/ like the real server (`/` = index.html,
// `/assets/<path>`) and answers the JSON API by running the `vpmap` command line
// (build, detect, plan) in a temporary folder. The example photo is rendered from the
// example's truth (render-example.mjs) on first request.
//
//   node crates/vpmap-web/e2e/mock-server.mjs [--port 8080] [--api http://127.0.0.1:8081]
//
// With --api, API requests are passed on to that running `vpmap serve` instead: the page's
// files come fresh from the disk (the real server embeds them when it is compiled), the
// answers from the real server.
//
// Prints `vpmap mock listening on http://127.0.0.1:PORT/`. Needs target/release/vpmap (or
// VPMAP_BIN). Node built-ins only. Not a production server: one request at a time is fine.

import { createServer } from 'node:http';
import { execFile } from 'node:child_process';
import { mkdtemp, readFile, writeFile, rm } from 'node:fs/promises';
import { existsSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, normalize, extname, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import { renderExample } from './render-example.mjs';

const HERE = dirname(fileURLToPath(import.meta.url));
const ASSETS = join(HERE, '..', 'assets');
const REPO = join(HERE, '..', '..', '..');
const VPMAP = process.env.VPMAP_BIN || join(REPO, 'target', 'release', 'vpmap');
const EXAMPLE = join(REPO, 'examples', 'office.json');
const TRUTH = join(REPO, 'examples', 'office.truth.json');

const TYPES = {
  '.html': 'text/html; charset=utf-8',
  '.js': 'text/javascript; charset=utf-8',
  '.mjs': 'text/javascript; charset=utf-8',
  '.css': 'text/css; charset=utf-8',
  '.svg': 'image/svg+xml',
  '.png': 'image/png',
  '.json': 'application/json',
  '.txt': 'text/plain; charset=utf-8',
};

class HttpError extends Error {
  constructor(status, message) {
    super(message);
    this.status = status;
  }
}

function run(args) {
  return new Promise((resolve, reject) => {
    execFile(VPMAP, args, { maxBuffer: 64 << 20 }, (err, stdout, stderr) => {
      if (err) {
        const line = (stderr || err.message).split('\n').find((l) => l.trim()) || 'vpmap failed';
        reject(new HttpError(400, line.replace(/^error:\s*/, '')));
      } else resolve(stdout);
    });
  });
}

async function withTemp(fn) {
  const dir = await mkdtemp(join(tmpdir(), 'vpmap-mock-'));
  try {
    return await fn(dir);
  } finally {
    await rm(dir, { recursive: true, force: true });
  }
}

function num(v, name, dflt) {
  if (v === null || v === undefined || v === '') return dflt;
  const x = Number(v);
  if (!Number.isFinite(x)) throw new HttpError(400, `${name} must be a number, got ${JSON.stringify(v)}`);
  return x;
}

function parseYaml(text) {
  const out = {};
  for (const line of text.split('\n')) {
    const m = line.match(/^(\w+):\s*(.*)$/);
    if (m) out[m[1]] = m[2];
  }
  return out;
}

function pgmSize(bytes) {
  const head = bytes.subarray(0, 64).toString('latin1').split(/\s+/);
  return { width: Number(head[1]), height: Number(head[2]) };
}

async function buildIn(dir, scene, { method, resolution, robot_radius, click_sigma }) {
  await writeFile(join(dir, 'scene.json'), JSON.stringify(scene));
  const out = join(dir, 'out');
  const sigma = click_sigma === undefined ? [] : ['--click-sigma', String(click_sigma)];
  const stdout = await run(['build', join(dir, 'scene.json'), '--out', out, '--method', method, '--resolution', String(resolution), '--robot-radius', String(robot_radius), ...sigma]);
  const map = JSON.parse(await readFile(join(out, 'map.json'), 'utf8'));
  const svg = await readFile(join(out, 'map.svg'), 'utf8');
  const glb = await readFile(join(out, 'model.glb'));
  const yaml = await readFile(join(out, 'occupancy.yaml'), 'utf8');
  const pgm = await readFile(join(out, 'occupancy.pgm'));
  const y = parseYaml(yaml);
  const origin = JSON.parse(y.origin);
  const { width, height } = pgmSize(pgm);
  const c = map.camera;
  const [v1, v2] = c.vanishing_points;
  return {
    map,
    svg,
    glb_base64: glb.toString('base64'),
    occupancy: { yaml, pgm_base64: pgm.toString('base64'), width, height, resolution: Number(y.resolution), origin },
    camera: { pitch_deg: c.pitch_deg, roll_deg: c.roll_deg, focal_px: c.focal_px, principal_point: c.principal_point, height: c.height, horizon: [v1, v2] },
    warnings: stdout.split('\n').filter((l) => /^warning/i.test(l)).map((l) => l.replace(/^warning:\s*/i, '')),
    _dir: out,
  };
}

function buildSettings(q, body = {}) {
  const method = body.method ?? q.get('method') ?? 'sideview';
  if (!['fit', 'sideview', 'projective'].includes(method)) throw new HttpError(400, `unknown method ${JSON.stringify(method)}`);
  const sigma = body.click_sigma ?? q.get('click_sigma');
  return {
    method,
    resolution: num(body.resolution ?? q.get('resolution'), 'resolution', 0.05),
    robot_radius: num(body.robot_radius ?? q.get('robot_radius'), 'robot_radius', 0.2),
    click_sigma: sigma === null || sigma === undefined || sigma === '' ? undefined : num(sigma, 'click_sigma', 1),
  };
}

/** Turn a map-from-camera rotation (rows) by `deg` about +z (counter-clockwise seen from above). */
function turned(r, deg) {
  const t = (deg * Math.PI) / 180, c = Math.cos(t), s = Math.sin(t);
  return [
    [0, 1, 2].map((k) => c * r[0][k] - s * r[1][k]),
    [0, 1, 2].map((k) => s * r[0][k] + c * r[1][k]),
    r[2].slice(),
  ];
}

/**
 * A room file (`{"version": 1, "photos": [...]}`), the way the real server's contract answers it,
 * but canned: photo 1 is built as the map (objects, floor, pictures), every photo is built alone
 * for its own camera, and the cameras of photos 2, 3, ... are put at made-up places (1.2 m apart,
 * turned 35 degrees each): a stand-in to develop the page against, not a fit. Errors name the
 * photo as the real server's do: "photos[i] (photo i+1): `objects[1]...`" and "photo N is not tied to photo 1".
 */
async function buildRoom(room, settings) {
  const photos = room.photos;
  if (!Array.isArray(photos) || photos.length === 0) throw new HttpError(400, 'the room file has no photos');
  const names = (i) => new Set((photos[i].objects || []).map((o) => o.name));
  for (let i = 1; i < photos.length; i++) {
    const mine = names(i);
    const tied = photos.slice(0, i).some((_, j) => [...names(j)].some((n) => mine.has(n)));
    if (!tied) throw new HttpError(400, `photo ${i + 1} is not tied to photo 1: no object is named in both it and an earlier photo`);
  }
  const built = [];
  for (const [i, scene] of photos.entries()) {
    try {
      built.push(await withTemp(async (dir) => {
        const b = await buildIn(dir, scene, settings);
        delete b._dir;
        return b;
      }));
    } catch (e) {
      throw new HttpError(e.status || 400, `scene: photos[${i}] (photo ${i + 1}): ${e.message.replace(/^building \S+: /, '')}`);
    }
  }
  const first = built[0];
  first.map.cameras = built.map((b, i) => {
    const c = b.map.camera;
    const heading = 35 * i;
    const t = (heading * Math.PI) / 180;
    const at = [1.2 * i, 0.3 * i];
    const place = (p) => [at[0] + Math.cos(t) * p[0] - Math.sin(t) * p[1], at[1] + Math.sin(t) * p[0] + Math.cos(t) * p[1]];
    return {
      ...c,
      position: [at[0], at[1], c.height],
      heading_deg: heading,
      view_on_floor: (c.view_on_floor || []).map(place),
      rotation_map_from_camera: c.rotation_map_from_camera ? turned(c.rotation_map_from_camera, heading) : undefined,
    };
  });
  return first;
}

let examplePhoto = null;

async function example() {
  const scene = JSON.parse(await readFile(EXAMPLE, 'utf8'));
  if (!examplePhoto) {
    const truth = JSON.parse(await readFile(TRUTH, 'utf8'));
    const built = await withTemp((dir) => buildIn(dir, scene, { method: 'sideview', resolution: 0.05, robot_radius: 0 }));
    examplePhoto = renderExample(built.map.camera, truth).toString('base64');
  }
  return { scene, photo_png_base64: examplePhoto };
}

async function detect(q, bytes) {
  if (!bytes.length) throw new HttpError(400, 'empty body: send the photo bytes');
  return withTemp(async (dir) => {
    const png = bytes[0] === 0x89 && bytes[1] === 0x50;
    const photo = join(dir, png ? 'photo.png' : 'photo.jpg');
    await writeFile(photo, bytes);
    const args = ['detect', photo, '--out', join(dir, 'scene.json')];
    if (q.get('focal_px')) args.push('--focal-px', String(num(q.get('focal_px'), 'focal_px')));
    if (q.get('principal_point')) args.push('--principal-point', q.get('principal_point'));
    await run(args);
    const scene = JSON.parse(await readFile(join(dir, 'scene.json'), 'utf8'));
    // The command line keeps only each direction's supporting segments: list those.
    const segments = [];
    const vanishing_points = scene.vanishing_points.map((vp, k) => {
      const idx = [];
      for (const s of vp.lines || []) idx.push(segments.push(s) - 1);
      return { point: vp.point ?? null, segments: idx, vertical: k === 2 };
    });
    return { scene, segments, vanishing_points, perspective: scene.perspective, focal_px: scene.focal_px, principal_point: scene.principal_point };
  });
}

function bugsFromSvg(svg) {
  const bugs = [];
  const get = (i) => (bugs[i] ??= { cells: [], hits: [], leaves: [], fate: null });
  for (const m of svg.matchAll(/<polyline class="bug-track" data-bug="(\d+)"[^>]*points="([^"]*)"/g)) {
    get(Number(m[1])).cells = m[2].trim().split(/\s+/).map((p) => p.split(',').map((v) => Math.floor(Number(v))));
  }
  for (const m of svg.matchAll(/<path class="bug-hits" data-bug="(\d+)"[^>]*d="([^"]*)"/g)) {
    const nums = [...m[2].matchAll(/M([\d.]+) ([\d.]+)L([\d.]+) ([\d.]+)M/g)];
    get(Number(m[1])).hits = nums.map((n) => [Math.floor((Number(n[1]) + Number(n[3])) / 2), Math.floor((Number(n[2]) + Number(n[4])) / 2)]);
  }
  for (const m of svg.matchAll(/<circle class="bug-leave" data-bug="(\d+)" cx="([\d.]+)" cy="([\d.]+)"/g)) {
    get(Number(m[1])).leaves.push([Math.floor(Number(m[2])), Math.floor(Number(m[3]))]);
  }
  return bugs.filter(Boolean);
}

async function plan(body) {
  const { start, goal } = body;
  // A room: the mock plans on photo 1's map (buildRoom's map).
  const scene = Array.isArray(body.scene?.photos) ? body.scene.photos[0] : body.scene;
  if (!scene) throw new HttpError(400, 'missing field `scene`');
  for (const [k, p] of [['start', start], ['goal', goal]]) {
    if (!Array.isArray(p) || p.length !== 2 || !p.every(Number.isFinite)) throw new HttpError(400, `\`${k}\` must be [x, y] in metres`);
  }
  const planners = body.planners || ['mbpp', 'astar-ps', 'optimal'];
  const settings = buildSettings(new URLSearchParams(), body);
  return withTemp(async (dir) => {
    const built = await buildIn(dir, scene, settings);
    const o = built.occupancy;
    // Cells (column, row from the top) to map points at their centres, like the real server.
    const world = (c) => [o.origin[0] + (c[0] + 0.5) * o.resolution, o.origin[1] + (o.height - c[1] - 0.5) * o.resolution];
    const results = [];
    for (const planner of planners) {
      const args = ['plan', join(built._dir, 'map.json'), `--from=${start[0]},${start[1]}`, `--to=${goal[0]},${goal[1]}`, '--planner', planner, '--json', '--robot-radius', String(settings.robot_radius), '--resolution', String(settings.resolution)];
      const svgPath = join(dir, `${planner}.svg`);
      if (planner === 'mbpp') args.push('--svg', svgPath);
      const out = JSON.parse(await run(args));
      results.push({
        planner,
        found: out.found,
        length_m: out.length,
        waypoints: out.waypoints,
        alternatives: (out.alternatives || []).map((a) => ({ length_m: a.length, waypoints: a.waypoints })),
        bugs: planner === 'mbpp'
          ? bugsFromSvg(await readFile(svgPath, 'utf8')).map((b) => ({ ...b, cells: b.cells.map(world), hits: b.hits.map(world), leaves: b.leaves.map(world) }))
          : [],
        time_ms: out.stats.time_s * 1000,
      });
    }
    return { results, grid: { width: o.width, height: o.height, resolution: o.resolution, origin: o.origin.slice(0, 2) } };
  });
}

async function readBody(req) {
  const chunks = [];
  for await (const c of req) chunks.push(c);
  return Buffer.concat(chunks);
}

function jsonBody(buf) {
  try {
    return JSON.parse(buf.toString('utf8'));
  } catch (e) {
    throw new HttpError(400, `the body is not JSON: ${e.message}`);
  }
}

async function serveAsset(res, path) {
  const file = normalize(join(ASSETS, path));
  if (!file.startsWith(ASSETS) || !existsSync(file)) throw new HttpError(404, `no asset ${path}`);
  const body = await readFile(file);
  res.writeHead(200, { 'Content-Type': TYPES[extname(file)] || 'application/octet-stream', 'Cache-Control': 'no-store' });
  res.end(body);
}

const apiArg = process.argv.indexOf('--api');
const API = apiArg > 0 ? process.argv[apiArg + 1].replace(/\/$/, '') : null;

/** Pass an API request on to the real server (without the browser's Origin, which names this proxy). */
async function proxy(req, res, url) {
  const body = req.method === 'POST' ? await readBody(req) : undefined;
  const headers = {};
  if (req.headers['content-type']) headers['content-type'] = req.headers['content-type'];
  const r = await fetch(API + url.pathname + url.search, { method: req.method, headers, body });
  res.writeHead(r.status, { 'Content-Type': r.headers.get('content-type') || 'application/json' });
  res.end(Buffer.from(await r.arrayBuffer()));
}

const server = createServer(async (req, res) => {
  const url = new URL(req.url, 'http://localhost');
  const send = (status, obj) => {
    res.writeHead(status, { 'Content-Type': 'application/json' });
    res.end(JSON.stringify(obj));
  };
  try {
    const p = url.pathname;
    if (req.method === 'GET' && (p === '/' || p === '/index.html')) return await serveAsset(res, 'index.html');
    if (req.method === 'GET' && p.startsWith('/assets/')) return await serveAsset(res, decodeURIComponent(p.slice(8)));
    if (API && p.startsWith('/api/')) return await proxy(req, res, url);
    if (p === '/api/example' && req.method === 'GET') return send(200, await example());
    if (p === '/api/build' && req.method === 'POST') {
      const body = jsonBody(await readBody(req));
      if (Array.isArray(body.photos)) return send(200, await buildRoom(body, buildSettings(url.searchParams)));
      const built = await withTemp(async (dir) => buildIn(dir, body, buildSettings(url.searchParams)));
      delete built._dir;
      return send(200, built);
    }
    if (p === '/api/detect' && req.method === 'POST') return send(200, await detect(url.searchParams, await readBody(req)));
    if (p === '/api/plan' && req.method === 'POST') return send(200, await plan(jsonBody(await readBody(req))));
    throw new HttpError(404, `no route ${req.method} ${p}`);
  } catch (e) {
    if (!(e instanceof HttpError)) console.error(e);
    send(e.status || 500, { error: e.message });
  }
});

const portArg = process.argv.indexOf('--port');
const port = portArg > 0 ? Number(process.argv[portArg + 1]) : 0;
server.listen(port, '127.0.0.1', () => {
  console.log(`vpmap mock listening on http://127.0.0.1:${server.address().port}/`);
});
