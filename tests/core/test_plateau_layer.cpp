// The plateau layer as a packed LEAN map stores it (leanfade/core/plateau.hpp, docs/math.md §10):
// the packed bakes write exactly add_plateau_layer's bytes, the stored values filter as the layer
// does, f = 0 decodes to exactly 0, and maps without the layer stay without it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "leanfade/core/error.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/plateau.hpp"
#include "leanfade/core/procedural.hpp"

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
    for (const auto& [w, h] : {std::pair{64, 64}, std::pair{48, 32}, std::pair{37, 20},
                              std::pair{64, 3}, std::pair{1, 1}}) {
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

TEST(PlateauLayer, StoredLayerDecodesToThePlateauMipsWithinTheStoragesRounding) {
    BakeOptions options;
    options.strength = 4.0f;
    const PackedLeanMap baked =
        bake_packed(bumps_height(64, 64), BakeSource::Height, options, Storage::Unorm16, "t")
            .packed;
    const std::vector<Image> want = plateau_mips(packed_top_slopes(baked));
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
    EXPECT_LT(flat_fraction, 0.95);
}

TEST(PlateauLayer, OffPlateauTexelsDecodeToExactlyZero) {
    // A map with no plateau at all: steep noise everywhere (every neighbour differs).
    Image slopes_height(32, 32, 1);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x)
            slopes_height.at(x, y, 0) = 3.0f * std::sin(float(x * x + 7 * y * y + 3 * x * y));
    const PackedLeanMap baked =
        bake_packed(slopes_height, BakeSource::Height, BakeOptions{}, Storage::Unorm16, "t").packed;
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
