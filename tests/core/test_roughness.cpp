// Roughness MIPs (leanfade/core/roughness.hpp): the Beckmann α of every level folds the slopes'
// covariance over the texel's footprint into the base roughness, computed here independently
// from the top-level slopes.
#include <algorithm>
#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/procedural.hpp"
#include "leanfade/core/roughness.hpp"
#include "leanfade/core/shading.hpp"
#include "test_helpers.hpp"

namespace leanfade::test {
namespace {

Image slopes_of(const std::string& set, int size) {
    return slopes_from_height(make_builtin_height(set, size, 5), BakeOptions{}).slopes;
}

// Covariance (xx, yy, xy) of all slopes, in double.
glm::dvec3 slope_covariance(const Image& slopes) { return test::slope_moments(slopes).covariance(); }

// The one-pass 8-bit textures are the float textures rounded as write_png rounds, byte for byte,
// with a base roughness map and a metallic-roughness input, and without; each texture only when
// asked for.
TEST(Roughness, EightBitTexturesAreTheFloatTexturesRounded) {
    const LeanMap map = build_lean_map(slopes_of("ridges", 37), BakeOptions{});
    Image mr(37, 37, 3);
    for (std::size_t i = 0; i < mr.pixels.size(); ++i) mr.pixels[i] = float((i * 7919) % 101) / 100.0f;
    const Image r = base_roughness_channel(mr);
    for (const bool with_map : {false, true}) {
        RoughnessOptions options;
        options.base_roughness = 0.35f;
        if (with_map) options.roughness_map = &r;
        const Image* input = with_map ? &mr : nullptr;
        const RoughnessTextures floats = roughness_textures(roughness_mips(map, options), input);
        const RoughnessTexturesRgba8 bytes = roughness_textures_rgba8(map, options, input);
        const auto expect_rounded = [](const std::vector<Image>& f, const std::vector<Rgba8Image>& b) {
            ASSERT_EQ(f.size(), b.size());
            for (std::size_t l = 0; l < f.size(); ++l) {
                ASSERT_EQ(b[l].width, f[l].width);
                for (std::size_t i = 0; i < f[l].pixels.size(); ++i)
                    ASSERT_EQ(int(b[l].texels[i]),
                              int(std::lround(std::clamp(f[l].pixels[i], 0.0f, 1.0f) * 255.0f)))
                        << "level " << l << " value " << i;
            }
        };
        expect_rounded(floats.metallic_roughness, bytes.metallic_roughness);
        expect_rounded(floats.normal, bytes.normal);
        expect_rounded(floats.anisotropy, bytes.anisotropy);
        const RoughnessTexturesRgba8 only = roughness_textures_rgba8(map, options, input, {false, false});
        EXPECT_TRUE(only.normal.empty());
        EXPECT_TRUE(only.anisotropy.empty());
        EXPECT_EQ(only.metallic_roughness.size(), map.levels.size());
    }
}

TEST(Roughness, FlatMapGivesTheBaseRoughnessAtEveryLevel) {
    const LeanMap map = build_lean_map(slopes_of("flat", 32), BakeOptions{});
    RoughnessOptions options;
    options.base_roughness = 0.5f;
    const std::vector<RoughnessLevel> levels = roughness_mips(map, options);
    ASSERT_EQ(levels.size(), map.levels.size());
    for (const RoughnessLevel& l : levels)
        for (std::size_t t = 0; t < l.alpha.size(); ++t) {
            EXPECT_FLOAT_EQ(l.alpha[t], 0.25f);
            EXPECT_FLOAT_EQ(l.alpha_t[t], 0.25f);
            EXPECT_FLOAT_EQ(l.alpha_b[t], 0.25f);
            EXPECT_EQ(l.normal[t], glm::vec3(0.0f, 0.0f, 1.0f));
        }
    EXPECT_FLOAT_EQ(perceptual_roughness(levels.back().alpha[0]), 0.5f);
}

TEST(Roughness, CoarsestLevelFoldsTheSlopeVariance) {
    const Image slopes = slopes_of("bumps", 64);
    const LeanMap map = build_lean_map(slopes, BakeOptions{});
    RoughnessOptions options;
    options.base_roughness = 0.3f;
    const std::vector<RoughnessLevel> levels = roughness_mips(map, options);
    const glm::dvec3 cov = slope_covariance(slopes);
    const double a0 = std::pow(0.3, 4.0);
    const RoughnessLevel& last = levels.back();
    ASSERT_EQ(last.alpha.size(), 1u);
    EXPECT_NEAR(double(last.alpha[0]) * last.alpha[0], a0 + cov.x + cov.y,
                1e-4 * (a0 + cov.x + cov.y));
    // The anisotropic split keeps the trace: α_t² + α_b² = 2 α0² + 2 (λmax + λmin).
    EXPECT_NEAR(
        double(last.alpha_t[0]) * last.alpha_t[0] + double(last.alpha_b[0]) * last.alpha_b[0],
        2.0 * a0 + 2.0 * (cov.x + cov.y), 1e-4 * (a0 + cov.x + cov.y));
    // Roughness grows from the finest level (one texel's slopes: no covariance) to the coarsest.
    for (std::size_t t = 0; t < levels[0].alpha.size(); ++t)
        EXPECT_NEAR(levels[0].alpha[t], 0.09f, 1e-6f);
    EXPECT_GT(last.alpha[0], 2.0f * levels[0].alpha[0]);
    // The normal is that of the mean slope.
    for (std::size_t l = 0; l < levels.size(); ++l)
        for (std::size_t t = 0; t < levels[l].normal.size(); ++t) {
            const glm::vec2 b = map.levels[l].mean[t];
            const glm::vec3 n = levels[l].normal[t];
            EXPECT_NEAR(glm::length(n), 1.0f, 1e-6f);
            EXPECT_NEAR(n.x / n.z, b.x, 1e-5f);
            EXPECT_NEAR(n.y / n.z, b.y, 1e-5f);
        }
}

TEST(Roughness, RidgesAreAnisotropicAcrossTheRidges) {
    // Ridges run along v: their slopes vary along u (x) only.
    const Image slopes = slopes_of("ridges", 64);
    const LeanMap map = build_lean_map(slopes, BakeOptions{});
    RoughnessOptions options;
    options.base_roughness = 0.2f;
    const RoughnessLevel last = roughness_mips(map, options).back();
    const glm::dvec3 cov = slope_covariance(slopes);
    const double a0 = std::pow(0.2, 4.0);
    EXPECT_GT(cov.x, 0.05);
    EXPECT_LT(std::abs(cov.y), 1e-9);
    EXPECT_NEAR(std::abs(last.direction[0].x), 1.0f, 1e-4f);
    EXPECT_NEAR(double(last.alpha_t[0]) * last.alpha_t[0], a0 + 2.0 * cov.x, 1e-4);
    EXPECT_NEAR(last.alpha_b[0], 0.04f, 1e-4f);
    EXPECT_GT(anisotropy_strength(last.alpha_t[0], last.alpha_b[0]), 0.5f);
    EXPECT_EQ(anisotropy_strength(0.3f, 0.3f), 0.0f);
    EXPECT_EQ(anisotropy_strength(1.0f, 0.0f), 1.0f);
}

TEST(Roughness, RoughnessMapIsFilteredLinearlyInAlphaSquared) {
    const LeanMap map = build_lean_map(slopes_of("flat", 16), BakeOptions{});
    Image r(16, 16, 1);
    double mean_a2 = 0.0;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            const float v = ((x / 4 + y / 4) % 2) ? 0.8f : 0.2f;
            r.at(x, y) = v;
            mean_a2 += std::pow(double(v), 4.0) / 256.0;
        }
    RoughnessOptions options;
    options.roughness_map = &r;
    const std::vector<RoughnessLevel> levels = roughness_mips(map, options);
    EXPECT_NEAR(levels[0].alpha[0], 0.04f, 1e-6f);
    EXPECT_NEAR(double(levels.back().alpha[0]) * levels.back().alpha[0], mean_a2, 1e-6);
    // Level 2 (4x4 texels of 4x4): each texel is one checker cell.
    EXPECT_NEAR(levels[2].alpha[0], 0.04f, 1e-6f);
    EXPECT_NEAR(levels[2].alpha[1], 0.64f, 1e-6f);
}

TEST(Roughness, BadInputsAreErrors) {
    const Image slopes = slopes_of("bumps", 16);
    const LeanMap map = build_lean_map(slopes, BakeOptions{});
    RoughnessOptions options;
    options.base_roughness = 1.5f;
    EXPECT_THROW(roughness_mips(map, options), Error);
    options.base_roughness = std::nanf("");
    EXPECT_THROW(roughness_mips(map, options), Error);
    options.base_roughness = 0.5f;
    Image wrong(8, 8, 1);
    options.roughness_map = &wrong;
    EXPECT_THROW(roughness_mips(map, options), Error);
    Image bad(16, 16, 1);
    bad.at(3, 4) = -0.1f;
    options.roughness_map = &bad;
    try {
        roughness_mips(map, options);
        FAIL() << "a negative roughness must be refused";
    } catch (const Error& e) {
        EXPECT_NE(e.cause().find("(3, 4)"), std::string::npos) << e.what();
    }
    options.roughness_map = nullptr;
    BakeOptions baked;
    baked.bake_roughness_shininess = 64.0f;
    EXPECT_THROW(roughness_mips(build_lean_map(slopes, baked), options), Error);
    EXPECT_THROW(roughness_mips(LeanMap{}, options), Error);
}

// The render-time chain (base_alpha_squared_mips, docs/math.md §9): α0² = r⁴ per texel, each
// level's texel the mean of its 2x2 children (linear in α0², the moments' own box filter).
TEST(Roughness, RenderTimeChainIsTheMeanOfAlphaSquared) {
    Image r(16, 8, 1);
    for (int y = 0; y < r.height; ++y)
        for (int x = 0; x < r.width; ++x) r.at(x, y) = 0.05f + 0.9f * float(x * 8 + y) / 127.0f;
    const std::vector<Image> chain = base_alpha_squared_mips(r);
    ASSERT_EQ(chain.size(), 5u);  // 16x8, 8x4, 4x2, 2x1, 1x1
    for (int y = 0; y < r.height; ++y)
        for (int x = 0; x < r.width; ++x)
            EXPECT_FLOAT_EQ(chain[0].at(x, y), std::pow(r.at(x, y), 4.0f));
    for (std::size_t l = 1; l < chain.size(); ++l) {
        const Image& fine = chain[l - 1];
        const Image& level = chain[l];
        ASSERT_EQ(level.channels, 1);
        ASSERT_EQ(level.width, std::max(1, fine.width / 2));
        ASSERT_EQ(level.height, std::max(1, fine.height / 2));
        for (int y = 0; y < level.height; ++y)
            for (int x = 0; x < level.width; ++x) {
                double mean = 0.0;
                const int ny = fine.height > 1 ? 2 : 1;
                for (int dy = 0; dy < ny; ++dy)
                    for (int dx = 0; dx < 2; ++dx)
                        mean += fine.at(2 * x + dx, 2 * y + dy) / double(2 * ny);
                EXPECT_NEAR(level.at(x, y), mean, 1e-6 * mean) << "level " << l;
            }
    }
    // The mean over the whole map is kept: the coarsest texel is the mean α0², not (mean r)⁴.
    double mean_a2 = 0.0;
    for (float v : r.pixels) mean_a2 += std::pow(double(v), 4.0) / double(r.texel_count());
    EXPECT_NEAR(chain.back().at(0, 0), mean_a2, 1e-6 * mean_a2);
}

// The bake's roughness MIPs with a map take their α0² from the very chain the renderer samples.
TEST(Roughness, BakeAndRenderShareTheAlphaSquaredChain) {
    const LeanMap map = build_lean_map(slopes_of("bumps", 16), BakeOptions{});
    Image r(16, 16, 1);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) r.at(x, y) = x < 8 ? 0.2f : 0.6f;
    RoughnessOptions options;
    options.roughness_map = &r;
    const std::vector<RoughnessLevel> levels = roughness_mips(map, options);
    const std::vector<Image> chain = base_alpha_squared_mips(r);
    ASSERT_EQ(levels.size(), chain.size());
    for (std::size_t l = 0; l < levels.size(); ++l)
        for (std::size_t t = 0; t < levels[l].alpha.size(); ++t) {
            const glm::vec3 sigma = shading::lf_covariance(map.levels[l].mean[t],
                                                           map.levels[l].second[t], 0.0f);
            const float alpha = std::sqrt(chain[l].pixels[t] + std::max(0.0f, sigma.x) +
                                          std::max(0.0f, sigma.y));
            EXPECT_NEAR(levels[l].alpha[t], alpha, 1e-5f) << "level " << l << " texel " << t;
        }
}

// The map's channel: a grey image's first, a glTF metallic-roughness texture's G; values outside
// [0, 1] or NaN are errors naming the texel.
TEST(Roughness, RenderTimeMapChannelAndErrors) {
    Image rgba(2, 1, 4);
    rgba.pixels = {0.9f, 0.25f, 0.1f, 1.0f, 0.0f, 0.75f, 1.0f, 1.0f};
    const Image g = base_roughness_channel(rgba);
    ASSERT_EQ(g.channels, 1);
    EXPECT_EQ(g.pixels, (std::vector<float>{0.25f, 0.75f}));
    Image grey_alpha(2, 1, 2);
    grey_alpha.pixels = {0.3f, 1.0f, 0.4f, 0.0f};
    EXPECT_EQ(base_roughness_channel(grey_alpha).pixels, (std::vector<float>{0.3f, 0.4f}));
    for (float bad : {1.5f, -0.25f, std::nanf("")}) {
        Image r(4, 4, 1, 0.5f);
        r.at(2, 1) = bad;
        try {
            base_alpha_squared_mips(r);
            FAIL() << bad << " must be refused";
        } catch (const Error& e) {
            EXPECT_EQ(e.file(), "roughness map");
            EXPECT_NE(e.cause().find("(2, 1)"), std::string::npos) << e.what();
        }
    }
    EXPECT_THROW(base_alpha_squared_mips(Image{}), Error);
    // The caller's name for the map (its file) is what the errors name.
    Image over(2, 2, 1, 2.0f);
    try {
        base_alpha_squared_mips(over, 0, "rough.exr");
        FAIL() << "2 must be refused";
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), "rough.exr");
    }
}

}  // namespace
}  // namespace leanfade::test
