// leanfade shading math, docs/math.md §4 — written once, compiled both as GLSL 4.50 (included by
// the shaders) and as C++ with glm (libs/core/include/leanfade/core/shading.hpp, for the CPU
// reference and the tests). Keep to the common subset: float literals with an f suffix, no in/out
// parameters, structs built field by field, LF_FN before every function.
//
// All vectors are in tangent space (x = +u, y = +v, z = surface normal) unless named otherwise.
// Radiance values are linear (not sRGB).
#ifndef LEANFADE_LEAN_SHADING_GLSL
#define LEANFADE_LEAN_SHADING_GLSL

#ifndef LF_FN
#define LF_FN
#endif
// A struct member's default value: `= value` in C++, nothing in GLSL, whose structs have no
// initialisers. In C++ a default-constructed LfShadingUniforms is a valid block: the parameter
// table's defaults (ShadingSettings{}, through to_lf_params), sc 1 and the offset encoding, no
// fog, no surface maps, identity texture coordinate transforms of set 0, opaque and one-sided.
#ifndef LF_DEFAULT
#define LF_DEFAULT(value)
#endif
// The identity transforms of LfShadingUniforms::uv_transforms in C++ (leanfade/core/shading.hpp).
#ifndef LF_UV_TRANSFORMS_IDENTITY
#define LF_UV_TRANSFORMS_IDENTITY
#endif

const float LF_PI = 3.14159265358979f;

const int LF_FADE_DISTANCE_TANGENT_Z = 0;  // d = Vt.z, the eye's height above the tangent plane
const int LF_FADE_DISTANCE_EYE = 1;        // d = length(Vt)

const int LF_FOG_NONE = 0;
const int LF_FOG_LINEAR = 1;
const int LF_FOG_EXP = 2;
const int LF_FOG_EXP2 = 3;

// Shading techniques: the lobe stage of lf_shade. The C++ technique table
// (libs/core/include/leanfade/core/technique.hpp) names each one and checks these values; the
// supersampled reference shades with LF_TECHNIQUE_BUMP at the finest MIP level.
const int LF_TECHNIQUE_BUMP = 0;     // Blinn-Phong around the renormalised filtered normal
const int LF_TECHNIQUE_LEAN = 1;     // LEAN's Gaussian over slopes (LEAN eq. 1)
const int LF_TECHNIQUE_FADE = 2;     // LEAN with specular fading (fading paper eq. 6-7)
const int LF_TECHNIQUE_TOKSVIG = 3;  // Blinn-Phong with Toksvig's exponent
const int LF_TECHNIQUE_CLEAN = 4;    // LEAN's lobe with CLEAN's isotropic covariance
const int LF_TECHNIQUE_ROUGHNESS_MIPS = 5;  // the BRDF on roughness + normal MIPs (engines)
const int LF_TECHNIQUE_TWO_LOBE = 6;  // a plateau's spike plus LEAN's halo (docs/math.md §10)
const int LF_TECHNIQUE_COUNT = 7;  // the lobe constants above are 0 .. LF_TECHNIQUE_COUNT - 1

// BRDFs: the reflection model every technique's lobe stage evaluates (docs/math.md §4, §9). The
// renderer compiles one (LF_BRDF of scene.frag); the CPU reads LfParams::brdf.
const int LF_BRDF_BLINN_PHONG = 0;    // the normalised Blinn-Phong lobe as radiance (the papers')
const int LF_BRDF_COOK_TORRANCE = 1;  // D G F / (4 (n.l)(n.v)), Beckmann D, Smith G, Schlick F

// Shading parameters (docs/math.md §4). Colours are linear RGB. Each vec3 is followed by a scalar
// so that the std140 layout of the renderer's uniform block (LfShadingUniforms below) equals the
// C++ layout of the same struct with glm (checked in
// libs/gl/include/leanfade/gl/detail/shading_block.hpp).
struct LfParams {
    vec3 light_color;     // radiance scale of the light
    float shininess;      // Blinn-Phong exponent s (> 0)
    vec3 ambient;         // Ka
    float inv_s_shading;  // base slope variance per axis added to the covariance at shading
                          // time: 1/s (LEAN eq. 6), or a0^2/2 with Cook-Torrance; 0 when baked
    vec3 kd;              // diffuse albedo Kd
    float fresnel_bias;   // Fb
    vec3 ks;              // specular colour Ks
    float fresnel_scale;  // Fs
    float fade;           // Fade >= 0 (fading paper eq. 6)
    float pmax;           // Pmax >= 1
    float fade_exponent;  // p
    int fade_distance;    // LF_FADE_DISTANCE_*
    vec3 f0 LF_DEFAULT(vec3(0.04f));     // Cook-Torrance: Schlick's F0, linear RGB
    int brdf LF_DEFAULT(LF_BRDF_BLINN_PHONG);  // LF_BRDF_*
};

// Texture coordinate transforms of LfShadingUniforms::uv_transforms (two rows each): the LEAN
// map's (its plateau layer's too) and each surface map kind's (leanfade/scene/detail/map_kinds.hpp,
// MapKindInfo::uv_transform).
const int LF_UV_LEAN_MAP = 0;
const int LF_UV_BASE_COLOR = 1;
const int LF_UV_BASE_ROUGHNESS = 2;
const int LF_UV_METALLIC = 3;
const int LF_UV_OCCLUSION = 4;
const int LF_UV_EMISSIVE = 5;
const int LF_UV_ANISOTROPY = 6;
const int LF_UV_TRANSFORM_COUNT = 7;

// A glTF material's factors, which multiply its surface maps' texels (lf_surface; glTF 2.0
// §3.9.2-3.9.5 and KHR_materials_anisotropy). All 0 for other materials: no metalness beyond the
// frame's (in LfParams already), no occlusion, no emission, no anisotropy.
struct LfMaterialFactors {
    vec3 emissive LF_DEFAULT(vec3(0.0f));  // emissiveFactor, linear RGB radiance
    float metallic LF_DEFAULT(0.0f);       // metallicFactor in [0, 1]
    // (cos, sin) of anisotropyRotation (counter-clockwise from +u)
    vec2 anisotropy_rotation LF_DEFAULT(vec2(1.0f, 0.0f));
    float anisotropy_strength LF_DEFAULT(0.0f);  // anisotropyStrength in [0, 1]
    float occlusion_strength LF_DEFAULT(0.0f);   // occlusionTexture.strength in [0, 1]
};

// Everything the fragment stage of the renderer reads per draw, as one std140 uniform block
// (binding LF_BINDING_SHADING_BLOCK, shaders/bindings.glsl).
struct LfShadingUniforms {
    LfParams params LF_DEFAULT(lf_default_params());
    float scale LF_DEFAULT(1.0f);  // sc of the LEAN map (docs/math.md §3)
    int output_mode LF_DEFAULT(0);  // OUTPUT_* of scene.frag (0: OUTPUT_COLOR)
    int fog_mode LF_DEFAULT(to_shader_constant(ShadingSettings{}.fog));  // LF_FOG_*
    float fog_start LF_DEFAULT(ShadingSettings{}.fog_start);  // world units
    vec3 fog_color LF_DEFAULT(ShadingSettings{}.fog_color);  // linear RGB
    float fog_end LF_DEFAULT(ShadingSettings{}.fog_end);  // world units
    float fog_density LF_DEFAULT(ShadingSettings{}.fog_density);  // per world unit
    // LF_MAP_* bits of the material's surface maps the shader reads (shaders/bindings.glsl); with
    // LF_MAP_BASE_ROUGHNESS Cook-Torrance's base roughness comes per texel from the map's
    // alpha0^2, not from params.inv_s_shading.
    int maps LF_DEFAULT(0);
    // Geometric specular antialiasing (docs/math.md §11): the clamp kappa of the pixel
    // footprint's alpha^2 (lf_footprint_covariance), read by the shaders compiled with
    // LF_GEOMETRIC_AA.
    float geometric_aa_kappa LF_DEFAULT(ShadingSettings{}.geometric_aa_kappa);
    // glTF alphaMode MASK: a fragment whose base colour alpha times base_alpha is below
    // alpha_cutoff is discarded; alpha_cutoff < 0: opaque (every other material).
    float alpha_cutoff LF_DEFAULT(-1.0f);
    float base_alpha LF_DEFAULT(1.0f);  // the material's base colour factor's alpha
    // glTF alphaMode BLEND: 1 makes the output's alpha the base colour's (texture times
    // base_alpha), blended over what is behind; 0: alpha 1 (opaque).
    float blend LF_DEFAULT(0.0f);
    // glTF doubleSided: 1 shades back faces with the reversed frame; 0: as front faces.
    float double_sided LF_DEFAULT(0.0f);
    // The LEAN map's offset o (lf_unpack): 1 for the offset encoding (UNORM maps, and float maps
    // of leanfade 0.1), 0 for the signed encoding of float maps (LEANFADElayout "... v2").
    float lean_offset LF_DEFAULT(1.0f);
    // Texture coordinate transforms (glTF KHR_texture_transform) of the LEAN map (and its plateau
    // layer) and of each surface map kind, at LF_UV_* (above): two rows each,
    // uv' = (dot(r0.xy, uv) + r0.z, dot(r1.xy, uv) + r1.z) in leanfade's uv (v up), uv the
    // texture coordinate set r0.w names (0: the mesh's set 0, 1: its set 1, a glTF texture
    // reference's texCoord); the identity of set 0 for other materials.
    vec4 uv_transforms[2 * LF_UV_TRANSFORM_COUNT] LF_UV_TRANSFORMS_IDENTITY;
    LfMaterialFactors material;  // the glTF material's factors (zero for other materials)
};

// Moments unpacked from the two LEAN textures (docs/math.md §3-4), with what else a pixel knows
// about its slope distribution.
struct LfMoments {
    vec3 normal;  // filtered normal, not renormalised
    vec2 mean;    // B
    vec3 second;  // M = (Mxx, Myy, Mxy)
    // The plateau map's filtered texel (docs/math.md §10): (f, f Bs.x, f Bs.y, f |Bs|^2), the
    // fraction f of the footprint on a plateau and the plateau texels' first and (isotropic)
    // second moments; 0 without one.
    vec4 plateau LF_DEFAULT(vec4(0.0f));
    // A slope covariance (Sxx, Syy, Sxy) added to the lobe's: the pixel footprint's of geometric
    // specular antialiasing (docs/math.md §11) and the anisotropic part of the base roughness
    // (lf_anisotropy_covariance); 0 without them.
    vec3 footprint LF_DEFAULT(vec3(0.0f));
};

// Shading result split so that tests can compare diffuse and specular separately.
struct LfShade {
    vec3 diffuse;   // (Ka + Kd * NdotL) * light
    vec3 specular;  // Ks * NdotL^sf * D * F * light
};

// Unpacking, docs/math.md §4, of a map stored with the offset o (1: the offset encoding of UNORM
// maps and 0.1's float maps, s = 0.5 v + 0.5; 0: the signed encoding of float maps, s = v):
// n = (1 + o) lean1.rgb - o, B = ((1 + o) lean2.rg - o) sc,
// M = (lean2.b sc^2, lean2.a sc^2, ((1 + o) lean1.a - o) sc^2).
LF_FN LfMoments lf_unpack(vec4 lean1, vec4 lean2, float sc, float offset) {
    LfMoments m;
    float gain = 1.0f + offset;
    m.normal = gain * vec3(lean1.x, lean1.y, lean1.z) - vec3(offset);
    m.mean = (gain * vec2(lean2.x, lean2.y) - vec2(offset)) * sc;
    m.second = vec3(lean2.z * sc * sc, lean2.w * sc * sc, (gain * lean1.w - offset) * sc * sc);
    m.plateau = vec4(0.0f);
    m.footprint = vec3(0.0f);
    return m;
}

// Bump layers (LEAN §3.5, docs/math.md §6): the moments of several layers mixed with weights t_i
// (sum 1) before the lobe: B = sum t_i B_i, M = sum t_i^2 M_i + sum_{i<j} t_i t_j C_ij, where C_ij
// comes from the pair's four slope products. Start from lf_mix_start(), add each layer and each
// pair, end with lf_mix_end().

// The four products of two layers' slopes (Bi.x Bj.x, Bi.y Bj.y, Bi.x Bj.y, Bj.x Bi.y): a texel
// of the pair's cross-term texture at the finest level ("mixing textures"), or the same products
// of filtered B's at shading time ("mixing approximation", exact at the finest level only).
LF_FN vec4 lf_cross_products(vec2 bi, vec2 bj) {
    return vec4(bi.x * bj.x, bi.y * bj.y, bi.x * bj.y, bj.x * bi.y);
}

// A layer's moments at strength k: B k and M k^2 (k < 0 flips the layer's slopes).
LF_FN LfMoments lf_layer_strength(LfMoments m, float k) {
    LfMoments r;
    r.normal = m.normal;
    r.mean = m.mean * k;
    r.second = m.second * (k * k);
    r.plateau = vec4(0.0f);  // bump layers shade without a plateau (docs/math.md §10)
    r.footprint = m.footprint;
    return r;
}

LF_FN LfMoments lf_mix_start() {
    LfMoments r;
    r.normal = vec3(0.0f);
    r.mean = vec2(0.0f);
    r.second = vec3(0.0f);
    r.plateau = vec4(0.0f);
    r.footprint = vec3(0.0f);
    return r;
}

// Adds layer i with weight t: t B_i to B and t^2 M_i to M.
LF_FN LfMoments lf_mix_layer(LfMoments mixed, LfMoments layer, float t) {
    LfMoments r;
    r.normal = mixed.normal;
    r.mean = mixed.mean + t * layer.mean;
    r.second = mixed.second + (t * t) * layer.second;
    r.plateau = mixed.plateau;
    r.footprint = mixed.footprint;
    return r;
}

// Adds the pair (i, j) with weights t_i t_j: C_ij = (2 Pxx, 2 Pyy, Pxy + Pyx) of its products P
// (at the strengths of the two layers: P scaled by k_i k_j).
LF_FN LfMoments lf_mix_pair(LfMoments mixed, vec4 products, float ti_tj) {
    LfMoments r;
    r.normal = mixed.normal;
    r.mean = mixed.mean;
    r.second = mixed.second +
               ti_tj * vec3(2.0f * products.x, 2.0f * products.y, products.z + products.w);
    r.plateau = mixed.plateau;
    r.footprint = mixed.footprint;
    return r;
}

// The mixed surface's normal for the tail (NdotL, Fresnel): the normal of its mean slope B.
LF_FN LfMoments lf_mix_end(LfMoments mixed) {
    LfMoments r;
    r.normal = normalize(vec3(mixed.mean.x, mixed.mean.y, 1.0f));
    r.mean = mixed.mean;
    r.second = mixed.second;
    r.plateau = mixed.plateau;
    r.footprint = mixed.footprint;
    return r;
}

// Mixing methods of a layered material (leanfade/core/detail/layers.hpp, kLayerMixings): where the
// cross terms C_ij come from. HEIGHT materials are drawn from one map mixed before filtering.
const int LF_MIXING_HEIGHT = 0;
const int LF_MIXING_TEXTURES = 1;  // the pair's cross-term texture (its slice of the array)
const int LF_MIXING_APPROX = 2;    // lf_cross_products of the filtered, strength-scaled B's

// What the fragment stage reads about a layered material, as one std140 uniform block (binding
// LF_BINDING_LAYER_BLOCK). Layer i is sampled at uv * tilings[i] + its offset (velocity * time).
struct LfLayerUniforms {
    vec4 weights;     // t_0..t_3, sum 1 (0 for absent layers)
    vec4 strengths;   // k_0..k_3 (k < 0 flips a layer)
    vec4 scales LF_DEFAULT(vec4(1.0f));  // sc of each layer's LEAN map (docs/math.md §3)
    vec4 lean_offsets LF_DEFAULT(vec4(1.0f));  // o of each layer's LEAN map (lf_unpack)
    vec4 tilings LF_DEFAULT(vec4(1.0f));  // repeats of each layer per unit of the surface's tiled uv
    vec4 offsets[2];  // uv offsets: (u_0, v_0, u_1, v_1), (u_2, v_2, u_3, v_3)
    int count;        // 2..4 layers
    int mixing;       // LF_MIXING_*
    int weight_map;   // 1: the weights come per texel from the weight map (RGBA = t_0..t_3)
    int padding;
};

// Flow-map weights of moving layers (LEAN §3.5, Fig. 11: "layers are weighted in proportion to
// their movement direction"): layer i's agreement with the local flow f is
// max(0, dot(normalize(v_i), normalize(f))), and its weight t_i is its agreement over the sum of
// all (so the weights sum to 1). Velocities and flow share one frame (texture u, v; any units);
// a layer with zero velocity agrees nowhere. Where no layer agrees (f = 0, or f opposes every
// layer) the `count` layers share equally. Layers at and beyond `count` (1..4) get 0.
LF_FN float lf_flow_agreement(vec2 velocity, vec2 flow) {
    float speed = length(velocity);
    float strength = length(flow);
    if (speed <= 0.0f || strength <= 0.0f) return 0.0f;
    return max(0.0f, dot(velocity / speed, flow / strength));
}

LF_FN vec4 lf_flow_weights(vec2 flow, vec2 v0, vec2 v1, vec2 v2, vec2 v3, int count) {
    vec4 used = vec4(count > 0 ? 1.0f : 0.0f, count > 1 ? 1.0f : 0.0f, count > 2 ? 1.0f : 0.0f,
                     count > 3 ? 1.0f : 0.0f);
    vec4 agreement = vec4(lf_flow_agreement(v0, flow), lf_flow_agreement(v1, flow),
                          lf_flow_agreement(v2, flow), lf_flow_agreement(v3, flow)) *
                     used;
    float total = agreement.x + agreement.y + agreement.z + agreement.w;
    if (total > 1e-6f) return agreement / total;
    return used / max(used.x + used.y + used.z + used.w, 1.0f);
}

// Covariance (LEAN eq. 5 plus the base roughness 1/s of docs/math.md §2): (Sxx, Syy, Sxy). The
// variances M - B^2 are 0 or more in exact arithmetic; quantised textures (8-bit above all) can
// round them below 0, and a negative definite Sigma would turn the lobe's exponent positive and
// overflow, so they are clamped at 0 before 1/s is added.
LF_FN vec3 lf_covariance(vec2 mean, vec3 second, float inv_s) {
    return vec3(max(second.x - mean.x * mean.x, 0.0f) + inv_s,
                max(second.y - mean.y * mean.y, 0.0f) + inv_s, second.z - mean.x * mean.y);
}

// LEAN lobe (LEAN eq. 1 with the authors' errata normalisation 1/(2 pi sqrt(det))), evaluated at
// the half vector H (tangent space, unit). Units: 1/slope^2 (a density over projected slopes).
// The lobe as exp(x) / y: returns (x, y) = (-e/2, 2 pi sqrt(det)), or (0, 0) where the lobe is 0
// (det <= 0 or H below the tangent plane).
LF_FN vec2 lf_lean_lobe_terms(vec3 half_vector, vec2 mean, vec3 sigma) {
    float det = sigma.x * sigma.y - sigma.z * sigma.z;
    if (det <= 0.0f || sigma.x <= 0.0f || half_vector.z <= 0.0f) return vec2(0.0f);
    vec2 h = vec2(half_vector.x, half_vector.y) / half_vector.z - mean;
    float e = (h.x * h.x * sigma.y + h.y * h.y * sigma.x - 2.0f * h.x * h.y * sigma.z) / det;
    return vec2(-0.5f * e, 2.0f * LF_PI * sqrt(det));
}

// exp(x) / y of lf_lean_lobe_terms: the lobe's value.
LF_FN float lf_lean_lobe_value(vec2 terms) {
    return (terms.y > 0.0f) ? exp(terms.x) / terms.y : 0.0f;
}

LF_FN float lf_lean_lobe(vec3 half_vector, vec2 mean, vec3 sigma) {
    return lf_lean_lobe_value(lf_lean_lobe_terms(half_vector, mean, sigma));
}

// Normalised Blinn-Phong lobe of the baseline: s/(2 pi) max(0, nb.H)^s, so that at the finest
// level it peaks where LEAN with Sigma = I/s peaks.
LF_FN float lf_blinn_phong_lobe(vec3 bump_normal, vec3 half_vector, float s) {
    float c = max(0.0f, dot(bump_normal, half_vector));
    return s / (2.0f * LF_PI) * pow(c, s);
}

// Schlick-form Fresnel of the fading paper's listing: clamp(Fb + Fs (1 - n.V)^5, 0, 1).
LF_FN float lf_fresnel(vec3 n, vec3 view_dir, float bias, float scale) {
    float c = max(0.0f, 1.0f - dot(n, view_dir));
    // c^5 by multiplication: a pow would cost a log2 and an exp2 per pixel (docs/perf.md).
    float c2 = c * c;
    return clamp(bias + scale * (c2 * c2 * c), 0.0f, 1.0f);
}

// Distance measure of specular fading. view_unnormalised: tangent-space vector from the shaded
// point to the eye, in world units (docs/math.md §1 Vt).
// Shaders compiled with LF_FADE_TANGENT_Z_ONLY (the renderer's variant for the default mode)
// ignore `mode`.
LF_FN float lf_fade_distance(vec3 view_unnormalised, int mode) {
#if !defined(LF_FADE_TANGENT_Z_ONLY)
    if (mode == LF_FADE_DISTANCE_EYE) return length(view_unnormalised);
#endif
    return max(0.0f, view_unnormalised.z);
}

// Specular fading exponent (fading paper eq. 6-7): sf = clamp(1 + (d Fade)^p, 1, Pmax).
// Shaders compiled with LF_FADE_EXPONENT_2 (the renderer's variant for the default p = 2) take
// (d Fade)^2 as a product: on a GPU pow(x, 2) = exp2(2 log2 x) costs a log2 and an exp2 per pixel
// and is not exact (docs/perf.md); `exponent` is then ignored.
LF_FN float lf_fade_factor(float distance, float fade, float exponent, float pmax) {
    float x = max(0.0f, distance * fade);
#if defined(LF_FADE_EXPONENT_2)
    float power = x * x;
#else
    float power = pow(x, exponent);
#endif
    return clamp(1.0f + power, 1.0f, max(pmax, 1.0f));
}

// Shared tail of every technique: (Ka + Kd NdotL) + Ks A F, times the light colour, where
// A = NdotL^sf D is the attenuated lobe (fading paper eq. 7).
LF_FN LfShade lf_combine_attenuated(vec3 n, vec3 light_dir, vec3 view_dir, float attenuated_lobe,
                                   LfParams p) {
    float n_dot_l = clamp(dot(n, light_dir), 0.0f, 1.0f);
    float fresnel = lf_fresnel(n, view_dir, p.fresnel_bias, p.fresnel_scale);
    LfShade result;
    result.diffuse = (p.ambient + p.kd * n_dot_l) * p.light_color;
    result.specular = p.ks * (attenuated_lobe * fresnel) * p.light_color;
    return result;
}

// The same with A = NdotL^sf D from the lobe D and sf. sf == 1 (the baseline, LEAN, Fade = 0)
// takes NdotL itself: the same value, but exact, whereas a GPU pow(x, 1) = exp2(log2(x)) is not,
// so that Fade = 0 renders bit-identically to LEAN.
LF_FN LfShade lf_combine(vec3 n, vec3 light_dir, vec3 view_dir, float lobe, float sf,
                        LfParams p) {
    float n_dot_l = clamp(dot(n, light_dir), 0.0f, 1.0f);
    float attenuation = (sf == 1.0f) ? n_dot_l : pow(n_dot_l, sf);
    return lf_combine_attenuated(n, light_dir, view_dir, attenuation * lobe, p);
}

// Peer techniques, baked from the same two LEAN layers. Both keep LEAN's diffuse term (the
// filtered, unnormalised normal for NdotL and Fresnel) so that they differ from LEAN only in the
// specular lobe.

// Toksvig factor (Toksvig 2005, "Mipmapping normal maps", JGT 10(3)): a filtered normal of length
// |Na| < 1 is read as a Gaussian spread of normals with variance sigma^2 = (1 - |Na|) / |Na|, and
// the Blinn-Phong exponent s becomes ft s with ft = 1 / (1 + s sigma^2) = |Na| / (|Na| + s (1 -
// |Na|)). The length is clamped to (0, 1]: quantisation can make a level-0 normal slightly long.
LF_FN float lf_toksvig_factor(float normal_length, float s) {
    float a = clamp(normal_length, 1e-6f, 1.0f);
    return a / (a + s * (1.0f - a));
}

// Toksvig's lobe around the renormalised filtered normal Na / |Na| with the effective exponent
// s' = ft s and Toksvig's energy factor (1 + ft s) / (1 + s) (same paper), on the baseline's
// normalisation s / (2 pi) (docs/math.md §4), so that ft = 1 is exactly lf_blinn_phong_lobe.
LF_FN float lf_toksvig_lobe(vec3 filtered_normal, vec3 half_vector, float s) {
    float len = length(filtered_normal);
    if (len <= 0.0f) return 0.0f;
    float ft = lf_toksvig_factor(len, s);
    float c = max(0.0f, dot(filtered_normal / len, half_vector));
    return s / (2.0f * LF_PI) * ((1.0f + ft * s) / (1.0f + s)) * pow(c, ft * s);
}

// CLEAN covariance (Baker 2011, "CLEAN mapping", the isotropic reduction of LEAN eq. 5): only the
// mean B and the scalar second moment m = E[Bx^2 + By^2] = Mxx + Myy are kept, and the covariance
// is isotropic with LEAN's trace: Sigma = ((m - |B|^2) / 2 + 1/s) I, as (Sxx, Syy, Sxy).
LF_FN vec3 lf_clean_covariance(vec2 mean, float second_isotropic, float inv_s) {
    float variance = max(0.5f * (second_isotropic - dot(mean, mean)), 0.0f) + inv_s;
    return vec3(variance, variance, 0.0f);
}

// Cook-Torrance (docs/math.md §9): f = D G F / (4 (n.l)(n.v)), Cook & Torrance 1982 with the
// normalisation of Walter et al. 2007 eq. 20. D is LEAN's Gaussian over slopes, made a
// distribution of normals; G is Smith's for Beckmann; F is Schlick's on h.v. The slope covariance
// holds the base roughness as a per-axis variance a0^2/2 (a Beckmann distribution of roughness a
// is a Gaussian over slopes of variance a^2/2 per axis).

// Smith's masking G1 = 1 / (1 + Lambda(a)) of a Beckmann surface, a = cot(theta) / alpha, by the
// rational approximation of Walter et al. 2007 eq. 27 (GLSL has no erfc): exact 1 from a = 1.6
// on, relative error below 0.4% under it (tests/core/test_brdf.cpp), capped at 1 (the rational
// form exceeds 1 by up to 6e-5 just below 1.6). a <= 0: fully masked.
LF_FN float lf_smith_g1_beckmann(float a) {
    if (a <= 0.0f) return 0.0f;
    if (a >= 1.6f) return 1.0f;
    return min(1.0f, (3.535f * a + 2.181f * a * a) / (1.0f + 2.276f * a + 2.577f * a * a));
}

// Smith's G1 of the direction w (tangent space, unit) over facets whose slopes are a Gaussian of
// mean B and covariance Sigma. The mean enters through the frame sheared by B, in which the
// slopes are centred (LEADR, Dupuy et al. 2013, sec. 4): w's cotangent there is the height of w
// over the mean facet plane, (B, 1).w / |w_xy|, and the directional roughness along w's azimuth
// is alpha_w^2 = 2 w_xy^T Sigma w_xy / |w_xy|^2, so a = (B, 1).w / sqrt(2 w_xy^T Sigma w_xy).
LF_FN float lf_smith_g1(vec3 w, vec2 mean, vec3 sigma) {
    float height = w.z + mean.x * w.x + mean.y * w.y;
    float spread =
        2.0f * (w.x * w.x * sigma.x + w.y * w.y * sigma.y + 2.0f * w.x * w.y * sigma.z);
    if (height <= 0.0f) return 0.0f;
    if (spread <= 0.0f) return 1.0f;  // w along the normal: nothing masks it (a = infinity)
    return lf_smith_g1_beckmann(height / sqrt(spread));
}

// The Cook-Torrance lobe D G / (4 (n.l)(n.v)) (the tail multiplies by F, NdotL^sf and the light)
// for slopes of mean B and covariance Sigma over the tangent plane; h, l, v unit, tangent space.
// D(h) = P(h~) / h.z^4: LEAN's Gaussian P over projected slopes (LEAN eq. 1) as a distribution of
// normals, normalised as the integral of D(h) h.z over the hemisphere = 1. n.l and n.v are taken
// on the unit mean facet normal n = (B, 1) / |(B, 1)|, which G1 of the sheared frame takes to 0
// as fast as l or v grazes the mean facet plane: a smooth surface tilted by B then reflects all
// the light that arrives along n, as a tilted mirror does (docs/math.md §9). B = 0 gives the
// usual form.
LF_FN float lf_cook_torrance_lobe(vec3 h, vec3 l, vec3 v, vec2 mean, vec3 sigma) {
    float inv_length = 1.0f / sqrt(1.0f + mean.x * mean.x + mean.y * mean.y);
    float n_dot_l = (l.z + mean.x * l.x + mean.y * l.y) * inv_length;
    float n_dot_v = (v.z + mean.x * v.x + mean.y * v.y) * inv_length;
    if (n_dot_l <= 0.0f || n_dot_v <= 0.0f || h.z <= 0.0f) return 0.0f;
    float hz2 = h.z * h.z;
    float d = lf_lean_lobe(h, mean, sigma) / (hz2 * hz2);
    float g = lf_smith_g1(l, mean, sigma) * lf_smith_g1(v, mean, sigma);
    return d * g / (4.0f * n_dot_l * n_dot_v);
}

// w in a frame around the unit normal n, for an isotropic lobe centred on n: only the cosine
// c = n.w and the length of the rest, sqrt(1 - c^2), matter, so w becomes (sqrt(1 - c^2), 0, c).
LF_FN vec3 lf_in_isotropic_frame(vec3 n, vec3 w) {
    float c = dot(n, w);
    return vec3(sqrt(max(0.0f, 1.0f - c * c)), 0.0f, c);
}

// The isotropic Beckmann lobe of roughness alpha^2 around the unit normal n (the baseline's bump
// normal): lf_cook_torrance_lobe with B = 0 and Sigma = (alpha^2 / 2) I in n's frame.
LF_FN float lf_cook_torrance_isotropic(vec3 n, vec3 h, vec3 l, vec3 v, float alpha_squared) {
    float variance = 0.5f * alpha_squared;
    return lf_cook_torrance_lobe(lf_in_isotropic_frame(n, h), lf_in_isotropic_frame(n, l),
                                 lf_in_isotropic_frame(n, v), vec2(0.0f),
                                 vec3(variance, variance, 0.0f));
}

// A base roughness map (docs/math.md §9): the texel's alpha0^2 = r^4, MIP-filtered linearly as
// the moments are, becomes the per-axis slope variance alpha0^2 / 2 that a uniform roughness
// gives (to_lf_params), before the lobe is evaluated. Cook-Torrance only.
LF_FN LfParams lf_with_base_roughness(LfParams p, float alpha0_squared) {
    LfParams r = p;
    r.inv_s_shading = 0.5f * max(alpha0_squared, 0.0f);
    return r;
}

// The material's parameters at one fragment, stage 2 of lf_shade's pipeline, from the surface
// maps' texels the caller fetched (shaders/scene.frag: filtered reads at the surface's uv; the
// CPU reference: the texel values): Kd times the base colour's RGB (white without a map), and
// with has_base_roughness (the material's roughness map, Cook-Torrance) the base roughness from
// the map's alpha0^2.
LF_FN LfParams lf_material_params(LfParams p, vec4 base_color, bool has_base_roughness,
                                  float alpha0_squared) {
    LfParams r = p;
    r.kd *= vec3(base_color.x, base_color.y, base_color.z);
    if (has_base_roughness) {
        r = lf_with_base_roughness(r, alpha0_squared);
    }
    return r;
}

// Schlick's Fresnel on h.v: F0 + (1 - F0) (1 - h.v)^5 (Schlick 1994), per colour channel.
LF_FN vec3 lf_fresnel_schlick(vec3 h, vec3 view_dir, vec3 f0) {
    float c = clamp(1.0f - dot(h, view_dir), 0.0f, 1.0f);
    float c2 = c * c;
    return f0 + (vec3(1.0f) - f0) * (c2 * c2 * c);
}

// The shared tail with Cook-Torrance: (Ka + Kd NdotL) + Ks NdotL^sf L F, times the light, where
// L = D G / (4 (n.l)(n.v)) is the lobe and NdotL the tail's normal's (as lf_combine). At sf = 1
// the specular term is the BRDF times the cosine; sf > 1 fades it as with Blinn-Phong (fading
// paper eq. 7).
LF_FN LfShade lf_combine_cook_torrance(vec3 n, vec3 light_dir, vec3 view_dir, vec3 h, float lobe,
                                       float sf, LfParams p) {
    float n_dot_l = clamp(dot(n, light_dir), 0.0f, 1.0f);
    float attenuation = (sf == 1.0f) ? n_dot_l : pow(n_dot_l, sf);
    LfShade result;
    result.diffuse = (p.ambient + p.kd * n_dot_l) * p.light_color;
    result.specular =
        p.ks * lf_fresnel_schlick(h, view_dir, p.f0) * (attenuation * lobe) * p.light_color;
    return result;
}

// Roughness MIPs for engines (docs/roughness.md, docs/math.md §9): the texel an engine's textures
// hold for a LEAN texel of some MIP level: (0.5 n + 0.5, r) with n the unit normal of the mean
// slope B and r = sqrt(alpha) the perceptual roughness of alpha^2 = alpha0^2 + Sxx + Syy, each
// rounded to 8 bits as `leanfade bake --roughness-out` writes them. A map with baked roughness
// holds 1/s in M already: pass alpha0^2 = 0 then (2 p.inv_s_shading is). sc and offset as
// lf_unpack's.
LF_FN vec4 lf_roughness_mip_texel(vec4 lean1, vec4 lean2, float sc, float offset,
                                  float alpha0_squared) {
    LfMoments m = lf_unpack(lean1, lean2, sc, offset);
    vec3 sigma = lf_covariance(m.mean, m.second, 0.0f);
    float alpha = sqrt(alpha0_squared + sigma.x + sigma.y);
    vec3 n = normalize(vec3(m.mean.x, m.mean.y, 1.0f));
    vec4 texel = vec4(0.5f * n.x + 0.5f, 0.5f * n.y + 0.5f, 0.5f * n.z + 0.5f, sqrt(alpha));
    return round(clamp(texel, vec4(0.0f), vec4(1.0f)) * 255.0f) / 255.0f;
}

// The moments lf_shade reads for LF_TECHNIQUE_ROUGHNESS_MIPS from a filtered roughness-MIP texel:
// normal = 2 rgb - 1 (renormalised by the lobe), second.x = r; B and the rest unused.
LF_FN LfMoments lf_roughness_mips_moments(vec4 texel) {
    LfMoments m;
    m.normal = 2.0f * vec3(texel.x, texel.y, texel.z) - vec3(1.0f);
    m.mean = vec2(0.0f);
    m.second = vec3(texel.w, 0.0f, 0.0f);
    m.plateau = vec4(0.0f);
    m.footprint = vec3(0.0f);
    return m;
}

// The lobe of a technique, set up once from the moments and fed to either BRDF: an isotropic
// lobe around a normal (the baseline, the roughness MIPs), Toksvig's lobe around the filtered
// normal, or a Gaussian over slopes (LEAN, fading, CLEAN).
const int LF_LOBE_NORMAL = 0;    // isotropic around the unit lobe_normal
const int LF_LOBE_TOKSVIG = 1;   // around lobe_normal / |lobe_normal|, spread by its length
const int LF_LOBE_GAUSSIAN = 2;  // a Gaussian over slopes of mean B and covariance Sigma
const int LF_LOBE_TWO_LOBE = 3;  // a plateau's spike plus the halo of the other slopes, both
                                 // Gaussians over slopes (docs/math.md §10)

struct LfLobe {
    int kind;             // LF_LOBE_*
    vec3 tail_normal;     // the normal of the shared tail (NdotL^sf, Fresnel)
    vec3 lobe_normal;     // NORMAL: unit; TOKSVIG: the filtered normal, |n| <= 1
    float exponent;       // Blinn-Phong: the exponent s of NORMAL and TOKSVIG
    float alpha_squared;  // Cook-Torrance: Beckmann alpha^2 of NORMAL and TOKSVIG
    vec2 mean;            // GAUSSIAN: the slope mean B
    vec3 sigma;           // GAUSSIAN: the slope covariance (Sxx, Syy, Sxy), base roughness included;
                          // TWO_LOBE: the halo's mean and covariance
    bool fades;           // specular fading's NdotL^sf on the tail (fading paper eq. 6-7)
    float spike_weight;   // TWO_LOBE: f, the plateau's share; the halo's is 1 - f
    vec2 spike_mean;      // TWO_LOBE: the plateau's mean slope Bs
    vec3 spike_sigma;     // TWO_LOBE: the plateau's covariance, base roughness included
};

// Two-lobe LEAN (docs/math.md §10): the footprint's slopes as a plateau of weight f = p.x (texels
// whose slope hardly differs from their neighbours', stored as (f, f Bs, f |Bs|^2) so that MIP
// filtering stays exact) and the halo of the rest, each a Gaussian:
//   D = f N(h~; Bs, Sigma_s + Sigma0) + (1 - f) N(h~; B_h, Sigma_h + Sigma0),
// with Bs = (f Bs) / f, Sigma_s = ((f |Bs|^2) / f - |Bs|^2) / 2 I, and the halo's moments the map's
// minus the plateau's: B_h = (B - f Bs) / (1 - f), M_h = (M - f (Bs Bs^T + Sigma_s)) / (1 - f).
// Sigma0 is the base roughness (inv_s per axis). f = 0 leaves `lobe` as LEAN's; 1 - f below
// 1e-3 (where the halo's moments would be quantisation noise divided by 1 - f) is all plateau.
LF_FN LfLobe lf_two_lobe_split(LfLobe lobe, LfMoments m, float inv_s) {
    float f = clamp(m.plateau.x, 0.0f, 1.0f);
    if (f <= 0.0f) return lobe;
    LfLobe r = lobe;
    r.kind = LF_LOBE_TWO_LOBE;
    vec2 f_mean = vec2(m.plateau.y, m.plateau.z);
    vec2 spike_mean = f_mean / f;
    float spread = max(0.5f * (m.plateau.w / f - dot(spike_mean, spike_mean)), 0.0f);
    r.spike_weight = f;
    r.spike_mean = spike_mean;
    r.spike_sigma = vec3(spread + inv_s, spread + inv_s, 0.0f);
    float g = 1.0f - f;
    if (g > 1e-3f) {
        vec2 halo_mean = (m.mean - f_mean) / g;
        vec3 f_second = vec3(f_mean.x * spike_mean.x + f * spread,
                             f_mean.y * spike_mean.y + f * spread, f_mean.x * spike_mean.y);
        r.mean = halo_mean;
        r.sigma = lf_covariance(halo_mean, (m.second - f_second) / g, inv_s);
    } else {
        r.spike_weight = 1.0f;
        r.mean = r.spike_mean;
        r.sigma = r.spike_sigma;
    }
    return r;
}

// The two-lobe slope density at the half vector h (tangent space, unit): f N(h~; Bs, spike) +
// (1 - f) N(h~; B_h, halo), in 1/slope^2 (Blinn-Phong's lobe; the bake's spike fit,
// leanfade/core/detail/plateau.hpp, measures with it too).
LF_FN float lf_two_lobe_density(LfLobe lobe, vec3 h) {
    return lobe.spike_weight * lf_lean_lobe(h, lobe.spike_mean, lobe.spike_sigma) +
           (1.0f - lobe.spike_weight) * lf_lean_lobe(h, lobe.mean, lobe.sigma);
}

// Geometric specular antialiasing (Kaplanyan et al. 2016; Tokuyoshi and Kaplanyan 2019, Listing
// 1; docs/math.md §11): the half vector's slope h~ = h.xy / h.z changes across a pixel with the
// surface's curvature and the view; a Gaussian pixel filter of variance 1/(2 pi) pixel^2 spreads
// the slopes one pixel sees by Sigma = (1 / (2 pi)) (dh~/dx^2 + dh~/dy^2) per axis, whose alpha^2
// = 2 Sigma is clamped at kappa. dslope_dx, dslope_dy: the screen-space derivatives of h~ (per
// pixel). Returns (Sxx, Syy, 0), added to every lobe's covariance (lf_lobe_setup).
LF_FN vec3 lf_footprint_covariance(vec2 dslope_dx, vec2 dslope_dy, float kappa) {
    vec2 variance = 0.15915494f * (dslope_dx * dslope_dx + dslope_dy * dslope_dy);
    float limit = 0.5f * max(kappa, 0.0f);
    return vec3(min(variance.x, limit), min(variance.y, limit), 0.0f);
}

// How much of the footprint covariance a pixel may add (docs/math.md §11). The derivatives
// extrapolate one triangle's interpolated normal across the pixel; that is the pixel's spread
// only while the pixel's 2 x 2 quad lies within the triangle or the normals are smooth beyond
// it. linear_change: the largest trusted change of the normal's slope per pixel
// (scene::Vertex::linear_normal_change; 0: smooth, always trusted). Beyond it the pixel spans
// several triangles of normals that are not smooth: its interpolated normal is then already one
// sample of the pixel's normals, and adding their spread again brightens the tail of the image's
// normal distribution (a hilly terrain's far highlight 1.3-3.6x). The weight is 1 up to that
// change and falls as (linear_change / change)^4 beyond it.
LF_FN float lf_footprint_trust(vec2 dslope_dx, vec2 dslope_dy, float linear_change) {
    if (linear_change <= 0.0f) return 1.0f;
    float change_squared = max(dot(dslope_dx, dslope_dx), dot(dslope_dy, dslope_dy));
    float ratio = change_squared / (linear_change * linear_change);
    return ratio <= 1.0f ? 1.0f : 1.0f / (ratio * ratio);
}

// The footprint covariance added to a lobe: each Gaussian's covariance grows by it, and an
// isotropic lobe's alpha^2 by its trace (Blinn-Phong: the per-axis variance 1/s by half of it).
// A zero footprint leaves the lobe as it is, bit for bit.
LF_FN LfLobe lf_with_footprint(LfLobe lobe, vec3 footprint) {
    float trace = footprint.x + footprint.y;
    if (trace <= 0.0f) return lobe;
    LfLobe r = lobe;
    r.sigma = lobe.sigma + footprint;
    r.spike_sigma = lobe.spike_sigma + footprint;
    r.alpha_squared = lobe.alpha_squared + trace;
    r.exponent = 1.0f / (1.0f / max(lobe.exponent, 1e-12f) + 0.5f * trace);
    return r;
}

// Each technique is one branch here: what its lobe is, from the moments and the parameters. The
// base roughness is p.inv_s_shading per axis (1/s, or a0^2/2 with Cook-Torrance).
LF_FN LfLobe lf_lobe_setup(int technique, LfMoments m, LfParams p) {
    LfLobe lobe;
    lobe.kind = LF_LOBE_GAUSSIAN;
    lobe.tail_normal = m.normal;
    lobe.lobe_normal = m.normal;
    lobe.exponent = p.shininess;
    lobe.alpha_squared = 2.0f * p.inv_s_shading;
    lobe.mean = m.mean;
    lobe.sigma = vec3(0.0f);
    lobe.fades = false;
    lobe.spike_weight = 0.0f;
    lobe.spike_mean = vec2(0.0f);
    lobe.spike_sigma = vec3(0.0f);
    if (technique == LF_TECHNIQUE_BUMP) {
        // Baseline bump mapping: the filtered normal renormalised is the bump normal for the lobe
        // and for the tail; Cook-Torrance's isotropic Beckmann lobe of a0.
        lobe.kind = LF_LOBE_NORMAL;
        lobe.lobe_normal = normalize(m.normal);
        lobe.tail_normal = lobe.lobe_normal;
    } else if (technique == LF_TECHNIQUE_ROUGHNESS_MIPS) {
        // The engine's BRDF around the filtered normal renormalised, alpha = r^2: Beckmann of
        // alpha, or Blinn-Phong of the exponent whose per-axis variance 1/s' is alpha^2 / 2
        // (docs/math.md §9).
        lobe.kind = LF_LOBE_NORMAL;
        lobe.lobe_normal = normalize(m.normal);
        lobe.tail_normal = lobe.lobe_normal;
        lobe.alpha_squared = m.second.x * m.second.x * m.second.x * m.second.x;
        lobe.exponent = 2.0f / max(lobe.alpha_squared, 1e-12f);
    } else if (technique == LF_TECHNIQUE_TOKSVIG) {
        // Toksvig's variance (1 - |Na|) / |Na| per axis on top of the base (Toksvig 2005).
        lobe.kind = LF_LOBE_TOKSVIG;
        float a = clamp(length(m.normal), 1e-6f, 1.0f);
        lobe.alpha_squared = 2.0f * p.inv_s_shading + 2.0f * (1.0f - a) / a;
    } else if (technique == LF_TECHNIQUE_CLEAN) {
        lobe.sigma = lf_clean_covariance(m.mean, m.second.x + m.second.y, p.inv_s_shading);
    } else if (technique == LF_TECHNIQUE_TWO_LOBE) {
        // LEAN's Gaussian split into a plateau's spike and a halo (docs/math.md §10).
        lobe.sigma = lf_covariance(m.mean, m.second, p.inv_s_shading);
        lobe = lf_two_lobe_split(lobe, m, p.inv_s_shading);
    } else {
        // LEAN (eq. 5) and LEAN with specular fading.
        lobe.sigma = lf_covariance(m.mean, m.second, p.inv_s_shading);
        lobe.fades = technique == LF_TECHNIQUE_FADE;
    }
    return lf_with_footprint(lobe, m.footprint);
}

// A Gaussian lobe in Blinn-Phong, with specular fading when it fades: A = NdotL^sf D (fading paper
// eq. 7 times LEAN eq. 1), then the shared tail.
LF_FN LfShade lf_shade_gaussian_blinn_phong(LfLobe lobe, vec3 light_dir, vec3 view_unnormalised,
                                            vec3 v, vec3 h, LfParams p) {
    vec2 terms = lf_lean_lobe_terms(h, lobe.mean, lobe.sigma);
    if (lobe.fades) {
        float sf = lf_fade_factor(lf_fade_distance(view_unnormalised, p.fade_distance), p.fade,
                                  p.fade_exponent, p.pmax);
#if !defined(LF_FADE_ACTIVE)
        // Where nothing fades (sf == 1: Fade = 0, Pmax = 1 or d = 0) the pixel is LEAN's, exactly.
        // Shaders compiled with LF_FADE_ACTIVE (drawn only when Fade > 0 and Pmax > 1) skip this
        // test and its second exponential.
        if (sf == 1.0f) {
            return lf_combine(lobe.tail_normal, light_dir, v, lf_lean_lobe_value(terms), 1.0f, p);
        }
#endif
        // NdotL^sf exp(-e/2) in one exponential, exp2(sf log2(NdotL) - (e/2) log2(e)) (fading
        // paper eq. 7 times LEAN eq. 1): one log2 and one exp2 per pixel fewer than pow then exp.
        // NdotL = 0 gives log2 = -inf and 0, as NdotL^sf does; the clamp keeps log2 off 0 where a
        // driver would not.
        float n_dot_l = clamp(dot(lobe.tail_normal, light_dir), 0.0f, 1.0f);
        float faded = (terms.y > 0.0f)
                          ? exp2(sf * log2(max(n_dot_l, 1e-30f)) + terms.x * 1.44269504088896f) /
                                terms.y
                          : 0.0f;
        return lf_combine_attenuated(lobe.tail_normal, light_dir, v, faded, p);
    }
    return lf_combine(lobe.tail_normal, light_dir, v, lf_lean_lobe_value(terms), 1.0f, p);
}

// The papers' BRDF: the lobe itself as radiance, then the shared tail (lf_combine).
LF_FN LfShade lf_shade_blinn_phong(LfLobe lobe, vec3 light_dir, vec3 view_unnormalised, vec3 v,
                                   vec3 h, LfParams p) {
    if (lobe.kind == LF_LOBE_NORMAL) {
        return lf_combine(lobe.tail_normal, light_dir, v,
                          lf_blinn_phong_lobe(lobe.lobe_normal, h, lobe.exponent), 1.0f, p);
    }
    if (lobe.kind == LF_LOBE_TOKSVIG) {
        return lf_combine(lobe.tail_normal, light_dir, v,
                          lf_toksvig_lobe(lobe.lobe_normal, h, lobe.exponent), 1.0f, p);
    }
    if (lobe.kind == LF_LOBE_TWO_LOBE) {
        return lf_combine(lobe.tail_normal, light_dir, v, lf_two_lobe_density(lobe, h), 1.0f,
                          p);
    }
    return lf_shade_gaussian_blinn_phong(lobe, light_dir, view_unnormalised, v, h, p);
}

// Cook-Torrance (docs/math.md §9): D G / (4 (n.l)(n.v)) of the lobe, then Schlick's F and the
// light (lf_combine_cook_torrance), NdotL^sf when the lobe fades.
LF_FN LfShade lf_shade_cook_torrance(LfLobe lobe, vec3 light_dir, vec3 view_unnormalised, vec3 v,
                                     vec3 h, LfParams p) {
    float sf = 1.0f;
    if (lobe.fades) {
        sf = lf_fade_factor(lf_fade_distance(view_unnormalised, p.fade_distance), p.fade,
                            p.fade_exponent, p.pmax);
    }
    float value = 0.0f;
    if (lobe.kind == LF_LOBE_NORMAL) {
        value = lf_cook_torrance_isotropic(lobe.lobe_normal, h, light_dir, v, lobe.alpha_squared);
    } else if (lobe.kind == LF_LOBE_TOKSVIG) {
        float len = length(lobe.lobe_normal);
        value = (len > 0.0f) ? lf_cook_torrance_isotropic(lobe.lobe_normal / len, h, light_dir, v,
                                                          lobe.alpha_squared)
                             : 0.0f;
    } else if (lobe.kind == LF_LOBE_TWO_LOBE) {
        value = lobe.spike_weight *
                    lf_cook_torrance_lobe(h, light_dir, v, lobe.spike_mean, lobe.spike_sigma) +
                (1.0f - lobe.spike_weight) *
                    lf_cook_torrance_lobe(h, light_dir, v, lobe.mean, lobe.sigma);
    } else {
        value = lf_cook_torrance_lobe(h, light_dir, v, lobe.mean, lobe.sigma);
    }
    return lf_combine_cook_torrance(lobe.tail_normal, light_dir, v, h, value, sf, p);
}

// The shading pipeline of every technique, one entry for the shaders and the CPU reference:
//   1. fetch each map's texels (the caller: filtered texture reads on the GPU, texel fetches on
//      the CPU) and unpack them to moments (lf_unpack: filtered normal, B, M);
//   2. combine the moments of the material's sources (bump layers: lf_mix_*; one LEAN map: its
//      moments unchanged);
//   3. the technique's lobe from the moments (lf_lobe_setup, one branch per technique);
//   4. the lobe in the BRDF p.brdf: the lobe itself (Blinn-Phong) or D G / (4 (n.l)(n.v))
//      (Cook-Torrance), and the shared tail: NdotL^sf, Fresnel and the light (lf_combine,
//      lf_combine_cook_torrance).
// technique: LF_TECHNIQUE_*. light_dir: unit tangent-space direction to the light;
// view_unnormalised: Vt, from the shaded point to the eye in world units. Linear radiance.
LF_FN LfShade lf_shade(int technique, LfMoments m, vec3 light_dir, vec3 view_unnormalised,
                       LfParams p) {
    vec3 v = normalize(view_unnormalised);
    vec3 h = normalize(light_dir + v);
    LfLobe lobe = lf_lobe_setup(technique, m, p);
    if (p.brdf == LF_BRDF_COOK_TORRANCE) {
        return lf_shade_cook_torrance(lobe, light_dir, view_unnormalised, v, h, p);
    }
    return lf_shade_blinn_phong(lobe, light_dir, view_unnormalised, v, h, p);
}

// The fragment pipeline after the fetch, for the shaders and the CPU reference alike: the caller
// fetches the texels (shaders/scene.frag: filtered reads at the surface's uv; the CPU reference:
// texel values), these turn them into moments and a shade.

// Stage 1 for one LEAN map: the moments of its two texels (lf_unpack) with the plateau layer's
// texel (docs/math.md §10; vec4(0) for a material without one).
LF_FN LfMoments lf_map_moments(vec4 lean1, vec4 lean2, float sc, float offset, vec4 plateau) {
    LfMoments m = lf_unpack(lean1, lean2, sc, offset);
    m.plateau = plateau;
    return m;
}

// Stages 3-4 from the moments and the surface maps' texels: the material's parameters
// (lf_material_params: Kd times the base colour, the base roughness map's alpha0^2 with
// has_base_roughness) and lf_shade.
LF_FN LfShade lf_shade_material(int technique, LfMoments m, vec4 base_color,
                                bool has_base_roughness, float alpha0_squared, vec3 light_dir,
                                vec3 view_unnormalised, LfParams p) {
    LfParams params = lf_material_params(p, base_color, has_base_roughness, alpha0_squared);
    return lf_shade(technique, m, light_dir, view_unnormalised, params);
}

// A material's surface at one fragment, from its surface maps' texels and its factors
// (lf_surface): what lf_surface_params and lf_shade_surface read besides LfParams.
struct LfSurface {
    vec4 base_color;           // the base colour texture's linear RGBA (white without one)
    bool has_base_roughness;   // Cook-Torrance's base roughness from the roughness map
    float alpha0_squared;      // the roughness map's alpha0^2 (with has_base_roughness)
    float metallic;            // metalness in [0, 1]
    float occlusion;           // the ambient term's factor, 1 + strength (occlusion - 1)
    vec3 emission;             // linear RGB radiance added to the colour
    vec2 anisotropy_direction;  // unit, tangent space: where the base roughness stretches
    float anisotropy;          // its strength in [0, 1]
    vec3 specular_color;       // the specular map's linear RGB, scaling Ks or F0 (1 without one)
};

// The surface from the texels the caller fetched (shaders/scene.frag: filtered reads at each
// map's uv; white for a map the material lacks, (1, 0.5, 1, 1) for a missing anisotropy
// texture) and the material's factors:
// - metalness = metallicFactor x the metallic-roughness texture's B (glTF 2.0 §3.9.2);
// - occlusion: the ambient term becomes lerp(c, c occ, strength) = c (1 + strength (occ - 1))
//   (glTF 2.0 §3.9.4, occlusionTexture.strength);
// - emission = emissiveFactor x the emissive texture's RGB (glTF 2.0 §3.9.5);
// - anisotropy (KHR_materials_anisotropy): direction = R(rotation) (2 texel.rg - 1), normalised
//   (the tangent +u where it is 0), strength = texel.b x anisotropyStrength.
LF_FN LfSurface lf_surface(vec4 base_color, bool has_base_roughness, float alpha0_squared,
                           float metallic_texel, float occlusion_texel, vec4 emissive_texel,
                           vec4 anisotropy_texel, LfMaterialFactors f) {
    LfSurface s;
    s.base_color = base_color;
    s.has_base_roughness = has_base_roughness;
    s.alpha0_squared = alpha0_squared;
    s.metallic = clamp(f.metallic * metallic_texel, 0.0f, 1.0f);
    s.occlusion = 1.0f + f.occlusion_strength * (occlusion_texel - 1.0f);
    s.emission = f.emissive * vec3(emissive_texel.x, emissive_texel.y, emissive_texel.z);
    vec2 d = 2.0f * vec2(anisotropy_texel.x, anisotropy_texel.y) - vec2(1.0f);
    vec2 r = f.anisotropy_rotation;
    vec2 rotated = vec2(r.x * d.x - r.y * d.y, r.y * d.x + r.x * d.y);
    float length_rotated = length(rotated);
    s.anisotropy_direction = (length_rotated > 0.0f) ? rotated / length_rotated : vec2(1.0f, 0.0f);
    s.anisotropy = clamp(anisotropy_texel.z * f.anisotropy_strength, 0.0f, 1.0f);
    s.specular_color = vec3(1.0f);  // the caller sets the specular map's texel where it has one
    return s;
}

// The material's parameters on the surface: lf_material_params (Kd times the base colour, the
// roughness map's alpha0^2), then the metal-roughness model of glTF 2.0 Appendix B with the base
// colour c = Kd x texture: the diffuse Kd = c (1 - metallic), and the specular colour metals
// reflect, F0 = mix(f0 spec, c, metallic) with Cook-Torrance (f0 the dielectric's, 0.04 by
// default; spec the specular map's colour, as KHR_materials_specular's specularColorTexture scales
// the dielectric's F0); Blinn-Phong, which has no F0, takes the same rule on Ks:
// Ks = mix(Ks spec, c, metallic). The ambient term Ka is multiplied by the occlusion factor (the
// renderer's one indirect term).
LF_FN LfParams lf_surface_params(LfParams p, LfSurface s) {
    LfParams r = lf_material_params(p, s.base_color, s.has_base_roughness, s.alpha0_squared);
    vec3 base = r.kd;
    r.kd = base * (1.0f - s.metallic);
    if (p.brdf == LF_BRDF_COOK_TORRANCE) {
        r.f0 = mix(p.f0 * s.specular_color, base, s.metallic);
    } else {
        r.ks = mix(p.ks * s.specular_color, base, s.metallic);
    }
    r.ambient = p.ambient * s.occlusion;
    return r;
}

// KHR_materials_anisotropy on Cook-Torrance's base roughness alpha (Beckmann, alpha^2 = alpha0^2,
// docs/math.md §9): alpha_t = mix(alpha, 1, strength^2) along the direction d, alpha_b = alpha
// across it (the extension's "Implementation" section). As a slope covariance (per-axis variance
// alpha^2 / 2) that is the isotropic base (alpha^2 / 2) I plus (alpha_t^2 - alpha^2) / 2 d d^T;
// this returns the second part, (Sxx, Syy, Sxy), added to the lobe's covariance as the pixel
// footprint's is (lf_with_footprint: exact for the Gaussian lobes, the trace for the isotropic
// ones).
LF_FN vec3 lf_anisotropy_covariance(vec2 direction, float strength, float alpha_squared) {
    float alpha = sqrt(max(alpha_squared, 0.0f));
    float alpha_t = mix(alpha, 1.0f, strength * strength);
    float stretch = 0.5f * max(alpha_t * alpha_t - alpha * alpha, 0.0f);
    return stretch * vec3(direction.x * direction.x, direction.y * direction.y,
                          direction.x * direction.y);
}

// Stages 3-4 on a material's surface (scene.frag's pipeline): lf_surface_params, the anisotropic
// base roughness with Cook-Torrance (Blinn-Phong ignores it), and lf_shade. The emission is not
// part of the shade: lf_surface_color adds it.
LF_FN LfShade lf_shade_surface(int technique, LfMoments m, LfSurface s, vec3 light_dir,
                               vec3 view_unnormalised, LfParams p) {
    LfParams params = lf_surface_params(p, s);
    LfMoments moments = m;
    if (p.brdf == LF_BRDF_COOK_TORRANCE && s.anisotropy > 0.0f) {
        moments.footprint = m.footprint + lf_anisotropy_covariance(s.anisotropy_direction,
                                                                   s.anisotropy,
                                                                   2.0f * params.inv_s_shading);
    }
    return lf_shade(technique, moments, light_dir, view_unnormalised, params);
}

// The colour of a shaded surface before fog: (Ka + Kd NdotL) light + specular + emission (glTF
// 2.0 §3.9.5: the emission is added to the reflected light).
LF_FN vec3 lf_surface_color(LfShade shade, LfSurface s) {
    return shade.diffuse + shade.specular + s.emission;
}

// Inputs of specular fading at a LEAN texel, for calibration: (NdotL, d) with NdotL as
// lf_combine computes it from the filtered normal and d as lf_fade_distance. A LEAN pixel with
// specular term S becomes S NdotL^(sf - 1) with fading (fading paper eq. 7).
LF_FN vec2 lf_fade_terms(vec4 lean1, vec3 light_dir, vec3 view_unnormalised, int mode) {
    vec3 n = 2.0f * vec3(lean1.x, lean1.y, lean1.z) - vec3(1.0f);
    return vec2(clamp(dot(n, light_dir), 0.0f, 1.0f), lf_fade_distance(view_unnormalised, mode));
}

// Fog blend factor f (docs/math.md §4, fog): 1 = no fog. eye_depth in world units.
LF_FN float lf_fog_factor(float eye_depth, int mode, float start, float end, float density) {
    // One exp for both exponential modes: a SIMD rasteriser (llvmpipe) evaluates every branch.
    float x = density * eye_depth;
    float f = exp(-(mode == LF_FOG_EXP2 ? x * x : x));
    if (mode == LF_FOG_LINEAR) f = (end - eye_depth) / max(end - start, 1e-6f);
    if (mode == LF_FOG_NONE) f = 1.0f;
    return clamp(f, 0.0f, 1.0f);
}

// C' = f C + (1 - f) C_fog.
LF_FN vec3 lf_apply_fog(vec3 color, vec3 fog_color, float f) {
    return f * color + (1.0f - f) * fog_color;
}

#endif  // LEANFADE_LEAN_SHADING_GLSL
