// RGBA8 MIP chains -> KTX2 files of Basis Universal UASTC (the payload glTF's KHR_texture_basisu
// takes), for `leanfade bake --compress basis`: every level encoded from leanfade's own level (the
// encoder makes no MIPs), Zstandard-supercompressed, colour space set for non-colour data
// (primaries unspecified, linear transfer). Encoder: Basis Universal's WebAssembly build, as the
// npm package ktx2-encoder ships it (pinned by package-lock.json); container: ktx-parse.
//
// Usage: node encode_uastc.mjs JOB.json
// JOB.json: { "textures": [ { "output": "OUT.ktx2", "channels": "rgb" | "rgba",
//             "levels": [ { "file": "L0.rgba", "width": W, "height": H }, ... ] }, ... ] }
// Each level file holds width x height x 4 bytes, rows top first. Prints one line per texture
// written; on the first failure prints "<output>: <cause>" and exits 1.
import { readFileSync, writeFileSync } from 'node:fs';

const [jobFile] = process.argv.slice(2);
if (!jobFile) {
  console.error('usage: node encode_uastc.mjs JOB.json');
  process.exit(2);
}
let BASIS, ktx;
try {
  // The WebAssembly encoder module inside the package (not one of its exports).
  BASIS = (await import(new URL('./node_modules/ktx2-encoder/dist/basis/basis_encoder.js', import.meta.url))).default;
  ktx = await import('ktx-parse');
} catch (error) {
  console.error(`ktx2-encoder is not installed beside the encoder script (npm ci in its folder; ` +
                `scripts/install-deps.sh): ${String(error).split('\n')[0]}`);
  process.exit(1);
}

// KHR_DF_PRIMARIES_UNSPECIFIED, KHR_DF_TRANSFER_LINEAR: what KHR_texture_basisu asks of
// non-colour data (normals, roughness).
const kPrimariesUnspecified = 0;
const kTransferLinear = 1;
// UASTC's DFD channel ids (KHR_DF_CHANNEL_UASTC_RGB / _RGBA).
const kChannel = { rgb: 0, rgba: 3 };

// The encoder's progress lines are printed only when this is set (as ktx2-encoder does).
globalThis.__KTX2_DEBUG__ = false;
const basis = await BASIS({ print: () => {} });
basis.initializeBasis();

// One level as a one-level UASTC KTX2 (Zstandard), read back with ktx-parse.
function encodeLevel(rgba, width, height, alpha) {
  const encoder = new basis.BasisEncoder();
  try {
    encoder.setDebug(false);
    encoder.setSliceSourceImage(0, rgba, width, height, 0);  // raw RGBA8
    encoder.setUASTC(true);
    encoder.setMipGen(false);
    encoder.setCreateKTX2File(true);
    encoder.setKTX2UASTCSupercompression(true);
    encoder.setPerceptual(false);
    (encoder.setKTX2AndBasisSRGBTransferFunc ?? encoder.setKTX2SRGBTransferFunc).call(encoder, false);
    encoder.setCheckForAlpha(false);
    encoder.setForceAlpha(alpha);
    const output = new Uint8Array(width * height * 4 * 2 + 65536);
    const size = encoder.encode(output);
    if (!size) throw new Error(`the Basis encoder refused level ${width}x${height}`);
    return ktx.read(output.slice(0, size));
  } finally {
    encoder.delete();
  }
}

const job = JSON.parse(readFileSync(jobFile, 'utf8'));
for (const texture of job.textures) {
  try {
    const channels = kChannel[texture.channels];
    if (channels === undefined) throw new Error(`channels '${texture.channels}' (rgb or rgba)`);
    const levels = texture.levels.map((level) => {
      const rgba = new Uint8Array(readFileSync(level.file));
      if (rgba.byteLength !== level.width * level.height * 4)
        throw new Error(`${level.file} holds ${rgba.byteLength} bytes, not ${level.width * level.height * 4}`);
      const encoded = encodeLevel(rgba, level.width, level.height, texture.channels === 'rgba');
      if (encoded.levels.length !== 1 || encoded.supercompressionScheme !== 2)
        throw new Error(`the encoder wrote ${encoded.levels.length} levels, scheme ${encoded.supercompressionScheme}`);
      return encoded;
    });
    const container = levels[0];
    container.levels = levels.map((l) => l.levels[0]);
    container.levelCount = container.levels.length;
    const dfd = container.dataFormatDescriptor[0];
    dfd.colorPrimaries = kPrimariesUnspecified;
    dfd.transferFunction = kTransferLinear;
    dfd.samples[0].channelType = channels;
    container.keyValue = { KTXwriter: job.writer ?? 'leanfade' };
    writeFileSync(texture.output, ktx.write(container, { keepWriter: true }));
    console.log(`${texture.output}: ${container.levels.length} levels`);
  } catch (error) {
    console.error(`${texture.output}: ${String(error.message ?? error).split('\n')[0]}`);
    process.exit(1);
  }
}
