// Finite but absurd values (docs/robustness.md). Found by fuzz_image_bake: an OpenEXR height
// map of values near 3e38 gave slopes whose squares overflowed the float range; sc became
// infinite, the packed moments NaN, and the 8/16-bit packing converted NaN to an integer
// (undefined behaviour). Slopes steeper than kMaxSlope are now refused, naming the texel.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "leanfade/core/error.hpp"
#include "leanfade/core/lean_map.hpp"

using namespace leanfade;

namespace {

template <class Call>
void expect_error(Call&& call, const std::string& file, const std::string& cause) {
    try {
        call();
        ADD_FAILURE() << "no leanfade::Error thrown; expected " << cause;
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), file);
        EXPECT_NE(e.cause().find(cause), std::string::npos) << e.what();
    }
}

Image flat(int width, int height, int channels, float value) {
    return Image(width, height, channels, value);
}

}  // namespace

TEST(HostileValues, HugeFiniteHeightsAreRefusedNamingTheTexel) {
    Image height = flat(5, 4, 1, 0.0f);
    height.at(3, 2) = 3e38f;
    BakeOptions options;
    options.wrap = Wrap::Clamp;
    // The first texel (rows top first) whose Sobel slope is steep: (2, 1), beside the spike.
    expect_error([&] { slopes_from_height(height, options, "h.exr"); }, "h.exr",
                 "at texel (2, 1) is steeper than the limit of 1e6 (height steps times the "
                 "strength are too large)");
    expect_error([&] { bake_lean_map(height, BakeSource::Auto, options, "h.exr"); }, "h.exr",
                 "is steeper than the limit of 1e6");
}

TEST(HostileValues, HugeStrengthIsRefusedButTheLimitIsFarFromRealMaps) {
    Image height = flat(4, 4, 1, 0.0f);
    height.at(1, 1) = 1.0f;
    BakeOptions options;
    options.strength = 1e30f;
    expect_error([&] { bake_lean_map(height, BakeSource::Height, options, "h.png"); }, "h.png",
                 "steeper than the limit");
    // A unit step at strength 1e5 (slopes of 25000, 89.998 degrees) still bakes, finitely.
    options.strength = 1e5f;
    const BakeResult result = bake_lean_map(height, BakeSource::Height, options, "h.png");
    EXPECT_TRUE(std::isfinite(result.map.scale));
    for (const Storage storage :
         {Storage::Unorm8, Storage::Unorm16, Storage::Float16, Storage::Float32}) {
        const PackedLeanMap packed = pack_lean_map(result.map, storage, "test");
        const LeanMap back = unpack_lean_map(packed);
        for (const glm::vec3& m : back.levels.front().second) {
            EXPECT_TRUE(std::isfinite(m.x) && std::isfinite(m.y) && std::isfinite(m.z));
        }
    }
}

TEST(HostileValues, NormalComponentsFarOutsideTheUnitRangeAreRefused) {
    Image normals = flat(3, 3, 3, 0.5f);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 3; ++x) normals.at(x, y, 2) = 1.0f;
    normals.at(1, 2, 0) = 1e30f;  // x component of texel (1, 2)
    expect_error([&] { slopes_from_normals(normals, BakeOptions{}, "n.exr"); }, "n.exr",
                 "at texel (1, 2) is steeper than the limit of 1e6 (normal components far "
                 "outside [0, 1])");
}

TEST(HostileValues, BuildLeanMapRefusesNonFiniteOrSteepSlopes) {
    Image slopes = flat(2, 2, 2, 0.1f);
    slopes.at(1, 0, 1) = 2e6f;
    expect_error([&] { build_lean_map(slopes, BakeOptions{}); }, "", "steeper than the limit");
    slopes.at(1, 0, 1) = std::numeric_limits<float>::quiet_NaN();
    expect_error([&] { build_lean_map(slopes, BakeOptions{}); }, "", "not finite");
}

// pack_lean_map takes any LeanMap: NaN moments are stored as 0 in the UNORM storages instead of
// being converted to an integer (undefined behaviour, checked by `make sanitize`).
TEST(HostileValues, PackingStoresNaNAsZeroInUnormStorages) {
    LeanMap map;
    map.scale = 1.0f;
    MomentLevel level;
    level.width = level.height = 1;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    level.normal = {glm::vec3(nan)};
    level.mean = {glm::vec2(nan)};
    level.second = {glm::vec3(nan)};
    map.levels.push_back(level);
    for (const Storage storage : {Storage::Unorm8, Storage::Unorm16}) {
        const PackedLeanMap packed = pack_lean_map(map, storage, "test");
        for (int slice = 0; slice < 2; ++slice) {
            EXPECT_EQ(fetch_packed_texel(packed, 0, slice, 0, 0), glm::vec4(0.0f));
        }
    }
}
