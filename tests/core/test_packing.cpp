#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <vector>

#include "leanfade/core/detail/bake.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/procedural.hpp"

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
    // sc is chosen so that no packed channel overflows [0, 1]: check on float storage in the
    // offset encoding, where nothing is clamped, over every level of every built-in set.
    for (const std::string& name : builtin_bump_names()) {
        BakeOptions options;
        const LeanMap map = build_lean_map(
            slopes_from_height(make_builtin_height(name, 64, 2), options).slopes, options);
        const PackedLeanMap packed =
            pack_lean_map(map, Storage::Float32, LeanEncoding::Offset, "test");
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

// Half floats in the signed encoding keep the covariance of flat ground (slopes of a few
// hundredths with the base variance 1/s = 1/13777 baked in), which the offset encoding of
// leanfade 0.1 rounded away: its 0.5 B / sc + 0.5 held B to sc / 2^11 whatever B's size.
TEST(Packing, SignedHalfFloatsKeepTheCovarianceOfFlatGround) {
    Image slopes(64, 64, 2);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            slopes.row(y)[2 * x] = 0.03f * std::sin(0.37f * float(x) + 0.11f * float(y));
            slopes.row(y)[2 * x + 1] = 0.02f * std::cos(0.23f * float(y) - 0.05f * float(x));
        }
    // One steep texel sets sc far above the ground's slopes (as a gap between tiles does).
    slopes.row(5)[2 * 9] = 3.0f;
    BakeOptions options;
    options.bake_roughness_shininess = 13777.0f;
    options.scale_excludes_outliers = false;
    const LeanMap map = build_lean_map(slopes, options);
    ASSERT_GE(map.scale, 3.0f);
    const float inv_s = 1.0f / 13777.0f;
    // The largest error of Sxx = Mxx - Bx^2 over the finest level, in units of 1/s.
    const auto covariance_error = [&](const PackedLeanMap& packed) {
        const MomentLevel back = unpack_lean_map(packed).levels[0];
        const MomentLevel& exact = map.levels[0];
        double worst = 0.0;
        for (std::size_t i = 0; i < exact.mean.size(); ++i) {
            const double want = double(exact.second[i].x) - double(exact.mean[i].x) * exact.mean[i].x;
            const double got = double(back.second[i].x) - double(back.mean[i].x) * back.mean[i].x;
            if (std::abs(double(exact.mean[i].x)) < 0.1)  // the flat ground only
                worst = std::max(worst, std::abs(got - want) / double(inv_s));
        }
        return worst;
    };
    const PackedLeanMap signed_half = pack_lean_map(map, Storage::Float16, "test");
    ASSERT_EQ(signed_half.encoding, LeanEncoding::Signed);
    const double signed_error = covariance_error(signed_half);
    const double offset_error =
        covariance_error(pack_lean_map(map, Storage::Float16, LeanEncoding::Offset, "test"));
    EXPECT_LT(signed_error, 0.02) << "signed 16f";
    EXPECT_GT(offset_error, 0.5) << "offset 16f";
    EXPECT_LT(covariance_error(pack_lean_map(map, Storage::Float32, "test")), 1e-4);
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
            const float offset = lean_offset(packed.encoding);
            const float bx = ((1.0f + offset) * lean2.x - offset) * packed.scale;
            EXPECT_NEAR(bx, expected_bx, expected_bx * 2e-3f) << to_string(storage);
        }
    }
}

// --bits auto (StorageProbe): the 16-bit storage that changes a render of the map's own texels
// less, measured on the bake's float moments.
Image planks_height(int size) {
    // Planks 16 texels wide with 1-texel gaps and a faint grain: steep walls between flat ground.
    Image height(size, size, 1, 0.0f);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x)
            height.row(y)[x] = x % 16 == 0 ? -0.25f
                                           : 0.002f * std::sin(0.3f * float(y) + float(x));
    return height;
}

TEST(StorageProbe, MeasuresTheBakesFloatsAsTheFloatMapsAndPicksWhatKeepsTheHighlight) {
    const auto probe_of_bake = [](const Image& input, const BakeOptions& options,
                                  PackedBakeResult& baked) {
        auto probe = std::make_unique<StorageProbe>(input.width, input.height);
        baked = bake_packed(input, BakeSource::Height, options, Storage::Unorm16, "t", "",
                            probe->sink());
        return probe;
    };
    // A gentle map (the built-in bumps): every storage measured, the finer the better.
    BakeOptions gentle;
    const Image bumps = make_builtin_height("bumps", 64);
    PackedBakeResult baked;
    const auto probe = probe_of_bake(bumps, gentle, baked);
    const double unorm = probe->psnr(Storage::Unorm16, baked.packed.scale);
    const double half = probe->psnr(Storage::Float16, baked.packed.scale);
    EXPECT_GT(unorm, 30.0);
    EXPECT_EQ(probe->psnr(Storage::Float32, baked.packed.scale),
              std::numeric_limits<double>::infinity());
    EXPECT_LT(probe->psnr(Storage::Unorm8, baked.packed.scale), unorm);
    EXPECT_EQ(probe->choose(baked.packed.scale),
              unorm >= half ? Storage::Unorm16 : Storage::Float16);
    // The same floats through a float map give the same measure.
    StorageProbe from_map(64, 64);
    from_map.add(bake_lean_map(bumps, BakeSource::Height, gentle).map);
    EXPECT_EQ(from_map.psnr(Storage::Unorm16, baked.packed.scale), unorm);
    EXPECT_EQ(from_map.psnr(Storage::Float16, baked.packed.scale), half);

    // Planks with steep gaps: the walls set sc, and UNORM's step of M (sc^2 / 65535) rounds away
    // the flat planks' covariance; signed half floats keep it.
    BakeOptions steep;
    steep.strength = 128.0f;
    PackedBakeResult planks;
    const auto planks_probe = probe_of_bake(planks_height(64), steep, planks);
    ASSERT_GT(planks.packed.scale, 8.0f);
    const double planks_unorm = planks_probe->psnr(Storage::Unorm16, planks.packed.scale);
    const double planks_half = planks_probe->psnr(Storage::Float16, planks.packed.scale);
    EXPECT_GT(planks_half, planks_unorm + 10.0);
    EXPECT_EQ(planks_probe->choose(planks.packed.scale), Storage::Float16);
    const StorageProbe::Scores scores = planks_probe->scores(planks.packed.scale);
    EXPECT_EQ(scores.unorm16, planks_unorm);
    EXPECT_EQ(scores.float16, planks_half);
    std::printf("probe PSNR: bumps 16 %.1f dB, 16f %.1f dB; planks 16 %.1f dB, 16f %.1f dB\n",
                unorm, half, planks_unorm, planks_half);
}

// bake_with_auto_storage bakes once when the first storage is the probe's choice, twice when not.
TEST(StorageProbe, AutoStorageBakesAgainOnlyForAnotherStorage) {
    BakeOptions steep;
    steep.strength = 128.0f;
    for (const bool planks : {false, true}) {
        const Image input = planks ? planks_height(64) : make_builtin_height("bumps", 64);
        const BakeOptions options = planks ? steep : BakeOptions{};
        std::vector<Storage> bakes;
        const PackedBakeResult result = bake_with_auto_storage(
            Storage::Unorm16, true, input.width, input.height,
            [&](Storage s, const MomentRunSink& probe) {
                bakes.push_back(s);
                return bake_packed(input, BakeSource::Height, options, s, "t", "", probe);
            });
        ASSERT_FALSE(bakes.empty());
        EXPECT_EQ(bakes.front(), Storage::Unorm16);
        EXPECT_EQ(result.packed.storage, bakes.back());
        EXPECT_EQ(bakes.size(), bakes.back() == Storage::Unorm16 ? 1u : 2u);
        if (planks) {
            EXPECT_NE(result.packed.storage, Storage::Unorm16);
        }
    }
    // Not automatic: one bake in the storage asked for, no probe.
    int calls = 0;
    bake_with_auto_storage(Storage::Float16, false, 8, 8, [&](Storage s, const MomentRunSink& p) {
        ++calls;
        EXPECT_FALSE(bool(p));
        return bake_packed(make_builtin_height("bumps", 8), BakeSource::Height, {}, s, "t");
    });
    EXPECT_EQ(calls, 1);
}
