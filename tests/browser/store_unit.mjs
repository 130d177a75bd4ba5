// The viewer's store (client/web/public/store.js) and its actions
// (viewer_state.js) in Node: the state changes only through named actions,
// a write anywhere else throws, subscribers see each change once with the
// state before it, and the actions that carry the page's rules keep them.
import assert from 'node:assert/strict';

import { createStore, thawed } from '../../client/web/public/store.js';
import { actions, initialState } from '../../client/web/public/viewer_state.js';

let checks = 0;
const check = (name, f) => {
  f();
  ++checks;
  console.log(`ok   ${name}`);
};

const controls = {
  preset: 'figure10',
  sample: 'text',
  text: { string: 'Ada', font: 'DejaVuSans', size_mm: 0.6, depth_mm: 0.05 },
  settings: { up: 'auto', anchor: 'center', rigid: 'none', subdivision: 'adaptive', distortion: false },
};
const bezier = {
  kind: 'bezier',
  degree_u: 1,
  degree_v: 1,
  control_points: [
    [0, 0, 0],
    [1, 0, 0],
    [0, 1, 0],
    [1, 1, 0],
  ],
};
const fresh = () => createStore(initialState(controls), actions);

check('the state is frozen: a write outside an action throws', () => {
  const store = fresh();
  assert.throws(() => {
    store.state.surfaceId = 'x';
  }, TypeError);
  assert.throws(() => {
    store.state.placement.rotation_deg = 5;
  }, TypeError);
  store.dispatch('surfaceChosen', bezier);
  assert.throws(() => {
    store.state.spec.control_points[0][2] = 1;
  }, TypeError);
  assert.equal(store.state.spec.control_points[0][2], 0);
});

check('an unknown action, or one setting a field the state lacks, throws', () => {
  const store = createStore({ a: 1 }, { bad: () => ({ b: 2 }) });
  assert.throws(() => store.dispatch('nothing'), /no action "nothing"/);
  assert.throws(() => store.dispatch('bad'), /sets "b"/);
  assert.equal(store.state.b, undefined);
});

check('subscribers see each change once, with the state before it and the action', () => {
  const store = fresh();
  const seen = [];
  const stop = store.subscribe((s, old, name) =>
    seen.push([name, old.placement.rotation_deg, s.placement.rotation_deg]),
  );
  store.dispatch('placed', { rotation_deg: 30 });
  store.dispatch('errorCleared'); // no error: nothing changes, nobody is told
  stop();
  store.dispatch('placed', { rotation_deg: 60 });
  assert.deepEqual(seen, [['placed', 0, 30]]);
  assert.deepEqual(store.recentActions(), ['placed', 'placed']);
});

check("a model's bytes and positions are held as they are, not frozen", () => {
  const store = fresh();
  const model = { name: 'm.ply', bytes: new ArrayBuffer(8), positions: new Float32Array([1, 2, 3]), lod: null };
  store.dispatch('modelChosen', model);
  store.state.model.positions[0] = 7; // a typed array stays writable
  assert.equal(store.state.model.positions[0], 7);
  store.dispatch('modelSimplified', model, { triangles: [4, 1], error: 1e-4 });
  assert.deepEqual(store.state.model.lod.triangles, [4, 1]);
  // The lod of a model no longer shown is dropped.
  store.dispatch('modelSimplified', model, { triangles: [9, 9], error: 0 });
  assert.deepEqual(store.state.model.lod.triangles, [4, 1]);
});

check('a control point moved to where it is makes no new surface version', () => {
  const store = fresh();
  store.dispatch('surfaceChosen', bezier);
  const v = store.state.specVersion;
  store.dispatch('controlPointMoved', 1, [1, 0, 0]);
  assert.equal(store.state.specVersion, v);
  store.dispatch('controlPointMoved', 1, [1, 0, 0.5]);
  assert.equal(store.state.specVersion, v + 1);
  assert.deepEqual(store.state.spec.control_points[1], [1, 0, 0.5]);
  assert.deepEqual(bezier.control_points[1], [1, 0, 0]); // the preset's spec is not changed
});

check('an exact result fitted to the sheet gives the placement its scale, once', () => {
  const store = fresh();
  assert.equal(store.state.fitNext, true);
  const stats = { surface_id: 's1', placement: { scale: 2.5, up: '+y' } };
  store.dispatch('exactShown', stats, { round_trip_ms: 1 });
  assert.equal(store.state.placement.scale, 2.5);
  assert.equal(store.state.fitNext, false);
  assert.equal(store.state.upResolved, '+y');
  assert.equal(JSON.parse(store.state.exactShown)[1].scale, 2.5);
  store.dispatch('scaled', 3);
  store.dispatch('exactShown', { surface_id: 's1', placement: { scale: 9, up: '+y' } }, {});
  assert.equal(store.state.placement.scale, 3); // not fitted: the page's own scale stays
});

check('a new up axis fits the model again', () => {
  const store = fresh();
  store.dispatch('scaled', 3);
  store.dispatch('settingChanged', 'anchor', 'bottom');
  assert.equal(store.state.fitNext, false);
  store.dispatch('settingChanged', 'up', '+z');
  assert.equal(store.state.fitNext, true);
  assert.equal(store.state.settings.up, '+z');
});

check('a new sheet centres the model only when it is new or asked to', () => {
  const store = fresh();
  store.dispatch('sheetShown', [['stress', '0']], [1, 2]);
  assert.deepEqual(store.state.placement.center, [1, 2]);
  assert.equal(store.state.recentre, false);
  store.dispatch('sheetShown', [], [5, 5]);
  assert.deepEqual(store.state.placement.center, [1, 2]);
});

check('an undo restores the step, and bumps the surface version only where the spec differs', () => {
  const store = fresh();
  store.dispatch('surfaceChosen', bezier);
  const v = store.state.specVersion;
  const placement = { center: [0.2, 0.3], rotation_deg: 10, scale: 1 };
  store.dispatch('stepRestored', { spec: thawed(bezier), placement, placementSheet: 'a' });
  assert.equal(store.state.specVersion, v);
  assert.deepEqual(store.state.placement, placement);
  const raised = thawed(bezier);
  raised.control_points[3][2] = 1;
  store.dispatch('stepRestored', { spec: raised, placement, placementSheet: 'b' });
  assert.equal(store.state.specVersion, v + 1);
  assert.equal(store.state.placementSheet, 'b');
});

check('a placement from the sheet view is copied: the view may keep moving its own', () => {
  const store = fresh();
  const own = { center: [1, 1], rotation_deg: 0, scale: 1 };
  store.dispatch('placed', own);
  own.center[0] = 9; // the sheet view drags on
  assert.deepEqual(store.state.placement.center, [1, 1]);
  const copy = thawed(store.state.placement);
  copy.center[1] = 4;
  assert.equal(store.state.placement.center[1], 1);
});

check('a field named shallow is frozen at its top only (a large reply, read only)', () => {
  const store = createStore(
    { field: null, other: null },
    { got: (s, field, other) => ({ field, other }) },
    {
      shallow: ['field'],
    },
  );
  const field = { positions: [[0, 0, 0]] };
  store.dispatch('got', field, { positions: [[0, 0, 0]] });
  assert.throws(() => {
    store.state.field.positions = [];
  }, TypeError);
  assert.equal(Object.isFrozen(store.state.field.positions), false);
  assert.equal(Object.isFrozen(store.state.other.positions[0]), true);
});

check('status: an error stays until cleared, and settles as "error"', () => {
  const store = fresh();
  store.dispatch('failed', 'the server said no');
  assert.equal(store.state.status, 'error');
  store.dispatch('busy');
  store.dispatch('settled');
  assert.equal(store.state.status, 'error');
  store.dispatch('errorCleared');
  store.dispatch('settled');
  assert.equal(store.state.status, 'ready');
});

console.log(`store: ${checks} checks passed`);
