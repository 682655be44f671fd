// A default-constructed LfShadingUniforms is a valid block (shaders/lean_shading.glsl,
// docs/integration.md): the parameter table's defaults, identity texture coordinate transforms of
// set 0, the offset encoding with sc 1, opaque, one-sided, no fog, maps or glTF factors. An engine
// that fills it from its defaults and the documented setters draws what `leanfade render` draws.
#include <gtest/gtest.h>

#include <memory>

#include "leanfade/core/settings.hpp"
#include "leanfade/core/shading.hpp"

namespace leanfade {
namespace {

using shading::LfParams;
using shading::LfShadingUniforms;

void expect_same_params(const LfParams& a, const LfParams& b) {
    EXPECT_EQ(a.light_color, b.light_color);
    EXPECT_EQ(a.shininess, b.shininess);
    EXPECT_EQ(a.ambient, b.ambient);
    EXPECT_EQ(a.inv_s_shading, b.inv_s_shading);
    EXPECT_EQ(a.kd, b.kd);
    EXPECT_EQ(a.fresnel_bias, b.fresnel_bias);
    EXPECT_EQ(a.ks, b.ks);
    EXPECT_EQ(a.fresnel_scale, b.fresnel_scale);
    EXPECT_EQ(a.fade, b.fade);
    EXPECT_EQ(a.pmax, b.pmax);
    EXPECT_EQ(a.fade_exponent, b.fade_exponent);
    EXPECT_EQ(a.fade_distance, b.fade_distance);
    EXPECT_EQ(a.f0, b.f0);
    EXPECT_EQ(a.brdf, b.brdf);
}

void expect_valid_defaults(const LfShadingUniforms& block) {
    expect_same_params(block.params, to_lf_params(ShadingSettings{}, false));
    const ShadingSettings defaults;
    EXPECT_EQ(block.params.shininess, defaults.shininess);
    EXPECT_FLOAT_EQ(block.params.inv_s_shading, 1.0f / defaults.shininess);  // LEAN eq. 6
    EXPECT_EQ(block.scale, 1.0f);
    EXPECT_EQ(block.lean_offset, 1.0f);
    EXPECT_EQ(block.output_mode, 0);
    EXPECT_EQ(block.fog_mode, shading::LF_FOG_NONE);
    EXPECT_EQ(block.fog_start, defaults.fog_start);
    EXPECT_EQ(block.fog_end, defaults.fog_end);
    EXPECT_EQ(block.fog_density, defaults.fog_density);
    EXPECT_EQ(block.fog_color, defaults.fog_color);
    EXPECT_EQ(block.geometric_aa_kappa, defaults.geometric_aa_kappa);
    EXPECT_EQ(block.maps, 0);
    EXPECT_LT(block.alpha_cutoff, 0.0f);  // opaque
    EXPECT_EQ(block.base_alpha, 1.0f);
    EXPECT_EQ(block.blend, 0.0f);
    EXPECT_EQ(block.double_sided, 0.0f);
    EXPECT_EQ(block.material.emissive, glm::vec3(0.0f));
    EXPECT_EQ(block.material.metallic, 0.0f);
    EXPECT_EQ(block.material.anisotropy_rotation, glm::vec2(1.0f, 0.0f));
    EXPECT_EQ(block.material.anisotropy_strength, 0.0f);
    EXPECT_EQ(block.material.occlusion_strength, 0.0f);
}

TEST(ShadingDefaults, ValueInitialisedBlockHoldsTheParameterTableDefaults) {
    expect_valid_defaults(LfShadingUniforms{});
}

TEST(ShadingDefaults, DefaultInitialisedBlockIsTheSame) {
    // `LfShadingUniforms block;` (no braces) too: every member has its default, none is left
    // indeterminate.
    const auto block = std::make_unique<LfShadingUniforms>();
    expect_valid_defaults(*block);
    LfShadingUniforms on_stack;
    expect_valid_defaults(on_stack);
}

TEST(ShadingDefaults, EveryUvTransformIsTheIdentityOfSetZero) {
    const LfShadingUniforms block;
    for (int slot = 0; slot < shading::LF_UV_TRANSFORM_COUNT; ++slot) {
        const glm::vec4 r0 = block.uv_transforms[2 * slot];
        const glm::vec4 r1 = block.uv_transforms[2 * slot + 1];
        // uv' = (dot(r0.xy, uv) + r0.z, dot(r1.xy, uv) + r1.z) of scene.frag, set r0.w.
        for (const glm::vec2 uv : {glm::vec2(0.25f, 0.75f), glm::vec2(-3.0f, 8.5f)}) {
            const glm::vec2 mapped(glm::dot(glm::vec2(r0), uv) + r0.z,
                                   glm::dot(glm::vec2(r1), uv) + r1.z);
            EXPECT_EQ(mapped, uv) << "slot " << slot;
        }
        EXPECT_EQ(r0.w, 0.0f) << "slot " << slot;  // the mesh's texture coordinate set 0
        EXPECT_EQ(r1.w, 0.0f) << "slot " << slot;
    }
}

TEST(ShadingDefaults, LfParamsDefaultIsToLfParamsOfDefaultSettings) {
    expect_same_params(shading::lf_default_params(), to_lf_params(ShadingSettings{}, false));
}

}  // namespace
}  // namespace leanfade
