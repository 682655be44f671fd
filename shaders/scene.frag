#version 450 core
// Fragment stage of every technique. The renderer defines (from the technique table,
// libs/core/include/leanfade/core/technique.hpp):
//   LF_TECHNIQUE          the lobe stage of lf_shade, one of LF_TECHNIQUE_* (lean_shading.glsl)
//   LF_READS_MOMENTS      when the technique reads the lean2 layer (B and M), not only lean1
//   LF_FINEST_LEVEL_ONLY  for the supersampled reference: shade at LOD 0; the renderer draws it
//                         at k x k the resolution and box-filters (docs/math.md §7)
// LF_PLAIN_COLOR (optional) fixes the output to OUTPUT_COLOR without fog at compile time.
// All shading math comes from the shared header (docs/math.md §4). Output: linear radiance.
#include "lean_shading.glsl"
#include "bindings.glsl"

#if !defined(LF_TECHNIQUE)
#error "the renderer defines LF_TECHNIQUE (one of LF_TECHNIQUE_*)"
#endif

const int OUTPUT_COLOR = 0;       // (Ka + Kd NdotL + specular) light, then fog
const int OUTPUT_DIFFUSE = 1;     // (Ka + Kd NdotL) light, no fog
const int OUTPUT_SPECULAR = 2;    // Ks NdotL^sf D F light, no fog
const int OUTPUT_FADE_TERMS = 3;  // (NdotL, d, 0) of fading from lean1 (lf_fade_terms), no fog

in VertexData {
    vec2 uv;
    vec3 light_t;
    vec3 view_t;
    float eye_depth;
} v_in;

// Slice 0: lean1 = (0.5 n + 0.5, 0.5 Mxy / sc^2 + 0.5); slice 1: lean2 = (0.5 B / sc + 0.5,
// Mxx / sc^2, Myy / sc^2) (docs/math.md §3). The baseline's normal map is lean1.rgb.
layout(binding = LF_BINDING_LEAN_MAP) uniform sampler2DArray u_lean;

layout(std140, binding = LF_BINDING_SHADING_BLOCK) uniform LfShadingBlock {
    LfShadingUniforms u_shading;
};

layout(location = 0) out vec4 o_color;

vec4 lean_texel(float slice) {
#if defined(LF_FINEST_LEVEL_ONLY)
    return textureLod(u_lean, vec3(v_in.uv, slice), 0.0);  // finest level only (docs/math.md §7)
#else
    return texture(u_lean, vec3(v_in.uv, slice));  // trilinear / anisotropic
#endif
}

void main() {
    vec3 light_dir = normalize(v_in.light_t);
    vec4 lean1 = lean_texel(LF_SLICE_LEAN1);
#if defined(LF_READS_MOMENTS)
    vec4 lean2 = lean_texel(LF_SLICE_LEAN2);
#else
    vec4 lean2 = vec4(0.5, 0.5, 0.0, 0.0);  // B = 0, M = 0: unused by the technique's lobe
#endif
    LfParams params = u_shading.params;
    LfShade shade = lf_shade(LF_TECHNIQUE, lf_unpack(lean1, lean2, u_shading.scale), light_dir,
                             v_in.view_t, params);
#if defined(LF_PLAIN_COLOR)
    // The renderer's ordinary frames (OUTPUT_COLOR, no fog): the colour of the general path below,
    // bit for bit, without its uniform branches, which a SIMD rasteriser such as llvmpipe executes
    // in full for every pixel (docs/perf.md).
    vec3 color = shade.diffuse + shade.specular;
#else
    vec3 color;
    if (u_shading.output_mode == OUTPUT_DIFFUSE) {
        color = shade.diffuse;
    } else if (u_shading.output_mode == OUTPUT_SPECULAR) {
        color = shade.specular;
    } else if (u_shading.output_mode == OUTPUT_FADE_TERMS) {
        color = vec3(lf_fade_terms(lean1, light_dir, v_in.view_t, params.fade_distance), 0.0);
    } else {
        float f = lf_fog_factor(v_in.eye_depth, u_shading.fog_mode, u_shading.fog_start,
                                u_shading.fog_end, u_shading.fog_density);
        color = lf_apply_fog(shade.diffuse + shade.specular, u_shading.fog_color, f);
    }
#endif
    o_color = vec4(color, 1.0);
}
