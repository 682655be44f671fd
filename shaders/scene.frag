#version 450 core
// Fragment stage of every technique; exactly one of these is defined by the renderer:
//   TECHNIQUE_BUMP       Blinn-Phong bump mapping with the trilinear-filtered normal map (baseline)
//   TECHNIQUE_LEAN       LEAN mapping (Olano & Baker 2010)
//   TECHNIQUE_FADE       LEAN mapping with specular fading (fading paper eq. 6-7)
//   TECHNIQUE_TOKSVIG    Toksvig mapping: exponent from the filtered normal's length (Toksvig 2005)
//   TECHNIQUE_CLEAN      CLEAN mapping: LEAN with one isotropic second moment (Baker 2011)
//   TECHNIQUE_REFERENCE  the baseline at LOD 0, one sample of the supersampled ground truth
//                        (SPEC §7; the renderer draws it at k x k the resolution and box-filters)
// LF_PLAIN_COLOR (optional) fixes the output to OUTPUT_COLOR without fog at compile time.
// All shading math comes from the shared header (SPEC §4). Output: linear radiance.
#include "lean_shading.glsl"

#if defined(TECHNIQUE_BUMP) || defined(TECHNIQUE_REFERENCE)
#define LF_USES_LEAN 0
#elif defined(TECHNIQUE_LEAN) || defined(TECHNIQUE_FADE) || defined(TECHNIQUE_TOKSVIG) || \
    defined(TECHNIQUE_CLEAN)
#define LF_USES_LEAN 1
#else
#error "define one of TECHNIQUE_BUMP, _LEAN, _FADE, _TOKSVIG, _CLEAN or _REFERENCE"
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

// Layer 0: lean1 = (0.5 n + 0.5, 0.5 Mxy / sc^2 + 0.5); layer 1: lean2 = (0.5 B / sc + 0.5,
// Mxx / sc^2, Myy / sc^2) (SPEC §3). The baseline's normal map is lean1.rgb.
layout(binding = 0) uniform sampler2DArray u_lean;
uniform float u_scale;  // sc
uniform LfParams u_params;
uniform int u_output;  // OUTPUT_*
uniform int u_fog_mode;  // LF_FOG_*
uniform vec3 u_fog_color;
uniform float u_fog_start;
uniform float u_fog_end;
uniform float u_fog_density;

layout(location = 0) out vec4 o_color;

vec4 lean_texel(float layer) {
#if defined(TECHNIQUE_REFERENCE)
    return textureLod(u_lean, vec3(v_in.uv, layer), 0.0);  // finest level only (SPEC §7)
#else
    return texture(u_lean, vec3(v_in.uv, layer));  // trilinear / anisotropic
#endif
}

void main() {
    vec3 light_dir = normalize(v_in.light_t);
#if defined(TECHNIQUE_TOKSVIG)
    LfShade shade = lf_shade_toksvig(lean_texel(0.0), light_dir, v_in.view_t, u_params);
#elif defined(TECHNIQUE_CLEAN)
    LfShade shade = lf_shade_clean(lean_texel(0.0), lean_texel(1.0), u_scale, light_dir,
                                   v_in.view_t, u_params);
#elif LF_USES_LEAN
#if defined(TECHNIQUE_FADE)
    const bool fade_enabled = true;
#else
    const bool fade_enabled = false;
#endif
    LfShade shade = lf_shade_lean(lean_texel(0.0), lean_texel(1.0), u_scale, light_dir,
                                  v_in.view_t, u_params, fade_enabled);
#else
    LfShade shade = lf_shade_blinn_phong(lean_texel(0.0).rgb, light_dir, v_in.view_t, u_params);
#endif
#if defined(LF_PLAIN_COLOR)
    // The renderer's ordinary frames (OUTPUT_COLOR, no fog): the colour of the general path below,
    // bit for bit, without its uniform branches, which a SIMD rasteriser such as llvmpipe executes
    // in full for every pixel (docs/perf.md).
    vec3 color = shade.diffuse + shade.specular;
#else
    vec3 color;
    if (u_output == OUTPUT_DIFFUSE) {
        color = shade.diffuse;
    } else if (u_output == OUTPUT_SPECULAR) {
        color = shade.specular;
    } else if (u_output == OUTPUT_FADE_TERMS) {
        color = vec3(lf_fade_terms(lean_texel(0.0), light_dir, v_in.view_t,
                                   u_params.fade_distance), 0.0);
    } else {
        float f = lf_fog_factor(v_in.eye_depth, u_fog_mode, u_fog_start, u_fog_end, u_fog_density);
        color = lf_apply_fog(shade.diffuse + shade.specular, u_fog_color, f);
    }
#endif
    o_color = vec4(color, 1.0);
}
