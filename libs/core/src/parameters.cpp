// The shading parameter schema (leanfade/core/detail/parameters.hpp).
#include "leanfade/core/detail/parameters.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>

#include "leanfade/core/error.hpp"
#include "leanfade/core/settings.hpp"
#include "leanfade/core/detail/text.hpp"

namespace leanfade {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();

constexpr std::string_view kFadeDistances[] = {"tangent-z", "eye"};
constexpr std::string_view kFogModes[] = {"none", "linear", "exp", "exp2"};
constexpr std::string_view kBrdfs[] = {"blinn-phong", "cook-torrance"};
constexpr std::string_view kReferenceModels[] = {"baseline", "lean"};
constexpr std::string_view kGeometricAaModes[] = {"auto", "on", "off"};

int get_fade_distance(const ShadingSettings& s) {
    return s.fade_distance == FadeDistance::Eye ? 1 : 0;
}
void set_fade_distance(ShadingSettings& s, int i) {
    s.fade_distance = i == 1 ? FadeDistance::Eye : FadeDistance::TangentZ;
}
int get_fog(const ShadingSettings& s) {
    return int(s.fog);
}
void set_fog(ShadingSettings& s, int i) {
    s.fog = FogMode(i);
}

int get_brdf(const ShadingSettings& s) {
    return int(s.brdf);
}
void set_brdf(ShadingSettings& s, int i) {
    s.brdf = Brdf(i);
}
int get_geometric_aa(const ShadingSettings& s) {
    return int(s.geometric_aa);
}
void set_geometric_aa(ShadingSettings& s, int i) {
    s.geometric_aa = GeometricAa(i);
}
int get_reference_model(const ShadingSettings& s) {
    return int(s.reference_model);
}
void set_reference_model(ShadingSettings& s, int i) {
    s.reference_model = ReferenceModel(i);
}

using K = ParameterKind;
using S = ShadingSettings;

// clang-format off
const std::array<ParameterInfo, 29> kParameters{{
    {.key = "light_direction", .kind = K::Direction, .group = "Light", .label = "light direction",
     .unit = "world space", .help = "Direction toward the light (y up, the camera on +z; the plane scene's default is near "
             "the mirror direction of the view, where a map's flat ground glints)",
     .equation = "L of docs/math.md §4", .min = kMinLightDirectionLength,
     .max = kMaxLightDirectionLength, .ui_min = -1.0f, .ui_max = 1.0f,
     .vector = &S::light_direction},
    {.key = "light_color", .kind = K::Colour, .group = "Light", .label = "light colour",
     .help = "Light colour, linear RGB", .min = 0.0f, .max = kMaxColourComponent,
     .vector = &S::light_color},
    {.key = "ambient", .kind = K::Colour, .group = "Material", .label = "ambient Ka",
     .help = "Ambient Ka, linear RGB", .min = 0.0f, .max = kMaxColourComponent,
     .vector = &S::ambient},
    {.key = "kd", .kind = K::Colour, .group = "Material", .label = "diffuse Kd",
     .help = "Diffuse Kd, linear RGB", .min = 0.0f, .max = kMaxColourComponent, .vector = &S::kd},
    {.key = "ks", .kind = K::Colour, .group = "Material", .label = "specular Ks",
     .help = "Specular Ks, linear RGB", .min = 0.0f, .max = kMaxColourComponent, .vector = &S::ks},
    {.key = "shininess", .kind = K::Scalar, .group = "Material", .label = "shininess s",
     .help = "Blinn-Phong exponent s; LEAN adds 1/s to the covariance",
     .equation = "LEAN eq. 6", .min = kMinShininess, .max = kMaxShininess, .logarithmic = true,
     .ui_min = 1.0f, .ui_max = 20000.0f,
     .scalar = &S::shininess},
    {.key = "brdf", .kind = K::Choice, .group = "Material", .label = "BRDF",
     .help = "Reflection model of every technique: the papers' Blinn-Phong, or Cook-Torrance "
             "(Beckmann D, Smith G, Schlick F)",
     .equation = "docs/math.md §9", .choices = kBrdfs, .get_choice = get_brdf,
     .set_choice = set_brdf},
    {.key = "roughness", .kind = K::Scalar, .group = "Material", .label = "roughness r",
     .help = "Cook-Torrance perceptual roughness r: Beckmann alpha0 = r^2, slope variance "
             "alpha0^2/2 per axis",
     .equation = "docs/math.md §9", .min = kMinRoughness, .max = 1.0f, .ui_min = kMinRoughness,
     .ui_max = 1.0f, .scalar = &S::roughness},
    {.key = "metallic", .kind = K::Scalar, .group = "Material", .label = "metallic",
     .help = "Cook-Torrance metalness: F0 = mix(f0, Kd, metallic), diffuse Kd (1 - metallic)",
     .equation = "docs/math.md §9", .min = 0.0f, .max = 1.0f, .ui_min = 0.0f, .ui_max = 1.0f,
     .scalar = &S::metallic},
    {.key = "f0", .kind = K::Scalar, .group = "Material", .label = "F0",
     .help = "Cook-Torrance reflectance at normal incidence of the dielectric part (Schlick)",
     .equation = "docs/math.md §9", .min = 0.0f, .max = 1.0f, .ui_min = 0.0f, .ui_max = 1.0f,
     .scalar = &S::f0},
    {.key = "fresnel_bias", .kind = K::Scalar, .group = "Fresnel", .label = "Fresnel bias Fb",
     .help = "Fresnel bias Fb of clamp(Fb + Fs (1 - n.V)^5, 0, 1)",
     .equation = "fading paper, listing 1", .min = 0.0f, .max = kInfinity, .ui_min = 0.0f,
     .ui_max = 1.0f,
     .scalar = &S::fresnel_bias},
    {.key = "fresnel_scale", .kind = K::Scalar, .group = "Fresnel", .label = "Fresnel scale Fs",
     .help = "Fresnel scale Fs", .equation = "fading paper, listing 1", .min = 0.0f,
     .max = kInfinity, .ui_min = 0.0f, .ui_max = 1.0f, .scalar = &S::fresnel_scale},
    {.key = "fade", .kind = K::Scalar, .group = "Fading", .label = "Fade",
     .unit = "per bounding radius",
     .help = "Fading rate Fade of sf = clamp(1 + (d Fade)^p, 1, Pmax)",
     .equation = "fading paper eq. 6", .min = 0.0f, .max = kInfinity, .logarithmic = true,
     .ui_min = 0.0f, .ui_max = 4.0f, .scalar = &S::fade},
    {.key = "pmax", .kind = K::Scalar, .group = "Fading", .label = "Pmax",
     .help = "Largest fading exponent Pmax", .equation = "fading paper eq. 6", .min = 1.0f,
     .max = kInfinity, .logarithmic = true, .ui_min = 1.0f, .ui_max = 256.0f, .scalar = &S::pmax},
    {.key = "fade_exponent", .kind = K::Scalar, .group = "Fading", .label = "power p",
     .help = "Power p of (d Fade)^p", .equation = "fading paper eq. 6", .min = 0.0f,
     .max = kInfinity, .min_exclusive = true, .ui_min = 0.25f, .ui_max = 8.0f,
     .scalar = &S::fade_exponent},
    {.key = "fade_distance", .kind = K::Choice, .group = "Fading", .label = "distance mode",
     .help = "Fading distance d: the eye's height over the tangent plane, or the eye distance",
     .equation = "fading paper eq. 6", .choices = kFadeDistances,
     .get_choice = get_fade_distance, .set_choice = set_fade_distance},
    {.key = "fog", .kind = K::Choice, .group = "Fog", .label = "fog mode", .help = "Distance fog",
     .equation = "C' = f C + (1 - f) C_fog", .choices = kFogModes, .get_choice = get_fog,
     .set_choice = set_fog},
    {.key = "fog_color", .kind = K::Colour, .group = "Fog", .label = "fog colour",
     .help = "Fog colour, linear RGB", .min = 0.0f, .max = kMaxColourComponent,
     .vector = &S::fog_color},
    {.key = "fog_start", .kind = K::Scalar, .group = "Fog", .label = "fog start",
     .unit = "bounding radii from the eye", .help = "Linear fog start", .min = -kInfinity,
     .max = kInfinity, .logarithmic = true, .ui_min = 0.0f, .ui_max = 500.0f,
     .scalar = &S::fog_start},
    {.key = "fog_end", .kind = K::Scalar, .group = "Fog", .label = "fog end",
     .unit = "bounding radii from the eye", .help = "Linear fog end", .min = -kInfinity,
     .max = kInfinity, .logarithmic = true, .ui_min = 0.01f, .ui_max = 1000.0f,
     .scalar = &S::fog_end},
    {.key = "fog_density", .kind = K::Scalar, .group = "Fog", .label = "fog density",
     .unit = "per bounding radius", .help = "Exp / exp2 fog density", .min = 0.0f,
     .max = kInfinity, .logarithmic = true, .ui_min = 0.0f, .ui_max = 2.0f,
     .scalar = &S::fog_density},
    {.key = "geometric_aa", .kind = K::Choice, .group = "Antialiasing",
     .label = "geometric AA",
     .help = "Geometric specular antialiasing: the pixel footprint's slope variance added to the "
             "lobe; auto: two-lobe only, on: every technique, off: none",
     .equation = "docs/math.md §11", .choices = kGeometricAaModes,
     .get_choice = get_geometric_aa, .set_choice = set_geometric_aa},
    {.key = "geometric_aa_kappa", .kind = K::Scalar, .group = "Antialiasing",
     .label = "geometric AA kappa",
     .help = "Clamp kappa of the footprint's alpha^2 per axis (Tokuyoshi and Kaplanyan 2019)",
     .equation = "docs/math.md §11", .min = 0.0f, .max = 1.0f, .ui_min = 0.0f, .ui_max = 1.0f,
     .scalar = &S::geometric_aa_kappa},
    {.key = "bump_strength", .kind = K::Scalar, .group = "Texturing", .label = "bump strength",
     .unit = "height per texel spacing",
     .help = "Bump height scale of height maps baked on the fly (not 0; negative inverts the "
             "heights)",
     .equation = "docs/math.md §2",
     .min = -kInfinity, .max = kInfinity, .nonzero = true, .logarithmic = true, .ui_min = 0.05f,
     .ui_max = 20.0f, .scalar = &S::bump_strength},
    {.key = "tiling", .kind = K::Scalar, .group = "Texturing", .label = "tiling",
     .unit = "repeats per uv unit", .help = "Texture repeats per unit of the mesh's uv",
     .min = 0.0f, .max = kMaxTiling, .min_exclusive = true, .logarithmic = true, .ui_min = 0.05f,
     .ui_max = 64.0f,
     .scalar = &S::tiling},
    {.key = "mip_bias", .kind = K::Scalar, .group = "Texturing", .label = "MIP bias",
     .unit = "levels", .help = "Texture LOD bias (negative = sharper)", .min = -kInfinity,
     .max = kInfinity, .ui_min = -4.0f, .ui_max = 4.0f, .scalar = &S::mip_bias},
    {.key = "anisotropy", .kind = K::Integer, .group = "Texturing", .label = "anisotropy",
     .help = "Anisotropic filtering ratio (1 = trilinear)", .min = 1.0f, .max = 16.0f,
     .ui_min = 1.0f, .ui_max = 16.0f,
     .integer = &S::anisotropy},
    {.key = "reference_model", .kind = K::Choice, .group = "Material", .label = "reference model",
     .help = "What the supersampled truth shades each LOD-0 sample with: the BRDF on the bump "
             "normal, or LEAN's own lobe",
     .equation = "docs/math.md §7", .choices = kReferenceModels,
     .get_choice = get_reference_model, .set_choice = set_reference_model},
    {.key = "msaa", .kind = K::Integer, .group = "Texturing", .label = "MSAA samples",
     .help = "Multisample anti-aliasing samples (1 = off): 1, 2, 4, 8 or 16", .min = 1.0f,
     .max = 16.0f, .ui_min = 1.0f, .ui_max = 16.0f, .integer = &S::msaa},
}};
// clang-format on

std::string text(float value) {
    std::ostringstream out;
    out << value;
    return out.str();
}

// Shortest decimal that reads back as the same float ("0.15").
std::string exact(float value) { return shortest_text(value); }


void require_finite(const ParameterInfo& row, float value) {
    if (!std::isfinite(value))
        throw Error::setting(std::string(row.key), "must be a finite number, got " + text(value));
}

void check_range(const ParameterInfo& row, float v) {
    const std::string key(row.key);
    if (row.nonzero && v == 0.0f) throw Error::setting(key, "must not be 0, got " + text(v));
    const bool below = row.min_exclusive ? !(v > row.min) : !(v >= row.min);
    const bool above = !(v <= row.max);
    if (!below && !above) return;
    // A positive lower bound that is only a float-safety limit: say first that it must be > 0.
    if (row.min > 0.0f && !(v > 0.0f)) throw Error::setting(key, "must be > 0, got " + text(v));
    if (std::isinf(row.max))
        throw Error::setting(key, std::string("must be ") + (row.min_exclusive ? "> " : ">= ") +
                                      text(row.min) + ", got " + text(v));
    throw Error::setting(key, "must be in " + std::string(row.min_exclusive ? "(" : "[") +
                                  text(row.min) + ", " + text(row.max) + "], got " + text(v));
}

}  // namespace

std::span<const ParameterInfo> shading_parameters() {
    return kParameters;
}

std::vector<std::string_view> parameter_groups() {
    std::vector<std::string_view> groups;
    for (const ParameterInfo& row : kParameters)
        if (std::find(groups.begin(), groups.end(), row.group) == groups.end())
            groups.push_back(row.group);
    return groups;
}

const ParameterInfo* find_shading_parameter(std::string_view key) {
    for (const ParameterInfo& row : kParameters)
        if (row.key == key) return &row;
    return nullptr;
}

std::string format_parameter(const ParameterInfo& row, const ShadingSettings& s) {
    switch (row.kind) {
        case ParameterKind::Scalar:
            return exact(s.*row.scalar);
        case ParameterKind::Integer:
            return std::to_string(s.*row.integer);
        case ParameterKind::Colour:
        case ParameterKind::Direction: {
            const glm::vec3 v = s.*row.vector;
            return exact(v.x) + "," + exact(v.y) + "," + exact(v.z);
        }
        case ParameterKind::Choice:
            return std::string(row.choices[std::size_t(row.get_choice(s))]);
    }
    return {};
}

void parse_parameter(const ParameterInfo& row, const std::string& value, ShadingSettings& s) {
    const std::string key(row.key);
    switch (row.kind) {
        case ParameterKind::Scalar: {
            float v = 0.0f;
            if (!parse_finite(value, v))
                throw Error::setting(key, "expected a number, got '" + value + "'");
            s.*row.scalar = v;
            return;
        }
        case ParameterKind::Integer: {
            char* end = nullptr;
            const long v = std::strtol(value.c_str(), &end, 10);
            if (value.empty() || *end != 0 || v < -1000000 || v > 1000000)
                throw Error::setting(key, "expected an integer, got '" + value + "'");
            s.*row.integer = int(v);
            return;
        }
        case ParameterKind::Colour:
        case ParameterKind::Direction: {
            const bool colour = row.kind == ParameterKind::Colour;
            const std::vector<std::string> parts = split(value, ',');
            glm::vec3 v(0.0f);
            if (parts.size() == 1 && colour && parse_finite(parts[0], v.x)) {
                s.*row.vector = glm::vec3(v.x);
                return;
            }
            if (parts.size() == 3 && parse_finite(parts[0], v.x) && parse_finite(parts[1], v.y) &&
                parse_finite(parts[2], v.z)) {
                s.*row.vector = v;
                return;
            }
            throw Error::setting(key, std::string("expected ") +
                                          (colour ? "R,G,B or one value" : "X,Y,Z") + ", got '" +
                                          value + "'");
        }
        case ParameterKind::Choice: {
            for (std::size_t i = 0; i < row.choices.size(); ++i) {
                if (value == row.choices[i]) {
                    row.set_choice(s, int(i));
                    return;
                }
            }
            throw Error::setting(key, "unknown " + std::string(row.label) + " '" + value +
                                          "' (expected " + name_list(row.choices) + ")");
        }
    }
}

void validate_parameter(const ParameterInfo& row, const ShadingSettings& s) {
    const std::string key(row.key);
    switch (row.kind) {
        case ParameterKind::Scalar: {
            const float v = s.*row.scalar;
            require_finite(row, v);
            check_range(row, v);
            return;
        }
        case ParameterKind::Integer: {
            const int v = s.*row.integer;
            if (v < int(row.min) || v > int(row.max))
                throw Error::setting(key, "must be in [" + std::to_string(int(row.min)) + ", " +
                                              std::to_string(int(row.max)) + "], got " +
                                              std::to_string(v));
            return;
        }
        case ParameterKind::Colour: {
            const glm::vec3 c = s.*row.vector;
            for (int i = 0; i < 3; ++i) {
                require_finite(row, c[i]);
                if (c[i] < row.min)
                    throw Error::setting(key, "colour components must be >= " + text(row.min) +
                                                  ", got " + text(c[i]));
                if (c[i] > row.max)
                    throw Error::setting(key, "colour components must be <= " + text(row.max) +
                                                  ", got " + text(c[i]));
            }
            return;
        }
        case ParameterKind::Direction: {
            const glm::vec3 d = s.*row.vector;
            for (int i = 0; i < 3; ++i) require_finite(row, d[i]);
            if (d == glm::vec3(0.0f)) throw Error::setting(key, "must not be the zero vector");
            // It is normalised in float: its squared length must neither underflow nor overflow.
            const double length =
                std::sqrt(double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z);
            if (!(length >= row.min && length <= row.max))
                throw Error::setting(key, "its length must be in [" + text(row.min) + ", " +
                                              text(row.max) + "] (it is normalised), got " +
                                              text(float(length)));
            return;
        }
        case ParameterKind::Choice: {
            const int i = row.get_choice(s);
            if (i < 0 || i >= int(row.choices.size()))
                throw Error::setting(key, "not one of the choices");
            return;
        }
    }
}

}  // namespace leanfade
