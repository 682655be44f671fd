// LEAN-filtered normals and roughness for three.js's own physically based materials, lit by every
// three.js light: per pixel, from the LEAN map's trilinearly filtered moments (B, M), the mean
// normal normalize(B.x, B.y, 1) and the roughness that folds the slopes' covariance
// Σ = M − B Bᵀ into the material's: α² = α0² + Σxx + Σyy with α0 = r² (docs/math.md §9, the
// roughness MIPs' rule, here applied after filtering the moments rather than before). That is
// "roughness from normal-map variance" with the variance of exactly the texels under the pixel.
//
// WebGLRenderer: leanStandardMaterial (a MeshStandardMaterial or MeshPhysicalMaterial patched
// with onBeforeCompile). WebGPURenderer: leanStandardNodes in webgpu.js (TSL).
import * as THREE from 'three';

// The moments' unpacking (lf_unpack of leanfade's shading header: o = 1 for the offset encoding,
// 0 for the signed) and the roughness fold, in GLSL.
const kLeanGlsl = /* glsl */ `
uniform highp sampler2DArray leanMap;
uniform float leanScale;   // sc (LEANFADEscale)
uniform float leanOffset;  // o
uniform float leanBaseVariance;  // a base variance baked into the moments, taken out again
struct LeanSample { vec3 normal; float variance; };
LeanSample leanSample(vec2 uv) {
  vec4 lean2 = texture(leanMap, vec3(uv, 1.0));
  float gain = 1.0 + leanOffset;
  vec2 b = (gain * lean2.xy - leanOffset) * leanScale;
  vec2 m = lean2.zw * leanScale * leanScale;
  LeanSample s;
  s.normal = normalize(vec3(b, 1.0));
  s.variance = max(m.x - b.x * b.x, 0.0) + max(m.y - b.y * b.y, 0.0) - leanBaseVariance;
  return s;
}
`;

// A tangent-space normal map for three.js to set up its tangent frame (USE_NORMALMAP_TANGENTSPACE,
// vNormalMapUv): never sampled, the LEAN map's mean normal replaces its texel.
let flatNormal;
function flatNormalTexture() {
  if (!flatNormal) {
    flatNormal = new THREE.DataTexture(new Uint8Array([128, 128, 255, 255]), 1, 1);
    flatNormal.needsUpdate = true;
  }
  return flatNormal;
}

// Patches `material` (MeshStandardMaterial or MeshPhysicalMaterial) to shade with the LEAN map
// `leanTexture` (leanMapTexture or LeanMapLoader's map): its normal and roughness per pixel as
// above, its roughness (and roughnessMap) as the base α0. The mesh needs uv (the map's
// coordinates, through normalMap's channel and transform) and, for a stable frame, tangents.
// Returns the material.
export function leanStandardMaterial(material, leanTexture) {
  const data = leanTexture.userData ?? {};
  material.normalMap = flatNormalTexture();
  material.normalScale = new THREE.Vector2(1, 1);
  material.userData.leanMap = leanTexture;
  const uniforms = {
    leanMap: { value: leanTexture },
    leanScale: { value: data.scale ?? 1 },
    leanOffset: { value: data.leanOffset ?? 0 },
    // A map baked with 1/s in its moments (roughnessBaked) carries LEAN's base lobe: not here.
    leanBaseVariance: { value: 0 },
  };
  material.onBeforeCompile = (shader) => {
    Object.assign(shader.uniforms, uniforms);
    shader.fragmentShader = shader.fragmentShader
      .replace('#include <normalmap_pars_fragment>', `#include <normalmap_pars_fragment>\n${kLeanGlsl}`)
      // three.js reads the roughness before it builds the normal: the texel is sampled there.
      .replace('#include <normal_fragment_maps>', /* glsl */ `
        normal = normalize(tbn * leanTexel.normal);`)
      .replace('#include <roughnessmap_fragment>', /* glsl */ `
        #include <roughnessmap_fragment>
        LeanSample leanTexel = leanSample(vNormalMapUv);
        float leanAlpha0 = roughnessFactor * roughnessFactor;
        roughnessFactor = sqrt(sqrt(leanAlpha0 * leanAlpha0 + max(leanTexel.variance, 0.0)));`);
  };
  material.customProgramCacheKey = () => 'leanfade-lean-standard';
  material.needsUpdate = true;
  return material;
}
