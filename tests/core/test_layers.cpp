// Bump layers (leanfade/core/detail/layers.hpp, LEAN §3.5): the mixed moments equal the moments of the
// mixed height field, exactly for the height method, at every MIP level for mixing textures, at
// the finest level only for the approximation; coherent layers (sine and its negation) mix to a
// flat surface except under the approximation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/layers.hpp"
#include "leanfade/core/detail/procedural.hpp"
#include "leanfade/core/shading.hpp"

namespace leanfade::test {
namespace {

Image slopes_of(const Image& height) {
    return slopes_from_height(height, BakeOptions{}).slopes;
}

// The moments of the mixed height field, baked as one map.
LeanMap mixed_height_map(const std::vector<Image>& heights, const LayerBlend& blend) {
    Image mixed(heights[0].width, heights[0].height, 1);
    for (std::size_t i = 0; i < heights.size(); ++i)
        for (std::size_t v = 0; v < mixed.pixels.size(); ++v)
            mixed.pixels[v] += blend.weights[i] * blend.strengths[i] * heights[i].pixels[v];
    return build_lean_map(slopes_of(mixed), BakeOptions{});
}

// Largest |a - b| over a level's B and M, relative to the level's largest |M| (or B^2).
double level_difference(const MomentLevel& a, const MomentLevel& b) {
    double scale = 1e-12, diff = 0.0;
    for (std::size_t t = 0; t < a.mean.size(); ++t) {
        for (int c = 0; c < 3; ++c) {
            scale = std::max(scale, double(std::abs(b.second[t][c])));
            diff = std::max(diff, double(std::abs(a.second[t][c] - b.second[t][c])));
        }
        for (int c = 0; c < 2; ++c) {
            scale = std::max(scale, double(b.mean[t][c] * b.mean[t][c]));
            diff = std::max(diff, double(std::abs(a.mean[t][c] - b.mean[t][c])) * std::sqrt(scale));
        }
    }
    return diff / scale;
}

struct Layers {
    std::vector<Image> heights, slopes;
    std::vector<LeanMap> maps;
    std::vector<std::vector<Image>> cross;
};

Layers make_layers(const std::vector<Image>& heights) {
    Layers l;
    l.heights = heights;
    for (const Image& h : heights) {
        l.slopes.push_back(slopes_of(h));
        l.maps.push_back(build_lean_map(l.slopes.back(), BakeOptions{}));
    }
    const int n = int(heights.size());
    for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j) {
            EXPECT_EQ(pair_index(i, j, n), int(l.cross.size()));
            l.cross.push_back(
                build_cross_terms(l.slopes[std::size_t(i)], l.slopes[std::size_t(j)]));
        }
    return l;
}

TEST(Layers, HeightMixingIsTheMixedHeightField) {
    const std::vector<Image> heights = {make_builtin_height("bumps", 64, 3),
                                        make_builtin_height("noise", 64, 4),
                                        make_builtin_height("ridges", 64, 1)};
    const LayerBlend blend{{0.5f, 0.3f, 0.2f}, {1.0f, -0.7f, 1.5f}};
    const Layers l = make_layers(heights);
    const Image mixed = mix_slopes(l.slopes, blend);
    // The Sobel filter is linear: the slopes of the mixed heights are the mixed slopes.
    const Image direct = slopes_of([&] {
        Image h(64, 64, 1);
        for (std::size_t i = 0; i < heights.size(); ++i)
            for (std::size_t v = 0; v < h.pixels.size(); ++v)
                h.pixels[v] += blend.weights[i] * blend.strengths[i] * heights[i].pixels[v];
        return h;
    }());
    ASSERT_EQ(mixed.pixels.size(), direct.pixels.size());
    for (std::size_t v = 0; v < mixed.pixels.size(); ++v)
        ASSERT_NEAR(mixed.pixels[v], direct.pixels[v], 1e-5f) << v;
    const LeanMap a = build_lean_map(mixed, BakeOptions{});
    const LeanMap b = mixed_height_map(heights, blend);
    for (std::size_t level = 0; level < a.levels.size(); ++level)
        EXPECT_LT(level_difference(a.levels[level], b.levels[level]), 1e-5) << level;
}

TEST(Layers, MixingTexturesIsExactAtEveryLevel) {
    const std::vector<Image> heights = {
        make_builtin_height("bumps", 64, 3), make_builtin_height("noise", 64, 4),
        make_builtin_height("waves", 64, 5), make_builtin_height("checker", 64, 1)};
    const LayerBlend blend{{0.4f, 0.3f, 0.2f, 0.1f}, {1.0f, -0.7f, 1.5f, 0.5f}};
    const Layers l = make_layers(heights);
    const LeanMap truth = mixed_height_map(heights, blend);
    ASSERT_EQ(truth.levels.size(), 7u);
    for (int level = 0; level < 7; ++level) {
        const MomentLevel mixed =
            mix_layer_level(l.maps, l.cross, level, LayerMixing::Textures, blend);
        EXPECT_LT(level_difference(mixed, truth.levels[std::size_t(level)]), 2e-5) << level;
    }
}

TEST(Layers, ApproximationIsExactAtTheFinestLevelOnly) {
    const std::vector<Image> heights = {make_builtin_height("bumps", 64, 3),
                                        make_builtin_height("noise", 64, 4)};
    const LayerBlend blend{{0.6f, 0.4f}, {1.0f, 1.0f}};
    const Layers l = make_layers(heights);
    const LeanMap truth = mixed_height_map(heights, blend);
    const MomentLevel finest = mix_layer_level(l.maps, {}, 0, LayerMixing::Approx, blend);
    EXPECT_LT(level_difference(finest, truth.levels[0]), 2e-5);
    // Coarser, the products of filtered B's are not the filtered products.
    const MomentLevel coarse = mix_layer_level(l.maps, {}, 3, LayerMixing::Approx, blend);
    EXPECT_GT(level_difference(coarse, truth.levels[3]), 1e-3);
}

// The paper's coherent test: sine at strength 1 and -1, weights 1/2: the mixed surface is flat.
// Height and textures give M = 0 at every level; the approximation keeps half the sine's M.
TEST(Layers, CoherentSineAndItsNegationMixToFlat) {
    const Image sine = make_builtin_height("sine", 64);
    const std::vector<Image> heights = {sine, sine};
    const LayerBlend blend{{0.5f, 0.5f}, {1.0f, -1.0f}};
    const Layers l = make_layers(heights);
    const LeanMap height_map = build_lean_map(mix_slopes(l.slopes, blend), BakeOptions{});
    const LeanMap sine_map = l.maps[0];
    for (int level : {0, 3, 6}) {
        const MomentLevel textures =
            mix_layer_level(l.maps, l.cross, level, LayerMixing::Textures, blend);
        const MomentLevel approx = mix_layer_level(l.maps, {}, level, LayerMixing::Approx, blend);
        const MomentLevel& h = height_map.levels[std::size_t(level)];
        const MomentLevel& s = sine_map.levels[std::size_t(level)];
        for (std::size_t t = 0; t < h.mean.size(); ++t) {
            EXPECT_EQ(h.mean[t], glm::vec2(0.0f));
            EXPECT_EQ(h.second[t], glm::vec3(0.0f));
            EXPECT_NEAR(textures.second[t].x, 0.0f, 1e-6f) << level;
            EXPECT_NEAR(textures.mean[t].x, 0.0f, 1e-6f) << level;
        }
        if (level > 0) {
            // B of the sine averages out at coarse levels; M stays: the approximation keeps
            // t^2 M + u^2 M - 2 t u B B = M / 2 (up to the residual B^2).
            for (std::size_t t = 0; t < s.mean.size(); ++t)
                EXPECT_NEAR(approx.second[t].x, 0.5f * s.second[t].x, 0.05f * s.second[t].x);
            EXPECT_GT(approx.second[0].x, 0.01f);
        }
    }
}

// With the shared header's lobe: the coherent pair at a coarse level shades like the flat set
// by the height and texture methods, not by the approximation.
TEST(Layers, CoherentPairShadesLikeFlatExceptApproximation) {
    const Image sine = make_builtin_height("sine", 64);
    const std::vector<Image> heights = {sine, sine};
    const LayerBlend blend{{0.5f, 0.5f}, {1.0f, -1.0f}};
    const Layers l = make_layers(heights);
    const LeanMap flat = build_lean_map(slopes_of(make_builtin_height("flat", 64)), BakeOptions{});
    const int level = 4;
    shading::LfParams p{};
    p.light_color = glm::vec3(1.0f);
    p.ks = glm::vec3(1.0f);
    p.shininess = 400.0f;
    p.inv_s_shading = 1.0f / 400.0f;
    p.fresnel_bias = 1.0f;
    const glm::vec3 light = glm::normalize(glm::vec3(0.1f, 0.05f, 1.0f));
    const glm::vec3 view = glm::vec3(-0.1f, -0.05f, 1.0f) * 5.0f;
    auto shade = [&](const MomentLevel& m) {
        shading::LfMoments moments;
        moments.normal = m.normal[0];
        moments.mean = m.mean[0];
        moments.second = m.second[0];
        return shading::lf_shade(shading::LF_TECHNIQUE_LEAN, moments, light, view, p).specular.x;
    };
    const MomentLevel& flat_level = flat.levels[level];
    const float want = shade(flat_level);
    const float textures =
        shade(mix_layer_level(l.maps, l.cross, level, LayerMixing::Textures, blend));
    const float height = shade(
        build_lean_map(mix_slopes(l.slopes, blend), BakeOptions{}).levels[std::size_t(level)]);
    const float approx = shade(mix_layer_level(l.maps, {}, level, LayerMixing::Approx, blend));
    EXPECT_GT(want, 1.0f);
    EXPECT_NEAR(height, want, 1e-4f * want);
    EXPECT_NEAR(textures, want, 1e-3f * want);
    EXPECT_LT(approx, 0.5f * want) << "the approximation keeps the sine's variance";
}

TEST(Layers, BadBlendsAndInputsAreErrors) {
    const Image s = slopes_of(make_builtin_height("bumps", 16, 1));
    const std::vector<Image> two = {s, s};
    EXPECT_THROW(mix_slopes(two, LayerBlend{{0.5f, 0.4f}, {1.0f, 1.0f}}), Error);  // sum 0.9
    EXPECT_THROW(mix_slopes(two, LayerBlend{{0.5f, 0.5f}, {1.0f, 0.0f}}), Error);  // k = 0
    EXPECT_THROW(mix_slopes(two, LayerBlend{{0.5f, 0.5f}, {1.0f}}), Error);
    EXPECT_THROW(mix_slopes(two, LayerBlend{{1.5f, -0.5f}, {1.0f, 1.0f}}), Error);
    EXPECT_THROW(mix_slopes(two, LayerBlend{{0.5f, 0.5f}, {1.0f, std::nanf("")}}), Error);
    const std::vector<Image> five(5, s);
    EXPECT_THROW(mix_slopes(five, LayerBlend{{0.2f, 0.2f, 0.2f, 0.2f, 0.2f},
                                             {1.0f, 1.0f, 1.0f, 1.0f, 1.0f}}),
                 Error);
    const Image other = slopes_of(make_builtin_height("bumps", 32, 1));
    EXPECT_THROW(build_cross_terms(s, other), Error);
    EXPECT_THROW(pair_index(1, 1, 3), Error);
    EXPECT_EQ(pair_index(0, 1, 4), 0);
    EXPECT_EQ(pair_index(0, 3, 4), 2);
    EXPECT_EQ(pair_index(1, 2, 4), 3);
    EXPECT_EQ(pair_index(2, 3, 4), 5);
    EXPECT_EQ(parse_layer_mixing("textures"), LayerMixing::Textures);
    EXPECT_THROW(parse_layer_mixing("blend"), Error);
    const LeanMap map = build_lean_map(s, BakeOptions{});
    const std::vector<LeanMap> maps = {map, map};
    EXPECT_THROW(
        mix_layer_level(maps, {}, 0, LayerMixing::Textures, LayerBlend{{0.5f, 0.5f}, {1.0f, 1.0f}}),
        Error);  // no cross-term texture
    EXPECT_THROW(
        mix_layer_level(maps, {}, 0, LayerMixing::Height, LayerBlend{{0.5f, 0.5f}, {1.0f, 1.0f}}),
        Error);
}

// Moving layers mixed by height (mix_slopes_at): aligned layers give mix_slopes; a whole-texel
// offset rolls the layer; half a texel averages two texels; tiling 2 of a half-size layer reads
// every layer texel once.
Image test_slopes(int width, int height, unsigned seed) {
    Image s(width, height, 2);
    for (std::size_t v = 0; v < s.pixels.size(); ++v)
        s.pixels[v] = 0.3f * std::sin(0.37f * float(v) + float(seed)) +
                      0.1f * std::cos(1.3f * float(v * v % 97));
    return s;
}

TEST(Layers, MixSlopesAtAlignedLayersIsMixSlopes) {
    const Image a = test_slopes(16, 8, 1), b = test_slopes(16, 8, 2);
    const Image both[2] = {a, b};
    const LayerBlend blend{{0.3f, 0.7f}, {1.2f, -0.6f}};
    const LayerPlacement aligned[2] = {};
    const Image at = mix_slopes_at(both, blend, aligned, nullptr, 16, 8);
    const Image plain = mix_slopes(both, blend);
    ASSERT_EQ(at.pixels.size(), plain.pixels.size());
    for (std::size_t v = 0; v < at.pixels.size(); ++v)
        ASSERT_NEAR(at.pixels[v], plain.pixels[v], 1e-6f) << v;
}

TEST(Layers, MixSlopesAtOffsetsAndTilingSampleTheLayers) {
    const Image a = test_slopes(8, 4, 3), b = test_slopes(8, 4, 4);
    const Image both[2] = {a, b};
    const LayerBlend only_first{{1.0f, 0.0f}, {1.0f, 1.0f}};
    // u offset of 3 texels (3/8 uv): output texel x reads layer texel x + 3 (mod 8); v offset of
    // one texel (1/4 uv): rows move one down (rows are top first, v up).
    LayerPlacement moved[2] = {{1.0f, glm::vec2(3.0f / 8.0f, 1.0f / 4.0f)}, {}};
    const Image rolled = mix_slopes_at(both, only_first, moved, nullptr, 8, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x)
            for (int c = 0; c < 2; ++c)
                ASSERT_NEAR(rolled.at(x, y, c), a.at((x + 3) % 8, (y + 3) % 4, c), 1e-6f)
                    << x << "," << y;
    // Half a texel along u: the mean of two neighbours.
    moved[0].offset = glm::vec2(0.5f / 8.0f, 0.0f);
    const Image half = mix_slopes_at(both, only_first, moved, nullptr, 8, 4);
    for (int x = 0; x < 8; ++x)
        EXPECT_NEAR(half.at(x, 1, 0), 0.5f * (a.at(x, 1, 0) + a.at((x + 1) % 8, 1, 0)), 1e-6f);
    // Tiling 2 of a 4 x 2 layer over an 8 x 4 map: texel x reads layer texel x mod 4.
    const Image small = test_slopes(4, 2, 5);
    const Image tiled_pair[2] = {small, b};
    LayerPlacement tiled[2] = {{2.0f, glm::vec2(0.0f)}, {}};
    const Image t = mix_slopes_at(tiled_pair, only_first, tiled, nullptr, 8, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) ASSERT_NEAR(t.at(x, y, 0), small.at(x % 4, y % 2, 0), 1e-6f);
}

TEST(Layers, MixSlopesAtWeightMapWeighsPerTexel) {
    const Image a = test_slopes(4, 4, 6), b = test_slopes(4, 4, 7);
    const Image both[2] = {a, b};
    const LayerBlend blend{{0.5f, 0.5f}, {1.0f, 2.0f}};
    Image weights(4, 4, 4);  // the left half all a, the right half all b
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            weights.at(x, y, 0) = x < 2 ? 1.0f : 0.0f;
            weights.at(x, y, 1) = x < 2 ? 0.0f : 1.0f;
        }
    const LayerPlacement aligned[2] = {};
    const Image mixed = mix_slopes_at(both, blend, aligned, &weights, 4, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
            EXPECT_NEAR(mixed.at(x, y, 1), x < 2 ? a.at(x, y, 1) : 2.0f * b.at(x, y, 1), 1e-6f);
}

TEST(Layers, MixedMapSizeIsTheFinestLayerTimesItsTiling) {
    const glm::ivec2 sizes[2] = {{64, 64}, {32, 16}};
    const LayerPlacement placements[2] = {{1.0f, {}}, {4.0f, {0.3f, 0.1f}}};
    EXPECT_EQ(mixed_map_size(sizes, placements), glm::ivec2(128, 64));
    const LayerPlacement fractional[2] = {{1.0f, {}}, {1.5f, {}}};
    EXPECT_THROW(mixed_map_size(sizes, fractional), Error);
    const LayerPlacement huge[2] = {{1.0f, {}}, {512.0f, {}}};  // 32 * 512 = 16384 texels
    EXPECT_THROW(mixed_map_size(sizes, huge), Error);
    const LayerPlacement below_one[2] = {{1.0f, {}}, {0.5f, {}}};
    EXPECT_THROW(mixed_map_size(sizes, below_one), Error);
}

}  // namespace
}  // namespace leanfade::test
