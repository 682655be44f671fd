// @leanfade/three: leanfade's LEAN maps in three.js (WebGLRenderer). WebGPURenderer's TSL nodes
// are in '@leanfade/three/webgpu'. README.md says what each is for.
export {
  bottomRowFirst, fromHalf, LeanfadeError, parseLeanMap, parseTexture, plateauFromLeanMap, toHalf,
} from './lean_map.js';
export { halfFloatTexture, leanMapTexture, LeanMapLoader } from './textures.js';
export { leanfadeCamera, LeanMaterial, leanMesh, meshGeometry } from './lean_material.js';
export { leanStandardMaterial } from './lean_standard.js';
