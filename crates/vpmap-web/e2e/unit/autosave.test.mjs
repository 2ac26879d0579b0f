// Each photo's scene kept in the browser (autosave.js), with a Map-backed fake of localStorage.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { KEY_PREFIX, hashBytes, loadScene, photoKey, storeScene } from '../../assets/js/autosave.js';

class FakeStorage {
  constructor() {
    this.m = new Map();
  }
  get length() {
    return this.m.size;
  }
  key(i) {
    return [...this.m.keys()][i] ?? null;
  }
  getItem(k) {
    return this.m.has(k) ? this.m.get(k) : null;
  }
  setItem(k, v) {
    this.m.set(k, String(v));
  }
  removeItem(k) {
    this.m.delete(k);
  }
}

test('a photo is known by its name, size and bytes', () => {
  const a = new Uint8Array([1, 2, 3]);
  assert.equal(hashBytes(new Uint8Array()), '811c9dc5');
  assert.notEqual(hashBytes(a), hashBytes(new Uint8Array([1, 2, 4])));
  assert.equal(photoKey('p.png', 4, 3, a), `${KEY_PREFIX}p.png|4x3|3|${hashBytes(a)}`);
  assert.notEqual(photoKey('p.png', 4, 3, a), photoKey('q.png', 4, 3, a));
});

test('scenes are kept and come back; the oldest go beyond the limit; other keys stay', () => {
  const st = new FakeStorage();
  st.setItem('unrelated', 'x');
  for (let i = 0; i < 5; i++) assert.ok(storeScene(st, `${KEY_PREFIX}${i}`, { version: 1, n: i }, 1000 + i, 3));
  assert.equal(loadScene(st, `${KEY_PREFIX}0`), null);
  assert.equal(loadScene(st, `${KEY_PREFIX}1`), null);
  assert.deepEqual(loadScene(st, `${KEY_PREFIX}4`), { saved_at: 1004, scene: { version: 1, n: 4 } });
  assert.equal(st.getItem('unrelated'), 'x');
  // Written again, a scene is the newest.
  storeScene(st, `${KEY_PREFIX}2`, { version: 1, n: 22 }, 2000, 3);
  storeScene(st, `${KEY_PREFIX}5`, { version: 1, n: 5 }, 2001, 3);
  assert.equal(loadScene(st, `${KEY_PREFIX}3`), null);
  assert.equal(loadScene(st, `${KEY_PREFIX}2`).scene.n, 22);
  // Broken entries read as nothing; a full storage is reported.
  st.setItem(`${KEY_PREFIX}bad`, '{');
  assert.equal(loadScene(st, `${KEY_PREFIX}bad`), null);
  st.setItem = () => {
    throw new Error('QuotaExceededError');
  };
  assert.equal(storeScene(st, `${KEY_PREFIX}6`, {}, 3000), false);
});
