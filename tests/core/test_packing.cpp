#include <gtest/gtest.h>

#include <cmath>

#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/procedural.hpp"

using namespace leanfade;

namespace {

LeanMap bumps_map(int size, float bake_s = 0.0f) {
    BakeOptions options;
    options.bake_roughness_shininess = bake_s;
    return build_lean_map(slopes_from_height(make_builtin_height("bumps", size, 11), options).slopes,
                          options);
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
    for (Storage storage : {Storage::Unorm8, Storage::Unorm16, Storage::Float16, Storage::Float32}) {
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
                    for (int layer = 0; layer < 2; ++layer) {
                        const glm::vec4 t = fetch_packed_texel(packed, int(l), layer, x, y);
                        for (int c = 0; c < 4; ++c) {
                            EXPECT_GE(t[c], 0.0f) << name;
                            EXPECT_LE(t[c], 1.0f) << name;
                        }
                    }
    }
}

TEST(Packing, PackingIsAffineSoFilteringCommutesWithIt) {
    // Averaging packed texels equals packing the averaged moments (what lets hardware trilinear
    // filtering stand in for filtering the moments, SPEC §3).
    const LeanMap map = bumps_map(8);
    const PackedLeanMap packed = pack_lean_map(map, Storage::Float32, "test");
    for (int layer = 0; layer < 2; ++layer) {
        const glm::vec4 avg = 0.25f * (fetch_packed_texel(packed, 0, layer, 0, 0) +
                                      fetch_packed_texel(packed, 0, layer, 1, 0) +
                                      fetch_packed_texel(packed, 0, layer, 0, 1) +
                                      fetch_packed_texel(packed, 0, layer, 1, 1));
        const glm::vec4 coarse = fetch_packed_texel(packed, 1, layer, 0, 0);
        for (int c = 0; c < 4; ++c) EXPECT_NEAR(avg[c], coarse[c], 1e-6f);
    }
}
