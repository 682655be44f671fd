// Height or normal? BakeSource::Auto takes 1-2 channels as a height map, 3-4 as a normal map,
// except grey colour images (r = g = b everywhere: a height map saved as RGB, RGBA or palette),
// which are height maps; a normal map refused for z <= 0 (strict_normals) names the setting that
// bakes it as a height map.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "leanfade/core/detail/bake.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/image.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/procedural.hpp"

using namespace leanfade;
using ::testing::HasSubstr;

namespace {

// The height map `height` (1 channel) repeated in r, g and b (and an alpha of `alpha`).
Image as_colour(const Image& height, int channels, float alpha = 1.0f) {
    Image colour(height.width, height.height, channels);
    for (std::size_t i = 0; i < height.texel_count(); ++i) {
        for (int c = 0; c < 3; ++c)
            colour.pixels[i * std::size_t(channels) + std::size_t(c)] = height.pixels[i];
        if (channels == 4) colour.pixels[i * 4 + 3] = alpha;
    }
    return colour;
}

// Integer samples of a float image in [0, 1] (as an 8-bit file, a palette PNG expanded, holds).
UnormImage as_bytes(const Image& image) {
    UnormImage unorm(image.width, image.height, image.channels, 255);
    for (std::size_t i = 0; i < image.pixels.size(); ++i)
        unorm.samples[i] = std::uint16_t(std::lround(image.pixels[i] * 255.0f));
    return unorm;
}

PackedBakeResult bake_unorm(const UnormImage& input, BakeSource source,
                            const std::string& name = "in.png", const BakeOptions& options = {}) {
    PackedLeanMap filled;
    return bake_packed_to(
        [&](const PackedLeanMap& layout) {
            filled = layout;
            std::vector<PackedLevelTarget> targets;
            for (PackedLevel& level : filled.levels) {
                const std::size_t bytes = std::size_t(level.width) * std::size_t(level.height) *
                                          std::size_t(bytes_per_texel(Storage::Unorm16));
                level.lean1.assign(bytes, 0);
                level.lean2.assign(bytes, 0);
                if (layout.has_plateau()) level.plateau.assign(bytes, 0);
                targets.push_back({level.lean1.data(), level.lean2.data(), level.plateau.data()});
            }
            return targets;
        },
        input, source, options, Storage::Unorm16, "test", name);
}

}  // namespace

TEST(BakeSource, GreyColourImagesAreDetected) {
    const Image height = make_builtin_height("noise", 16);
    EXPECT_FALSE(is_grey_colour_image(height));  // one channel: not a colour image
    EXPECT_TRUE(is_grey_colour_image(as_colour(height, 3)));
    EXPECT_TRUE(is_grey_colour_image(as_colour(height, 4, 0.25f)));  // alpha is not compared
    Image tinted = as_colour(height, 3);
    tinted.at(15, 15, 1) += 1e-6f;  // one sample of the last texel
    EXPECT_FALSE(is_grey_colour_image(tinted));
    EXPECT_TRUE(is_grey_colour_image(as_bytes(as_colour(height, 4))));
    UnormImage tinted_bytes = as_bytes(as_colour(height, 3));
    tinted_bytes.samples.back() ^= 1;  // blue of the last texel
    EXPECT_FALSE(is_grey_colour_image(tinted_bytes));
}

TEST(BakeSource, AutoTakesGreyColourImagesAsHeightMaps) {
    const Image height = make_builtin_height("bumps", 32);
    const BakeResult reference = bake_lean_map(height, BakeSource::Height, {}, "h.png");
    for (const int channels : {3, 4}) {
        SCOPED_TRACE(channels);
        const Image colour = as_colour(height, channels);
        EXPECT_EQ(resolve_bake_source(BakeSource::Auto, colour), BakeSource::Height);
        const BakeResult baked = bake_lean_map(colour, BakeSource::Auto, {}, "h.png");
        EXPECT_EQ(baked.source, BakeSource::Height);
        ASSERT_EQ(baked.map.levels.size(), reference.map.levels.size());
        EXPECT_EQ(baked.map.levels[0].mean, reference.map.levels[0].mean);
        EXPECT_EQ(baked.map.levels[0].second, reference.map.levels[0].second);
        // The fused fast path resolves it the same way, to the same bytes.
        const PackedBakeResult fast =
            bake_packed(colour, BakeSource::Auto, {}, Storage::Unorm16, "test", "h.png");
        const PackedBakeResult fast_reference =
            bake_packed(height, BakeSource::Height, {}, Storage::Unorm16, "test", "h.png");
        EXPECT_EQ(fast.source, BakeSource::Height);
        EXPECT_EQ(fast.packed.levels[0].lean1, fast_reference.packed.levels[0].lean1);
        EXPECT_EQ(fast.packed.levels[0].lean2, fast_reference.packed.levels[0].lean2);
    }
}

TEST(BakeSource, AutoTakesGreyIntegerSamplesAsHeightMaps) {
    // 8-bit samples (a grey RGB or palette PNG, as read_image_compact returns them).
    const Image height = make_builtin_height("ridges", 24);
    const UnormImage grey = as_bytes(as_colour(height, 3));
    const UnormImage single = as_bytes(height);
    EXPECT_EQ(resolve_bake_source(BakeSource::Auto, grey), BakeSource::Height);
    const PackedBakeResult baked = bake_unorm(grey, BakeSource::Auto);
    const PackedBakeResult reference = bake_unorm(single, BakeSource::Height);
    EXPECT_EQ(baked.source, BakeSource::Height);
    EXPECT_EQ(baked.packed.scale, reference.packed.scale);
    EXPECT_FLOAT_EQ(baked.summary.mean_slope, reference.summary.mean_slope);
    EXPECT_GT(baked.summary.mean_slope, 0.0f);  // a real height map, not a flat one
}

TEST(BakeSource, ColourNormalMapsStayNormalMapsAndExplicitKindsWin) {
    Image normals(8, 8, 3);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            normals.at(x, y, 0) = 0.5f + 0.02f * float(x);
            normals.at(x, y, 1) = 0.5f;
            normals.at(x, y, 2) = 0.98f;
        }
    EXPECT_EQ(resolve_bake_source(BakeSource::Auto, normals), BakeSource::Normal);
    EXPECT_EQ(bake_lean_map(normals, BakeSource::Auto, {}).source, BakeSource::Normal);
    const Image grey = as_colour(make_builtin_height("noise", 8), 3);
    EXPECT_EQ(resolve_bake_source(BakeSource::Normal, grey), BakeSource::Normal);
    EXPECT_EQ(resolve_bake_source(BakeSource::Height, normals), BakeSource::Height);
}

TEST(BakeSource, NormalRefusedForZBelowZeroSuggestsTheHeightSetting) {
    // A height map with colour (not grey, so Auto keeps it a normal map): dark texels give z < 0.
    Image coloured(4, 4, 3);
    for (std::size_t i = 0; i < coloured.texel_count(); ++i) {
        coloured.pixels[3 * i + 0] = 0.2f;
        coloured.pixels[3 * i + 1] = 0.3f;
        coloured.pixels[3 * i + 2] = 0.1f;  // z = -0.8
    }
    const auto expect_hint = [](const auto& bake) {
        try {
            bake();
            FAIL() << "expected an error";
        } catch (const Error& error) {
            EXPECT_EQ(error.file(), "dark.png");
            EXPECT_THAT(error.cause(), HasSubstr("normal with z <= 0 at texel (0, 0)"));
            EXPECT_THAT(error.cause(), HasSubstr("refused by 'strict_normals'"));
            EXPECT_THAT(error.cause(),
                        HasSubstr("a height map stored as colour? read it with 'from' height"));
        }
    };
    BakeOptions strict;
    strict.strict_normals = true;
    expect_hint([&] { bake_lean_map(coloured, BakeSource::Auto, strict, "dark.png"); });
    expect_hint([&] {
        bake_packed(coloured, BakeSource::Auto, strict, Storage::Unorm16, "test", "dark.png");
    });
    expect_hint([&] { bake_unorm(as_bytes(coloured), BakeSource::Auto, "dark.png", strict); });
    // Without strict_normals every texel is raised, and counted.
    EXPECT_EQ(bake_lean_map(coloured, BakeSource::Auto, {}, "dark.png").map.normal_repairs
                  .raised_texels,
              16u);
    EXPECT_EQ(bake_unorm(as_bytes(coloured), BakeSource::Auto).packed.normal_repairs.raised_texels,
              16u);
    // As a height map it bakes.
    EXPECT_EQ(bake_lean_map(coloured, BakeSource::Height, {}, "dark.png").source,
              BakeSource::Height);
}

namespace {

// An 8-bit-exact normal map of gentle bumps (k / 255 values), 24 x 20.
Image bumpy_normals() {
    Image normals(24, 20, 3);
    for (int y = 0; y < normals.height; ++y)
        for (int x = 0; x < normals.width; ++x) {
            normals.at(x, y, 0) = float(128 + (x * 7 + y * 3) % 41 - 20) / 255.0f;
            normals.at(x, y, 1) = float(128 + (x * 5 + y * 11) % 37 - 18) / 255.0f;
            normals.at(x, y, 2) = 250.0f / 255.0f;
        }
    return normals;
}

void expect_same_bytes(const PackedLeanMap& a, const PackedLeanMap& b) {
    ASSERT_EQ(a.levels.size(), b.levels.size());
    EXPECT_EQ(a.scale, b.scale);
    for (std::size_t l = 0; l < a.levels.size(); ++l) {
        EXPECT_TRUE(a.levels[l].lean1 == b.levels[l].lean1) << "level " << l;
        EXPECT_TRUE(a.levels[l].lean2 == b.levels[l].lean2) << "level " << l;
    }
}

}  // namespace

// Real assets: (0, 0, 0) padding outside the UV islands is taken as flat, texels slightly below
// the surface are raised; each counted, and the map is exactly the one of the repaired image, in
// every bake (reference, fast path from floats, fast path from integer samples).
TEST(BakeSource, PaddingIsFlatAndNegativeZRaisedUnlessStrict) {
    Image padded = bumpy_normals();
    Image repaired = padded;
    std::uint64_t padding = 0;
    for (int y = 0; y < padded.height; ++y)
        for (int x = 0; x < padded.width; ++x)
            if (x < 3 || y >= 16) {  // a border of padding, as a baker leaves it
                for (int c = 0; c < 3; ++c) padded.at(x, y, c) = 0.0f;
                repaired.at(x, y, 0) = repaired.at(x, y, 1) = 0.5f;
                repaired.at(x, y, 2) = 1.0f;
                ++padding;
            }
    // Two authored texels below the surface (z = -0.1 and -0.02), one exactly at the reject
    // threshold's other side (z = -1/255: an 8-bit 0, raised by the bake as before, not counted).
    padded.at(10, 5, 2) = repaired.at(10, 5, 2) = 115.0f / 255.0f;
    padded.at(11, 6, 2) = repaired.at(11, 6, 2) = 125.0f / 255.0f;
    padded.at(12, 7, 2) = repaired.at(12, 7, 2) = 127.0f / 255.0f;
    repaired.at(10, 5, 2) = repaired.at(11, 6, 2) = 0.5f;

    const BakeResult reference = bake_lean_map(padded, BakeSource::Auto, {}, "padded.png");
    EXPECT_EQ(reference.source, BakeSource::Normal);
    EXPECT_EQ(reference.map.normal_repairs.padding_texels, padding);
    EXPECT_EQ(reference.map.normal_repairs.raised_texels, 2u);
    EXPECT_EQ(reference.clamped_texels, 3u);  // the two raised ones and the z = -1/255 one
    const PackedLeanMap expected =
        bake_packed(repaired, BakeSource::Normal, {}, Storage::Unorm16, "test").packed;
    EXPECT_FALSE(expected.normal_repairs.any());
    const PackedLeanMap from_reference = pack_lean_map(reference.map, Storage::Unorm16, "test");
    EXPECT_EQ(from_reference.normal_repairs.padding_texels, padding);
    expect_same_bytes(from_reference, expected);
    const PackedBakeResult fast =
        bake_packed(padded, BakeSource::Auto, {}, Storage::Unorm16, "test", "padded.png");
    EXPECT_EQ(fast.packed.normal_repairs.padding_texels, padding);
    EXPECT_EQ(fast.packed.normal_repairs.raised_texels, 2u);
    EXPECT_EQ(fast.clamped_texels, 3u);
    expect_same_bytes(fast.packed, expected);
    const PackedBakeResult integers = bake_unorm(as_bytes(padded), BakeSource::Auto);
    EXPECT_EQ(integers.packed.normal_repairs.padding_texels, padding);
    EXPECT_EQ(integers.packed.normal_repairs.raised_texels, 2u);
    // The flat texels are flat: B = 0 at a padding texel of the top level, within one code of
    // 16-bit UNORM (2 sc / 65535).
    const LeanMap unpacked = unpack_lean_map(fast.packed);
    const float code = 2.0f * fast.packed.scale / 65535.0f;
    EXPECT_NEAR(unpacked.levels[0].mean[std::size_t(18 * 24 + 1)].x, 0.0f, code);
    EXPECT_NEAR(unpacked.levels[0].mean[std::size_t(18 * 24 + 1)].y, 0.0f, code);

    // strict_normals refuses the first such texel (rows top first: (0, 0), a padding texel).
    BakeOptions strict;
    strict.strict_normals = true;
    for (const auto& bake : std::vector<std::function<void()>>{
             [&] { bake_lean_map(padded, BakeSource::Auto, strict, "padded.png"); },
             [&] {
                 bake_packed(padded, BakeSource::Auto, strict, Storage::Unorm16, "t",
                             "padded.png");
             },
             [&] { bake_unorm(as_bytes(padded), BakeSource::Auto, "padded.png", strict); }}) {
        try {
            bake();
            ADD_FAILURE() << "expected an error";
        } catch (const Error& error) {
            EXPECT_EQ(error.file(), "padded.png");
            EXPECT_THAT(error.cause(), HasSubstr("normal with z <= 0 at texel (0, 0)"));
        }
    }
    // A map with nothing to repair is baked as before, with nothing counted.
    const PackedBakeResult clean =
        bake_packed(bumpy_normals(), BakeSource::Auto, {}, Storage::Unorm16, "test");
    EXPECT_FALSE(clean.packed.normal_repairs.any());
    expect_same_bytes(clean.packed, bake_packed(bumpy_normals(), BakeSource::Auto, strict,
                                                Storage::Unorm16, "test")
                                        .packed);
}
