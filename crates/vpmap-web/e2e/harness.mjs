// What the browser tests (e2e.mjs, usability.mjs, room.mjs, snap.mjs) share: starting the
// server under test, launching Debian's Chromium through playwright-core, and the run around
// their steps (log, failure with a screenshot, watchdog, cleanup).

import { spawn } from 'node:child_process';
import { existsSync } from 'node:fs';
import { rm } from 'node:fs/promises';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { deflateSync } from 'node:zlib';
import { chromium } from 'playwright-core';

const HERE = dirname(fileURLToPath(import.meta.url));
/** The repository's root. */
export const REPO = join(HERE, '..', '..', '..');
/** The browser: Debian's Chromium unless VPMAP_E2E_CHROMIUM names another. */
export const CHROMIUM = process.env.VPMAP_E2E_CHROMIUM || '/usr/bin/chromium';

/**
 * Start the server under test and resolve to `{url, server}`: `url` its base URL (ending in
 * `/`), `server` the child process (null with VPMAP_URL, which tests a running server). The
 * server is `vpmap serve --port 0` from VPMAP_BIN (default target/release/vpmap), or with
 * `mock: true` and VPMAP_E2E_MOCK=1 the mock server. `log` gets the command line.
 */
export function startServer({ mock = false, log = () => {} } = {}) {
  if (process.env.VPMAP_URL) return Promise.resolve({ url: process.env.VPMAP_URL.replace(/\/?$/, '/'), server: null });
  let cmd, args;
  if (mock && process.env.VPMAP_E2E_MOCK === '1') {
    cmd = process.execPath;
    args = [join(HERE, 'mock-server.mjs'), '--port', '0'];
  } else {
    cmd = process.env.VPMAP_BIN || join(REPO, 'target', 'release', 'vpmap');
    if (!existsSync(cmd)) return Promise.reject(new Error(`${cmd} does not exist: run \`cargo build --release\` first, or set VPMAP_BIN or VPMAP_URL`));
    args = ['serve', '--port', '0'];
  }
  log(`starting ${cmd} ${args.join(' ')}`);
  const server = spawn(cmd, args, { stdio: ['ignore', 'pipe', 'pipe'] });
  return new Promise((resolve, reject) => {
    let seen = '';
    const timer = setTimeout(() => {
      server.kill('SIGTERM');
      reject(new Error(`the server printed no http:// address within 20 s; it printed:\n${seen}`));
    }, 20_000);
    const onData = (buf) => {
      seen += buf.toString();
      const m = seen.match(/https?:\/\/[^\s"'<>]+/);
      if (m) {
        clearTimeout(timer);
        // Bind-all addresses are not browsable: use the loopback address.
        resolve({ url: m[0].replace('://0.0.0.0', '://127.0.0.1').replace('://[::]', '://[::1]').replace(/\/?$/, '/'), server });
      }
    };
    server.stdout.on('data', onData);
    server.stderr.on('data', onData);
    server.on('exit', (code) => {
      clearTimeout(timer);
      reject(new Error(`the server exited with code ${code} before printing its address:\n${seen}`));
    });
  });
}

/** Launch Chromium (headless unless VPMAP_E2E_HEADED=1); throws when it is not installed. */
export async function launchChromium() {
  if (!existsSync(CHROMIUM)) throw new Error(`${CHROMIUM} not found: install Chromium (apt-get install -y chromium) or set VPMAP_E2E_CHROMIUM`);
  return chromium.launch({
    executablePath: CHROMIUM,
    headless: process.env.VPMAP_E2E_HEADED !== '1',
    // Software WebGL for the 3D view on machines without a GPU; no background connections
    // (on a closed network they fail, many at a time, and slow the start).
    args: [
      '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist',
      '--disable-background-networking', '--disable-component-update', '--disable-sync',
      '--disable-quic', '--no-first-run',
    ],
  });
}

/** A grey PNG of `w` x `h` pixels (8-bit greyscale, stored zlib blocks). */
export function greyPng(w, h) {
  const crcTable = Array.from({ length: 256 }, (_, n) => {
    let c = n;
    for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
    return c >>> 0;
  });
  const crc = (buf) => {
    let c = 0xffffffff;
    for (const b of buf) c = crcTable[(c ^ b) & 0xff] ^ (c >>> 8);
    return (c ^ 0xffffffff) >>> 0;
  };
  const chunk = (type, data) => {
    const t = Buffer.concat([Buffer.from(type), data]);
    const out = Buffer.alloc(12 + data.length);
    out.writeUInt32BE(data.length, 0);
    t.copy(out, 4);
    out.writeUInt32BE(crc(t), 8 + data.length);
    return out;
  };
  const ihdr = Buffer.alloc(13);
  ihdr.writeUInt32BE(w, 0);
  ihdr.writeUInt32BE(h, 4);
  ihdr.set([8, 0, 0, 0, 0], 8);
  const raw = Buffer.alloc((w + 1) * h, 128);
  for (let r = 0; r < h; r++) raw[r * (w + 1)] = 0; // filter byte
  return Buffer.concat([
    Buffer.from([0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a]),
    chunk('IHDR', ihdr),
    chunk('IDAT', deflateSync(raw)),
    chunk('IEND', Buffer.alloc(0)),
  ]);
}

/**
 * The run around a browser test's steps: `log` (seconds since the start), `check`, `step`
 * (runs one named step; any error fails the run naming the step), `fail` (prints
 * `<label> FAILED in step "...": message`, takes a screenshot of the page to `failureShot`,
 * cleans up and exits 1), `pass` (cleans up, prints `<label> PASSED` and exits 0) and a
 * watchdog that fails the run after `totalMs`. `resources()` returns what the script has made
 * so far, `{server, browser, page, tmp}` (any may be null): the cleanup closes the browser,
 * stops the server and removes the temporary folder, and the failure screenshot is of the
 * page. With `only` (step numbers as strings), steps named `N. ...` run only when N is listed.
 */
export function testRun({ label, totalMs, failureShot, resources, only = [] }) {
  const started = Date.now();
  let currentStep = 'start-up';
  const log = (msg) => console.log(`[${((Date.now() - started) / 1000).toFixed(1).padStart(5)} s] ${msg}`);
  const check = (cond, msg) => {
    if (!cond) throw new Error(msg);
  };
  async function cleanup() {
    const { server, browser, tmp } = resources();
    try {
      await browser?.close();
    } catch {
      // Closing a dead browser.
    }
    if (server && server.exitCode === null) server.kill('SIGTERM');
    if (tmp) await rm(tmp, { recursive: true, force: true });
  }
  async function fail(msg) {
    console.error(`\n${label} FAILED in step "${currentStep}": ${msg}`);
    const { page } = resources();
    if (page) {
      try {
        await page.screenshot({ path: failureShot, timeout: 5000 });
        console.error(`screenshot of the failure: ${failureShot}`);
      } catch {
        // No screenshot: the browser is gone.
      }
    }
    await cleanup();
    process.exit(1);
  }
  const watchdog = setTimeout(() => fail(`did not finish within ${totalMs / 1000} s`), totalMs);
  async function step(name, fn) {
    const num = /^(\d+)\./.exec(name)?.[1];
    if (num && only.length && !only.includes(num)) return undefined;
    currentStep = name;
    log(name);
    try {
      return await fn();
    } catch (err) {
      return fail(err && err.message ? err.message : String(err));
    }
  }
  async function pass() {
    clearTimeout(watchdog);
    await cleanup();
    log(`${label} PASSED`);
    process.exit(0);
  }
  return { log, check, step, fail, pass };
}
