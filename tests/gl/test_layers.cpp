// Bump layers on the GPU (docs/math.md §6): the renderer's mixed moments equal the shared header's
// on the CPU for every method, and the coherent pair sine / -sine renders as the flat surface
// with the height and textures methods, not with approx.
#include <cmath>
#include <ostream>

#include "gl_test_helpers.hpp"
#include "leanfade/core/detail/layers.hpp"
#include "leanfade/core/detail/procedural.hpp"
#include "leanfade/core/settings.hpp"
#include "leanfade/core/shading.hpp"
#include "leanfade/scene/detail/scene.hpp"

namespace leanfade::test {
namespace {

// One constant cross-term chain (every texel of every level = `products`) of a `size` map.
std::vector<Image> constant_cross_terms(glm::vec4 products, int size) {
    std::vector<Image> chain;
    for (int w = size;; w = std::max(1, w / 2)) {
        Image level(w, w, 4);
        for (std::size_t t = 0; t < level.texel_count(); ++t)
            for (int c = 0; c < 4; ++c) level.pixels[4 * t + std::size_t(c)] = products[c];
        chain.push_back(std::move(level));
        if (w == 1) break;
    }
    return chain;
}

struct LayerCase {
    const char* name;
    LayerMixing mixing;
    int layers;           // 2 or 3
    bool weight_map;      // weights from a (constant) weight map instead of the uniforms
    gl::Technique technique = gl::Technique::Lean;
};

void PrintTo(const LayerCase& c, std::ostream* os) {
    *os << c.name;
}

class LayersGpuMatchesCpu : public GlTest, public ::testing::WithParamInterface<LayerCase> {};

// Constant layer maps and cross terms (so that every MIP level and filter gives the same texel):
// each pixel of the quad must equal lf_mix_* + lf_shade on the CPU. The cross-term values are not
// the products of the layers' means, so that textures and approx give different surfaces.
TEST_P(LayersGpuMatchesCpu, PixelByPixel) {
    const LayerCase& c = GetParam();
    const glm::vec2 means[3] = {{0.12f, -0.07f}, {-0.05f, 0.09f}, {0.02f, 0.15f}};
    const glm::vec3 covariances[3] = {
        {0.010f, 0.018f, 0.004f}, {0.006f, 0.012f, -0.003f}, {0.02f, 0.005f, 0.001f}};
    const glm::vec4 cross[3] = {{0.004f, -0.003f, 0.002f, -0.001f},
                                {-0.002f, 0.005f, 0.001f, 0.003f},
                                {0.003f, 0.001f, -0.002f, 0.002f}};
    const float strengths[3] = {1.0f, -0.8f, 1.3f};
    const std::vector<float> weights =
        c.layers == 2 ? std::vector<float>{0.6f, 0.4f} : std::vector<float>{0.5f, 0.3f, 0.2f};

    scene::Scene s;
    s.objects.push_back(scene::Object{make_test_quad(), 0, glm::mat4(1.0f)});
    scene::Material material;
    material.name = "layers";
    material.layered.mixing = c.mixing;
    material.layered.weights = weights;
    for (int i = 0; i < c.layers; ++i) {
        s.lean_maps.push_back(
            make_constant_lean_map(means[i], covariances[i], 0.97f, Storage::Float32, 8));
        scene::MaterialLayer layer;
        layer.lean_map = i;
        layer.strength = strengths[i];
        layer.tiling = 1.0f + 0.5f * float(i);
        layer.velocity = glm::vec2(0.1f * float(i), -0.05f);
        material.layered.layers.push_back(layer);
    }
    if (c.mixing == LayerMixing::Textures)
        for (int p = 0; p < c.layers * (c.layers - 1) / 2; ++p) {
            material.layered.cross_terms.push_back(p);
            s.cross_terms.push_back(constant_cross_terms(cross[p], 8));
        }
    if (c.weight_map) {
        // Weights of the map differ from the uniforms: the map must win.
        Image map(4, 4, 4);
        const glm::vec4 t = c.layers == 2 ? glm::vec4(0.25f, 0.75f, 0.0f, 0.0f)
                                          : glm::vec4(0.2f, 0.2f, 0.6f, 0.0f);
        for (std::size_t i = 0; i < map.texel_count(); ++i)
            for (int ch = 0; ch < 4; ++ch) map.pixels[4 * i + std::size_t(ch)] = t[ch];
        material.layered.weight_map = 0;
        s.weight_maps.push_back(map);
    }
    s.materials.push_back(material);

    gl::Renderer renderer(context());
    renderer.set_scene(s);
    gl::RenderRequest request;
    request.technique = c.technique;
    request.width = 64;
    request.height = 48;
    request.time = 1.7f;
    request.view = gl::view_at_distance(2.2f, 40.0f, {0.35f, -0.25f, 1.0f});
    ShadingSettings& settings = request.settings;
    settings.light_direction = {-0.4f, 0.5f, 0.8f};
    settings.shininess = 64.0f;
    request.background = glm::vec3(-1.0f);
    const Image gpu = renderer.render(request);

    // CPU: the same mix with the shared header (fetching the maps' only texel).
    std::vector<float> t = weights;
    if (c.weight_map)
        for (int i = 0; i < c.layers; ++i)
            t[std::size_t(i)] = s.weight_maps[0].pixels[std::size_t(i)];
    shading::LfMoments mixed = shading::lf_mix_start();
    shading::LfMoments scaled[3];
    for (int i = 0; i < c.layers; ++i) {
        const PackedLeanMap& map = s.lean_maps[std::size_t(i)];
        scaled[i] =
            shading::lf_layer_strength(shading::lf_unpack(fetch_packed_texel(map, 0, 0, 0, 0),
                                                          fetch_packed_texel(map, 0, 1, 0, 0),
                                                          map.scale, lean_offset(map.encoding)),
                                       strengths[i]);
        mixed = shading::lf_mix_layer(mixed, scaled[i], t[std::size_t(i)]);
    }
    for (int i = 0; i < c.layers; ++i)
        for (int j = i + 1; j < c.layers; ++j) {
            const glm::vec4 products =
                c.mixing == LayerMixing::Textures
                    ? cross[pair_index(i, j, c.layers)] * (strengths[i] * strengths[j])
                    : shading::lf_cross_products(scaled[i].mean, scaled[j].mean);
            mixed = shading::lf_mix_pair(mixed, products, t[std::size_t(i)] * t[std::size_t(j)]);
        }
    mixed = shading::lf_mix_end(mixed);

    const shading::LfParams params = to_lf_params(settings, false);
    const glm::mat4 inverse = glm::inverse(
        request.view.projection_matrix(float(request.width) / float(request.height)) *
        request.view.view_matrix());
    const float half = 1.0f / std::sqrt(2.0f);
    const glm::vec3 light = glm::normalize(settings.light_direction);
    int compared = 0;
    for (int y = 0; y < gpu.height; ++y)
        for (int x = 0; x < gpu.width; ++x) {
            const glm::vec2 ndc((x + 0.5f) / gpu.width * 2.0f - 1.0f,
                                (gpu.height - 1 - y + 0.5f) / gpu.height * 2.0f - 1.0f);
            const glm::vec4 a = inverse * glm::vec4(ndc, -1.0f, 1.0f);
            const glm::vec4 b = inverse * glm::vec4(ndc, 1.0f, 1.0f);
            const glm::vec3 p0 = glm::vec3(a) / a.w, p1 = glm::vec3(b) / b.w;
            const glm::vec3 p = p0 + (p0.z / (p0.z - p1.z)) * (p1 - p0);
            if (gpu.at(x, y, 0) == -1.0f ||
                !(std::abs(p.x) < half * 0.97f && std::abs(p.y) < half * 0.97f))
                continue;
            const shading::LfShade shade = shading::lf_shade(
                info(c.technique).shader_technique, mixed, light, request.view.eye - p, params);
            const glm::vec3 expected = shade.diffuse + shade.specular;
            for (int ch = 0; ch < 3; ++ch) {
                const double want = expected[ch], got = gpu.at(x, y, ch);
                ASSERT_LE(std::abs(got - want), 2e-3 * std::abs(want) + 2e-4)
                    << c.name << " pixel " << x << "," << y << " channel " << ch << ": gpu "
                    << got << " cpu " << want;
            }
            ++compared;
        }
    EXPECT_GT(compared, gpu.width * gpu.height / 4);
}

INSTANTIATE_TEST_SUITE_P(
    Mixing, LayersGpuMatchesCpu,
    ::testing::Values(LayerCase{"textures_2", LayerMixing::Textures, 2, false},
                      LayerCase{"textures_3", LayerMixing::Textures, 3, false},
                      LayerCase{"approx_2", LayerMixing::Approx, 2, false},
                      LayerCase{"approx_3", LayerMixing::Approx, 3, false},
                      LayerCase{"textures_weight_map", LayerMixing::Textures, 3, true},
                      LayerCase{"approx_weight_map", LayerMixing::Approx, 2, true},
                      LayerCase{"textures_fade", LayerMixing::Textures, 2, false,
                                gl::Technique::Fade},
                      LayerCase{"approx_bump", LayerMixing::Approx, 2, false,
                                gl::Technique::Bump}),
    [](const ::testing::TestParamInfo<LayerCase>& info) { return std::string(info.param.name); });

// LEAN §3.5's coherent test: "sine" at strength 1 and -1, half and half, is a flat surface. The
// height and textures methods render it as "flat" (same image within float noise); approx keeps
// the layers' variance at coarse MIP levels and widens the highlight.
class CoherentLayers : public GlTest {};

TEST_F(CoherentLayers, SineAndItsNegationRenderFlatExceptWithApprox) {
    const int size = 128;
    BakeOptions options;
    const LeanMap sine = bake_lean_map(make_builtin_height("sine", size, 1), BakeSource::Height,
                                       options, "sine")
                             .map;
    const LeanMap flat = bake_lean_map(make_builtin_height("flat", size, 1), BakeSource::Height,
                                       options, "flat")
                             .map;
    Image slopes(size, size, 2);
    for (std::size_t t = 0; t < sine.levels[0].mean.size(); ++t) {
        slopes.pixels[2 * t] = sine.levels[0].mean[t].x;
        slopes.pixels[2 * t + 1] = sine.levels[0].mean[t].y;
    }
    const scene::Mesh sphere = scene::make_scene_mesh("sphere");

    auto render_at = [&](const scene::Scene& s, float time) {
        gl::Renderer renderer(context());
        renderer.set_scene(s);
        gl::RenderRequest request;
        request.technique = gl::Technique::Lean;
        request.width = request.height = 96;
        request.view = gl::view_at_distance(6.0f);  // coarse MIP levels over the sphere
        request.settings.shininess = 256.0f;
        request.settings.tiling = 8.0f;
        request.output = gl::OutputMode::Specular;
        request.time = time;
        return renderer.render(request);
    };
    auto render = [&](const scene::Scene& s) { return render_at(s, 0.0f); };
    auto single = [&](const LeanMap& map) {
        scene::Scene s;
        s.objects.push_back(scene::Object{sphere, 0, glm::mat4(1.0f)});
        s.materials.push_back(scene::Material{"single", 0, {}, {}, {}, {}});
        s.lean_maps.push_back(pack_lean_map(map, Storage::Float32, "tests"));
        return s;
    };
    auto layered = [&](LayerMixing mixing) {
        scene::Scene s = single(sine);
        s.lean_maps.push_back(s.lean_maps[0]);
        scene::Material& m = s.materials[0];
        m.layered.mixing = mixing;
        m.layered.weights = {0.5f, 0.5f};
        m.layered.layers = {scene::MaterialLayer{0, 1.0f, 1.0f, glm::vec2(0.0f)},
                            scene::MaterialLayer{1, -1.0f, 1.0f, glm::vec2(0.0f)}};
        if (mixing == LayerMixing::Textures) {
            m.layered.cross_terms = {0};
            s.cross_terms.push_back(build_cross_terms(slopes, slopes));
        }
        return s;
    };
    // The height method: one map baked from the mixed slopes (what load_render_scene does).
    LayerBlend blend{{0.5f, 0.5f}, {1.0f, -1.0f}};
    const Image both[2] = {slopes, slopes};
    const LeanMap height_mixed = build_lean_map(mix_slopes(both, blend), options);

    const Image reference = render(single(flat));
    const Image height = render(single(height_mixed));
    const Image textures = render(layered(LayerMixing::Textures));
    const Image approx = render(layered(LayerMixing::Approx));
    // Moving together, the pair stays flat: height regenerates its map for the frame's time
    // (on the GPU), textures stays exact because the pair does not move relative to itself.
    auto moving = [&](LayerMixing mixing) {
        scene::Scene s = layered(mixing);
        for (scene::MaterialLayer& layer : s.materials[0].layered.layers)
            layer.velocity = glm::vec2(0.031f, -0.017f);
        return s;
    };
    const Image height_moving = render_at(moving(LayerMixing::Height), 2.3f);
    const Image textures_moving = render_at(moving(LayerMixing::Textures), 2.3f);
    const Image sine_alone = render(single(sine));
    ASSERT_GT(image_sum(reference), 1.0) << "the flat sphere must show a highlight";
    // Sanity: the bumpy sine alone is far from flat at this distance.
    EXPECT_GT(relative_l1(sine_alone, reference), 0.2);
    EXPECT_LT(relative_l1(height, reference), 1e-4);
    EXPECT_LT(relative_l1(textures, reference), 1e-3);
    EXPECT_GT(relative_l1(approx, reference), 0.2);
    EXPECT_LT(relative_l1(height_moving, reference), 1e-3);
    EXPECT_LT(relative_l1(textures_moving, reference), 1e-3);
    std::printf("relative L1 to flat: sine %.3g, height %.3g, textures %.3g, approx %.3g; "
                "moving together: height %.3g, textures %.3g\n",
                relative_l1(sine_alone, reference), relative_l1(height, reference),
                relative_l1(textures, reference), relative_l1(approx, reference),
                relative_l1(height_moving, reference), relative_l1(textures_moving, reference));
}

// The "height" method for layers that move, tile differently or have per-texel weights: the map
// the renderer generates on the GPU for a frame's time equals the CPU's definition
// (mix_slopes_at, then build_lean_map) at every MIP level, and at time 0 it renders like the map
// baked once on the CPU.
struct MovingHeightCase {
    const char* name;
    bool weight_map;
};

class MovingLayersHeight : public GlTest, public ::testing::WithParamInterface<MovingHeightCase> {
  protected:
    // Layers bumps (64^2) and noise (32^2, tiling 2), moving apart; weights 0.3 / 0.7 or, with
    // a weight map, varying along u.
    scene::Scene make_scene(const std::vector<glm::vec2>& velocities) const {
        scene::Scene s;
        s.objects.push_back(scene::Object{scene::make_scene_mesh("sphere"), 0, glm::mat4(1.0f)});
        scene::Material material;
        material.name = "moving";
        material.layered.mixing = LayerMixing::Height;
        material.layered.weights = {0.3f, 0.7f};
        const char* sets[2] = {"bumps", "noise"};
        const int sizes[2] = {64, 32};
        for (int i = 0; i < 2; ++i) {
            const LeanMap map = bake_lean_map(make_builtin_height(sets[i], sizes[i], 5),
                                              BakeSource::Height, BakeOptions{}, sets[i])
                                    .map;
            s.lean_maps.push_back(pack_lean_map(map, Storage::Float32, "tests"));
            material.layered.layers.push_back(scene::MaterialLayer{
                i, i == 0 ? 1.0f : -1.4f, float(i + 1), velocities[std::size_t(i)]});
        }
        if (GetParam().weight_map) {
            Image weights(16, 8, 4);
            for (int y = 0; y < 8; ++y)
                for (int x = 0; x < 16; ++x) {
                    weights.at(x, y, 0) = float(x) / 15.0f;
                    weights.at(x, y, 1) = 1.0f - float(x) / 15.0f;
                }
            s.weight_maps.push_back(weights);
            material.layered.weight_map = 0;
        }
        s.materials.push_back(material);
        return s;
    }
};

TEST_P(MovingLayersHeight, GeneratedMapIsTheCpuMixAtEveryLevel) {
    const std::vector<glm::vec2> velocities = {{0.013f, 0.0f}, {-0.004f, 0.021f}};
    const scene::Scene s = make_scene(velocities);
    gl::Renderer renderer(context());
    renderer.set_scene(s);
    const float time = 17.3f;
    const LeanMap gpu = unpack_lean_map(renderer.mixed_lean_map(0, time));

    std::vector<Image> slopes;
    LayerBlend blend{{0.3f, 0.7f}, {}};
    std::vector<LayerPlacement> placements;
    for (std::size_t i = 0; i < 2; ++i) {
        const LeanMap layer = unpack_lean_map(s.lean_maps[i]);
        Image b(layer.levels[0].width, layer.levels[0].height, 2);
        for (std::size_t t = 0; t < layer.levels[0].mean.size(); ++t) {
            b.pixels[2 * t] = layer.levels[0].mean[t].x;
            b.pixels[2 * t + 1] = layer.levels[0].mean[t].y;
        }
        slopes.push_back(b);
        const scene::MaterialLayer& l = s.materials[0].layered.layers[i];
        blend.strengths.push_back(l.strength);
        const double ox = double(l.velocity.x) * time, oy = double(l.velocity.y) * time;
        placements.push_back({l.tiling, glm::vec2(float(ox - std::floor(ox)),
                                                  float(oy - std::floor(oy)))});
    }
    ASSERT_EQ(gpu.levels[0].width, 64);  // max(64 x 1, 32 x 2)
    const Image* weights = s.weight_maps.empty() ? nullptr : &s.weight_maps[0];
    const LeanMap cpu = build_lean_map(
        mix_slopes_at(slopes, blend, placements, weights, 64, 64), BakeOptions{});
    ASSERT_EQ(gpu.levels.size(), cpu.levels.size());
    double worst = 0.0, variance_scale = 0.0;
    for (std::size_t level = 0; level < cpu.levels.size(); ++level) {
        const MomentLevel& a = gpu.levels[level];
        const MomentLevel& b = cpu.levels[level];
        ASSERT_EQ(a.mean.size(), b.mean.size());
        for (std::size_t t = 0; t < b.mean.size(); ++t) {
            for (int c = 0; c < 2; ++c)
                worst = std::max(worst, double(std::abs(a.mean[t][c] - b.mean[t][c])));
            for (int c = 0; c < 3; ++c) {
                worst = std::max(worst, double(std::abs(a.second[t][c] - b.second[t][c])));
                variance_scale = std::max(variance_scale, double(std::abs(b.second[t][c])));
            }
        }
    }
    ASSERT_GT(variance_scale, 1e-3) << "the mixed layers must be bumpy";
    EXPECT_LT(worst, 2e-5 + 1e-4 * variance_scale);
    std::printf("GPU mixed map vs CPU, every level: max |difference| %.3g (largest M %.3g)\n",
                worst, variance_scale);
    // A later time moves the layers: the map changes.
    const LeanMap later = unpack_lean_map(renderer.mixed_lean_map(0, time + 3.0f));
    double moved = 0.0;
    for (std::size_t t = 0; t < later.levels[0].mean.size(); ++t)
        moved = std::max(moved, double(std::abs(later.levels[0].mean[t].x -
                                                gpu.levels[0].mean[t].x)));
    EXPECT_GT(moved, 1e-3);
}

INSTANTIATE_TEST_SUITE_P(Weights, MovingLayersHeight,
                         ::testing::Values(MovingHeightCase{"constant", false},
                                           MovingHeightCase{"weight_map", true}),
                         [](const ::testing::TestParamInfo<MovingHeightCase>& info) {
                             return std::string(info.param.name);
                         });

class MovingLayersAtTimeZero : public GlTest {};

TEST_F(MovingLayersAtTimeZero, RenderLikeTheMapBakedOnceOnTheCpu) {
    scene::Scene moving;
    moving.objects.push_back(
        scene::Object{scene::make_scene_mesh("sphere"), 0, glm::mat4(1.0f)});
    scene::Material material;
    material.name = "moving";
    material.layered.mixing = LayerMixing::Height;
    material.layered.weights = {0.4f, 0.6f};
    std::vector<Image> slopes;
    const char* sets[2] = {"bumps", "noise"};
    for (int i = 0; i < 2; ++i) {
        const LeanMap map = bake_lean_map(make_builtin_height(sets[i], 64, 9), BakeSource::Height,
                                          BakeOptions{}, sets[i])
                                .map;
        Image b(64, 64, 2);
        for (std::size_t t = 0; t < map.levels[0].mean.size(); ++t) {
            b.pixels[2 * t] = map.levels[0].mean[t].x;
            b.pixels[2 * t + 1] = map.levels[0].mean[t].y;
        }
        slopes.push_back(b);
        moving.lean_maps.push_back(pack_lean_map(map, Storage::Float32, "tests"));
        material.layered.layers.push_back(scene::MaterialLayer{
            i, i == 0 ? 1.0f : 0.8f, 1.0f, glm::vec2(0.05f * float(i + 1), -0.02f)});
    }
    moving.materials.push_back(material);

    scene::Scene baked;
    baked.objects = moving.objects;
    baked.materials.push_back(scene::Material{"baked", 0, {}, {}, {}, {}});
    const LayerBlend blend{{0.4f, 0.6f}, {1.0f, 0.8f}};
    baked.lean_maps.push_back(pack_lean_map(
        build_lean_map(mix_slopes(slopes, blend), BakeOptions{}), Storage::Float32, "tests"));

    auto render = [&](const scene::Scene& s, float time) {
        gl::Renderer renderer(context());
        renderer.set_scene(s);
        gl::RenderRequest request;
        request.technique = gl::Technique::Fade;
        request.width = request.height = 96;
        request.view = gl::view_at_distance(4.0f);
        request.settings.shininess = 128.0f;
        request.settings.tiling = 4.0f;
        request.time = time;
        return renderer.render(request);
    };
    const Image once = render(baked, 0.0f);
    const Image per_frame = render(moving, 0.0f);
    const Image later = render(moving, 1.5f);
    ASSERT_GT(image_sum(once), 1.0);
    EXPECT_LT(relative_l1(per_frame, once), 1e-4);
    EXPECT_GT(relative_l1(later, once), 1e-3) << "the layers move";
    std::printf("relative L1 to the map baked once: t = 0 %.3g, t = 1.5 s %.3g\n",
                relative_l1(per_frame, once), relative_l1(later, once));
}

}  // namespace
}  // namespace leanfade::test

namespace leanfade::test {
namespace {

// Two-lobe LEAN on moving bump layers mixed by the "height" method reads the plateau layer the
// GPU generates with the mixed map (shaders/generate_plateau.comp): bumps on flat ground under
// bumps on flat ground leave flat ground, so two-lobe differs from LEAN; layers mixed at shading
// time have no plateau and draw two-lobe as LEAN, bit for bit.
class GeneratedPlateau : public GlTest {};

TEST_F(GeneratedPlateau, HeightMixingGetsTheLayerAndTheOtherMethodsShadeAsLean) {
    auto scene_of = [](LayerMixing mixing) {
        scene::Scene s;
        s.objects.push_back(scene::Object{scene::make_scene_mesh("sphere"), 0, glm::mat4(1.0f)});
        scene::Material material;
        material.name = "moving bumps";
        material.layered.mixing = mixing;
        material.layered.weights = {0.5f, 0.5f};
        for (int i = 0; i < 2; ++i) {
            const LeanMap map = bake_lean_map(make_builtin_height("bumps", 64, 3 + i),
                                              BakeSource::Height, BakeOptions{}, "bumps")
                                    .map;
            s.lean_maps.push_back(pack_lean_map(map, Storage::Float32, "tests"));
            material.layered.layers.push_back(scene::MaterialLayer{
                i, 1.0f, 1.0f, glm::vec2(0.011f * float(i + 1), -0.007f)});
        }
        s.materials.push_back(material);
        return s;
    };
    auto render = [&](const scene::Scene& s, gl::Technique technique) {
        gl::Renderer renderer(context());
        renderer.set_scene(s);
        gl::RenderRequest request;
        request.technique = technique;
        request.width = request.height = 96;
        request.view = gl::view_at_distance(16.0f);
        request.settings.shininess = 4096.0f;
        request.settings.tiling = 4.0f;
        request.settings.geometric_aa = GeometricAa::Off;
        request.output = gl::OutputMode::Specular;
        request.time = 1.7f;
        return renderer.render(request);
    };
    const scene::Scene height = scene_of(LayerMixing::Height);
    const Image lean = render(height, gl::Technique::Lean);
    const Image two = render(height, gl::Technique::TwoLobe);
    ASSERT_GT(image_sum(lean), 0.0);
    EXPECT_GT(relative_l1(two, lean), 0.02) << "the generated plateau's spike must show";
    // Mixed at shading time ("approx"; "textures" alike): no plateau.
    const scene::Scene approx = scene_of(LayerMixing::Approx);
    EXPECT_TRUE(render(approx, gl::Technique::Lean).pixels ==
                render(approx, gl::Technique::TwoLobe).pixels);
}

}  // namespace
}  // namespace leanfade::test
