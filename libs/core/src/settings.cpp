// Shading settings: validation and conversion to the shared header's parameters (SPEC §4).
#include "leanfade/core/settings.hpp"

#include <cmath>
#include <sstream>

#include "leanfade/core/error.hpp"

namespace leanfade {
namespace {

std::string text(float value) {
    std::ostringstream out;
    out << value;
    return out.str();
}

void require_finite(float value, const char* flag) {
    if (!std::isfinite(value)) throw Error(flag, "must be a finite number, got " + text(value));
}

void require_colour(const glm::vec3& c, const char* flag) {
    for (int i = 0; i < 3; ++i) {
        require_finite(c[i], flag);
        if (c[i] < 0.0f) throw Error(flag, "colour components must be >= 0, got " + text(c[i]));
        if (c[i] > kMaxColourComponent)
            throw Error(flag, "colour components must be <= " + text(kMaxColourComponent) +
                                  ", got " + text(c[i]));
    }
}

void require(bool ok, const char* flag, const std::string& cause) {
    if (!ok) throw Error(flag, cause);
}

}  // namespace

void validate(const ShadingSettings& s) {
    for (int i = 0; i < 3; ++i) require_finite(s.light_direction[i], "--light-dir");
    require(s.light_direction != glm::vec3(0.0f), "--light-dir", "must not be the zero vector");
    // It is normalised in float: its squared length must neither underflow nor overflow.
    const double length = std::sqrt(double(s.light_direction.x) * s.light_direction.x +
                                    double(s.light_direction.y) * s.light_direction.y +
                                    double(s.light_direction.z) * s.light_direction.z);
    require(length >= kMinLightDirectionLength && length <= kMaxLightDirectionLength,
            "--light-dir",
            "its length must be in [" + text(kMinLightDirectionLength) + ", " +
                text(kMaxLightDirectionLength) + "] (it is normalised), got " +
                text(float(length)));
    require_colour(s.light_color, "--light-color");
    require_colour(s.ambient, "--ambient");
    require_colour(s.kd, "--kd");
    require_colour(s.ks, "--ks");
    require_colour(s.fog_color, "--fog-color");
    const struct {
        float value;
        const char* flag;
    } scalars[] = {{s.shininess, "--shininess"},
                   {s.fresnel_bias, "--fresnel-bias"},
                   {s.fresnel_scale, "--fresnel-scale"},
                   {s.fade, "--fade"},
                   {s.pmax, "--pmax"},
                   {s.fade_exponent, "--fade-exponent"},
                   {s.fog_start, "--fog-start"},
                   {s.fog_end, "--fog-end"},
                   {s.fog_density, "--fog-density"},
                   {s.bump_strength, "--strength"},
                   {s.tiling, "--tiling"},
                   {s.mip_bias, "--mip-bias"}};
    for (const auto& v : scalars) require_finite(v.value, v.flag);
    require(s.shininess > 0.0f, "--shininess", "must be > 0, got " + text(s.shininess));
    require(s.shininess >= kMinShininess && s.shininess <= kMaxShininess, "--shininess",
            "must be in [" + text(kMinShininess) + ", " + text(kMaxShininess) + "], got " +
                text(s.shininess));
    require(s.fresnel_bias >= 0.0f, "--fresnel-bias", "must be >= 0, got " + text(s.fresnel_bias));
    require(s.fresnel_scale >= 0.0f, "--fresnel-scale",
            "must be >= 0, got " + text(s.fresnel_scale));
    require(s.fade >= 0.0f, "--fade", "must be >= 0, got " + text(s.fade));
    require(s.pmax >= 1.0f, "--pmax", "must be >= 1, got " + text(s.pmax));
    require(s.fade_exponent > 0.0f, "--fade-exponent", "must be > 0, got " + text(s.fade_exponent));
    require(s.fog != FogMode::Linear || s.fog_end > s.fog_start, "--fog-end",
            "must be greater than --fog-start for linear fog");
    require(s.fog_density >= 0.0f, "--fog-density", "must be >= 0, got " + text(s.fog_density));
    require(s.bump_strength > 0.0f, "--strength", "must be > 0, got " + text(s.bump_strength));
    require(s.tiling > 0.0f && s.tiling <= kMaxTiling, "--tiling",
            "must be in (0, " + text(kMaxTiling) + "], got " + text(s.tiling));
    require(s.anisotropy >= 1 && s.anisotropy <= 16, "--aniso",
            "must be in [1, 16], got " + std::to_string(s.anisotropy));
    const int m = s.msaa;
    require(m == 1 || m == 2 || m == 4 || m == 8 || m == 16, "--msaa",
            "must be 1, 2, 4, 8 or 16, got " + std::to_string(m));
}

shading::LfParams to_lf_params(const ShadingSettings& s, bool roughness_baked) {
    shading::LfParams p;
    p.light_color = s.light_color;
    p.ambient = s.ambient;
    p.kd = s.kd;
    p.ks = s.ks;
    p.shininess = s.shininess;
    p.inv_s_shading = roughness_baked ? 0.0f : 1.0f / s.shininess;  // SPEC §2, LEAN eq. 6
    p.fresnel_bias = s.fresnel_bias;
    p.fresnel_scale = s.fresnel_scale;
    p.fade = s.fade;
    p.pmax = s.pmax;
    p.fade_exponent = s.fade_exponent;
    p.fade_distance = to_shader_constant(s.fade_distance);
    return p;
}

int to_shader_constant(FadeDistance mode) {
    return mode == FadeDistance::Eye ? shading::LF_FADE_DISTANCE_EYE
                                     : shading::LF_FADE_DISTANCE_TANGENT_Z;
}

int to_shader_constant(FogMode mode) {
    switch (mode) {
        case FogMode::None:
            return shading::LF_FOG_NONE;
        case FogMode::Linear:
            return shading::LF_FOG_LINEAR;
        case FogMode::Exp:
            return shading::LF_FOG_EXP;
        case FogMode::Exp2:
            return shading::LF_FOG_EXP2;
    }
    return shading::LF_FOG_NONE;
}

const char* to_string(FadeDistance mode) {
    return mode == FadeDistance::Eye ? "eye" : "tangent-z";
}

const char* to_string(FogMode mode) {
    switch (mode) {
        case FogMode::None:
            return "none";
        case FogMode::Linear:
            return "linear";
        case FogMode::Exp:
            return "exp";
        case FogMode::Exp2:
            return "exp2";
    }
    return "none";
}

FadeDistance parse_fade_distance(const std::string& text, const std::string& flag) {
    if (text == "tangent-z") return FadeDistance::TangentZ;
    if (text == "eye") return FadeDistance::Eye;
    throw Error(flag, "unknown distance mode '" + text + "' (expected tangent-z or eye)");
}

FogMode parse_fog_mode(const std::string& text, const std::string& flag) {
    for (FogMode m : {FogMode::None, FogMode::Linear, FogMode::Exp, FogMode::Exp2})
        if (text == to_string(m)) return m;
    throw Error(flag, "unknown fog mode '" + text + "' (expected none, linear, exp or exp2)");
}

}  // namespace leanfade
