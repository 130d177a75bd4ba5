// Offline checks of the Kubernetes manifests in docker/k8s (no cluster):
// 1. every document against the Kubernetes OpenAPI schema of its kind
//    (npm kubernetes-models: types, formats, required fields);
// 2. what the schema cannot say: the surfdeform Deployment has startup,
//    readiness and liveness probes on the server's endpoints, a preStop, a
//    grace period that covers preStop + drain + the request budget, CPU and
//    memory requests and limits, slots and threads no more than its CPU limit,
//    and the Services, the autoscaler and the disruption budget select it.
// A manifest known to be broken must fail (the check can fail).
// Usage: node validate.mjs DIR
import fs from 'node:fs';
import path from 'node:path';
import { parseAllDocuments } from 'yaml';

const models = {
  'apps/v1/Deployment': 'kubernetes-models/apps/v1/Deployment',
  'v1/Service': 'kubernetes-models/v1/Service',
  'v1/ConfigMap': 'kubernetes-models/v1/ConfigMap',
  'v1/PersistentVolumeClaim': 'kubernetes-models/v1/PersistentVolumeClaim',
  'autoscaling/v2/HorizontalPodAutoscaler': 'kubernetes-models/autoscaling/v2/HorizontalPodAutoscaler',
  'policy/v1/PodDisruptionBudget': 'kubernetes-models/policy/v1/PodDisruptionBudget',
  'networking.k8s.io/v1/Ingress': 'kubernetes-models/networking.k8s.io/v1/Ingress',
};

async function schemaErrors(doc) {
  const key = `${doc.apiVersion}/${doc.kind}`;
  if (doc.kind === 'Kustomization') return [];
  const module = models[key];
  if (!module) return [`${key}: no schema known here (add it to tests/k8s/validate.mjs)`];
  const Model = (await import(module))[doc.kind];
  try {
    new Model(doc).validate();
    return [];
  } catch (e) {
    return [`${key} ${doc.metadata?.name}: ${e.message}`];
  }
}

function env(container, name) {
  return (container.env || []).find((e) => e.name === name)?.value;
}
function cpus(quantity) {
  const q = String(quantity);
  return q.endsWith('m') ? Number(q.slice(0, -1)) / 1000 : Number(q);
}
function matches(selector, labels) {
  return Object.entries(selector || {}).every(([k, v]) => labels[k] === v);
}

function policyErrors(docs) {
  const errors = [];
  const fail = (m) => errors.push(m);
  const deployment = docs.find((d) => d.kind === 'Deployment' && d.metadata.name === 'surfdeform');
  if (!deployment) return ['no Deployment named surfdeform'];
  const pod = deployment.spec.template;
  const labels = pod.metadata.labels;
  const c = pod.spec.containers.find((x) => x.name === 'surfdeform');
  if (!c) return ['the surfdeform Deployment has no container named surfdeform'];
  const probe = (name, p) => {
    if (!c[name]?.httpGet) fail(`${name}: an HTTP probe is missing`);
    else if (c[name].httpGet.path !== p) fail(`${name}: probes ${c[name].httpGet.path}, not ${p}`);
  };
  probe('startupProbe', '/healthz');
  probe('readinessProbe', '/readyz');
  probe('livenessProbe', '/healthz');
  const preStop = c.lifecycle?.preStop?.exec?.command;
  const preStopS = preStop && preStop[0] === 'sleep' ? Number(preStop[1]) : NaN;
  if (!(preStopS > 0)) fail('preStop: expected [sleep, N]');
  const drainS = Number(env(c, 'SURFDEFORM_DRAIN_SECONDS'));
  const budgetS = Number(env(c, 'SURFDEFORM_REQUEST_BUDGET_MS')) / 1000;
  if (!(drainS > 0)) fail('SURFDEFORM_DRAIN_SECONDS is not set');
  if (!(budgetS > 0)) fail('SURFDEFORM_REQUEST_BUDGET_MS is not set');
  const grace = pod.spec.terminationGracePeriodSeconds;
  if (!(grace >= preStopS + drainS + budgetS)) {
    fail(`terminationGracePeriodSeconds ${grace} < preStop ${preStopS} + drain ${drainS} + request budget ${budgetS}`);
  }
  for (const kind of ['requests', 'limits']) {
    for (const r of ['cpu', 'memory']) {
      if (!c.resources?.[kind]?.[r]) fail(`resources.${kind}.${r} is missing`);
    }
  }
  const cpuLimit = cpus(c.resources?.limits?.cpu);
  for (const name of ['SURFDEFORM_MAX_IN_FLIGHT', 'SURFDEFORM_ENGINE_THREADS']) {
    const v = Number(env(c, name));
    if (!(v >= 1 && v <= Math.max(1, Math.floor(cpuLimit)))) {
      fail(`${name} is ${env(c, name)}: set it to the CPU limit (${cpuLimit}); the server sees the node's cores`);
    }
  }
  if (!env(c, 'SURFDEFORM_REDIS')) fail('SURFDEFORM_REDIS is not set: replicas would not share surfaces');
  if (!matches(deployment.spec.selector.matchLabels, labels)) fail("the Deployment's selector does not match its pods");
  const svc = docs.find((d) => d.kind === 'Service' && d.metadata.name === 'surfdeform');
  if (!svc || !matches(svc.spec.selector, labels)) fail('no Service named surfdeform selects the pods');
  const hpa = docs.find((d) => d.kind === 'HorizontalPodAutoscaler');
  if (!hpa || hpa.spec.scaleTargetRef.name !== 'surfdeform') fail('no autoscaler targets the Deployment');
  else if (!hpa.spec.metrics.some((m) => m.resource?.name === 'cpu')) fail('the autoscaler does not scale on CPU');
  const pdb = docs.find((d) => d.kind === 'PodDisruptionBudget');
  if (!pdb || !matches(pdb.spec.selector.matchLabels, labels)) fail('no PodDisruptionBudget selects the pods');
  else if (pdb.spec.minAvailable >= (hpa?.spec.minReplicas ?? deployment.spec.replicas)) {
    fail('the PodDisruptionBudget allows no disruption at the minimum replica count');
  }
  const redis = docs.find((d) => d.kind === 'Service' && d.metadata.name === 'surfdeform-redis');
  if (!redis || !env(c, 'SURFDEFORM_REDIS').includes(`//${redis.metadata.name}:`)) {
    fail('SURFDEFORM_REDIS does not name the Redis Service');
  }
  return errors;
}

function load(dir) {
  const docs = [];
  for (const file of fs.readdirSync(dir).filter((f) => f.endsWith('.yaml') && !f.startsWith('.'))) {
    for (const d of parseAllDocuments(fs.readFileSync(path.join(dir, file), 'utf8'))) {
      if (d.errors.length) throw new Error(`${file}: ${d.errors[0].message}`);
      docs.push({ file, doc: d.toJS() });
    }
  }
  return docs;
}

const dir = process.argv[2];
const loaded = load(dir);
let errors = [];
for (const { file, doc } of loaded) errors.push(...(await schemaErrors(doc)).map((e) => `${file}: ${e}`));
errors.push(...policyErrors(loaded.map((l) => l.doc)));

// The checks must be able to fail: a broken copy of the Deployment.
const broken = structuredClone(
  loaded.find((l) => l.doc.kind === 'Deployment' && l.doc.metadata.name === 'surfdeform').doc,
);
broken.spec.template.spec.containers[0].ports[0].containerPort = 'eighty';
broken.spec.template.spec.terminationGracePeriodSeconds = 5;
delete broken.spec.template.spec.containers[0].readinessProbe;
const brokenSchema = await schemaErrors(broken);
const brokenPolicy = policyErrors([broken]);
if (brokenSchema.length === 0) errors.push('self-test: a string containerPort passed the schema check');
if (!brokenPolicy.some((e) => e.includes('terminationGracePeriodSeconds')))
  errors.push('self-test: a short grace period passed');
if (!brokenPolicy.some((e) => e.includes('readinessProbe'))) errors.push('self-test: a missing readiness probe passed');

if (errors.length) {
  for (const e of errors) console.error('FAIL: ' + e);
  process.exit(1);
}
console.log(
  `k8s manifests: ${loaded.length} documents pass the Kubernetes schemas and the drain, probe and resource rules`,
);
