// Small helpers the panels share: elements by id, lists of figures, numbers
// as the page prints them, files saved.

export const $ = (id) => document.getElementById(id);

// `el` (a <dl>) filled with [term, value] pairs.
export function list(el, entries) {
  el.replaceChildren(
    ...entries.flatMap(([k, v]) => {
      const dt = document.createElement('dt');
      dt.textContent = k;
      const dd = document.createElement('dd');
      dd.textContent = v;
      return [dt, dd];
    }),
  );
}

export const fmt = (x, digits = 4) => (typeof x === 'number' ? Number(x.toPrecision(digits)).toString() : String(x));

// `blob` saved as the file `name`.
export function saveBlob(blob, name) {
  const a = document.createElement('a');
  a.href = URL.createObjectURL(blob);
  a.download = name;
  a.click();
  setTimeout(() => URL.revokeObjectURL(a.href), 10000);
}

// Indented JSON whose arrays of numbers stay on a line (a control point, a centre).
export function readableJson(value) {
  return JSON.stringify(value, null, 2).replace(
    /\[\s+([^[\]{}]*?)\s+\]/g,
    (_, inner) => `[${inner.split(/,\s+/).join(', ')}]`,
  );
}

// Resolves once the next frame has been drawn (or skipped: nothing changed),
// or after 250 ms where no frame comes (a hidden tab draws none).
export function afterNextFrame() {
  return new Promise((resolve) => {
    const timer = setTimeout(resolve, 250);
    requestAnimationFrame(() =>
      setTimeout(() => {
        clearTimeout(timer);
        resolve();
      }, 0),
    );
  });
}
