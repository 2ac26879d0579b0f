// Test doubles for the unit tests: a clock whose time only moves when told, and requests that
// answer when told (and reject like fetch when aborted).

/** A clock for `debouncer`/`latestRequest`: `advance(ms)` runs the timers that fall due, in order. */
export function fakeClock(start = 1000) {
  let t = start;
  let nextId = 0;
  const timers = new Map();
  return {
    now: () => t,
    setTimeout(fn, ms) {
      nextId += 1;
      timers.set(nextId, { at: t + ms, fn });
      return nextId;
    },
    clearTimeout(id) {
      timers.delete(id);
    },
    advance(ms) {
      const end = t + ms;
      for (;;) {
        let due = null;
        for (const [id, timer] of timers) {
          if (timer.at <= end && (!due || timer.at < due.timer.at)) due = { id, timer };
        }
        if (!due) break;
        timers.delete(due.id);
        t = due.timer.at;
        due.timer.fn();
      }
      t = end;
    },
    get waiting() {
      return timers.size;
    },
  };
}

/** A `run` for `latestRequest` whose calls are answered by hand: `calls[i].answer(v)` / `.error(e)`. */
export function manualRequests() {
  const calls = [];
  const run = (signal, ...args) =>
    new Promise((resolve, reject) => {
      signal.addEventListener('abort', () => reject(new DOMException('The operation was aborted.', 'AbortError')));
      calls.push({ signal, args, answer: resolve, error: reject });
    });
  return { calls, run };
}

/** Let every promise callback that is ready run. */
export function settle() {
  return new Promise((resolve) => setImmediate(resolve));
}
