#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/procedural.hpp"
#include "leanfade/core/shading.hpp"
#include "test_helpers.hpp"

using namespace leanfade;

namespace {

LeanMap bake_height(const Image& height, BakeOptions options = {}) {
    return build_lean_map(slopes_from_height(height, options).slopes, options);
}

// Mean of each moment over a level, in double.
struct LevelMeans {
    double n[3] = {0, 0, 0}, b[2] = {0, 0}, m[3] = {0, 0, 0};
};
LevelMeans means(const MomentLevel& level) {
    LevelMeans r;
    const double count = double(level.normal.size());
    for (std::size_t i = 0; i < level.normal.size(); ++i) {
        for (int c = 0; c < 3; ++c) r.n[c] += level.normal[i][c] / count;
        for (int c = 0; c < 2; ++c) r.b[c] += level.mean[i][c] / count;
        for (int c = 0; c < 3; ++c) r.m[c] += level.second[i][c] / count;
    }
    return r;
}

}  // namespace

TEST(LeanMap, LevelCountAndSizesFollowOpenGL) {
    EXPECT_EQ(mip_level_count(1, 1), 1);
    EXPECT_EQ(mip_level_count(1024, 1024), 11);
    EXPECT_EQ(mip_level_count(37, 20), 6);  // 37x20 18x10 9x5 4x2 2x1 1x1
    const LeanMap map = bake_height(Image(37, 20, 1));
    ASSERT_EQ(map.levels.size(), 6u);
    const int expected[6][2] = {{37, 20}, {18, 10}, {9, 5}, {4, 2}, {2, 1}, {1, 1}};
    for (int i = 0; i < 6; ++i) {
        EXPECT_EQ(map.levels[std::size_t(i)].width, expected[i][0]);
        EXPECT_EQ(map.levels[std::size_t(i)].height, expected[i][1]);
    }
}

TEST(LeanMap, MomentsAreLinearEveryLevelMeanEqualsTheTopMean) {
    // Odd, non-square sizes exercise the 3-tap reduction. Every level keeps the top level's mean
    // (area-weighted filter), so the 1x1 level is the mean of the top: float precision, 1e-6.
    for (auto [w, h] : {std::pair{37, 23}, std::pair{64, 64}, std::pair{129, 5}, std::pair{1, 9}}) {
        const Image height = test::height_from(w, h, [](double x, double y) {
            return 3 * std::sin(x * 0.37) + 2 * std::cos(y * 0.23 + x * 0.11);
        });
        const LeanMap map = bake_height(height);
        const LevelMeans top = means(map.levels.front());
        for (const MomentLevel& level : map.levels) {
            const LevelMeans l = means(level);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(l.n[c], top.n[c], 1e-6) << w << "x" << h;
            for (int c = 0; c < 2; ++c) EXPECT_NEAR(l.b[c], top.b[c], 1e-6) << w << "x" << h;
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(l.m[c], top.m[c], 1e-6) << w << "x" << h;
        }
    }
}

TEST(LeanMap, CovarianceIsPositiveSemiDefiniteEverywhere) {
    for (const std::string& name : builtin_bump_names()) {
        const LeanMap map = bake_height(make_builtin_height(name, 64, 7));
        for (const MomentLevel& level : map.levels) {
            for (std::size_t i = 0; i < level.mean.size(); ++i) {
                const glm::vec3 s = shading::lf_covariance(level.mean[i], level.second[i], 0.0f);
                // Cauchy-Schwarz holds for averages of outer products; allow float rounding
                // relative to the magnitudes involved.
                const float tol = 1e-5f * (level.second[i].x + level.second[i].y + 1e-3f);
                EXPECT_GE(s.x, -tol) << name;
                EXPECT_GE(s.y, -tol) << name;
                EXPECT_GE(s.x * s.y - s.z * s.z, -tol * tol - tol * (s.x + s.y)) << name;
            }
        }
    }
}

TEST(LeanMap, FlatMapHasZeroMeanAndOnlyTheBakedRoughness) {
    BakeOptions options;
    options.bake_roughness_shininess = 256.0f;
    const LeanMap map = bake_height(Image(16, 8, 1, 0.25f), options);
    EXPECT_TRUE(map.roughness_baked);
    for (const MomentLevel& level : map.levels)
        for (std::size_t i = 0; i < level.mean.size(); ++i) {
            EXPECT_EQ(level.mean[i], glm::vec2(0.0f));
            const glm::vec3 s = shading::lf_covariance(level.mean[i], level.second[i], 0.0f);
            EXPECT_FLOAT_EQ(s.x, 1.0f / 256.0f);
            EXPECT_FLOAT_EQ(s.y, 1.0f / 256.0f);
            EXPECT_FLOAT_EQ(s.z, 0.0f);
        }
}

TEST(LeanMap, PureTiltHasZeroCovarianceAtEveryLevel) {
    // h = 0.3 x + 0.2 row on a clamped border: every texel has the same slope.
    BakeOptions options;
    options.wrap = Wrap::Clamp;
    Image slopes(23, 17, 2);
    for (int y = 0; y < 17; ++y)
        for (int x = 0; x < 23; ++x) {
            slopes.at(x, y, 0) = 0.3f;
            slopes.at(x, y, 1) = -0.2f;
        }
    const LeanMap map = build_lean_map(slopes, options);
    for (const MomentLevel& level : map.levels)
        for (std::size_t i = 0; i < level.mean.size(); ++i) {
            const glm::vec3 s = shading::lf_covariance(level.mean[i], level.second[i], 0.0f);
            EXPECT_NEAR(s.x, 0.0f, 1e-7f);
            EXPECT_NEAR(s.y, 0.0f, 1e-7f);
            EXPECT_NEAR(s.z, 0.0f, 1e-7f);
            EXPECT_NEAR(level.mean[i].x, 0.3f, 1e-6f);
        }
}

TEST(LeanMap, RidgeVarianceMatchesAnalyticValue) {
    // h = A sin(2 pi x / lambda): Bx = -A w cos(w x) with w = 2 pi / lambda, so over whole periods
    // Var(Bx) = A^2 w^2 / 2 and Syy = Sxy = 0. The Sobel/8 estimate of the derivative of a
    // sinusoid is A sin(w) cos(w x): exactly (sin(w)/w)^2 of the continuous variance.
    const int n = 256;
    const RidgeParameters ridge = ridge_parameters(n);
    const Image height = make_builtin_height("ridges", n);
    const LeanMap map = bake_height(height);
    const MomentLevel& coarsest = map.levels.back();
    const glm::vec3 s = shading::lf_covariance(coarsest.mean[0], coarsest.second[0], 0.0f);
    const double w = 2 * std::numbers::pi / ridge.wavelength;
    const double continuous = ridge.amplitude * ridge.amplitude * w * w / 2;
    const double discrete = continuous * std::pow(std::sin(w) / w, 2);
    EXPECT_NEAR(s.x, discrete, 1e-5 * continuous);
    // Wavelength 16: (sin(w)/w)^2 = 0.950, so the continuous value is within 6%.
    EXPECT_NEAR(s.x, continuous, 0.06 * continuous);
    EXPECT_NEAR(s.y, 0.0, 1e-7);
    EXPECT_NEAR(s.z, 0.0, 1e-7);
}

TEST(LeanMap, ScaleBoundsEveryPackedChannel) {
    BakeOptions options;
    options.bake_roughness_shininess = 2.0f;  // 1/s large compared with the slopes
    const LeanMap map = bake_height(make_builtin_height("bumps", 64, 3), options);
    const float sc = map.scale, sc2 = sc * sc;
    for (const MomentLevel& level : map.levels)
        for (std::size_t i = 0; i < level.mean.size(); ++i) {
            EXPECT_LE(std::abs(level.mean[i].x), sc);
            EXPECT_LE(std::abs(level.mean[i].y), sc);
            EXPECT_LE(level.second[i].x, sc2);
            EXPECT_LE(level.second[i].y, sc2);
            EXPECT_LE(std::abs(level.second[i].z), sc2);
        }
}

TEST(LeanMap, NormalIsAveragedNotRenormalised) {
    const LeanMap map = bake_height(make_builtin_height("bumps", 64, 1));
    const glm::vec3 n = map.levels.back().normal[0];
    EXPECT_LT(glm::length(n), 0.999f);  // bumpy: shorter than unit
    EXPECT_GT(n.z, 0.5f);
    for (const glm::vec3& t : map.levels.front().normal) EXPECT_NEAR(glm::length(t), 1.0f, 1e-5f);
}

TEST(LeanMap, ThreadCountDoesNotChangeResults) {
    const Image height = make_builtin_height("noise", 96, 5);
    BakeOptions one, two;
    one.threads = 1;
    two.threads = 2;
    const LeanMap a = bake_height(height, one), b = bake_height(height, two);
    ASSERT_EQ(a.levels.size(), b.levels.size());
    EXPECT_EQ(a.scale, b.scale);
    for (std::size_t l = 0; l < a.levels.size(); ++l) {
        EXPECT_EQ(a.levels[l].normal, b.levels[l].normal);
        EXPECT_EQ(a.levels[l].mean, b.levels[l].mean);
        EXPECT_EQ(a.levels[l].second, b.levels[l].second);
    }
}

TEST(LeanMap, SummaryReportsSlopesAndAnisotropy) {
    const LeanMap ridges = bake_height(make_builtin_height("ridges", 128));
    const LeanMapSummary s = summarize(ridges);
    EXPECT_EQ(s.width, 128);
    EXPECT_EQ(s.levels, 8);
    EXPECT_NEAR(s.max_slope, 0.5f * std::sin(2 * std::numbers::pi / 8) / (2 * std::numbers::pi / 8), 0.01f);
    EXPECT_TRUE(std::isinf(s.coarsest_anisotropy) || s.coarsest_anisotropy > 100.0f);
    const LeanMapSummary b = summarize(bake_height(make_builtin_height("bumps", 128)));
    EXPECT_LT(b.coarsest_anisotropy, 2.0f);
    EXPECT_GT(b.coarsest_covariance.x, 0.0f);
}
