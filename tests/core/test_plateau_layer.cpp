// The plateau layer as a packed LEAN map stores it (leanfade/core/detail/plateau.hpp, docs/math.md §10):
// the packed bakes write exactly add_plateau_layer's bytes, the stored values filter as the layer
// does, f = 0 decodes to exactly 0, and maps without the layer stay without it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "leanfade/core/detail/bake.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/plateau.hpp"
#include "leanfade/core/detail/procedural.hpp"

namespace leanfade {
namespace {

// Bumps on flat ground (the built-in set most of whose texels are flat) at w x h.
Image bumps_height(int w, int h) {
    const Image square = make_builtin_height("bumps", std::max({8, w, h}), 3);
    Image out(w, h, 1);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) out.at(x, y, 0) = square.at(x, y, 0);
    return out;
}

TEST(PlateauLayer, PackedBakeWritesTheReferenceBytesForEverySizeAndStorage) {
    // 640 x 384 and 515 x 300: the rule's radius 3 x 2 and 2 x 1 (even and odd sizes). The
    // packed bake makes levels 0-4 of even sizes row block by row block: 24 x 40 halves 3
    // times, 2 x 2 once, 96 x 64 (and 64 x 64, 48 x 32, 640 x 384) 4 times before the rest.
    for (const auto& [w, h] : {std::pair{64, 64}, std::pair{48, 32}, std::pair{37, 20},
                              std::pair{64, 3}, std::pair{1, 1}, std::pair{640, 384},
                              std::pair{515, 300}, std::pair{24, 40}, std::pair{2, 2},
                              std::pair{96, 64}}) {
        for (Storage storage :
             {Storage::Unorm8, Storage::Unorm16, Storage::Float16, Storage::Float32}) {
            for (int threads : {1, 3}) {
                BakeOptions options;
                options.strength = 4.0f;
                options.threads = threads;
                const PackedLeanMap baked =
                    bake_packed(bumps_height(w, h), BakeSource::Height, options, storage, "t")
                        .packed;
                ASSERT_TRUE(baked.has_plateau());
                EXPECT_EQ(baked.plateau_epsilon, kDefaultPlateauEpsilon);
                PackedLeanMap reference = baked;
                remove_plateau_layer(reference);
                EXPECT_FALSE(reference.has_plateau());
                add_plateau_layer(reference, kDefaultPlateauEpsilon, 1);
                ASSERT_EQ(reference.levels.size(), baked.levels.size());
                for (std::size_t l = 0; l < baked.levels.size(); ++l) {
                    ASSERT_EQ(baked.levels[l].plateau.size(), baked.levels[l].lean1.size());
                    EXPECT_TRUE(baked.levels[l].plateau == reference.levels[l].plateau)
                        << w << "x" << h << " storage " << to_string(storage) << " level " << l
                        << " threads " << threads;
                }
            }
        }
    }
}

// The fraction of the texels the rule puts on a plateau.
double flat_fraction(const Image& layer0) {
    double sum = 0.0;
    for (std::size_t i = 0; i < layer0.texel_count(); ++i) sum += layer0.pixels[4 * i];
    return sum / double(layer0.texel_count());
}

// The slopes of the built-in bumps at size x size texels: one surface (the bumps' radii and
// heights are in texels, so their slopes are the same at every size), sampled more finely.
Image bumps_slopes(int size) {
    BakeOptions options;
    options.strength = 1.0f;
    return slopes_from_height(make_builtin_height("bumps", size, 3), options, "bumps").slopes;
}

TEST(PlateauRule, RadiusFollowsTheMapSizeAndEpsilonItsQuantisation) {
    const PlateauRule small = plateau_rule(256, 256, 0.005f);
    EXPECT_EQ(small.radius_x, 1);
    EXPECT_EQ(small.radius_y, 1);
    EXPECT_EQ(small.epsilon, 0.005f);
    const PlateauRule wide = plateau_rule(4096, 1024, 0.005f);
    EXPECT_EQ(wide.radius_x, 16);
    EXPECT_EQ(wide.radius_y, 4);
    EXPECT_EQ(plateau_rule(16, 3, 0.005f).radius_x, 1);
    // 8-bit normals: a step of 2/255 is more than epsilon; the rule takes 1.5 steps, radius >= 2.
    const float step8 = source_slope_step(BakeSource::Normal, 255, 1.0f);
    EXPECT_FLOAT_EQ(step8, 2.0f / 255.0f);
    const PlateauRule quantised = plateau_rule(256, 256, 0.005f, step8);
    EXPECT_FLOAT_EQ(quantised.epsilon, 1.5f * 2.0f / 255.0f);
    EXPECT_EQ(quantised.radius_x, 2);
    EXPECT_EQ(plateau_rule(2048, 2048, 0.005f, step8).radius_x, 8);
    // 16-bit sources and storages, and float sources: far below epsilon, nothing changes.
    for (const float fine : {source_slope_step(BakeSource::Normal, 65535, 1.0f),
                             source_slope_step(BakeSource::Height, 65535, 8.0f),
                             storage_slope_step(Storage::Unorm16, 2.0f),
                             source_slope_step(BakeSource::Normal, 0, 1.0f),
                             storage_slope_step(Storage::Float16, 2.0f)}) {
        const PlateauRule rule = plateau_rule(256, 256, 0.005f, fine);
        EXPECT_EQ(rule.epsilon, 0.005f) << fine;
        EXPECT_EQ(rule.radius_x, 1) << fine;
    }
    EXPECT_FLOAT_EQ(storage_slope_step(Storage::Unorm8, 0.5f), 1.0f / 255.0f);
    EXPECT_FLOAT_EQ(source_slope_step(BakeSource::Height, 255, 8.0f), 2.0f / 255.0f);
    EXPECT_THROW(plateau_rule(256, 256, 0.0f), Error);
    EXPECT_THROW(plateau_rule(0, 256, 0.005f), Error);
}

// The same surface at 256, 1024 and 4096 texels: the flat fraction stays (about 0.6 of `bumps`
// is flat ground: 0.64 at 256 texels, 0.56-0.57 finer, where the bumps' rims are resolved), where
// a rule of neighbours one texel apart takes the slowly curving flanks of the 4096 map for flat
// ground too (0.82: their slope changes by less than epsilon per texel there).
TEST(PlateauRule, TheSameSurfaceHasTheSameFlatFractionAtEveryResolution) {
    const double at_256 = flat_fraction(plateau_texels(bumps_slopes(256)));
    EXPECT_GT(at_256, 0.5);
    EXPECT_LT(at_256, 0.7);
    double previous = -1.0;
    for (const int size : {1024, 4096}) {
        const Image slopes = bumps_slopes(size);
        const double f = flat_fraction(plateau_texels(slopes));
        EXPECT_NEAR(f, at_256, 0.1) << size;
        if (previous >= 0.0) {
            EXPECT_NEAR(f, previous, 0.02) << size;
        }
        previous = f;
        PlateauRule one_texel = plateau_rule_for(slopes);
        one_texel.radius_x = one_texel.radius_y = 1;
        if (size == 4096) {
            EXPECT_GT(flat_fraction(plateau_texels(slopes, one_texel)), f + 0.2);
        }
    }
}

// Flat faces of an 8-bit map (their slopes dithered between two codes) stay flat; a ramp of
// one code per texel, which a one-texel rule with an epsilon above a step would take for flat, is
// not.
TEST(PlateauRule, QuantisedFlatFacesStayFlatAndQuantisedRampsDoNot) {
    const float step = 2.0f / 255.0f;
    const int n = 256;
    Image faces(n, n, 2), ramp(n, n, 2);
    std::uint32_t state = 12345u;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            state = state * 1664525u + 1013904223u;
            const float code = float((state >> 16) & 1u);  // 0 or 1: two codes of noise
            faces.at(x, y, 0) = (x < n / 2 ? 10.0f : -4.0f + code) * step;
            faces.at(x, y, 1) = (3.0f + float((state >> 20) & 1u)) * step;
            ramp.at(x, y, 0) = float(x % 64) * step;  // one code per texel, 64 codes
            ramp.at(x, y, 1) = float(y % 2) * step;   // and a code of noise
        }
    const PlateauRule rule = plateau_rule(n, n, kDefaultPlateauEpsilon, step);
    EXPECT_GT(flat_fraction(plateau_texels(faces, rule)), 0.9);
    EXPECT_LT(flat_fraction(plateau_texels(ramp, rule)), 0.05);
    // The rule of continuous slopes finds no flat face in them (a step is more than epsilon).
    EXPECT_LT(flat_fraction(plateau_texels(faces)), 0.1);
}

// A 16-bit file of 8-bit data (every sample a multiple of 257) has 8-bit steps.
TEST(PlateauRule, IntegerSamplesKnowTheirOwnPrecision) {
    UnormImage sixteen(4, 2, 3, 65535);
    for (std::size_t i = 0; i < sixteen.samples.size(); ++i)
        sixteen.samples[i] = std::uint16_t(257 * ((i * 37) % 256));
    EXPECT_EQ(sixteen.effective_max_code(), 255);
    sixteen.samples[5] = 1000;  // not a multiple of 257: 16-bit steps
    EXPECT_EQ(sixteen.effective_max_code(), 65535);
    EXPECT_EQ(sixteen.effective_max_code(1), 255) << "sample 5 is in channel 2";
    UnormImage eight(2, 2, 1, 255);
    eight.samples = {0, 17, 34, 255};  // multiples of 17 (4-bit data): 15
    EXPECT_EQ(eight.effective_max_code(), 15);
    EXPECT_EQ(UnormImage().effective_max_code(), 0);
}

TEST(PlateauLayer, BakeReportsTheFractionAndTheRule) {
    BakeOptions options;
    options.strength = 4.0f;
    const PackedBakeResult baked =
        bake_packed(bumps_height(512, 512), BakeSource::Height, options, Storage::Unorm16, "t");
    EXPECT_EQ(baked.summary.plateau_radius_x, 2);
    EXPECT_EQ(baked.summary.plateau_rule_epsilon, kDefaultPlateauEpsilon);
    EXPECT_NEAR(baked.summary.plateau_fraction, plateau_fraction(baked.packed), 1e-4);
    const std::vector<Image> chain = unpack_plateau_layer(baked.packed);
    EXPECT_NEAR(baked.summary.plateau_fraction, flat_fraction(chain.front()), 1e-4);
    EXPECT_GT(baked.summary.plateau_fraction, 0.3f);
    // The same map as 8-bit samples: the rule takes the source's step (strength / (4 * 255)).
    options.source_max_code = 255;
    const PackedBakeResult eight =
        bake_packed(bumps_height(512, 512), BakeSource::Height, options, Storage::Unorm16, "t");
    EXPECT_FLOAT_EQ(eight.summary.plateau_rule_epsilon,
                    std::max(kDefaultPlateauEpsilon, 1.5f * 4.0f / (4.0f * 255.0f)));
}

TEST(PlateauLayer, StoredLayerDecodesToThePlateauMipsWithinTheStoragesRounding) {
    BakeOptions options;
    options.strength = 4.0f;
    const PackedLeanMap baked =
        bake_packed(bumps_height(64, 64), BakeSource::Height, options, Storage::Unorm16, "t")
            .packed;
    // The bake's rule: the plateaus of the map's size and the central window fitted to its slopes
    // (16-bit UNORM's step is far below epsilon).
    const Image slopes = packed_top_slopes(baked);
    PlateauRule rule = plateau_rule_for(slopes);
    rule.window = fit_spike_window(slopes, rule).window;
    const std::vector<Image> want = plateau_mips(slopes, rule);
    const std::vector<Image> got = unpack_plateau_layer(baked);
    ASSERT_EQ(got.size(), want.size());
    const float sc = baked.scale;
    // One 16-bit step of each channel: f, f Bs (2 sc / Q), f |Bs|^2 (2 sc^2 / Q).
    const float step[4] = {1.0f / 65535.0f, 2.0f * sc / 65535.0f, 2.0f * sc / 65535.0f,
                           2.0f * sc * sc / 65535.0f};
    double flat_fraction = 0.0;
    for (std::size_t l = 0; l < got.size(); ++l)
        for (std::size_t i = 0; i < got[l].pixels.size(); ++i)
            EXPECT_NEAR(got[l].pixels[i], want[l].pixels[i], step[i % 4])
                << "level " << l << " value " << i;
    flat_fraction = got.back().pixels[0];
    EXPECT_GT(flat_fraction, 0.2) << "the bumps set is mostly flat ground";
    EXPECT_NEAR(flat_fraction, plateau_fraction(baked), 1e-4);
    EXPECT_LT(flat_fraction, 0.95);
}

TEST(PlateauLayer, OffPlateauTexelsDecodeToExactlyZero) {
    // A map with no plateau at all: steep noise everywhere (every neighbour differs), with the
    // plateaus alone forming the spike (no central window).
    Image slopes_height(32, 32, 1);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x)
            slopes_height.at(x, y, 0) = 3.0f * std::sin(float(x * x + 7 * y * y + 3 * x * y));
    BakeOptions options;
    options.spike_fit = SpikeFit::Plateaus;
    const PackedLeanMap baked =
        bake_packed(slopes_height, BakeSource::Height, options, Storage::Unorm16, "t").packed;
    for (const Image& level : unpack_plateau_layer(baked))
        for (float v : level.pixels) ASSERT_EQ(v, 0.0f);
}

TEST(PlateauLayer, StoredValuesFilterAsTheLayer) {
    // Each stored channel is affine in (f, f Bs, f |Bs|^2): the 2 x 2 mean of the decoded texels
    // of a level equals the decoded texel below it, up to the rounding of both.
    BakeOptions options;
    options.strength = 4.0f;
    const PackedLeanMap baked =
        bake_packed(bumps_height(64, 64), BakeSource::Height, options, Storage::Float32, "t")
            .packed;
    const std::vector<Image> chain = unpack_plateau_layer(baked);
    for (std::size_t l = 0; l + 1 < chain.size(); ++l) {
        const Image& fine = chain[l];
        const Image& coarse = chain[l + 1];
        for (int y = 0; y < coarse.height; ++y)
            for (int x = 0; x < coarse.width; ++x)
                for (int c = 0; c < 4; ++c) {
                    const float mean =
                        0.25f * (fine.at(2 * x, 2 * y, c) + fine.at(2 * x + 1, 2 * y, c) +
                                 fine.at(2 * x, 2 * y + 1, c) + fine.at(2 * x + 1, 2 * y + 1, c));
                    ASSERT_NEAR(coarse.at(x, y, c), mean, 1e-5f * (1.0f + std::abs(mean)))
                        << "level " << l + 1 << " (" << x << ", " << y << ") channel " << c;
                }
    }
}

TEST(PlateauLayer, EpsilonZeroBakesNoLayerAndTheMomentsStayTheSame) {
    BakeOptions with, without;
    without.plateau_epsilon = 0.0f;
    const Image height = bumps_height(32, 32);
    const PackedLeanMap a = bake_packed(height, BakeSource::Height, with, Storage::Unorm16, "t").packed;
    const PackedLeanMap b =
        bake_packed(height, BakeSource::Height, without, Storage::Unorm16, "t").packed;
    EXPECT_FALSE(b.has_plateau());
    EXPECT_TRUE(unpack_plateau_layer(b).empty());
    for (std::size_t l = 0; l < a.levels.size(); ++l) {
        EXPECT_TRUE(b.levels[l].plateau.empty());
        EXPECT_TRUE(a.levels[l].lean1 == b.levels[l].lean1);
        EXPECT_TRUE(a.levels[l].lean2 == b.levels[l].lean2);
    }
    // Reusing a result's buffers for a bake without the layer leaves none behind.
    PackedBakeResult reused;
    bake_packed_into(reused, height, BakeSource::Height, with, Storage::Unorm16, "t");
    bake_packed_into(reused, height, BakeSource::Height, without, Storage::Unorm16, "t");
    EXPECT_FALSE(reused.packed.has_plateau());
    for (const PackedLevel& level : reused.packed.levels) EXPECT_TRUE(level.plateau.empty());
}

TEST(PlateauLayer, RefusesABadEpsilon) {
    BakeOptions options;
    for (float bad : {-0.1f, std::nanf(""), INFINITY}) {
        options.plateau_epsilon = bad;
        EXPECT_THROW(bake_packed(bumps_height(8, 8), BakeSource::Height, options,
                                 Storage::Unorm16, "t"),
                     Error);
    }
    PackedLeanMap map =
        bake_packed(bumps_height(8, 8), BakeSource::Height, BakeOptions{}, Storage::Unorm16, "t")
            .packed;
    EXPECT_THROW(add_plateau_layer(map, 0.0f), Error);
    map.levels[1].plateau.pop_back();
    EXPECT_THROW(unpack_plateau_layer(map), Error);
}

}  // namespace
}  // namespace leanfade
