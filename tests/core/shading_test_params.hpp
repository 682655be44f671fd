#pragma once
// Shading parameters shared by the tests of the shading header (tests/core, tests/eval): a white
// light, a warm diffuse albedo, white specular, Schlick Fresnel 0.2 + 0.8 (1 - n.V)^5, no fading.
#include "leanfade/core/shading.hpp"

namespace leanfade::test {

inline shading::LfParams shading_test_params(float shininess) {
    shading::LfParams p;
    p.light_color = glm::vec3(1.0f);
    p.ambient = glm::vec3(0.05f);
    p.kd = glm::vec3(0.6f, 0.4f, 0.3f);
    p.ks = glm::vec3(1.0f);
    p.shininess = shininess;
    p.inv_s_shading = 1.0f / shininess;
    p.fresnel_bias = 0.2f;
    p.fresnel_scale = 0.8f;
    p.fade = 0.0f;
    p.pmax = 8.0f;
    p.fade_exponent = 2.0f;
    p.fade_distance = shading::LF_FADE_DISTANCE_TANGENT_Z;
    return p;
}

}  // namespace leanfade::test
