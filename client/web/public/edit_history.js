// Undo and redo of a person's edits (app.js): every settled state of the
// page (the exact result shown for a surface spec and a placement) is a
// step. A step is a plain object, copied in and out; two steps are the same
// when their JSON is, ignoring the keys listed in `derived` (the ids a spec
// and a placement come with: the same spec flattens to the same id).
// No imports: the Node tests run it as it is.

const copy = (x) => (x == null ? x : JSON.parse(JSON.stringify(x)));

export class EditHistory {
  constructor({ limit = 100, derived = [] } = {}) {
    this.limit = limit;
    this.derived = new Set(derived);
    this.current = null;
    this.back = []; // older steps, newest last
    this.ahead = []; // undone steps, the next redo last
  }

  key(step) {
    return JSON.stringify(step, (k, v) => (this.derived.has(k) ? undefined : v));
  }

  // A new start (another model or surface chosen): `step` with nothing to
  // undo or redo.
  reset(step) {
    this.current = copy(step);
    this.back = [];
    this.ahead = [];
  }

  // A settled state after an edit: the one before goes back, and what was
  // undone is gone (a new branch). The same state again is no step, but
  // takes its ids. Returns whether it was a step.
  record(step) {
    if (this.current === null) {
      this.reset(step);
      return false;
    }
    if (this.key(step) === this.key(this.current)) {
      this.current = copy(step);
      return false;
    }
    this.back.push(this.current);
    if (this.back.length > this.limit) this.back.shift();
    this.ahead = [];
    this.current = copy(step);
    return true;
  }

  canUndo() {
    return this.back.length > 0;
  }
  canRedo() {
    return this.ahead.length > 0;
  }

  // The step shown last (a copy), or null before the first.
  currentStep() {
    return copy(this.current);
  }

  // The step to show now (a copy), or null when there is none.
  undo() {
    if (!this.canUndo()) return null;
    this.ahead.push(this.current);
    this.current = this.back.pop();
    return copy(this.current);
  }

  redo() {
    if (!this.canRedo()) return null;
    this.back.push(this.current);
    this.current = this.ahead.pop();
    return copy(this.current);
  }
}
