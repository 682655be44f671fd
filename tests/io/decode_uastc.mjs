// Transcodes every level of a UASTC KTX2 file to RGBA8 with three.js's Basis Universal
// transcoder (its WebAssembly build, three/examples/jsm/libs/basis): a decoder independent of the
// encoder that wrote the file. Writes OUT/level<N>.rgba (rows top first) and prints one JSON
// line: { "levels": N, "width": W, "height": H, "sizes": [[w, h], ...] }.
//
// Usage: node decode_uastc.mjs BASIS_FOLDER FILE.ktx2 OUT
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import vm from 'node:vm';

const [basisFolder, file, out] = process.argv.slice(2);
// basis_transcoder.js is a classic script defining BASIS (as a browser's <script> would load it).
const context = { console, WebAssembly, performance, TextDecoder, setTimeout, clearTimeout };
vm.createContext(context);
vm.runInContext(`${readFileSync(join(basisFolder, 'basis_transcoder.js'), 'utf8')}\nthis.BASIS = BASIS;`, context);
const basis = await context.BASIS({ wasmBinary: readFileSync(join(basisFolder, 'basis_transcoder.wasm')) });
basis.initializeBasis();
const kRgba32 = 13;  // transcoder_texture_format::cTFRGBA32
const ktx2 = new basis.KTX2File(new Uint8Array(readFileSync(file)));
if (!ktx2.isValid() || !ktx2.isUASTC() || !ktx2.startTranscoding()) {
  console.error(`${file}: not a UASTC KTX2 file the transcoder takes`);
  process.exit(1);
}
const sizes = [];
for (let level = 0; level < ktx2.getLevels(); ++level) {
  const info = ktx2.getImageLevelInfo(level, 0, 0);
  const rgba = new Uint8Array(ktx2.getImageTranscodedSizeInBytes(level, 0, 0, kRgba32));
  if (!ktx2.transcodeImage(rgba, level, 0, 0, kRgba32, 0, -1, -1)) {
    console.error(`${file}: level ${level} does not transcode`);
    process.exit(1);
  }
  writeFileSync(join(out, `level${level}.rgba`), rgba);
  sizes.push([info.origWidth, info.origHeight]);
}
console.log(JSON.stringify({ levels: ktx2.getLevels(), width: ktx2.getWidth(), height: ktx2.getHeight(), sizes }));
ktx2.close();
ktx2.delete();
