#version 450 core
// Fragment stage of every technique. The renderer defines (from the technique table,
// libs/core/include/leanfade/core/technique.hpp):
//   LF_TECHNIQUE          the lobe stage of lf_shade, one of LF_TECHNIQUE_* (lean_shading.glsl)
//   LF_BRDF               the reflection model, one of LF_BRDF_* (LfParams::brdf on the CPU)
//   LF_READS_MOMENTS      when the technique reads the lean2 layer (B and M), not only lean1
//   LF_FINEST_LEVEL_ONLY  for the supersampled reference: shade at LOD 0; the renderer draws it
//                         at k x k the resolution and box-filters (docs/math.md §7)
//   LF_READS_PLATEAU      when the technique reads the plateau layer (two-lobe LEAN)
//   LF_GEOMETRIC_AA       geometric specular antialiasing: the footprint's slope covariance from
//                         the screen-space derivatives of the half vector (docs/math.md §11)
// LF_PLAIN_COLOR (optional) fixes the output to OUTPUT_COLOR without fog at compile time.
// LF_LAYERED (optional): the material's moments are mixed from 2..4 bump layers (docs/math.md §6)
// instead of read from one LEAN map.
// All shading math comes from the shared header (docs/math.md §4). Output: linear radiance.
#include "lean_shading.glsl"
#include "bindings.glsl"

#if !defined(LF_TECHNIQUE)
#error "the renderer defines LF_TECHNIQUE (one of LF_TECHNIQUE_*)"
#endif
#if !defined(LF_BRDF)
#error "the renderer defines LF_BRDF (one of LF_BRDF_*)"
#endif

const int OUTPUT_COLOR = 0;       // (Ka + Kd NdotL + specular) light + emission, then fog
const int OUTPUT_DIFFUSE = 1;     // (Ka + Kd NdotL) light, no fog
const int OUTPUT_SPECULAR = 2;    // Ks NdotL^sf D F light, no fog
const int OUTPUT_FADE_TERMS = 3;  // (NdotL, d, 0) of fading from lean1 (lf_fade_terms), no fog

#if defined(LF_SEPARATE_VARYINGS)
struct VertexData { LF_VERTEX_DATA(LF_VERTEX_MEMBER) };
VertexData v_in;
LF_VERTEX_DATA(LF_VERTEX_INPUT)
#else
in VertexData { LF_VERTEX_DATA(LF_VERTEX_MEMBER) } v_in;  // bindings.glsl
#endif

// Slice 0: lean1 = (0.5 n + 0.5, 0.5 Mxy / sc^2 + 0.5); slice 1: lean2 = (0.5 B / sc + 0.5,
// Mxx / sc^2, Myy / sc^2) (docs/math.md §3). The baseline's normal map is lean1.rgb.
layout(binding = LF_BINDING_LEAN_MAP) uniform sampler2DArray u_lean;

// The material's surface maps, one sampler u_<name> each (map_samplers.glsl, generated from
// kMapKinds; what each texel holds: map_kinds.glsl). The base roughness, the plateau layer and
// the roughness MIPs are read at the LEAN map's uv with its sampler state.
#include "map_samplers.glsl"

layout(std140, binding = LF_BINDING_SHADING_BLOCK) uniform LfShadingBlock {
    LfShadingUniforms u_shading;
};

layout(location = 0) out vec4 o_color;

#if defined(LF_FINEST_LEVEL_ONLY)
#define LF_SAMPLE(sampler, coord) textureLod(sampler, coord, 0.0)  // finest level (docs/math.md §7)
#else
#define LF_SAMPLE(sampler, coord) texture(sampler, coord)  // trilinear / anisotropic
#endif

// The texture coordinates of a map through its transform (u_shading.uv_transforms at LF_UV_*: the
// LEAN map and its plateau layer, then each surface map kind's): the set row 0's w names (0: uv,
// 1: uv1; a glTF texture reference's texCoord), then the affine map of its rows.
vec2 map_uv(int which) {
    vec4 r0 = u_shading.uv_transforms[2 * which];
    vec4 r1 = u_shading.uv_transforms[2 * which + 1];
    vec2 uv = r0.w > 0.5 ? v_in.uv1 : v_in.uv;  // a select, not a mix: the other set is unread
    return vec2(dot(r0.xy, uv) + r0.z, dot(r1.xy, uv) + r1.z);
}

vec4 lean_texel(float slice) {
    return LF_SAMPLE(u_lean, vec3(map_uv(LF_UV_LEAN_MAP), slice));
}

// Cook-Torrance with a base roughness map: the map's filtered alpha0^2 here.
bool has_roughness_map() {
    return LF_BRDF == LF_BRDF_COOK_TORRANCE && (u_shading.maps & LF_MAP_BASE_ROUGHNESS) != 0;
}

#if defined(LF_ROUGHNESS_MIPS)
// Another tool's roughness MIPs (u_roughness_mips, bit LF_MAP_ROUGHNESS_MIPS, `--roughness-mips`):
// perceptual r per level, read in place of the r the engine texel derives from the LEAN map.
// The texel of `map` (a full MIP chain) under the LEAN map's texel p of `level`: the same texel
// when both are of one size, else the map's level of the same footprint at the texel's centre.
float texel_under_lean_texel(sampler2D map, ivec2 p, int level) {
    ivec2 size = textureSize(map, 0);
    ivec2 lean_size = textureSize(u_lean, 0).xy;
    if (size == lean_size) return texelFetch(map, p, level).r;
    vec2 uv = (vec2(p) + 0.5) / vec2(textureSize(u_lean, level).xy);
    return textureLod(map, uv, float(level) + log2(float(size.x) / float(lean_size.x))).r;
}

// alpha0^2 of the LEAN map's texel p of `level` for the engine texel: the uniform roughness's, or
// the map's texel at that level (the bake's pairing, `bake --roughness-out --roughness-map`).
float roughness_mip_alpha0_squared(ivec2 p, int level) {
    if (!has_roughness_map()) return 2.0 * u_shading.params.inv_s_shading;
    return texel_under_lean_texel(u_base_roughness, p, level);
}

// Roughness MIPs (docs/roughness.md): every LEAN texel of a level becomes the texel the baked
// engine textures hold (lf_roughness_mip_texel: 8-bit normal and roughness), and those are
// filtered as a texture unit filters the baked files: bilinear in the two levels around the LOD
// the hardware computes for this pixel, linear between them (GL_LINEAR_MIPMAP_LINEAR, repeat).
vec4 roughness_mip_texel(ivec2 xy, int level) {
    ivec2 size = textureSize(u_lean, level).xy;
    ivec2 p = ((xy % size) + size) % size;
    vec4 texel = lf_roughness_mip_texel(texelFetch(u_lean, ivec3(p, 0), level),
                                        texelFetch(u_lean, ivec3(p, 1), level), u_shading.scale,
                                        u_shading.lean_offset,
                                        roughness_mip_alpha0_squared(p, level));
    if ((u_shading.maps & LF_MAP_ROUGHNESS_MIPS) != 0)
        texel.w = texel_under_lean_texel(u_roughness_mips, p, level);
    return texel;
}

vec4 roughness_mip_bilinear(vec2 uv, int level) {
    vec2 p = uv * vec2(textureSize(u_lean, level).xy) - 0.5;
    ivec2 i = ivec2(floor(p));
    vec2 f = p - floor(p);
    return mix(mix(roughness_mip_texel(i, level), roughness_mip_texel(i + ivec2(1, 0), level), f.x),
               mix(roughness_mip_texel(i + ivec2(0, 1), level),
                   roughness_mip_texel(i + ivec2(1, 1), level), f.x),
               f.y);
}

vec4 roughness_mip_trilinear(vec2 uv) {
    int last = textureQueryLevels(u_lean) - 1;
    float lod = clamp(textureQueryLod(u_lean, uv).y, 0.0, float(last));
    int level = min(int(floor(lod)), last);
    int next = min(level + 1, last);
    return mix(roughness_mip_bilinear(uv, level), roughness_mip_bilinear(uv, next),
               lod - float(level));
}
#endif

#if defined(LF_LAYERED)
// Bump layers (docs/math.md §6): each layer's LEAN map, the pairs' cross-term textures, the
// per-texel weights and the layers' uniforms (LfLayerUniforms of the shared header).
layout(binding = LF_BINDING_LAYER_MAPS) uniform sampler2DArray u_layer_maps[4];
layout(binding = LF_BINDING_CROSS_TERMS) uniform sampler2DArray u_cross_terms;
layout(binding = LF_BINDING_LAYER_WEIGHTS) uniform sampler2D u_layer_weights;
layout(std140, binding = LF_BINDING_LAYER_BLOCK) uniform LfLayerBlock {
    LfLayerUniforms u_layers;
};

vec2 layer_uv(int i) {
    vec4 offsets = u_layers.offsets[i / 2];
    vec2 offset = (i % 2 == 0) ? offsets.xy : offsets.zw;
    return v_in.uv * u_layers.tilings[i] + offset;
}

// Layer i's texel of `slice` at `uv`: the sampler array indexed with constants only, the one
// index GLSL ES 3.00 (WebGL2) allows; i is a loop counter bounded by a uniform, so every fragment
// takes the same branch and the implicit derivatives stay defined.
vec4 layer_texel(int i, vec2 uv, float slice) {
    if (i == 0) return LF_SAMPLE(u_layer_maps[0], vec3(uv, slice));
    if (i == 1) return LF_SAMPLE(u_layer_maps[1], vec3(uv, slice));
    if (i == 2) return LF_SAMPLE(u_layer_maps[2], vec3(uv, slice));
    return LF_SAMPLE(u_layer_maps[3], vec3(uv, slice));
}

// The material's mixed moments: B = sum t_i k_i B_i, M = sum t_i^2 k_i^2 M_i + sum_{i<j} t_i t_j
// C_ij (LEAN §3.5), with C_ij from the pair's texture or from the filtered B's (u_layers.mixing).
LfMoments layered_moments() {
    vec4 t = u_layers.weights;
    if (u_layers.weight_map != 0) t = LF_SAMPLE(u_layer_weights, v_in.uv);
    LfMoments mixed = lf_mix_start();
    vec2 means[4];
    vec2 uvs[4];
    // Loops bounded by the (uniform) layer count, not by 4: a SIMD rasteriser runs what a loop
    // spans, skipped iterations included.
    for (int i = 0; i < u_layers.count; ++i) {
        uvs[i] = layer_uv(i);
        vec4 lean1 = layer_texel(i, uvs[i], LF_SLICE_LEAN1);
        vec4 lean2 = layer_texel(i, uvs[i], LF_SLICE_LEAN2);
        LfMoments m = lf_layer_strength(
            lf_unpack(lean1, lean2, u_layers.scales[i], u_layers.lean_offsets[i]),
            u_layers.strengths[i]);
        means[i] = m.mean;
        mixed = lf_mix_layer(mixed, m, t[i]);
    }
    int pair = 0;
    for (int i = 0; i < u_layers.count; ++i) {
        for (int j = i + 1; j < u_layers.count; ++j) {
            vec4 products;
            if (u_layers.mixing == LF_MIXING_TEXTURES) {
                products = LF_SAMPLE(u_cross_terms, vec3(uvs[i], float(pair))) *
                           (u_layers.strengths[i] * u_layers.strengths[j]);
            } else {
                products = lf_cross_products(means[i], means[j]);
            }
            mixed = lf_mix_pair(mixed, products, t[i] * t[j]);
            ++pair;
        }
    }
    return lf_mix_end(mixed);
}
#endif

void main() {
#if defined(LF_SEPARATE_VARYINGS)
    LF_VERTEX_DATA(LF_VERTEX_LOAD)
#endif
    // glTF doubleSided: a back face is shaded with its tangent frame reversed (glTF 2.0 §3.9.2:
    // its normal flipped), so that both sides light alike.
    float side = (u_shading.double_sided > 0.5 && !gl_FrontFacing) ? -1.0 : 1.0;
    vec3 light_dir = normalize(side * v_in.light_t);
    vec3 view_t = side * v_in.view_t;
#if defined(LF_LAYERED)
    LfMoments moments = layered_moments();
    vec4 lean1 = vec4(0.5 * moments.normal + vec3(0.5), 0.5);  // for the fade terms' NdotL
#else
    vec4 lean1 = lean_texel(LF_SLICE_LEAN1);
#if defined(LF_READS_MOMENTS)
    vec4 lean2 = lean_texel(LF_SLICE_LEAN2);
#else
    vec4 lean2 = vec4(0.5, 0.5, 0.0, 0.0);  // B = 0, M = 0: unused by the technique's lobe
#endif
    vec4 plateau = vec4(0.0);  // f = 0 without the layer (docs/math.md §10)
#if defined(LF_READS_PLATEAU)
    if ((u_shading.maps & LF_MAP_PLATEAU) != 0)
        plateau = LF_SAMPLE(u_plateau, map_uv(LF_UV_LEAN_MAP));
#endif
    LfMoments moments =
        lf_map_moments(lean1, lean2, u_shading.scale, u_shading.lean_offset, plateau);
#if defined(LF_ROUGHNESS_MIPS)
    moments = lf_roughness_mips_moments(roughness_mip_trilinear(map_uv(LF_UV_LEAN_MAP)));
#endif
#endif
#if defined(LF_GEOMETRIC_AA)
    // The half vector's slope and its change to the neighbouring pixels (docs/math.md §11).
    vec3 half_t = normalize(light_dir + normalize(view_t));
    vec2 half_slope = half_t.xy / max(half_t.z, 1e-3);
    vec2 dslope_dx = dFdx(half_slope);
    vec2 dslope_dy = dFdy(half_slope);
    moments.footprint =
        lf_footprint_covariance(dslope_dx, dslope_dy, u_shading.geometric_aa_kappa) *
        lf_footprint_trust(dslope_dx, dslope_dy, v_in.linear_normal_change);
#endif
    // The surface maps' texels, then the material's surface, its parameters and the shade
    // (lf_surface, lf_shade_surface).
    vec4 base_color = LF_SAMPLE(u_base_color, map_uv(LF_UV_BASE_COLOR));
    // glTF alphaMode MASK (alpha_cutoff < 0 for every other material).
    if (base_color.w * u_shading.base_alpha < u_shading.alpha_cutoff) discard;
    float alpha0_squared =
        has_roughness_map() ? LF_SAMPLE(u_base_roughness, map_uv(LF_UV_BASE_ROUGHNESS)).r : 0.0;
    // Without the anisotropy texture: the direction +u (2 rg - 1 = (1, 0)) at full strength.
    vec4 anisotropy = vec4(1.0, 0.5, 1.0, 1.0);
    if (LF_BRDF == LF_BRDF_COOK_TORRANCE && (u_shading.maps & LF_MAP_ANISOTROPY) != 0)
        anisotropy = LF_SAMPLE(u_anisotropy, map_uv(LF_UV_ANISOTROPY));
    LfSurface surface = lf_surface(base_color, has_roughness_map(), alpha0_squared,
                                   LF_SAMPLE(u_metallic, map_uv(LF_UV_METALLIC)).r,
                                   LF_SAMPLE(u_occlusion, map_uv(LF_UV_OCCLUSION)).r,
                                   LF_SAMPLE(u_emissive, map_uv(LF_UV_EMISSIVE)), anisotropy,
                                   u_shading.material);
    if ((u_shading.maps & LF_MAP_SPECULAR) != 0)
        surface.specular_color = LF_SAMPLE(u_specular, map_uv(LF_UV_LEAN_MAP)).rgb;
    LfParams params = u_shading.params;
    params.brdf = LF_BRDF;  // a constant: the other BRDF's code is compiled out
    LfShade shade = lf_shade_surface(LF_TECHNIQUE, moments, surface, light_dir, view_t, params);
#if defined(LF_PLAIN_COLOR)
    // The renderer's ordinary frames (OUTPUT_COLOR, no fog): the colour of the general path below,
    // bit for bit, without its uniform branches, which a SIMD rasteriser such as llvmpipe executes
    // in full for every pixel (docs/perf.md).
    vec3 color = lf_surface_color(shade, surface);
#else
    vec3 color;
    if (u_shading.output_mode == OUTPUT_DIFFUSE) {
        color = shade.diffuse;
    } else if (u_shading.output_mode == OUTPUT_SPECULAR) {
        color = shade.specular;
    } else if (u_shading.output_mode == OUTPUT_FADE_TERMS) {
        color = vec3(lf_fade_terms(lean1, light_dir, view_t, params.fade_distance), 0.0);
    } else {
        float f = lf_fog_factor(v_in.eye_depth, u_shading.fog_mode, u_shading.fog_start,
                                u_shading.fog_end, u_shading.fog_density);
        color = lf_apply_fog(lf_surface_color(shade, surface), u_shading.fog_color, f);
    }
#endif
    // Alpha 1 (opaque and MASK), or the base colour's for a BLEND material.
    o_color = vec4(color, mix(1.0, base_color.w * u_shading.base_alpha, u_shading.blend));
}
