// Shading settings: validation and conversion to the shared header's parameters (docs/math.md §4).
#include "leanfade/core/settings.hpp"

#include <cmath>
#include <sstream>

#include <glm/common.hpp>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/parameters.hpp"
#include "leanfade/core/shading.hpp"

namespace leanfade {
void validate(const ShadingSettings& s) {
    for (const ParameterInfo& row : shading_parameters()) validate_parameter(row, s);
    if (s.fog == FogMode::Linear && !(s.fog_end > s.fog_start))
        throw Error::setting("fog_end", "must be greater than the fog start for linear fog");
    const int m = s.msaa;
    if (!(m == 1 || m == 2 || m == 4 || m == 8 || m == 16))
        throw Error::setting("msaa", "must be 1, 2, 4, 8 or 16, got " + std::to_string(m));
}

shading::LfParams to_lf_params(const ShadingSettings& s, bool roughness_baked) {
    shading::LfParams p;
    p.light_color = s.light_color;
    p.ambient = s.ambient;
    p.kd = s.kd;
    p.ks = s.ks;
    p.shininess = s.shininess;
    p.inv_s_shading = roughness_baked ? 0.0f : 1.0f / s.shininess;  // docs/math.md §2, LEAN eq. 6
    p.fresnel_bias = s.fresnel_bias;
    p.fresnel_scale = s.fresnel_scale;
    p.fade = s.fade;
    p.pmax = s.pmax;
    p.fade_exponent = s.fade_exponent;
    p.fade_distance = to_shader_constant(s.fade_distance);
    p.brdf = to_shader_constant(s.brdf);
    p.f0 = glm::vec3(s.f0);
    if (s.brdf == Brdf::CookTorrance) {
        if (roughness_baked)
            throw Error::setting(
                "brdf",
                "cook-torrance takes its base roughness from 'roughness', but the LEAN map "
                "has a baked 1/s in its second moments (bake it without one)",
                {"roughness"});
        // docs/math.md §9: a0 = r^2, per-axis slope variance a0^2 / 2 in place of 1/s.
        const float alpha0 = s.roughness * s.roughness;
        p.inv_s_shading = 0.5f * alpha0 * alpha0;
        // The metallic-roughness model of glTF: metals reflect their base colour, without diffuse.
        p.f0 = glm::mix(glm::vec3(s.f0), s.kd, s.metallic);
        p.kd = s.kd * (1.0f - s.metallic);
    }
    return p;
}

shading::LfParams shading::lf_default_params() {
    return to_lf_params(ShadingSettings{}, false);
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

int to_shader_constant(Brdf brdf) {
    return brdf == Brdf::CookTorrance ? shading::LF_BRDF_COOK_TORRANCE
                                      : shading::LF_BRDF_BLINN_PHONG;
}

// Names from the parameter schema's choices (leanfade/core/detail/parameters.hpp), listed in enum
// order.
const char* to_string(FadeDistance mode) {
    return find_shading_parameter("fade_distance")->choices[std::size_t(mode)].data();
}

const char* to_string(FogMode mode) {
    return find_shading_parameter("fog")->choices[std::size_t(mode)].data();
}

const char* to_string(Brdf brdf) {
    return find_shading_parameter("brdf")->choices[std::size_t(brdf)].data();
}

const char* to_string(ReferenceModel model) {
    return find_shading_parameter("reference_model")->choices[std::size_t(model)].data();
}

}  // namespace leanfade
