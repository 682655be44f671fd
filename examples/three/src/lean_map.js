// leanfade's KTX2 files read in JavaScript: LEAN maps (`leanfade bake --bits 16f`, two layers
// or three with two-lobe LEAN's plateau layer, Zstandard-supercompressed or not, every level)
// and 2D textures of RGBA half floats (`bake --plateau-out`). No three.js object is made here:
// three.js's bundled KTX2 parser (ktx-parse) and Zstandard decoder are the only imports, so
// plain WebGL2 and WebGPU code use it too. The layout: docs/ktx2.md.
import { read as readKtx2 } from 'three/addons/libs/ktx-parse.module.js';
import { ZSTDDecoder } from 'three/addons/libs/zstddec.module.js';

// Vulkan format numbers of the files leanfade writes for the web (`bake --bits 16f`,
// `bake --plateau-out`): RGBA half floats, which WebGL2 filters without extensions.
const VK_FORMAT_R16G16B16A16_SFLOAT = 97;

export class LeanfadeError extends Error {
  constructor(file, cause) {
    super(`${file}: ${cause}`);
    this.file = file;
  }
}

function keyValueText(container, key) {
  const value = container.keyValue[key];
  if (value === undefined) return undefined;
  if (typeof value === 'string') return value.replace(/\0$/, '');
  return new TextDecoder().decode(value).replace(/\0$/, '');
}

// KTX2 supercompression schemes leanfade writes: none, and Zstandard (`bake --supercompression
// zstd`, the default), each level one Zstandard frame.
const KTX2_SUPERCOMPRESSION_NONE = 0;
const KTX2_SUPERCOMPRESSION_ZSTD = 2;
let zstdDecoder;

// Each level's bytes as the GPU takes them: a Zstandard-supercompressed level inflated (three.js's
// ZSTDDecoder, the one its KTX2Loader uses).
async function levelBytes(container, name) {
  const scheme = container.supercompressionScheme;
  if (scheme === KTX2_SUPERCOMPRESSION_NONE) return container.levels.map((level) => level.levelData);
  if (scheme !== KTX2_SUPERCOMPRESSION_ZSTD)
    throw new LeanfadeError(name, `supercompression scheme ${scheme} is not read here (0: none, 2: Zstandard)`);
  if (!zstdDecoder) {
    zstdDecoder = new ZSTDDecoder();
    await zstdDecoder.init();
  }
  return container.levels.map((level, i) => {
    const bytes = zstdDecoder.decode(level.levelData, level.uncompressedByteLength);
    if (bytes.byteLength !== level.uncompressedByteLength)
      throw new LeanfadeError(name, `level ${i} inflates to ${bytes.byteLength} bytes, not ${level.uncompressedByteLength}`);
    return bytes;
  });
}

// The levels of a KTX2 file of RGBA half floats, level 0 first, each layer back to back in
// `data` (rows top first, as leanfade writes them).
async function halfFloatLevels(container, name) {
  if (container.vkFormat !== VK_FORMAT_R16G16B16A16_SFLOAT)
    throw new LeanfadeError(name, `expected VK_FORMAT_R16G16B16A16_SFLOAT (97), got vkFormat ${container.vkFormat}; bake with --bits 16f`);
  const layers = Math.max(1, container.layerCount);
  const levels = await levelBytes(container, name);
  return levels.map((bytes, i) => {
    const width = Math.max(1, container.pixelWidth >> i);
    const height = Math.max(1, container.pixelHeight >> i);
    if (bytes.byteLength !== width * height * 8 * layers)
      throw new LeanfadeError(name, `level ${i} holds ${bytes.byteLength} bytes, not ${width * height * 8 * layers}`);
    const copy = new Uint16Array(bytes.byteLength / 2);
    new Uint8Array(copy.buffer).set(bytes);
    return { width, height, data: copy };
  });
}

// A LEAN map written by `leanfade bake --bits 16f`: a 2D array of two layers (lean1, lean2), or
// three with the plateau layer, with every level, and its slope scale sc (LEANFADEscale); levels
// supercompressed with Zstandard or not. Async: Zstandard's decoder loads once. `levels` hold
// lean1 and lean2; `plateau` is the third layer decoded (plateauFromLeanMap), or null.
export async function parseLeanMap(arrayBuffer, name = 'LEAN map') {
  const container = readKtx2(new Uint8Array(arrayBuffer));
  if (container.layerCount !== 2 && container.layerCount !== 3)
    throw new LeanfadeError(name, 'a LEAN map has two layers (three with the plateau layer)');
  const scale = Number(keyValueText(container, 'LEANFADEscale'));
  if (!(scale > 0) || !Number.isFinite(scale)) throw new LeanfadeError(name, 'no LEANFADEscale key');
  // The encoding (docs/ktx2.md): layout version 2 stores n, B / sc and Mxy / sc^2 signed
  // (offset 0); version 1 (maps of leanfade 0.1) as 0.5 v + 0.5 (offset 1).
  const layout = keyValueText(container, 'LEANFADElayout') ?? '';
  const version = layout.match(/^lean1,lean2(,plateau)? v([12])$/);
  if (!version) throw new LeanfadeError(name, `unsupported LEANFADElayout '${layout}'`);
  if ((container.layerCount === 3) !== (version[1] !== undefined))
    throw new LeanfadeError(name, `LEANFADElayout '${layout}' does not match its ${container.layerCount} layers`);
  const levels = await halfFloatLevels(container, name);
  const map = {
    width: container.pixelWidth,
    height: container.pixelHeight,
    layers: 2,
    scale,
    leanOffset: version[2] === '2' ? 0 : 1,
    roughnessBaked: keyValueText(container, 'LEANFADEroughnessBaked') === '1',
    levels: levels.map((level) => ({ ...level, data: level.data.subarray(0, level.width * level.height * 4 * 2) })),
    plateau: null,
  };
  if (container.layerCount === 3) map.plateau = plateauFromLeanMap(levels, map);
  return map;
}

// The plateau layer (layer 2) of a LEAN map's levels decoded to the texture two-lobe LEAN
// samples: (f, f Bs.x, f Bs.y, f |Bs|^2) in half floats, as `bake --plateau-out` writes it. The
// stored layer is (f, f Bs / sc, f |Bs|^2 / sc^2), and for layout version 1 its last three
// channels as 0.5 v + 0.5 (docs/ktx2.md).
export function plateauFromLeanMap(levels, map) {
  const o = map.leanOffset, gain = 1 + o;
  const sc = map.scale;
  return {
    width: map.width,
    height: map.height,
    layers: 1,
    content: 'plateau v1',
    levels: levels.map((level) => {
      const texels = level.width * level.height;
      const stored = level.data.subarray(texels * 4 * 2, texels * 4 * 3);
      const out = new Uint16Array(texels * 4);
      for (let i = 0; i < texels; ++i) {
        const at = i * 4;
        out[at] = stored[at];
        out[at + 1] = toHalf((gain * fromHalf(stored[at + 1]) - o) * sc);
        out[at + 2] = toHalf((gain * fromHalf(stored[at + 2]) - o) * sc);
        out[at + 3] = toHalf((gain * fromHalf(stored[at + 3]) - o) * sc * sc);
      }
      return { width: level.width, height: level.height, data: out };
    }),
  };
}

// IEEE 754 binary16 bits <-> numbers (every class: zero, subnormal, normal, infinity, NaN).
export function fromHalf(bits) {
  const sign = bits & 0x8000 ? -1 : 1;
  const exponent = (bits >> 10) & 0x1f, mantissa = bits & 0x3ff;
  if (exponent === 0) return sign * mantissa * 2 ** -24;
  if (exponent === 31) return mantissa ? NaN : sign * Infinity;
  return sign * (1 + mantissa / 1024) * 2 ** (exponent - 15);
}

// The nearest binary16 (ties to even), saturating to infinity.
export function toHalf(value) {
  if (Number.isNaN(value)) return 0x7e00;
  const sign = value < 0 || Object.is(value, -0) ? 0x8000 : 0;
  const a = Math.abs(value);
  if (a >= 65520) return sign | 0x7c00;
  if (a < 2 ** -14) {  // subnormal (or zero): multiples of 2^-24
    const m = a / 2 ** -24;
    let r = Math.round(m);
    if (Math.abs(m - Math.trunc(m) - 0.5) < 1e-12 && Math.trunc(m) % 2 === 0) r = Math.trunc(m);
    return sign | r;
  }
  let exponent = Math.floor(Math.log2(a));
  if (2 ** exponent > a) exponent -= 1;  // log2's rounding
  if (2 ** (exponent + 1) <= a) exponent += 1;
  const scaled = a / 2 ** exponent * 1024 - 1024;  // 0 <= scaled < 1024
  let mantissa = Math.floor(scaled);
  const rest = scaled - mantissa;
  if (rest > 0.5 || (rest === 0.5 && mantissa % 2 === 1)) mantissa += 1;
  if (mantissa === 1024) { mantissa = 0; exponent += 1; }
  if (exponent > 15) return sign | 0x7c00;
  return sign | ((exponent + 15) << 10) | mantissa;
}

// A 2D texture of RGBA half floats with its levels (`leanfade bake --plateau-out`), and what
// its LEANFADEcontent key says it holds.
export async function parseTexture(arrayBuffer, name = 'texture') {
  const container = readKtx2(new Uint8Array(arrayBuffer));
  if (container.layerCount > 1) throw new LeanfadeError(name, 'expected a 2D texture');
  return {
    width: container.pixelWidth,
    height: container.pixelHeight,
    layers: 1,
    content: keyValueText(container, 'LEANFADEcontent'),
    levels: (await halfFloatLevels(container, name)).map((level) => ({
      ...level,
      data: level.data.subarray(0, level.width * level.height * 4 * 2),
    })),
  };
}

// Rows reversed in every layer: leanfade's files store the top row first, and its renderer
// uploads them bottom first so that +v points up the texture (the meshes' uv convention).
export function bottomRowFirst(level, layers) {
  const row = level.width * 4;
  const out = new Uint16Array(level.data.length);
  for (let layer = 0; layer < layers; ++layer) {
    const base = layer * row * level.height;
    for (let y = 0; y < level.height; ++y)
      out.set(level.data.subarray(base + y * row, base + (y + 1) * row), base + (level.height - 1 - y) * row);
  }
  return out;
}

