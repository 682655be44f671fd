#pragma once
// The C++ side of the uniform blocks and texture bindings (shaders/bindings.glsl, the structs
// LfParams, LfShadingUniforms and LfLayerUniforms of shaders/lean_shading.glsl, LfObjectBlock of
// shaders/scene.vert). Both sides compile the same struct definitions; each block's members are
// listed once below, std140 offsets are computed from the list (leanfade/gl/detail/std140.hpp) and
// checked against the C++ layout at compile time, and against the GL driver's reported offsets
// in tests/gl/test_shaders.cpp.
#include <cstddef>
#include <vector>

#include <glm/mat4x4.hpp>

#include "leanfade/core/detail/bindings.hpp"
#include "leanfade/core/shading.hpp"
#include "leanfade/gl/detail/std140.hpp"

namespace leanfade::gl {

namespace bindings = ::leanfade::bindings;

using shading::LfParams;
using shading::LfShadingUniforms;

// Each block's members, once: name, GLSL type, C++ offset. std140_matches_cpp() checks at compile
// time that std140 puts every member where the C++ struct has it (keep a vec3 followed by a
// scalar); the driver's offsets are checked against the same list by
// GlShaders.UniformBlocksMatchTheirCppMirrors.
#define LF_STD140(Struct, member, kind, ...) \
    Std140Field { #member, Std140Kind::kind, offsetof(Struct, member), __VA_ARGS__ }

inline constexpr Std140Field kLfParamsFields[] = {
    LF_STD140(LfParams, light_color, Vec3),    LF_STD140(LfParams, shininess, Float),
    LF_STD140(LfParams, ambient, Vec3),        LF_STD140(LfParams, inv_s_shading, Float),
    LF_STD140(LfParams, kd, Vec3),             LF_STD140(LfParams, fresnel_bias, Float),
    LF_STD140(LfParams, ks, Vec3),             LF_STD140(LfParams, fresnel_scale, Float),
    LF_STD140(LfParams, fade, Float),          LF_STD140(LfParams, pmax, Float),
    LF_STD140(LfParams, fade_exponent, Float), LF_STD140(LfParams, fade_distance, Int),
    LF_STD140(LfParams, f0, Vec3),             LF_STD140(LfParams, brdf, Int),
};
static_assert(std140_matches_cpp(kLfParamsFields));
static_assert(std140_struct_size(kLfParamsFields) == sizeof(LfParams));

using shading::LfMaterialFactors;
inline constexpr Std140Field kMaterialFactorsFields[] = {
    LF_STD140(LfMaterialFactors, emissive, Vec3),
    LF_STD140(LfMaterialFactors, metallic, Float),
    LF_STD140(LfMaterialFactors, anisotropy_rotation, Vec2),
    LF_STD140(LfMaterialFactors, anisotropy_strength, Float),
    LF_STD140(LfMaterialFactors, occlusion_strength, Float),
};
static_assert(std140_matches_cpp(kMaterialFactorsFields));
static_assert(std140_struct_size(kMaterialFactorsFields) == sizeof(LfMaterialFactors));

inline constexpr Std140Field kShadingBlockFields[] = {
    LF_STD140(LfShadingUniforms, params, Struct, 0, kLfParamsFields),
    LF_STD140(LfShadingUniforms, scale, Float),
    LF_STD140(LfShadingUniforms, output_mode, Int),
    LF_STD140(LfShadingUniforms, fog_mode, Int),
    LF_STD140(LfShadingUniforms, fog_start, Float),
    LF_STD140(LfShadingUniforms, fog_color, Vec3),
    LF_STD140(LfShadingUniforms, fog_end, Float),
    LF_STD140(LfShadingUniforms, fog_density, Float),
    LF_STD140(LfShadingUniforms, maps, Int),
    LF_STD140(LfShadingUniforms, geometric_aa_kappa, Float),
    LF_STD140(LfShadingUniforms, alpha_cutoff, Float),
    LF_STD140(LfShadingUniforms, base_alpha, Float),
    LF_STD140(LfShadingUniforms, blend, Float),
    LF_STD140(LfShadingUniforms, double_sided, Float),
    LF_STD140(LfShadingUniforms, lean_offset, Float),
    LF_STD140(LfShadingUniforms, uv_transforms, Vec4, 2 * shading::LF_UV_TRANSFORM_COUNT),
    LF_STD140(LfShadingUniforms, material, Struct, 0, kMaterialFactorsFields),
};
static_assert(std140_matches_cpp(kShadingBlockFields));
static_assert(std140_end(kShadingBlockFields) == sizeof(LfShadingUniforms));
// The buffer the renderer allocates: the block rounded up as a std140 struct (its last bytes are
// padding, not uploaded).
inline constexpr std::size_t kShadingBlockStd140Size = std140_struct_size(kShadingBlockFields);

inline std::vector<BlockMember> shading_block_members() {
    return std140_block_members(kShadingBlockFields, "u_shading.");
}

// The vertex stage's block LfObjectBlock (shaders/scene.vert): the object's and the camera's
// transforms, the eye, the light and the tiling. std140 pads each mat3 column to a vec4.
struct LfObjectUniforms {
    glm::mat4 model;             // object -> world
    glm::mat4 view;              // world -> eye
    glm::mat4 clip;              // world -> clip
    glm::vec4 normal_matrix[3];  // columns of transpose(inverse(mat3(model))), w unused
    glm::vec3 eye_world;
    float tiling;
    glm::vec3 light_world;
    float padding;
};
inline constexpr Std140Field kObjectBlockFields[] = {
    {"u_model", Std140Kind::Mat4, offsetof(LfObjectUniforms, model)},
    {"u_view", Std140Kind::Mat4, offsetof(LfObjectUniforms, view)},
    {"u_clip", Std140Kind::Mat4, offsetof(LfObjectUniforms, clip)},
    {"u_normal_matrix", Std140Kind::Mat3, offsetof(LfObjectUniforms, normal_matrix)},
    {"u_eye_world", Std140Kind::Vec3, offsetof(LfObjectUniforms, eye_world)},
    {"u_tiling", Std140Kind::Float, offsetof(LfObjectUniforms, tiling)},
    {"u_light_world", Std140Kind::Vec3, offsetof(LfObjectUniforms, light_world)},
};
static_assert(std140_matches_cpp(kObjectBlockFields));
static_assert(std140_struct_size(kObjectBlockFields) == sizeof(LfObjectUniforms));

inline std::vector<BlockMember> object_block_members() {
    return std140_block_members(kObjectBlockFields, "");
}

// The layers' block LfLayerBlock of layered materials (shaders/scene.frag, LfLayerUniforms of the
// shared header): seven vec4s (offsets is an array of two, stride 16) and four ints.
using shading::LfLayerUniforms;
inline constexpr Std140Field kLayerBlockFields[] = {
    LF_STD140(LfLayerUniforms, weights, Vec4),
    LF_STD140(LfLayerUniforms, strengths, Vec4),
    LF_STD140(LfLayerUniforms, scales, Vec4),
    LF_STD140(LfLayerUniforms, lean_offsets, Vec4),
    LF_STD140(LfLayerUniforms, tilings, Vec4),
    LF_STD140(LfLayerUniforms, offsets, Vec4, 2),
    LF_STD140(LfLayerUniforms, count, Int),
    LF_STD140(LfLayerUniforms, mixing, Int),
    LF_STD140(LfLayerUniforms, weight_map, Int),
    LF_STD140(LfLayerUniforms, padding, Int),
};
static_assert(std140_matches_cpp(kLayerBlockFields));
static_assert(std140_struct_size(kLayerBlockFields) == sizeof(LfLayerUniforms));

inline std::vector<BlockMember> layer_block_members() {
    return std140_block_members(kLayerBlockFields, "u_layers.");
}

#undef LF_STD140

}  // namespace leanfade::gl
