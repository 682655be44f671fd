// std140 offsets computed from a field list (leanfade/gl/detail/std140.hpp), against the rules of the
// OpenGL 4.5 specification §7.6.2.2, and the member names the driver lists for a block. The
// real blocks are checked against the driver in test_shaders.cpp.
#include <gtest/gtest.h>

#include "leanfade/gl/detail/shading_block.hpp"
#include "leanfade/gl/detail/std140.hpp"

namespace leanfade::gl {
namespace {

using K = Std140Kind;

TEST(Std140, ScalarsPackAndVec3TakesSixteenByteAlignment) {
    constexpr Std140Field fields[] = {
        {"a", K::Float, 0}, {"b", K::Vec3, 0}, {"c", K::Float, 0}, {"d", K::Vec2, 0},
        {"e", K::Float, 0}, {"f", K::Vec2, 0},
    };
    // a at 0; b rounds up to 16 (12 bytes); c fills b's fourth component; d at 32 (8-aligned);
    // e at 40; f rounds up to 48.
    EXPECT_EQ(std140_offset_of(fields, 0), 0u);
    EXPECT_EQ(std140_offset_of(fields, 1), 16u);
    EXPECT_EQ(std140_offset_of(fields, 2), 28u);
    EXPECT_EQ(std140_offset_of(fields, 3), 32u);
    EXPECT_EQ(std140_offset_of(fields, 4), 40u);
    EXPECT_EQ(std140_offset_of(fields, 5), 48u);
    EXPECT_EQ(std140_end(fields), 56u);
    EXPECT_EQ(std140_struct_size(fields), 64u);
}

TEST(Std140, ArrayElementsAndMatrixColumnsTakeAVec4Each) {
    constexpr Std140Field fields[] = {
        {"x", K::Float, 0}, {"arr", K::Float, 0, 3}, {"y", K::Float, 0},
        {"m", K::Mat3, 0},  {"z", K::Float, 0},      {"v", K::Vec4, 0, 2},
    };
    EXPECT_EQ(std140_offset_of(fields, 1), 16u);  // an array starts on 16
    EXPECT_EQ(std140_offset_of(fields, 2), 64u);  // 3 elements, stride 16
    EXPECT_EQ(std140_offset_of(fields, 3), 80u);
    EXPECT_EQ(std140_offset_of(fields, 4), 128u);  // mat3: 3 columns of 16
    EXPECT_EQ(std140_offset_of(fields, 5), 144u);
    EXPECT_EQ(std140_end(fields), 176u);
}

TEST(Std140, NestedStructsAlignAndRoundToSixteen) {
    static constexpr Std140Field inner[] = {{"a", K::Vec3, 0}, {"b", K::Float, 12},
                                            {"c", K::Float, 16}};
    constexpr Std140Field outer[] = {{"s", K::Float, 0},
                                     {"t", K::Struct, 16, 0, inner},
                                     {"u", K::Int, 48}};
    EXPECT_EQ(std140_struct_size(inner), 32u);
    EXPECT_EQ(std140_offset_of(outer, 1), 16u);
    EXPECT_EQ(std140_offset_of(outer, 2), 48u);  // after the rounded struct
    EXPECT_TRUE(std140_matches_cpp(outer));
    const std::vector<BlockMember> members = std140_block_members(outer, "u_block.");
    ASSERT_EQ(members.size(), 5u);
    EXPECT_EQ(members[1].name, "u_block.t.a");
    EXPECT_EQ(members[2].name, "u_block.t.b");
    EXPECT_EQ(members[2].offset, 28u);
    EXPECT_EQ(members[4].name, "u_block.u");
    EXPECT_EQ(members[4].offset, 48u);
}

TEST(Std140, AWrongCppOffsetIsCaught) {
    static constexpr Std140Field inner[] = {{"a", K::Vec3, 0}, {"b", K::Float, 16}};
    constexpr Std140Field outer[] = {{"t", K::Struct, 0, 0, inner}};
    EXPECT_FALSE(std140_matches_cpp(inner));  // b fills a's fourth component: 12, not 16
    EXPECT_FALSE(std140_matches_cpp(outer));  // found inside a nested struct too
}

TEST(Std140, TheRealBlocksListEveryMemberOnce) {
    const std::vector<BlockMember> shading = shading_block_members();
    // The two structs' entries become their members.
    EXPECT_EQ(shading.size(), std::size(kLfParamsFields) + std::size(kMaterialFactorsFields) +
                                  std::size(kShadingBlockFields) - 2);
    EXPECT_EQ(shading.front().name, "u_shading.params.light_color");
    EXPECT_EQ(shading[shading.size() - 6].offset, offsetof(LfShadingUniforms, uv_transforms));
    EXPECT_EQ(shading[shading.size() - 6].name, "u_shading.uv_transforms[0]");
    EXPECT_EQ(shading.back().offset, offsetof(LfShadingUniforms, material) +
                                         offsetof(shading::LfMaterialFactors, occlusion_strength));
    EXPECT_EQ(shading.back().name, "u_shading.material.occlusion_strength");
    // 160 bytes before the transforms, 7 transforms of two vec4s, the factors' 32 bytes.
    EXPECT_EQ(kShadingBlockStd140Size, 160u + 7u * 32u + 32u);
    const std::vector<BlockMember> layers = layer_block_members();
    EXPECT_EQ(layers[3].name, "u_layers.lean_offsets");
    EXPECT_EQ(layers[5].name, "u_layers.offsets[0]");
}

}  // namespace
}  // namespace leanfade::gl
