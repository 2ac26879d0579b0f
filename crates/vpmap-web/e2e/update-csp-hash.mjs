// Recompute the sha256 of index.html's inline import map and write it into the page's
// Content-Security-Policy (script-src). Run after editing the import map:
//   node crates/vpmap-web/e2e/update-csp-hash.mjs [--check]
// With --check it only reports whether the hash is current (exit 1 if not).
import { createHash } from 'node:crypto';
import { readFileSync, writeFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';

const file = fileURLToPath(new URL('../assets/index.html', import.meta.url));
const html = readFileSync(file, 'utf8');
const m = html.match(/<script type="importmap">([\s\S]*?)<\/script>/);
if (!m) {
  console.error('index.html has no <script type="importmap">');
  process.exit(1);
}
const hash = `sha256-${createHash('sha256').update(m[1], 'utf8').digest('base64')}`;
const current = html.match(/script-src 'self' '(sha256-[^']*)'/);
if (!current) {
  console.error("index.html's CSP has no script-src 'self' 'sha256-...'");
  process.exit(1);
}
if (current[1] === hash) {
  console.log(`CSP hash is current: ${hash}`);
  process.exit(0);
}
if (process.argv.includes('--check')) {
  console.error(`CSP hash is stale: page has ${current[1]}, import map is ${hash}`);
  process.exit(1);
}
writeFileSync(file, html.replace(current[1], hash));
console.log(`updated the CSP hash to ${hash}`);
