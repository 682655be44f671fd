#pragma once
// The one set of shading parameters of leanfade (docs/math.md §4), shared by the CLI (`render`,
// `view`, `eval`), the presets and the viewer. GL-free.
//
// Units and spaces:
// - Colours are linear RGB (not sRGB); radiance = (Ka + Kd NdotL + Specular) * light_color.
// - The renderer scales every object to a bounding radius of 1 about its centre, so "world
//   units" below are object bounding radii: fog distances and the Fade rate are in those units,
//   and the same settings suit every scene.
// - light_direction is in world space (y up, the default camera looks along -z), pointing from
//   the surface toward the light; it need not be unit length (normalised at use).
#include <string>

#include <glm/vec3.hpp>

namespace leanfade {

namespace shading {
struct LfParams;  // shaders/lean_shading.glsl, leanfade/core/shading.hpp
}  // namespace shading

// Distance measure d of specular fading (docs/math.md §4).
enum class FadeDistance {
    TangentZ,  // d = Vt.z, the eye's height above the tangent plane (the paper's listing)
    Eye,       // d = length(Vt), the distance to the eye
};

// Distance fog (the OpenGL fog factors, docs/math.md §4): C' = f C + (1 - f) C_fog.
enum class FogMode { None, Linear, Exp, Exp2 };

// The reflection model of every technique's lobe stage (docs/math.md §4, §9).
enum class Brdf {
    BlinnPhong,    // the normalised Blinn-Phong lobe of exponent s (the papers' model)
    CookTorrance,  // D G F / (4 (n.l)(n.v)): Beckmann D of roughness a0 = r^2, Smith G, Schlick F
};

// What the supersampled truth shades each LOD-0 sample with (docs/math.md §7).
enum class ReferenceModel {
    Baseline,  // the BRDF around the sample's bump normal: what a filtered bumpy surface shows
    Lean,      // LEAN's own lobe (base roughness only, centred on the sample's B): LEAN's model
};

// Which techniques get geometric specular antialiasing (docs/math.md §11): the pixel footprint's
// slope covariance added to the lobe.
enum class GeometricAa {
    Auto,  // the techniques whose row asks for it (TechniqueInfo::geometric_aa_by_default:
           // two-lobe); the papers' techniques keep their published look
    On,    // every technique but the supersampled truth
    Off,   // none
};

struct ShadingSettings {
    // Light (one directional light).
    // World space, toward the light: upper-left-front (the camera looks along -z).
    glm::vec3 light_direction{-1.0f, 1.0f, 1.0f};
    glm::vec3 light_color{1.0f};  // linear RGB radiance scale

    // Material (linear RGB).
    glm::vec3 ambient{0.03f, 0.03f, 0.035f};  // Ka
    glm::vec3 kd{0.50f, 0.22f, 0.07f};        // Kd: a warm terracotta
    glm::vec3 ks{1.0f};                       // Ks: white
    float shininess = 800.0f;                 // Blinn-Phong exponent s (> 0)

    // Cook-Torrance (brdf = CookTorrance; docs/math.md §9). Blinn-Phong reads shininess instead.
    Brdf brdf = Brdf::BlinnPhong;
    float roughness = 0.3f;  // perceptual roughness r in [0.01, 1]: Beckmann a0 = r^2
    float metallic = 0.0f;   // 0: dielectric (F0 = f0), 1: metal (F0 = Kd, no diffuse)
    float f0 = 0.04f;        // Schlick's F0 of the dielectric part

    // The supersampled truth's model (the reference technique, eval's ground truth).
    ReferenceModel reference_model = ReferenceModel::Baseline;

    // Fresnel of Blinn-Phong, Schlick form of the fading paper's listing:
    // clamp(Fb + Fs (1 - n.V)^5, 0, 1). Cook-Torrance uses Schlick on h.V with F0 instead.
    float fresnel_bias = 0.2f;   // Fb
    float fresnel_scale = 0.8f;  // Fs

    // Specular fading (fading paper eq. 6-7): sf = clamp(1 + (d Fade)^p, 1, Pmax).
    float fade = 0.15f;          // Fade >= 0, per world unit (bounding radius)
    float pmax = 16.0f;          // Pmax >= 1
    float fade_exponent = 2.0f;  // p > 0 (the paper's "optional" power of two)
    FadeDistance fade_distance = FadeDistance::TangentZ;

    // Fog; distances in world units (bounding radii) measured along the eye's view axis.
    FogMode fog = FogMode::None;
    glm::vec3 fog_color{0.5f, 0.55f, 0.6f};  // linear RGB
    float fog_start = 5.0f;
    float fog_end = 40.0f;
    float fog_density = 0.05f;  // per world unit (exp, exp2)

    // Geometric specular antialiasing (docs/math.md §11; Tokuyoshi and Kaplanyan 2019).
    GeometricAa geometric_aa = GeometricAa::Auto;
    float geometric_aa_kappa = 0.18f;  // the clamp of the footprint's alpha^2 per axis, [0, 1]

    // Bumps and texturing.
    float bump_strength = 1.0f;  // height per texel spacing of height maps (docs/math.md §2)
    float tiling = 1.0f;         // texture repeats per unit of the mesh's uv (built-in meshes
                                 // already repeat the texture about every 0.4 of their units)
    float mip_bias = 0.0f;       // added to the texture LOD (negative = sharper)
    int anisotropy = 1;          // maximum anisotropic filtering ratio (1 = trilinear only)
    int msaa = 1;                // samples per pixel of the colour buffer (1 = off)
};

// Ranges that keep the shading math finite in float (a non-finite pixel is an error, not black):
// the light direction is normalised (its squared length must not underflow or overflow), 1/s
// enters the covariance (LEAN eq. 6) and s/(2 pi) the Blinn-Phong lobe, and colours multiply
// that lobe.
inline constexpr float kMinLightDirectionLength = 1e-6f;
inline constexpr float kMaxLightDirectionLength = 1e6f;
inline constexpr float kMinShininess = 1e-3f;
// Cook-Torrance: a0 = r^2 = 1e-4 keeps the Beckmann peak 1 / (pi a0^2) below 1e8.
inline constexpr float kMinRoughness = 0.01f;
inline constexpr float kMaxShininess = 1e7f;
inline constexpr float kMaxColourComponent = 1e6f;
inline constexpr float kMaxTiling = 1e6f;

// Throws leanfade::Error(<setting>, cause) naming the first value outside its range in the
// parameter schema (leanfade/core/detail/parameters.hpp: the setting is the row's key, e.g.
// "shininess"), then fog_end > fog_start for linear fog and msaa in {1, 2, 4, 8, 16}.
void validate(const ShadingSettings& settings);

// The shared header's parameters (docs/math.md §4). inv_s_shading = roughness_baked ? 0 : 1/s: a
// LEAN map whose 1/s was baked into M (LEAN eq. 6) must not get it again at shading time. With
// Cook-Torrance (docs/math.md §9): inv_s_shading = a0^2 / 2 with a0 = roughness^2, F0 =
// mix(f0, Kd, metallic) and the diffuse Kd (1 - metallic); a map with baked roughness is refused
// (leanfade::Error("brdf", cause)): its M holds 1/s where a0^2/2 belongs.
shading::LfParams to_lf_params(const ShadingSettings& settings, bool roughness_baked);

// The shader constants LF_FADE_DISTANCE_* / LF_FOG_*.
int to_shader_constant(FadeDistance mode);
int to_shader_constant(FogMode mode);
int to_shader_constant(Brdf brdf);  // LF_BRDF_*

// Names in presets and on the command line: "tangent-z" | "eye"; "none" | "linear" | "exp" |
// "exp2" (the choices of the parameter schema, leanfade/core/detail/parameters.hpp, which also parses
// them).
const char* to_string(FadeDistance mode);
const char* to_string(FogMode mode);
const char* to_string(Brdf brdf);                  // "blinn-phong" | "cook-torrance"
const char* to_string(ReferenceModel model);       // "baseline" | "lean"

}  // namespace leanfade
