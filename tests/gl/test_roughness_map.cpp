// A base roughness map at render time (docs/roughness.md, docs/math.md §9): Cook-Torrance's α0²
// per texel from the material's map instead of the uniform roughness.
//
// A constant map of r renders as the uniform roughness r with every Cook-Torrance technique
// (the reference included, both truths): the map's α0² = (r²)² is the uniform's a0², and the
// trilinear filter of equal texels is that value again, so the only differences are float
// roundings of the filter's weights (measured on llvmpipe: bit-identical images, a relative L1
// of 0; 2e-20 for the roughness MIPs); the bound 1e-4 leaves room for other drivers.
#include <cstdio>

#include "gl_test_helpers.hpp"
#include "leanfade/core/roughness.hpp"
#include "leanfade/scene/material.hpp"
#include "leanfade/scene/detail/scene.hpp"

namespace leanfade::test {
namespace {

class RoughnessMap : public GlTest {};

// A sphere with the "bumps" set and, when `r_map` >= 0, a constant roughness map of r_map with
// `map_size` texels per side.
scene::Scene bumpy_sphere(float r_map, int map_size) {
    scene::Scene scene;
    scene::Object object;
    object.mesh = scene::make_scene_mesh("sphere");
    scene.objects.push_back(std::move(object));
    scene::Material material;
    material.name = "bumps";
    if (r_map >= 0.0f) {
        material.map(scene::MapKind::BaseRoughness) =
            scene.add_map(scene::MapKind::BaseRoughness,
                          base_alpha_squared_mips(Image(map_size, map_size, 1, r_map)));
    }
    scene.materials.push_back(material);
    scene.lean_maps.push_back(make_bumps_map(64, 1.5f));
    return scene;
}

Image render(gl::Renderer& renderer, gl::Technique technique, float roughness,
             ReferenceModel model = ReferenceModel::Baseline) {
    gl::RenderRequest request;
    request.technique = technique;
    request.width = request.height = 64;
    request.view = gl::view_at_distance(4.0f);
    request.reference_samples = 2;
    request.output = gl::OutputMode::Specular;
    ShadingSettings& s = request.settings;
    s.brdf = Brdf::CookTorrance;
    s.roughness = roughness;
    s.light_direction = {-0.3f, 0.6f, 0.8f};
    s.reference_model = model;
    return renderer.render(request);
}

TEST_F(RoughnessMap, ConstantMapRendersAsTheUniformRoughness) {
    gl::Renderer uniform(context()), mapped(context()), resized(context());
    uniform.set_scene(bumpy_sphere(-1.0f, 0));
    mapped.set_scene(bumpy_sphere(0.35f, 64));  // the LEAN map's size: the roughness
                                                // technique fetches the map's texels
    resized.set_scene(bumpy_sphere(0.35f, 16));  // another size: read at the texel's footprint
    struct Case {
        gl::Technique technique;
        ReferenceModel model;
        const char* name;
    };
    const Case cases[] = {
        {gl::Technique::Bump, ReferenceModel::Baseline, "bump"},
        {gl::Technique::Lean, ReferenceModel::Baseline, "lean"},
        {gl::Technique::Fade, ReferenceModel::Baseline, "fade"},
        {gl::Technique::Toksvig, ReferenceModel::Baseline, "toksvig"},
        {gl::Technique::Clean, ReferenceModel::Baseline, "clean"},
        {gl::Technique::Roughness, ReferenceModel::Baseline, "roughness"},
        {gl::Technique::Reference, ReferenceModel::Baseline, "reference (baseline)"},
        {gl::Technique::Reference, ReferenceModel::Lean, "reference (lean)"},
    };
    for (const Case& c : cases) {
        const Image want = render(uniform, c.technique, 0.35f, c.model);
        // The frame's uniform roughness is ignored where the material has a map.
        const Image got = render(mapped, c.technique, 0.9f, c.model);
        const Image got_resized = render(resized, c.technique, 0.9f, c.model);
        const Image other = render(uniform, c.technique, 0.5f, c.model);
        const double error = relative_l1(got, want);
        const double error_resized = relative_l1(got_resized, want);
        const double apart = relative_l1(other, want);
        std::printf("%s: relative L1 %.3g (map of another size %.3g), r 0.5 instead: %.3g\n",
                    c.name, error, error_resized, apart);
        EXPECT_LT(error, 1e-4) << c.name;
        EXPECT_LT(error_resized, 1e-4) << c.name;
        EXPECT_GT(apart, 0.05) << c.name << ": the roughness must matter in this view";
    }
}

// Blinn-Phong ignores the map (its base roughness is 1/s): the same pixels as without one.
TEST_F(RoughnessMap, BlinnPhongIgnoresTheMap) {
    gl::Renderer plain(context()), mapped(context());
    plain.set_scene(bumpy_sphere(-1.0f, 0));
    mapped.set_scene(bumpy_sphere(0.9f, 64));
    gl::RenderRequest request;
    request.technique = gl::Technique::Lean;
    request.width = request.height = 48;
    request.view = gl::view_at_distance(4.0f);
    EXPECT_EQ(relative_l1(mapped.render(request), plain.render(request)), 0.0);
}

}  // namespace
}  // namespace leanfade::test

namespace leanfade::test {
namespace {

// Another tool's roughness MIPs (MapKind::RoughnessMips, `--roughness-mips`): the roughness
// technique reads their r in place of its own. The chain leanfade itself writes for the map
// (roughness_textures_rgba8's G, what `bake --roughness-out` stores) renders as without it, up to
// the 8-bit rounding of the same value made on the CPU and on the GPU; a rougher chain widens the
// highlight; the other techniques ignore the map.
class RoughnessMips : public GlTest {};

TEST_F(RoughnessMips, TheTechniqueReadsTheGivenChainInPlaceOfItsOwn) {
    const float roughness = 0.35f;
    auto scene_with = [&](const std::vector<Image>* chain) {
        scene::Scene scene = bumpy_sphere(-1.0f, 0);
        if (chain != nullptr)
            scene.materials[0].map(scene::MapKind::RoughnessMips) =
                scene.add_map(scene::MapKind::RoughnessMips, *chain);
        return scene;
    };
    const scene::Scene plain = scene_with(nullptr);
    RoughnessOptions options;
    options.base_roughness = roughness;
    const RoughnessTexturesRgba8 own = roughness_textures_rgba8(
        unpack_lean_map(plain.lean_maps[0]), options, nullptr, {false, false});
    std::vector<Image> own_chain, rough_chain;
    for (const Rgba8Image& level : own.metallic_roughness) {
        Image r(level.width, level.height, 1);
        for (std::size_t t = 0; t < r.pixels.size(); ++t)
            r.pixels[t] = float(level.texels[4 * t + 1]) / 255.0f;  // G = perceptual r
        own_chain.push_back(r);
        rough_chain.push_back(Image(level.width, level.height, 1, 0.8f));
    }
    gl::Renderer without(context()), with_own(context()), with_rough(context());
    without.set_scene(plain);
    with_own.set_scene(scene_with(&own_chain));
    with_rough.set_scene(scene_with(&rough_chain));
    const Image want = render(without, gl::Technique::Roughness, roughness);
    const Image got = render(with_own, gl::Technique::Roughness, roughness);
    const Image rough = render(with_rough, gl::Technique::Roughness, roughness);
    const double error = relative_l1(got, want), apart = relative_l1(rough, want);
    std::printf("roughness MIPs: own chain given %.3g, r = 0.8 given %.3g\n", error, apart);
    EXPECT_LT(error, 2e-3);
    EXPECT_GT(apart, 0.1);
    EXPECT_EQ(relative_l1(render(with_rough, gl::Technique::Lean, roughness),
                          render(without, gl::Technique::Lean, roughness)),
              0.0);
}

}  // namespace
}  // namespace leanfade::test
