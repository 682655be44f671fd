#include <gtest/gtest.h>

#include "leanfade/core/error.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/procedural.hpp"

using namespace leanfade;

TEST(Procedural, EverySetIsDeterministicAndSeedDependent) {
    for (const std::string& name : builtin_bump_names()) {
        const Image a = make_builtin_height(name, 64, 42);
        const Image b = make_builtin_height(name, 64, 42);
        EXPECT_EQ(a.pixels, b.pixels) << name;
        if (name == "bumps" || name == "noise" || name == "waves") {
            EXPECT_NE(a.pixels, make_builtin_height(name, 64, 43).pixels) << name;
        }
    }
}

TEST(Procedural, SlopesAreModerateAndIndependentOfSize) {
    for (const std::string& name : builtin_bump_names()) {
        BakeOptions options;
        const auto small = summarize(build_lean_map(
            slopes_from_height(make_builtin_height(name, 128, 1), options).slopes, options));
        const auto large = summarize(build_lean_map(
            slopes_from_height(make_builtin_height(name, 512, 1), options).slopes, options));
        if (name == "flat") {  // the one set without slopes
            EXPECT_EQ(small.max_slope, 0.0f);
            EXPECT_EQ(large.max_slope, 0.0f);
            continue;
        }
        EXPECT_GT(small.mean_slope, 0.02f) << name;
        EXPECT_LT(small.max_slope, 2.5f) << name;
        EXPECT_NEAR(small.mean_slope, large.mean_slope, 0.15f * large.mean_slope) << name;
    }
}

TEST(Procedural, TilesSeamlessly) {
    // The slope across the wrap seam is as smooth as inside: compare the largest jump between
    // neighbouring columns at the seam with the largest jump anywhere.
    for (const std::string& name : builtin_bump_names()) {
        const Image h = make_builtin_height(name, 128, 9);
        float seam = 0.0f, inside = 0.0f;
        for (int y = 0; y < h.height; ++y) {
            seam = std::max(seam, std::abs(h.at(0, y) - h.at(h.width - 1, y)));
            for (int x = 1; x < h.width; ++x)
                inside = std::max(inside, std::abs(h.at(x, y) - h.at(x - 1, y)));
        }
        EXPECT_LE(seam, inside * 1.01f + 1e-6f) << name;
    }
}

TEST(Procedural, UnknownNameAndBadSizeAreErrors) {
    EXPECT_THROW(make_builtin_height("marble", 64), Error);
    EXPECT_THROW(make_builtin_height("bumps", 0), Error);
    EXPECT_THROW(make_builtin_height("bumps", 100000), Error);
}
