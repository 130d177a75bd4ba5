// One scheduler for every request the viewer makes. Requests run in named
// lanes ("surface", "exact", "live", "text", ...); a lane runs one task at a
// time, and the newest task wins, in one of two ways:
//  - "abort": a new task aborts the one in flight (its AbortController's
//    signal, which fetch honours) and starts at once: a keystroke's text, a
//    new surface, a download;
//  - "queue": a new task waits for the one in flight and then runs; only the
//    newest waiting task runs (older waiting ones are dropped): an exact
//    deformation or a live pose, whose request in flight is worth finishing
//    (the server's work is half done and its result still shows something).
// A task is `async (signal) => value`. run() resolves to {done: true, value}
// when the task ran to its end, {done: false} when a newer task superseded it
// (aborted, or dropped before it started); a task's own error rejects, unless
// it was aborted. whenIdle() resolves once no lane has work in flight or
// waiting (the browser tests wait on it).

export class Scheduler {
  constructor() {
    this.lanes = new Map();
    this.idleWaiters = [];
  }

  lane(name) {
    if (!this.lanes.has(name)) this.lanes.set(name, { running: null, waiting: null });
    return this.lanes.get(name);
  }

  run(name, task, { policy = 'abort' } = {}) {
    const lane = this.lane(name);
    return new Promise((resolve, reject) => {
      const entry = { task, resolve, reject, controller: new AbortController() };
      if (!lane.running) return this.start(name, lane, entry);
      if (policy === 'abort') {
        lane.running.controller.abort();
        if (lane.waiting) lane.waiting.resolve({ done: false });
        lane.waiting = null;
        return this.start(name, lane, entry);
      }
      if (lane.waiting) lane.waiting.resolve({ done: false });
      lane.waiting = entry;
    });
  }

  async start(name, lane, entry) {
    lane.running = entry;
    const { signal } = entry.controller;
    try {
      const value = await entry.task(signal);
      entry.resolve(signal.aborted ? { done: false } : { done: true, value });
    } catch (e) {
      if (signal.aborted || e?.name === 'AbortError') entry.resolve({ done: false });
      else entry.reject(e);
    } finally {
      if (lane.running === entry) {
        lane.running = null;
        const next = lane.waiting;
        lane.waiting = null;
        if (next) this.start(name, lane, next);
        else this.settle();
      }
    }
  }

  // Whether `name` (any lane when none is named) has a task in flight.
  busy(name) {
    if (name !== undefined) return Boolean(this.lanes.get(name)?.running);
    return [...this.lanes.values()].some((l) => l.running || l.waiting);
  }

  // Whether a task of `name` waits for the one in flight.
  queued(name) {
    return Boolean(this.lanes.get(name)?.waiting);
  }

  // Aborts what `name` runs and drops what waits.
  cancel(name) {
    const lane = this.lanes.get(name);
    if (!lane) return;
    if (lane.waiting) lane.waiting.resolve({ done: false });
    lane.waiting = null;
    lane.running?.controller.abort();
  }

  whenIdle() {
    if (!this.busy()) return Promise.resolve();
    return new Promise((resolve) => this.idleWaiters.push(resolve));
  }

  settle() {
    if (this.busy()) return;
    const waiters = this.idleWaiters;
    this.idleWaiters = [];
    for (const resolve of waiters) resolve();
  }
}

// The page's one scheduler.
export const scheduler = new Scheduler();
