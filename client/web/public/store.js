// The viewer's one store: the page's state as one object, changed only by
// named actions, with subscribers that render it.
//
// An action is a function (state, ...args) -> patch: the fields it changes,
// merged into a new state object. The state and every plain object or array
// in it are frozen, so a write anywhere but an action throws (modules are
// strict code). Typed arrays, ArrayBuffers and class instances (a model's
// bytes and positions) are held as they are, and the fields named in
// `shallow` (large replies of the server, read only) are frozen at their top
// level: a control-point drag gets a field of thousands of small arrays at
// every pose. After each action every
// subscriber is called with (state, previous, name); a panel renders what
// changed by comparing the two (a changed field is a new object).

// `value` and the plain objects and arrays in it, frozen.
export function deepFreeze(value) {
  if (value === null || typeof value !== 'object' || Object.isFrozen(value)) return value;
  const proto = Object.getPrototypeOf(value);
  if (!Array.isArray(value) && proto !== Object.prototype && proto !== null) return value;
  Object.freeze(value);
  for (const v of Object.values(value)) deepFreeze(v);
  return value;
}

// `value` as plain, unfrozen data: a copy to hand to code that changes what
// it holds (the sheet view moves the placement it is given).
export function thawed(value) {
  if (value === null || typeof value !== 'object') return value;
  if (Array.isArray(value)) return value.map(thawed);
  const proto = Object.getPrototypeOf(value);
  if (proto !== Object.prototype && proto !== null) return value;
  return Object.fromEntries(Object.entries(value).map(([k, v]) => [k, thawed(v)]));
}

export function createStore(initial, actions, { shallow = [] } = {}) {
  const freeze = (next) => {
    for (const key of shallow) if (next[key] && typeof next[key] === 'object') Object.freeze(next[key]);
    return deepFreeze(next);
  };
  let state = freeze({ ...initial });
  const subscribers = [];
  const log = []; // the last actions, by name (for the test surface)
  return {
    get state() {
      return state;
    },
    // Applies action `name` with `args`; the new state.
    dispatch(name, ...args) {
      const action = actions[name];
      if (!action) throw new Error(`no action "${name}"`);
      const patch = action(state, ...args);
      if (!patch) return state; // nothing changed
      for (const key of Object.keys(patch)) {
        if (!(key in state)) throw new Error(`action "${name}" sets "${key}", which the state does not have`);
      }
      const previous = state;
      state = freeze({ ...state, ...patch });
      log.push(name);
      if (log.length > 64) log.shift();
      // Subscribers render; they do not dispatch.
      for (const s of subscribers) s(state, previous, name);
      return state;
    },
    // fn(state, previous, name) after every action; returns the unsubscribe.
    subscribe(fn) {
      subscribers.push(fn);
      return () => subscribers.splice(subscribers.indexOf(fn), 1);
    },
    actionNames: () => Object.keys(actions),
    recentActions: () => [...log],
  };
}
