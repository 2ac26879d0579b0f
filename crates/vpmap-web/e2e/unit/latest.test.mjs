// The "latest request wins, debounced" helper that build, plan and detect share.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { debouncer, latestRequest } from '../../assets/js/latest.js';
import { fakeClock, manualRequests, settle } from './fake.mjs';

test('debouncer runs once, `wait` ms after the last schedule', () => {
  const clock = fakeClock();
  let runs = 0;
  const d = debouncer(() => runs++, 100, Infinity, clock);
  d.schedule();
  clock.advance(60);
  d.schedule();
  clock.advance(60);
  assert.equal(runs, 0, 'the second schedule restarted the wait');
  assert.equal(d.pending, true);
  clock.advance(40);
  assert.equal(runs, 1);
  assert.equal(d.pending, false);
  clock.advance(1000);
  assert.equal(runs, 1, 'one schedule, one run');
});

test('debouncer runs at least every `maxWait` ms while schedules keep coming', () => {
  const clock = fakeClock();
  const at = [];
  const d = debouncer(() => at.push(clock.now()), 100, 400, clock);
  // A drag: a schedule every 50 ms for 1 s.
  for (let i = 0; i < 20; i++) {
    d.schedule();
    clock.advance(50);
  }
  assert.deepEqual(at, [1400, 1800], 'runs maxWait after the first schedule since the last run');
  clock.advance(100);
  assert.deepEqual(at, [1400, 1800, 2050], 'and once more, `wait` after the last schedule');
});

test('debouncer cancel drops the run, flush runs it now', () => {
  const clock = fakeClock();
  let runs = 0;
  const d = debouncer(() => runs++, 100, 400, clock);
  d.schedule();
  d.cancel();
  clock.advance(500);
  assert.equal(runs, 0);
  d.flush();
  assert.equal(runs, 0, 'nothing scheduled: flush does nothing');
  d.schedule();
  d.flush();
  assert.equal(runs, 1);
  assert.equal(clock.waiting, 0, 'the timer is gone');
});

function recorder(options = {}) {
  const { calls, run } = manualRequests();
  const log = [];
  const req = latestRequest({
    run,
    busy: (on) => log.push(['busy', on]),
    done: (v, ...args) => log.push(['done', v, ...args]),
    fail: (e) => log.push(['fail', e.message]),
    always: () => log.push(['always']),
    ...options,
  });
  return { calls, log, req };
}

test('latest request wins: an older answer arriving late is dropped and its request aborted', async () => {
  const { calls, log, req } = recorder();
  req.now('first');
  req.now('second');
  assert.equal(calls.length, 2);
  assert.equal(calls[0].signal.aborted, true, 'the older request is aborted');
  assert.equal(calls[1].signal.aborted, false);
  calls[0].answer('old'); // too late: already aborted and superseded
  calls[1].answer('new');
  await settle();
  assert.deepEqual(log, [['busy', true], ['busy', true], ['done', 'new', 'second'], ['busy', false], ['always']]);
  assert.equal(req.running, false);
});

test('latest request wins even when the older one ignores the abort and answers last', async () => {
  const log = [];
  const answers = [];
  const req = latestRequest({
    run: () => new Promise((resolve) => answers.push(resolve)), // does not listen to the signal
    done: (v) => log.push(v),
  });
  req.now();
  req.now();
  answers[1]('new');
  await settle();
  answers[0]('old');
  await settle();
  assert.deepEqual(log, ['new']);
});

test('errors of the latest request reach `fail`, aborts and stale errors never do', async () => {
  const { calls, log, req } = recorder();
  req.now();
  req.now();
  calls[1].error(new Error('server says no'));
  await settle();
  assert.deepEqual(log, [['busy', true], ['busy', true], ['fail', 'server says no'], ['busy', false], ['always']]);
});

test('an error thrown by `done` is reported through `fail`', async () => {
  const { calls, log, req } = recorder({ done: () => { throw new Error('cannot show it'); } });
  req.now();
  calls[0].answer('x');
  await settle();
  assert.deepEqual(log, [['busy', true], ['fail', 'cannot show it'], ['busy', false], ['always']]);
});

test('cancel aborts the request on its way, drops its answer and ends busy', async () => {
  const { calls, log, req } = recorder();
  req.now();
  req.cancel();
  assert.equal(calls[0].signal.aborted, true);
  assert.equal(req.running, false);
  calls[0].answer('late');
  await settle();
  assert.deepEqual(log, [['busy', true], ['busy', false]]);
  req.cancel();
  assert.deepEqual(log, [['busy', true], ['busy', false]], 'cancel when idle tells nobody');
});

test('nothing starts and nothing is aborted while `ready` is false', async () => {
  let ready = true;
  const { calls, log, req } = recorder({ ready: () => ready });
  req.now();
  ready = false;
  req.now();
  assert.equal(calls.length, 1);
  assert.equal(calls[0].signal.aborted, false, 'the running request is left alone');
  calls[0].answer('a');
  await settle();
  assert.deepEqual(log, [['busy', true], ['done', 'a'], ['busy', false], ['always']]);
});

test('schedule debounces: a burst of edits sends one request', async () => {
  const clock = fakeClock();
  const { calls, log, req } = recorder({ wait: 100, maxWait: 400, clock });
  for (let i = 0; i < 5; i++) {
    req.schedule();
    clock.advance(20);
  }
  assert.equal(calls.length, 0);
  assert.equal(req.pending, true);
  clock.advance(100);
  assert.equal(req.pending, false);
  assert.equal(calls.length, 1);
  calls[0].answer('built');
  await settle();
  assert.deepEqual(log, [['busy', true], ['done', 'built'], ['busy', false], ['always']]);
});

test('now() drops a scheduled start; flush() starts it at once; cancel() drops it', () => {
  const clock = fakeClock();
  const { calls, req } = recorder({ wait: 100, clock });
  req.schedule();
  req.now();
  clock.advance(1000);
  assert.equal(calls.length, 1, 'the scheduled start was replaced by the immediate one');
  req.schedule();
  req.flush();
  assert.equal(calls.length, 2);
  req.schedule();
  req.cancel();
  clock.advance(1000);
  assert.equal(calls.length, 2);
});
