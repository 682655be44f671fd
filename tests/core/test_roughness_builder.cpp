// The engine textures made inside the fused bake (RoughnessTextureBuilder fed by bake_packed_to's
// and bake_moments' moment runs, leanfade/core/roughness.hpp) are the textures of the reference
// path, roughness_textures_rgba8(bake_lean_map(...).map), byte for byte, for every source, size,
// thread count and option; the isotropic loops equal the per-texel code.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <set>
#include <tuple>

#include "leanfade/core/detail/bake.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/procedural.hpp"
#include "leanfade/core/roughness.hpp"

namespace leanfade::test {
namespace {

// A 16-bit normal map of a built-in height set, with a few texels the bake repairs when asked:
// (0, 0, 0) padding and a normal pointing below the surface.
UnormImage normal_map(const std::string& set, int width, int height, bool with_repairs) {
    const Image square = make_builtin_height(set, std::max(width, height), 11);
    Image heights(width, height, 1);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) heights.at(x, y) = 4.0f * square.at(x, y);
    const Image slopes = slopes_from_height(heights, BakeOptions{}).slopes;
    UnormImage normals(width, height, 3, 65535);
    for (std::size_t t = 0; t < slopes.texel_count(); ++t) {
        const float bx = slopes.pixels[2 * t], by = slopes.pixels[2 * t + 1];
        const float inv = 1.0f / std::sqrt(bx * bx + by * by + 1.0f);
        const float n[3] = {bx * inv, by * inv, inv};
        for (int c = 0; c < 3; ++c)
            normals.samples[3 * t + std::size_t(c)] =
                std::uint16_t(std::lround((0.5f * n[c] + 0.5f) * 65535.0f));
    }
    if (with_repairs) {
        for (int c = 0; c < 3; ++c) normals.samples[std::size_t(c)] = 0;  // padding at (0, 0)
        normals.samples[3 * 5 + 2] = 100;                                 // z < 0 at (5, 0)
    }
    return normals;
}

// A metallic-roughness texture: distinct values per texel and channel in [0, 1].
Image metallic_roughness_texture(int width, int height) {
    Image mr(width, height, 4);
    for (std::size_t i = 0; i < mr.pixels.size(); ++i)
        mr.pixels[i] = float((i * 7919) % 257) / 256.0f;
    return mr;
}

void expect_same_levels(const std::vector<Rgba8Image>& got, const std::vector<Rgba8Image>& want,
                        const std::string& what) {
    ASSERT_EQ(got.size(), want.size()) << what;
    for (std::size_t l = 0; l < got.size(); ++l) {
        ASSERT_EQ(got[l].width, want[l].width) << what << " level " << l;
        ASSERT_EQ(got[l].height, want[l].height) << what << " level " << l;
        ASSERT_TRUE(got[l].texels == want[l].texels) << what << " level " << l;
    }
}

struct Case {
    int width, height;
    bool height_source;
    bool with_map;
    bool anisotropy;
    int threads;
};

// Every texel of every level reaches the builder exactly once, and the bytes are the reference's.
TEST(RoughnessBuilder, FusedBakeGivesTheReferenceBytes) {
    const std::vector<Case> cases = {
        {64, 64, false, false, false, 2},  {64, 64, false, false, true, 1},
        {37, 20, false, true, false, 2},   {37, 20, false, true, true, 2},
        {96, 48, true, false, false, 2},   {33, 65, true, true, true, 1},
        {256, 256, false, false, false, 2}, {1, 7, false, false, true, 2},
    };
    for (const Case& c : cases) {
        const std::string what = std::to_string(c.width) + "x" + std::to_string(c.height) +
                                 (c.height_source ? " height" : " normal") +
                                 (c.with_map ? " map" : "") + (c.anisotropy ? " aniso" : "") +
                                 " threads " + std::to_string(c.threads);
        BakeOptions options;
        options.threads = c.threads;
        const UnormImage normals = normal_map("bumps", c.width, c.height, !c.height_source);
        UnormImage heights(c.width, c.height, 1, 65535);
        const Image square = make_builtin_height("ridges", std::max(c.width, c.height), 3);
        for (int y = 0; y < c.height; ++y)
            for (int x = 0; x < c.width; ++x)
                heights.samples[std::size_t(y) * std::size_t(c.width) + std::size_t(x)] =
                    std::uint16_t(std::lround(std::clamp(square.at(x, y), 0.0f, 1.0f) * 65535.0f));
        const UnormImage& input = c.height_source ? heights : normals;
        const BakeSource source = c.height_source ? BakeSource::Height : BakeSource::Normal;

        const Image mr = metallic_roughness_texture(c.width, c.height);
        const Image r = base_roughness_channel(mr);
        RoughnessOptions ro;
        ro.base_roughness = 0.3f;
        ro.threads = c.threads;
        if (c.with_map) ro.roughness_map = &r;
        const Image* kept = c.with_map ? &mr : nullptr;
        const RoughnessTextureSet which{true, c.anisotropy};

        const LeanMap map = bake_lean_map(input.to_float(), source, options).map;
        const RoughnessTexturesRgba8 want = roughness_textures_rgba8(map, ro, kept, which);

        // Fed by the LEAN bake (16-bit output) and by the moments-only bake.
        for (const bool packed : {true, false}) {
            RoughnessTextureBuilder builder(c.width, c.height, ro, kept, which);
            std::mutex mutex;
            std::set<std::tuple<int, int, int>> seen;  // (level, y, x) of every run's texels
            bool repeated = false;
            const MomentRunSink sink = [&](const MomentRun& run) {
                builder.add(run);
                std::lock_guard lock(mutex);
                for (int x = run.x; x < run.x + run.count; ++x)
                    repeated = !seen.emplace(run.level, run.y, x).second || repeated;
            };
            if (packed) {
                const PackedBakeResult lean = bake_packed(input.to_float(), source, options,
                                                          Storage::Unorm16, "test", "", sink);
                // The sink changes nothing in the map.
                const PackedBakeResult plain =
                    bake_packed(input.to_float(), source, options, Storage::Unorm16, "test");
                ASSERT_EQ(lean.packed.levels.size(), plain.packed.levels.size()) << what;
                for (std::size_t l = 0; l < lean.packed.levels.size(); ++l) {
                    ASSERT_TRUE(lean.packed.levels[l].lean1 == plain.packed.levels[l].lean1) << what;
                    ASSERT_TRUE(lean.packed.levels[l].lean2 == plain.packed.levels[l].lean2) << what;
                    ASSERT_TRUE(lean.packed.levels[l].plateau == plain.packed.levels[l].plateau)
                        << what;
                }
            } else {
                bake_moments(input, source, options, "", sink);
            }
            EXPECT_FALSE(repeated) << what << ": a texel reached the builder twice";
            std::size_t texels = 0;
            for (const MomentLevel& l : map.levels) texels += l.mean.size();
            EXPECT_EQ(seen.size(), texels) << what;
            const RoughnessTexturesRgba8 got = builder.take();
            expect_same_levels(got.metallic_roughness, want.metallic_roughness, what + " roughness");
            expect_same_levels(got.normal, want.normal, what + " normal");
            expect_same_levels(got.anisotropy, want.anisotropy, what + " anisotropy");
        }
    }
}

// The isotropic loops (no anisotropy texture) give the bytes of the per-texel code that runs when
// the anisotropy texture is made too.
TEST(RoughnessBuilder, IsotropicLoopsEqualThePerTexelCode) {
    const Image slopes = slopes_from_height(make_builtin_height("noise", 45, 2), BakeOptions{}).slopes;
    const LeanMap map = build_lean_map(slopes, BakeOptions{});
    const Image mr = metallic_roughness_texture(45, 45);
    const Image r = base_roughness_channel(mr);
    for (const bool with_map : {false, true}) {
        for (const float base : {0.0f, 0.3f, 1.0f}) {
            RoughnessOptions ro;
            ro.base_roughness = base;
            if (with_map) ro.roughness_map = &r;
            const Image* kept = with_map ? &mr : nullptr;
            const RoughnessTexturesRgba8 iso = roughness_textures_rgba8(map, ro, kept, {true, false});
            const RoughnessTexturesRgba8 all = roughness_textures_rgba8(map, ro, kept, {true, true});
            const std::string what = std::string(with_map ? "map" : "constant ") + std::to_string(base);
            expect_same_levels(iso.metallic_roughness, all.metallic_roughness, what);
            expect_same_levels(iso.normal, all.normal, what);
            EXPECT_TRUE(iso.anisotropy.empty());
        }
    }
}

// Targets: the builder writes each level where it is told (a mapped file's levels), the same
// bytes it keeps without them, and nothing of those textures stays in the builder.
TEST(RoughnessBuilder, WritesIntoTargets) {
    const UnormImage normals = normal_map("bumps", 20, 12, false);
    RoughnessOptions ro;
    ro.base_roughness = 0.5f;
    RoughnessTextureBuilder own(20, 12, ro, nullptr, {true, false});
    bake_moments(normals, BakeSource::Normal, BakeOptions{}, "", own.sink());
    const RoughnessTexturesRgba8 want = own.take();

    std::vector<std::vector<std::uint8_t>> memory;
    RoughnessTextureTargets targets;
    for (const Rgba8Image& level : want.metallic_roughness) {
        memory.emplace_back(level.texels.size(), 0xAB);
        targets.metallic_roughness.push_back(memory.back().data());
    }
    RoughnessTextureBuilder builder(20, 12, ro, nullptr, {true, false}, targets);
    bake_moments(normals, BakeSource::Normal, BakeOptions{}, "", builder.sink());
    const RoughnessTexturesRgba8 kept = builder.take();
    EXPECT_TRUE(kept.metallic_roughness.empty());
    expect_same_levels(kept.normal, want.normal, "normal, no target: kept by the builder");
    for (std::size_t l = 0; l < memory.size(); ++l)
        EXPECT_TRUE(memory[l] == want.metallic_roughness[l].texels) << "level " << l;
    EXPECT_THROW(RoughnessTextureBuilder(20, 12, ro, nullptr, {true, false},
                                         RoughnessTextureTargets{{memory[0].data()}, {}, {}}),
                 std::invalid_argument);
}

// The integer count of repairs equals the float one, at the threshold of "below the surface" too.
TEST(RoughnessBuilder, IntegerRepairCountsEqualTheFloatCounts) {
    for (const std::uint16_t max : {std::uint16_t(255), std::uint16_t(65535)}) {
        UnormImage image(64, 64, 4, max);
        std::uint32_t state = 12345;
        for (std::uint16_t& s : image.samples) {
            state = state * 1664525u + 1013904223u;
            s = std::uint16_t((state >> 8) % (std::uint32_t(max) + 1));
        }
        // Samples around the threshold 2 v - 1 <= -2/255, and padding texels.
        const float edge = (1.0f - 2.0f / 255.0f) * 0.5f * float(max);
        for (int k = 0; k < 40; ++k) {
            const int s = std::clamp(int(edge) - 20 + k, 0, int(max));
            image.samples[4 * std::size_t(k) + 2] = std::uint16_t(s);
        }
        for (int k = 40; k < 50; ++k)
            for (int c = 0; c < 3; ++c) image.samples[4 * std::size_t(k) + std::size_t(c)] = 0;
        const NormalRepairs integer = count_normal_repairs(image);
        const NormalRepairs floats = count_normal_repairs(image.to_float());
        EXPECT_EQ(integer.padding_texels, floats.padding_texels) << max;
        EXPECT_EQ(integer.raised_texels, floats.raised_texels) << max;
        EXPECT_GE(integer.padding_texels, 10u);
        EXPECT_GT(integer.raised_texels, 0u);
    }
}

}  // namespace
}  // namespace leanfade::test
