// The page's state and its undo history.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { createState, History, busyNames } from '../../assets/js/state.js';

const scene = (n) => ({ version: 1, image: { width: 10, height: 10 }, objects: Array.from({ length: n }, (_, i) => ({ name: `o${i}` })) });

test('undo and redo walk the recorded scenes both ways', () => {
  const h = new History();
  assert.equal(h.canUndo, false);
  assert.equal(h.undo(scene(0)), null, 'nothing to undo');
  h.record(scene(0));
  h.record(scene(1));
  assert.deepEqual(h.undo(scene(2)), scene(1));
  assert.deepEqual(h.undo(scene(1)), scene(0));
  assert.equal(h.undo(scene(0)), null);
  assert.equal(h.canRedo, true);
  assert.deepEqual(h.redo(scene(0)), scene(1));
  assert.deepEqual(h.redo(scene(1)), scene(2));
  assert.equal(h.redo(scene(2)), null);
});

test('a new edit clears redo; null is not recorded', () => {
  const h = new History();
  h.record(scene(0));
  h.undo(scene(1));
  assert.equal(h.canRedo, true);
  h.record(scene(0));
  assert.equal(h.canRedo, false);
  h.record(null);
  assert.equal(h.undoStack.length, 1);
});

test('undo keeps a copy: later edits of the scene do not reach it', () => {
  const h = new History();
  const s = scene(1);
  h.record(s);
  s.objects[0].name = 'changed';
  const back = h.undo(s);
  assert.equal(back.objects[0].name, 'o0');
  assert.notEqual(back, s);
});

test('undo keeps at most `limit` steps, dropping the oldest', () => {
  const h = new History(3);
  for (let i = 0; i < 5; i++) h.record(scene(i));
  assert.equal(h.undoStack.length, 3);
  assert.deepEqual(h.undo(scene(5)), scene(4));
  assert.deepEqual(h.undo(scene(4)), scene(3));
  assert.deepEqual(h.undo(scene(3)), scene(2));
  assert.equal(h.undo(scene(2)), null);
});

test('createState gives fresh state every time; busyNames lists the busy requests', () => {
  const a = createState();
  const b = createState();
  a.settings.resolution = 1;
  a.busy.plan = true;
  assert.equal(b.settings.resolution, 0.05);
  assert.equal(b.settings.robot_radius, 0.2);
  assert.deepEqual(busyNames(b.busy), []);
  a.busy.build = true;
  assert.deepEqual(busyNames(a.busy), ['build', 'plan']);
});

test('clear forgets undo and redo (a new photo)', () => {
  const h = new History();
  h.record({ v: 1 });
  h.record({ v: 2 });
  assert.deepEqual(h.undo({ v: 3 }), { v: 2 });
  assert.ok(h.canUndo && h.canRedo);
  h.clear();
  assert.ok(!h.canUndo && !h.canRedo);
  assert.equal(h.undo({ v: 3 }), null);
  assert.equal(h.redo({ v: 3 }), null);
});
