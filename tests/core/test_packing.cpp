#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/procedural.hpp"

using namespace leanfade;

namespace {

LeanMap bumps_map(int size, float bake_s = 0.0f) {
    BakeOptions options;
    options.bake_roughness_shininess = bake_s;
    return build_lean_map(
        slopes_from_height(make_builtin_height("bumps", size, 11), options).slopes, options);
}

// Largest unpacking error allowed per channel: half a quantisation step of the packed value,
// times the unpack scale (2 sc for B, sc^2 for Mxx/Myy, 2 sc^2 for Mxy, 2 for n).
struct Bound { float n, b, mdiag, mxy; };
Bound bound_for(Storage storage, float sc, float max_value) {
    float step = 0.0f;
    switch (storage) {
        case Storage::Unorm8: step = 0.5f / 255.0f; break;
        case Storage::Unorm16: step = 0.5f / 65535.0f; break;
        case Storage::Float16: step = std::ldexp(1.0f, -11) * max_value; break;  // 11-bit mantissa
        case Storage::Float32: step = std::ldexp(1.0f, -24) * max_value; break;
    }
    // Float arithmetic in pack and unpack adds a few ulps of the unit range on top.
    step = step * 1.01f + 4e-7f;
    return {2 * step, 2 * sc * step, sc * sc * step, 2 * sc * sc * step};
}

}  // namespace

TEST(Packing, RoundTripWithinQuantisationForEveryStorage) {
    const LeanMap map = bumps_map(48, 512.0f);
    for (Storage storage :
         {Storage::Unorm8, Storage::Unorm16, Storage::Float16, Storage::Float32}) {
        const PackedLeanMap packed = pack_lean_map(map, storage, "test");
        ASSERT_EQ(packed.levels.size(), map.levels.size());
        const LeanMap back = unpack_lean_map(packed);
        const Bound bound = bound_for(storage, map.scale, 1.0f);
        for (std::size_t l = 0; l < map.levels.size(); ++l) {
            const MomentLevel& a = map.levels[l];
            const MomentLevel& b = back.levels[l];
            ASSERT_EQ(packed.levels[l].lean1.size(),
                      a.normal.size() * std::size_t(bytes_per_texel(storage)));
            for (std::size_t i = 0; i < a.normal.size(); ++i) {
                for (int c = 0; c < 3; ++c) EXPECT_NEAR(b.normal[i][c], a.normal[i][c], bound.n);
                for (int c = 0; c < 2; ++c) EXPECT_NEAR(b.mean[i][c], a.mean[i][c], bound.b);
                EXPECT_NEAR(b.second[i].x, a.second[i].x, bound.mdiag) << to_string(storage);
                EXPECT_NEAR(b.second[i].y, a.second[i].y, bound.mdiag) << to_string(storage);
                EXPECT_NEAR(b.second[i].z, a.second[i].z, bound.mxy) << to_string(storage);
            }
        }
        EXPECT_TRUE(back.roughness_baked);
        EXPECT_EQ(back.baked_shininess, 512.0f);
    }
}

TEST(Packing, PackedValuesNeverLeaveTheUnitRange) {
    // sc is chosen so that no packed channel overflows [0, 1]: check on float storage, where
    // nothing is clamped, over every level of every built-in set.
    for (const std::string& name : builtin_bump_names()) {
        BakeOptions options;
        const LeanMap map = build_lean_map(
            slopes_from_height(make_builtin_height(name, 64, 2), options).slopes, options);
        const PackedLeanMap packed = pack_lean_map(map, Storage::Float32, "test");
        for (std::size_t l = 0; l < packed.levels.size(); ++l)
            for (int y = 0; y < packed.levels[l].height; ++y)
                for (int x = 0; x < packed.levels[l].width; ++x)
                    for (int slice = 0; slice < 2; ++slice) {
                        const glm::vec4 t = fetch_packed_texel(packed, int(l), slice, x, y);
                        for (int c = 0; c < 4; ++c) {
                            EXPECT_GE(t[c], 0.0f) << name;
                            EXPECT_LE(t[c], 1.0f) << name;
                        }
                    }
    }
}

TEST(Packing, PackingIsAffineSoFilteringCommutesWithIt) {
    // Averaging packed texels equals packing the averaged moments (what lets hardware trilinear
    // filtering stand in for filtering the moments, docs/math.md §3).
    const LeanMap map = bumps_map(8);
    const PackedLeanMap packed = pack_lean_map(map, Storage::Float32, "test");
    for (int slice = 0; slice < 2; ++slice) {
        const glm::vec4 avg = 0.25f * (fetch_packed_texel(packed, 0, slice, 0, 0) +
                                      fetch_packed_texel(packed, 0, slice, 1, 0) +
                                      fetch_packed_texel(packed, 0, slice, 0, 1) +
                                      fetch_packed_texel(packed, 0, slice, 1, 1));
        const glm::vec4 coarse = fetch_packed_texel(packed, 1, slice, 0, 0);
        for (int c = 0; c < 4; ++c) EXPECT_NEAR(avg[c], coarse[c], 1e-6f);
    }
}

TEST(Packing, UnormCodesAreTheSpecValuesRoundedToNearest) {
    // UNORM packing is one multiply-add per channel (detail::unorm_texel); whatever the float
    // rounding, each code must be the docs/math.md §3 value times Q rounded to the nearest integer
    // (computed here in double), ties to even, clamped to [0, Q], NaN to 0.
    for (const float sc : {0.37f, 1.0f, 3.9f}) {
        LeanMap map;
        map.scale = sc;
        MomentLevel level;
        const int count = 4001;
        level.width = count;
        level.height = 1;
        for (int i = 0; i < count; ++i) {
            const float t = float(i) / float(count - 1);  // [0, 1]
            const float b = sc * (2.0f * t - 1.0f);     // [-sc, sc]
            const float angle = 6.2831853f * t;
            level.normal.push_back({0.6f * std::cos(angle), 0.6f * std::sin(angle), 0.8f});
            level.mean.push_back({b, -0.5f * b});
            level.second.push_back({sc * sc * t, sc * sc * (1.0f - t), b * sc * 0.9f});
        }
        map.levels.push_back(level);
        for (const Storage storage : {Storage::Unorm8, Storage::Unorm16}) {
            const double q = storage == Storage::Unorm8 ? 255.0 : 65535.0;
            const PackedLeanMap packed = pack_lean_map(map, storage, "test");
            const double s = sc, s2 = double(sc) * double(sc);
            // The float multiply-adds (and sc^2 and the factors rounded to float) move a value
            // by a few float ulps of Q: at most 4e-7 Q.
            const double slack = 4e-7 * q;
            int exact_checks = 0;
            for (int i = 0; i < count; ++i) {
                const glm::vec3 n = level.normal[std::size_t(i)];
                const glm::vec2 b = level.mean[std::size_t(i)];
                const glm::vec3 m = level.second[std::size_t(i)];
                const double spec[2][4] = {
                    {0.5 * n.x + 0.5, 0.5 * n.y + 0.5, 0.5 * n.z + 0.5, 0.5 * m.z / s2 + 0.5},
                    {0.5 * b.x / s + 0.5, 0.5 * b.y / s + 0.5, m.x / s2, m.y / s2}};
                for (int slice = 0; slice < 2; ++slice) {
                    const glm::vec4 got = fetch_packed_texel(packed, 0, slice, i, 0);
                    for (int c = 0; c < 4; ++c) {
                        const double code = std::round(double(got[c]) * q);
                        const double want = spec[slice][c] * q;
                        ASSERT_LE(std::abs(code - want), 0.5 + slack)
                            << to_string(storage) << " sc " << sc << " texel " << i;
                        if (std::abs(want - std::floor(want) - 0.5) > slack) {
                            ASSERT_EQ(code, std::round(want)) << to_string(storage) << " " << i;
                            ++exact_checks;
                        }
                    }
                }
            }
            EXPECT_GT(exact_checks, 8 * count * 3 / 4);
        }
    }

    // B = 0 and Mxy = 0 land exactly on Q/2 = k + 0.5 with k odd (where both tie rules round
    // up); out-of-range values clamp, NaN is 0.
    LeanMap map;
    map.scale = 2.0f;
    MomentLevel level;
    level.width = 3;
    level.height = 1;
    level.normal = {{0.0f, 0.0f, 1.0f}, {2.0f, -2.0f, 1.0f}, {NAN, 0.0f, 1.0f}};
    level.mean = {{0.0f, 0.0f}, {9.0f, -9.0f}, {0.0f, NAN}};
    level.second = {{0.0f, 0.0f, 0.0f}, {-1.0f, 100.0f, 100.0f}, {NAN, 1.0f, 0.0f}};
    map.levels.push_back(level);
    const PackedLeanMap p16 = pack_lean_map(map, Storage::Unorm16, "test");
    const PackedLeanMap p8 = pack_lean_map(map, Storage::Unorm8, "test");
    auto code16 = [&](int slice, int x, int c) {
        return std::lround(fetch_packed_texel(p16, 0, slice, x, 0)[c] * 65535.0f);
    };
    auto code8 = [&](int slice, int x, int c) {
        return std::lround(fetch_packed_texel(p8, 0, slice, x, 0)[c] * 255.0f);
    };
    EXPECT_EQ(code16(0, 0, 0), 32768);  // n.x = 0: 32767.5
    EXPECT_EQ(code16(0, 0, 3), 32768);  // Mxy = 0
    EXPECT_EQ(code16(1, 0, 0), 32768);  // B.x = 0
    EXPECT_EQ(code8(1, 0, 0), 128);     // 127.5
    EXPECT_EQ(code16(0, 0, 2), 65535);  // n.z = 1
    EXPECT_EQ(code16(0, 1, 0), 65535);  // n.x = 2 clamps
    EXPECT_EQ(code16(0, 1, 1), 0);      // n.y = -2 clamps
    EXPECT_EQ(code16(1, 1, 0), 65535);  // B.x = 4.5 sc
    EXPECT_EQ(code8(1, 1, 1), 0);       // B.y = -4.5 sc
    EXPECT_EQ(code16(1, 1, 2), 0);      // Mxx < 0
    EXPECT_EQ(code8(1, 1, 3), 255);     // Myy = 25 sc^2
    EXPECT_EQ(code16(0, 2, 0), 0);      // NaN
    EXPECT_EQ(code16(1, 2, 1), 0);
    EXPECT_EQ(code8(1, 2, 2), 0);

    // Ties with an even k go down, which tells ties-to-even from half-away-from-zero: with
    // sc = Q/2 the B factor is exactly 1, so B = 1 gives Q/2 + 1 = k + 0.5, k = (Q + 1)/2 even.
    for (const Storage storage : {Storage::Unorm8, Storage::Unorm16}) {
        const float q = storage == Storage::Unorm8 ? 255.0f : 65535.0f;
        LeanMap ties;
        ties.scale = 0.5f * q;
        MomentLevel one;
        one.width = 1;
        one.height = 1;
        one.normal = {{0.0f, 0.0f, 1.0f}};
        one.mean = {{1.0f, -1.0f}};
        one.second = {{0.0f, 0.0f, 0.0f}};
        ties.levels.push_back(one);
        const glm::vec4 lean2 =
            fetch_packed_texel(pack_lean_map(ties, storage, "test"), 0, 1, 0, 0);
        EXPECT_EQ(std::lround(lean2.x * q), std::lround(0.5f * (q + 1.0f))) << to_string(storage);
        EXPECT_EQ(std::lround(lean2.y * q), std::lround(0.5f * (q - 3.0f))) << to_string(storage);
    }
}

// ---- sc with outliers (docs/ktx2.md, "Choosing storage and sc") -------------------------------

namespace {

// Gentle bumps (slopes well below 1) as a 3-channel normal map of `size`^2 texels, with `outliers`
// texels turned into a normal along +x at the horizon (z = 0, raised to 1/64: slope 64).
Image normal_map_with_outliers(int size, int outliers) {
    const Image height = make_builtin_height("bumps", size, 3);
    BakeOptions gentle;
    gentle.strength = 0.5f;
    const Image slopes = slopes_from_height(height, gentle).slopes;
    Image normals(size, size, 3);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const float bx = slopes.at(x, y, 0), by = slopes.at(x, y, 1);
            const float inv = 1.0f / std::sqrt(bx * bx + by * by + 1.0f);
            normals.at(x, y, 0) = 0.5f * bx * inv + 0.5f;
            normals.at(x, y, 1) = 0.5f * by * inv + 0.5f;
            normals.at(x, y, 2) = 0.5f * inv + 0.5f;
        }
    for (int i = 0; i < outliers; ++i) {
        const int x = (7 + 37 * i) % size, y = (11 + 53 * i) % size;
        normals.at(x, y, 0) = 1.0f;
        normals.at(x, y, 1) = 0.5f;
        normals.at(x, y, 2) = 0.5f;
    }
    return normals;
}

float max_abs_slope(const LeanMap& map) {
    float m = 0.0f;
    for (const glm::vec2 b : map.levels.front().mean)
        m = std::max({m, std::abs(b.x), std::abs(b.y)});
    return m;
}

}  // namespace

TEST(ScaleChoice, AFewTexelsFarSteeperThanTheRestAreLeftBeyondSc) {
    const Image normals = normal_map_with_outliers(64, 2);  // 2 of 4096 texels <= 0.1 %
    const BakeResult result = bake_lean_map(normals, BakeSource::Normal, BakeOptions{});
    const LeanMap& map = result.map;
    EXPECT_EQ(map.texels_beyond_scale, 2u);
    // sc covers every other texel and is far below the outliers' slope 64.
    float rest = 0.0f;
    for (const glm::vec2 b : map.levels.front().mean) {
        const float steepest = std::max(std::abs(b.x), std::abs(b.y));
        if (steepest < 32.0f) rest = std::max(rest, steepest);
    }
    EXPECT_GE(map.scale, rest);
    // A histogram bin edge (4 per octave) at most 19 % above the rest, or the floor max / 128.
    EXPECT_LE(map.scale, std::max(1.1893f * rest, 64.0f / 128.0f) * 1.0001f);
    EXPECT_LT(map.scale, 64.0f / 2.0f);
    // With sc = the maximum nothing is beyond it.
    BakeOptions all_within;
    all_within.scale_excludes_outliers = false;
    const LeanMap max_map = bake_lean_map(normals, BakeSource::Normal, all_within).map;
    EXPECT_EQ(max_map.texels_beyond_scale, 0u);
    EXPECT_GE(max_map.scale, max_abs_slope(max_map));
}

TEST(ScaleChoice, ManySteepTexelsOrASmallGainKeepTheMaximum) {
    // 10 outliers of 4096 (0.24 %) are too many to leave beyond sc.
    const LeanMap many = bake_lean_map(normal_map_with_outliers(64, 10), BakeSource::Normal,
                                       BakeOptions{})
                             .map;
    EXPECT_EQ(many.texels_beyond_scale, 0u);
    EXPECT_GE(many.scale, max_abs_slope(many));
    // A plain bump map: its steepest texels are not twice as steep as the 99.9th percentile.
    const LeanMap plain = bumps_map(96);
    EXPECT_EQ(plain.texels_beyond_scale, 0u);
    EXPECT_GE(plain.scale, max_abs_slope(plain));
}

TEST(ScaleChoice, UnormClampsTexelsBeyondScAndTheFastPathGivesTheSameBytes) {
    const Image normals = normal_map_with_outliers(64, 3);
    const BakeResult reference = bake_lean_map(normals, BakeSource::Normal, BakeOptions{});
    ASSERT_EQ(reference.map.texels_beyond_scale, 3u);
    for (Storage storage :
         {Storage::Unorm8, Storage::Unorm16, Storage::Float16, Storage::Float32}) {
        const PackedLeanMap packed = pack_lean_map(reference.map, storage, "test");
        for (bool simd : {false, true}) {
            const bool previous = set_bake_simd(simd);
            const PackedBakeResult fast =
                bake_packed(normals, BakeSource::Normal, BakeOptions{}, storage, "test");
            set_bake_simd(previous);
            EXPECT_EQ(fast.texels_beyond_scale, 3u);
            EXPECT_EQ(fast.packed.scale, packed.scale);
            for (std::size_t l = 0; l < packed.levels.size(); ++l) {
                EXPECT_EQ(fast.packed.levels[l].lean1, packed.levels[l].lean1)
                    << to_string(storage) << " level " << l << " simd " << simd;
                EXPECT_EQ(fast.packed.levels[l].lean2, packed.levels[l].lean2)
                    << to_string(storage) << " level " << l << " simd " << simd;
            }
        }
        // An outlier's slope 64 lies beyond sc: UNORM stores the largest code, float the value.
        const int x = 7, y = 11;
        const glm::vec4 lean2 = fetch_packed_texel(packed, 0, 1, x, y);
        const float expected_bx = reference.map.levels[0].mean[std::size_t(y * 64 + x)].x;
        ASSERT_GT(expected_bx, 32.0f);
        if (storage == Storage::Unorm8 || storage == Storage::Unorm16) {
            EXPECT_EQ(lean2.x, 1.0f) << to_string(storage);
            EXPECT_EQ(lean2.z, 1.0f) << to_string(storage);
        } else {
            const float bx = (2.0f * lean2.x - 1.0f) * packed.scale;
            EXPECT_NEAR(bx, expected_bx, expected_bx * 2e-3f) << to_string(storage);
        }
    }
}

// --bits auto (auto_storage): UNORM16 unless texels lie beyond sc, or UNORM16's rounding of M
// (sc^2 / (2 * 65535)) reaches the base variance 1/13777 while most texels are far flatter than
// sc (the bound: sc = sqrt(2 * 65535 / 13777) = 3.08); then half floats, or 32-bit floats where
// half floats' rounding of B (sc / 4096) reaches the highlight's width 1 / sqrt(13777) (sc =
// 34.9).
TEST(AutoStorage, HalfFloatsForOutliersOrForCoarseMomentsOfAMostlyFlatMap) {
    EXPECT_NEAR(unorm16_moment_error(1.0f), 13777.0 / 131070.0, 1e-9);
    EXPECT_LT(unorm16_moment_error(3.05f), kAutoStorageMaxError);
    EXPECT_GT(unorm16_moment_error(3.1f), kAutoStorageMaxError);
    // The built-in sets (sc 0.6 - 1.5) and gentle maps: 16-bit UNORM.
    EXPECT_EQ(auto_storage(0.98f, 0, 0.3f), Storage::Unorm16);
    EXPECT_EQ(auto_storage(1.5f, 0, 0.0f), Storage::Unorm16);
    // Outliers beyond sc: half floats, whatever sc.
    EXPECT_EQ(auto_storage(1.0f, 1, 0.3f), Storage::Float16);
    // Steep gaps between flat planks (sc 32, median far below sc / 8): half floats.
    EXPECT_EQ(auto_storage(32.0f, 0, 0.05f), Storage::Float16);
    EXPECT_EQ(auto_storage(32.0f, 0, 4.0f), Storage::Float16);
    EXPECT_LT(float16_slope_error(34.8f), kAutoStorageMaxError);
    EXPECT_GT(float16_slope_error(35.0f), kAutoStorageMaxError);
    EXPECT_EQ(auto_storage(64.0f, 0, 0.05f), Storage::Float32);
    EXPECT_EQ(auto_storage(64.0f, 1, 0.05f), Storage::Float16);  // outliers: half floats
    // A map steep everywhere (median above sc / 8) keeps UNORM, finer than half floats near sc.
    EXPECT_EQ(auto_storage(32.0f, 0, 4.5f), Storage::Unorm16);
    // The median a bake reports: the upper bin edge of max(|Bx|, |By|) of half of the texels.
    Image slopes(4, 4, 2, 0.0f);
    for (int i = 0; i < 6; ++i) slopes.pixels[std::size_t(2 * i)] = 20.0f;  // 6 of 16 steep
    const LeanMap map = build_lean_map(slopes, {});
    EXPECT_LT(map.median_steepness, 1e-4f);
    EXPECT_EQ(auto_storage(map.scale, map.texels_beyond_scale, map.median_steepness),
              Storage::Float16);
    for (int i = 6; i < 10; ++i) slopes.pixels[std::size_t(2 * i)] = 20.0f;  // 10 of 16 steep
    const LeanMap steep = build_lean_map(slopes, {});
    EXPECT_GE(steep.median_steepness, 20.0f);
    EXPECT_LE(steep.median_steepness, 20.0f * 1.25f);  // four bins per octave: 16, 20, 24, 28
    EXPECT_EQ(auto_storage(steep.scale, steep.texels_beyond_scale, steep.median_steepness),
              Storage::Unorm16);
    // Both bakes report the same median.
    const Image height = make_builtin_height("bumps", 64);
    const float reference = bake_lean_map(height, BakeSource::Height, {}).map.median_steepness;
    EXPECT_GT(reference, 0.0f);
    EXPECT_EQ(bake_packed(height, BakeSource::Height, {}, Storage::Unorm16, "t").median_steepness,
              reference);
}
