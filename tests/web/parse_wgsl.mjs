// Parses every FOLDER/*.wgsl with wgsl_reflect (a WGSL parser independent of naga, which wrote
// them) and prints, as JSON, each file's entry points and its resources by binding:
// { "scene_lean.frag.wgsl": { "entries": ["fragment main"], "bindings": { "0": "u_lean", ... } } }
// or { "file": { "error": "..." } } for a file it cannot parse.
//
// Usage: node parse_wgsl.mjs WGSL_REFLECT_MODULE FOLDER
import { readdirSync, readFileSync } from 'node:fs';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';

const [modulePath, folder] = process.argv.slice(2);
const { WgslReflect } = await import(pathToFileURL(modulePath).href);
const out = {};
for (const name of readdirSync(folder).filter((n) => n.endsWith('.wgsl')).sort()) {
  try {
    const reflect = new WgslReflect(readFileSync(join(folder, name), 'utf8'));
    const bindings = {};
    for (const list of [reflect.uniforms, reflect.textures, reflect.samplers])
      for (const r of list) bindings[String(r.binding)] = { name: r.name, group: r.group };
    const entries = [];
    for (const stage of ['vertex', 'fragment', 'compute'])
      for (const e of reflect.entry[stage] ?? []) entries.push(`${stage} ${e.name}`);
    out[name] = { entries, bindings };
  } catch (error) {
    out[name] = { error: String(error) };
  }
}
process.stdout.write(JSON.stringify(out));
