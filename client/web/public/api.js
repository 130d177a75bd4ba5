// The surfdeform REST API from the browser. Every error reply is RFC 9457
// problem+json; it becomes an ApiError whose message a person can act on.

export class ApiError extends Error {
  constructor(status, problem) {
    let text = problem.detail || problem.title || `HTTP ${status}`;
    const extra = [];
    if (problem.field) extra.push(`field ${problem.field}`);
    if (problem.limit !== undefined && problem.actual !== undefined) {
      extra.push(`limit ${problem.limit}, actual ${problem.actual}`);
    }
    if (extra.length) text += ` (${extra.join('; ')})`;
    super(`${problem.title || 'Error'} (${status}): ${text}`);
    this.status = status;
    this.problem = problem;
  }
}

async function checked(response) {
  if (response.ok) return response;
  let problem;
  try {
    problem = await response.json();
  } catch {
    problem = { title: response.statusText, detail: `the server answered ${response.status}` };
  }
  throw new ApiError(response.status, problem);
}

// Every call takes an optional AbortSignal last (scheduler.js gives each
// request its lane's): an aborted request rejects with an AbortError.

// POST /v1/surfaces: {id, cached, grid, method, quality, timing_ms}, and
// with fieldSide the field of that side ({n, bounds, positions, normals,
// on_sheet}) in the same reply.
export async function createSurface(request, fieldSide = 0, signal = undefined) {
  const r = await checked(
    await fetch(fieldSide ? `/v1/surfaces?field=${fieldSide}` : '/v1/surfaces', {
      method: 'POST',
      signal,
      headers: { 'Content-Type': 'application/json' },
      body: JSON.stringify(request),
    }),
  );
  return r.json();
}

// GET /v1/surfaces/{id}: the summary plus points (surface) and flat (sheet).
export async function getSurface(id, signal = undefined) {
  return (await checked(await fetch(`/v1/surfaces/${id}`, { signal }))).json();
}

// POST /v1/surfaces/{id}/map: marks between the sheet and the surface
// ({points}, {polylines, tolerance, max_segment} or {surface_points}).
export async function mapOnSurface(id, request, signal = undefined) {
  const r = await checked(
    await fetch(`/v1/surfaces/${id}/map`, {
      method: 'POST',
      signal,
      headers: { 'Content-Type': 'application/json' },
      body: JSON.stringify(request),
    }),
  );
  return r.json();
}

// POST /v1/models: the mesh file's bytes, once; {id, format, vertices, ...}.
export async function uploadModel(meshBytes, meshName, signal = undefined) {
  const form = new FormData();
  form.append('mesh', new Blob([meshBytes]), meshName);
  const r = await checked(await fetch('/v1/models', { method: 'POST', body: form, signal }));
  return r.json();
}

// The server's id of each mesh this page has uploaded, by its bytes.
const modelIds = new WeakMap();

async function modelIdOf(meshBytes, meshName, signal) {
  if (!modelIds.has(meshBytes)) modelIds.set(meshBytes, (await uploadModel(meshBytes, meshName, signal)).id);
  return modelIds.get(meshBytes);
}

// POST /v1/deform with the mesh named by its id: uploaded on first use, and
// again when the server no longer holds it (404 unknown_model). Returns the
// bytes, the stats header and the Server-Timing entries.
export async function deform(meshBytes, meshName, params, accept, signal = undefined) {
  return postByModel('/v1/deform', meshBytes, meshName, params, accept, signal);
}

// POST /v1/animate: the same, a GLB of morph targets back.
export async function animate(meshBytes, meshName, params, signal = undefined) {
  return postByModel('/v1/animate', meshBytes, meshName, params, 'model/gltf-binary', signal);
}

async function postByModel(path, meshBytes, meshName, params, accept, signal) {
  // A text is its own model: the server shapes it (no mesh to send).
  if (params.text) return post(path, params, accept, signal);
  try {
    return await post(path, { ...params, model_id: await modelIdOf(meshBytes, meshName, signal) }, accept, signal);
  } catch (e) {
    if (!(e instanceof ApiError) || e.problem.code !== 'unknown_model') throw e;
    modelIds.delete(meshBytes); // evicted: upload again, once
    return post(path, { ...params, model_id: await modelIdOf(meshBytes, meshName, signal) }, accept, signal);
  }
}

// POST /v1/text: the text's mesh alone, flat, in mm, for the
// preview (binary PLY: a fifth of the OBJ's bytes, read without parsing
// text); `signal` aborts it (a newer keystroke wins).
export async function textMesh(text, signal) {
  const r = await checked(
    await fetch('/v1/text', {
      method: 'POST',
      signal,
      headers: { 'Content-Type': 'application/json' },
      body: JSON.stringify({ text, output: { format: 'ply' } }),
    }),
  );
  return { bytes: await r.arrayBuffer(), stats: JSON.parse(r.headers.get('X-Surfdeform-Stats') || '{}') };
}

// POST /v1/parts: a printable part ({surface_id, body, printer, output}),
// its bytes and report; with report, the report alone (its JSON).
export async function makePart(request, { report = false, signal = undefined } = {}) {
  if (report) {
    const r = await checked(
      await fetch('/v1/parts?report=json', {
        method: 'POST',
        signal,
        headers: { 'Content-Type': 'application/json' },
        body: JSON.stringify(request),
      }),
    );
    return { report: await r.json() };
  }
  const { bytes, stats } = await post('/v1/parts', request, undefined, signal);
  return { bytes, report: stats };
}

// GET /v1/fonts: the built-in fonts and the scripts each covers.
export async function fonts(signal = undefined) {
  return (await checked(await fetch('/v1/fonts', { signal }))).json();
}

async function post(path, params, accept, signal) {
  const headers = { 'Content-Type': 'application/json' };
  if (accept) headers.Accept = accept;
  // A load balancer routes by them (docker/nginx.conf), so that the replica
  // that already holds this surface (or model) serves it.
  if (params.surface_id) headers['X-Surfdeform-Surface-Id'] = params.surface_id;
  if (params.model_id) headers['X-Surfdeform-Model-Id'] = params.model_id;
  const r = await checked(await fetch(path, { method: 'POST', body: JSON.stringify(params), headers, signal }));
  const stats = JSON.parse(r.headers.get('X-Surfdeform-Stats') || '{}');
  const timing = {};
  for (const part of (r.headers.get('Server-Timing') || '').split(',')) {
    const m = part.trim().match(/^([\w-]+);dur=([\d.]+)/);
    if (m) timing[m[1]] = Number(m[2]);
  }
  return { bytes: await r.arrayBuffer(), stats, timing };
}
