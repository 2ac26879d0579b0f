// "Latest request wins, debounced": the one way the page talks to the server for build, plan
// and detect. Starting a request aborts the one still on its way; an answer or error that
// arrives after a newer request started (or after `cancel()`) is dropped, so the views only
// ever show the latest answer. Pure logic: the clock is injectable, so the unit tests run it
// with fake timers (e2e/unit/latest.test.mjs).

import { isAbort } from './api.js';

/** The browser's (or Node's) clock: what `debouncer` and `latestRequest` use unless given another. */
export const realClock = {
  now: () => performance.now(),
  setTimeout: (fn, ms) => setTimeout(fn, ms),
  clearTimeout: (id) => clearTimeout(id),
};

/**
 * A debounced call: runs `fn` `wait` ms after the last `schedule()`, but at least every
 * `maxWait` ms while calls keep coming (so a long drag still updates the views).
 */
export function debouncer(fn, wait, maxWait = Infinity, clock = realClock) {
  let timer = null;
  let first = 0;
  const run = () => {
    timer = null;
    first = 0;
    fn();
  };
  return {
    schedule() {
      const now = clock.now();
      if (!first) first = now;
      if (timer) clock.clearTimeout(timer);
      const left = Math.max(0, Math.min(wait, first + maxWait - now));
      timer = clock.setTimeout(run, left);
    },
    cancel() {
      if (timer) clock.clearTimeout(timer);
      timer = null;
      first = 0;
    },
    flush() {
      if (timer) {
        clock.clearTimeout(timer);
        run();
      }
    },
    get pending() {
      return timer !== null;
    },
  };
}

/**
 * A request of which only the latest counts.
 *
 * - `run(signal, ...args)` starts the request and returns a promise of its answer;
 * - `ready()` (optional) is asked first: when it is false nothing starts and nothing is aborted;
 * - `busy(on)` is told when the latest request starts (`true`) and when it ends or is
 *   cancelled (`false`);
 * - `done(answer, ...args)` gets the latest request's answer, `fail(err, ...args)` its error
 *   (never an abort), `always(...args)` runs after either (only for the latest request).
 *
 * `schedule()` starts it `wait` ms after the last call (at least every `maxWait` ms),
 * `now(...args)` starts it at once, `flush()` starts a scheduled one at once, `cancel()` drops
 * the scheduled one and the one on its way.
 */
export function latestRequest({ run, ready = () => true, busy = () => {}, done = () => {}, fail = () => {}, always = () => {}, wait = 0, maxWait = Infinity, clock = realClock }) {
  let seq = 0;
  let controller = null;
  let running = false;
  const setBusy = (on) => {
    running = on;
    busy(on);
  };

  async function start(...args) {
    if (!ready()) return;
    controller?.abort();
    const ctl = (controller = new AbortController());
    const mine = ++seq;
    const current = () => mine === seq;
    setBusy(true);
    try {
      const answer = await run(ctl.signal, ...args);
      if (!current()) return;
      done(answer, ...args);
    } catch (err) {
      if (isAbort(err) || !current()) return;
      fail(err, ...args);
    } finally {
      if (current()) {
        if (controller === ctl) controller = null;
        setBusy(false);
        always(...args);
      }
    }
  }

  const timer = debouncer(() => start(), wait, maxWait, clock);

  return {
    schedule: () => timer.schedule(),
    now(...args) {
      timer.cancel();
      return start(...args);
    },
    flush: () => timer.flush(),
    cancel() {
      timer.cancel();
      controller?.abort();
      controller = null;
      seq++;
      if (running) setBusy(false);
    },
    /** A start is scheduled and has not happened yet. */
    get pending() {
      return timer.pending;
    },
    /** The latest request is on its way. */
    get running() {
      return running;
    },
  };
}
