// The printable-part panel: the current surface thickened into a closed
// solid (POST /v1/parts, by the surface's id), checked by the server, its
// report shown, downloaded as 3MF or STL.
import { makePart } from './api.js';
import { $, fmt, list, saveBlob } from './dom.js';

// The report as the panel lists it.
function reportEntries(r) {
  const c = r.checks || {};
  const sound = c.closed && c.oriented && !c.self_intersections && c.volume_positive;
  const size = r.bounding_box_mm?.size || [0, 0, 0];
  return [
    ['part', sound ? 'closed and sound' : 'NOT sound'],
    ['volume', `${fmt(r.volume_mm3, 5)} mm³`],
    ['box', `${size.map((x) => fmt(x, 4)).join(' × ')} mm`],
    ['triangles', r.triangles],
    ['thinnest wall', `${fmt(r.thinnest_wall_mm, 3)} mm`],
    ...(r.warnings || []).map((w) => ['warning', w]),
  ];
}

export function installPartPanel(page) {
  const { store } = page;

  const request = (format) => {
    const minWall = Number($('part-min-wall').value) || 0;
    return {
      surface_id: store.state.surfaceId,
      body: { thickness_mm: Number($('part-thickness').value), side: $('part-side').value },
      ...(minWall > 0 ? { printer: { min_wall_mm: minWall } } : {}),
      ...(format ? { output: { format } } : {}),
    };
  };

  // The part's report, or the part as `format` saved; the "part" lane: a
  // newer ask aborts an older one.
  async function part(format) {
    if (!store.state.surfaceId) return;
    try {
      const made = await page.latest('part', (signal) => makePart(request(format), { report: !format, signal }));
      if (!made) return;
      list($('part-report'), reportEntries(made.report));
      if (format) saveBlob(new Blob([made.bytes]), `part.${format}`);
      page.showError(null);
    } catch (e) {
      $('part-report').replaceChildren();
      page.showError(e);
    }
  }

  $('part-check').addEventListener('click', () => part(null));
  $('download-3mf').addEventListener('click', () => part('3mf'));
  $('download-stl').addEventListener('click', () => part('stl'));
  // A new surface: the last report was of another one.
  store.subscribe((s, old) => {
    if (s.surfaceId !== old.surfaceId) $('part-report').replaceChildren();
  });
}
