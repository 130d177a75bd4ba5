// Validates GLB files with the Khronos glTF validator; exits non-zero when any
// file has errors. Usage: node validate.mjs file.glb ...
import { readFile } from 'node:fs/promises';
import validator from 'gltf-validator';

let failed = 0;
for (const path of process.argv.slice(2)) {
  const data = new Uint8Array(await readFile(path));
  const report = await validator.validateBytes(data, {
    maxIssues: 100,
    externalResourceFunction: () => Promise.reject(new Error('no external resources')),
  });
  const { numErrors, numWarnings } = report.issues;
  console.log(`${path}: ${numErrors} errors, ${numWarnings} warnings`);
  for (const m of report.issues.messages) {
    if (m.severity === 0) console.log(`  error ${m.code}: ${m.message} at ${m.pointer ?? ''}`);
  }
  if (numErrors > 0) failed += 1;
}
process.exit(failed > 0 ? 1 : 0);
