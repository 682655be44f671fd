// The Khronos glTF-Validator (npm gltf-validator, pinned by tools/node/package-lock.json) on a
// .gltf or .glb and the files it names, read from its folder. Prints the validator's report as
// JSON (issues: numErrors, numWarnings, messages with code, severity, pointer and message).
//
// Usage: node validate_gltf.mjs VALIDATOR_MODULE FILE
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { dirname, join } from 'node:path';

const [validatorModule, file] = process.argv.slice(2);
const validator = createRequire(import.meta.url)(validatorModule);
const folder = dirname(file);
const report = await validator.validateBytes(new Uint8Array(readFileSync(file)), {
  uri: file,
  maxIssues: 100,
  externalResourceFunction: async (uri) => new Uint8Array(readFileSync(join(folder, decodeURIComponent(uri)))),
});
process.stdout.write(JSON.stringify(report));
