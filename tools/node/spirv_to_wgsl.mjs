// SPIR-V -> WGSL by naga (npm package naga-wasm, pinned by package-lock.json), for
// `leanfade shaders --lang wgsl`: every IN/NAME.spv (combined samplers already split) is parsed,
// validated and written as OUT/NAME.wgsl, or, where naga refuses it (a construct WGSL lacks),
// OUT/NAME.refused with naga's reason on one line. Exits 1 only when it cannot run at all.
//
// Usage: node spirv_to_wgsl.mjs IN OUT
import { readdirSync, readFileSync, writeFileSync } from "node:fs";
import { join } from "node:path";

// The shaders sample with implicit derivatives inside branches on per-material settings, uniform
// in practice but not provably so by WGSL's static uniformity analysis.
const kPreamble = "diagnostic(off, derivative_uniformity);\n";

const [input, output] = process.argv.slice(2);
if (!input || !output) {
  console.error("usage: node spirv_to_wgsl.mjs IN OUT");
  process.exit(2);
}
let naga;
try {
  naga = await import("naga-wasm");
} catch (e) {
  console.error(`naga-wasm is not installed beside ${import.meta.filename ?? "the translator"} ` +
                `(npm ci in its folder; scripts/install-deps.sh): ${String(e).split("\n")[0]}`);
  process.exit(1);
}
// naga's message and, from its report, the notes that say why ("= ..." lines).
function reason(error) {
  const notes = String(error.formatted ?? "")
    .split("\n")
    .filter((line) => line.trim().startsWith("= "))
    .map((line) => line.trim().slice(2));
  return [String(error.message ?? error).split("\n")[0], ...notes].join("; ");
}

for (const name of readdirSync(input).filter((n) => n.endsWith(".spv")).sort()) {
  const bytes = readFileSync(join(input, name));
  const words = new Uint32Array(bytes.buffer, bytes.byteOffset, bytes.byteLength / 4);
  let module, info;
  try {
    module = naga.parseSpirv(words);
    info = naga.validate(module);
    const text = naga.writeWgsl(module, info, {});
    writeFileSync(join(output, name.replace(/\.spv$/, ".wgsl")), kPreamble + text);
  } catch (e) {
    writeFileSync(join(output, name.replace(/\.spv$/, ".refused")), reason(e) + "\n");
  } finally {
    info?.free();
    module?.free();
  }
}
