// meshoptimizer's parts, loaded when first asked for (its WebAssembly
// ready): meshopt('encoder') is MeshoptEncoder, meshopt('simplifier')
// MeshoptSimplifier; null where the package is not there (a viewer folder
// installed before it), and the callers leave their meshes as they are.
const parts = new Map();
const kExports = { encoder: 'MeshoptEncoder', simplifier: 'MeshoptSimplifier' };

export function meshopt(part) {
  if (!parts.has(part)) {
    parts.set(part, import(`meshoptimizer/${part}`)
      .then(async (module) => {
        const api = module[kExports[part]];
        await api.ready;
        return api;
      })
      .catch(() => null));
  }
  return parts.get(part);
}
