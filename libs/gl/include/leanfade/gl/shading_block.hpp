#pragma once
// The C++ side of the fragment stage's uniform block and texture bindings (shaders/bindings.glsl,
// the structs LfParams and LfShadingUniforms of shaders/lean_shading.glsl). Both sides compile
// the same struct definitions; the std140 offsets the GLSL block gets are written out below and
// checked against the C++ layout here, and against the GL driver's reported offsets in
// tests/gl/test_shaders.cpp (UniformBlock.*).
#include <cstddef>

#include <glm/mat4x4.hpp>

#include "leanfade/core/shading.hpp"

namespace leanfade::gl {

namespace bindings {
#include "bindings.glsl"
}  // namespace bindings

using shading::LfParams;
using shading::LfShadingUniforms;

// std140 offsets of LfParams: a vec3 takes 16-byte alignment and 12 bytes, so the scalar after
// it fills its fourth component.
static_assert(offsetof(LfParams, light_color) == 0);
static_assert(offsetof(LfParams, shininess) == 12);
static_assert(offsetof(LfParams, ambient) == 16);
static_assert(offsetof(LfParams, inv_s_shading) == 28);
static_assert(offsetof(LfParams, kd) == 32);
static_assert(offsetof(LfParams, fresnel_bias) == 44);
static_assert(offsetof(LfParams, ks) == 48);
static_assert(offsetof(LfParams, fresnel_scale) == 60);
static_assert(offsetof(LfParams, fade) == 64);
static_assert(offsetof(LfParams, pmax) == 68);
static_assert(offsetof(LfParams, fade_exponent) == 72);
static_assert(offsetof(LfParams, fade_distance) == 76);
static_assert(offsetof(LfParams, f0) == 80);
static_assert(offsetof(LfParams, brdf) == 92);
static_assert(sizeof(LfParams) == 96, "a std140 struct is a multiple of 16 bytes");

static_assert(offsetof(LfShadingUniforms, params) == 0);
static_assert(offsetof(LfShadingUniforms, scale) == 96);
static_assert(offsetof(LfShadingUniforms, output_mode) == 100);
static_assert(offsetof(LfShadingUniforms, fog_mode) == 104);
static_assert(offsetof(LfShadingUniforms, fog_start) == 108);
static_assert(offsetof(LfShadingUniforms, fog_color) == 112);
static_assert(offsetof(LfShadingUniforms, fog_end) == 124);
static_assert(offsetof(LfShadingUniforms, fog_density) == 128);
static_assert(offsetof(LfShadingUniforms, roughness_map) == 132);
// std140 rounds the struct up to 144 bytes; the last 8 are padding, not uploaded.
static_assert(sizeof(LfShadingUniforms) == 136);
inline constexpr std::size_t kShadingBlockStd140Size = 144;

// Each member's name in the GL program (as glGetProgramResourceIndex knows it) and its C++
// offset: what the driver reports must be the same.
struct BlockMember {
    const char* name;
    std::size_t offset;
};
#define LF_PARAM(member)                                                     \
    {                                                                        \
        "u_shading.params." #member,                                         \
            offsetof(LfShadingUniforms, params) + offsetof(LfParams, member) \
    }
#define LF_UNIFORM(member) \
    { "u_shading." #member, offsetof(LfShadingUniforms, member) }
inline constexpr BlockMember kShadingBlockMembers[] = {
    LF_PARAM(light_color),
    LF_PARAM(shininess),
    LF_PARAM(ambient),
    LF_PARAM(inv_s_shading),
    LF_PARAM(kd),
    LF_PARAM(fresnel_bias),
    LF_PARAM(ks),
    LF_PARAM(fresnel_scale),
    LF_PARAM(fade),
    LF_PARAM(pmax),
    LF_PARAM(fade_exponent),
    LF_PARAM(fade_distance),
    LF_PARAM(f0),
    LF_PARAM(brdf),
    LF_UNIFORM(scale),
    LF_UNIFORM(output_mode),
    LF_UNIFORM(fog_mode),
    LF_UNIFORM(fog_start),
    LF_UNIFORM(fog_color),
    LF_UNIFORM(fog_end),
    LF_UNIFORM(fog_density),
    LF_UNIFORM(roughness_map),
};
#undef LF_PARAM
#undef LF_UNIFORM

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
static_assert(offsetof(LfObjectUniforms, model) == 0);
static_assert(offsetof(LfObjectUniforms, view) == 64);
static_assert(offsetof(LfObjectUniforms, clip) == 128);
static_assert(offsetof(LfObjectUniforms, normal_matrix) == 192);
static_assert(offsetof(LfObjectUniforms, eye_world) == 240);
static_assert(offsetof(LfObjectUniforms, tiling) == 252);
static_assert(offsetof(LfObjectUniforms, light_world) == 256);
static_assert(sizeof(LfObjectUniforms) == 272);

inline constexpr BlockMember kObjectBlockMembers[] = {
    {"u_model", offsetof(LfObjectUniforms, model)},
    {"u_view", offsetof(LfObjectUniforms, view)},
    {"u_clip", offsetof(LfObjectUniforms, clip)},
    {"u_normal_matrix", offsetof(LfObjectUniforms, normal_matrix)},
    {"u_eye_world", offsetof(LfObjectUniforms, eye_world)},
    {"u_tiling", offsetof(LfObjectUniforms, tiling)},
    {"u_light_world", offsetof(LfObjectUniforms, light_world)},
};

// The layers' block LfLayerBlock of layered materials (shaders/scene.frag, LfLayerUniforms of the
// shared header): six vec4s (offsets is an array of two, stride 16) and four ints.
using shading::LfLayerUniforms;
static_assert(offsetof(LfLayerUniforms, weights) == 0);
static_assert(offsetof(LfLayerUniforms, strengths) == 16);
static_assert(offsetof(LfLayerUniforms, scales) == 32);
static_assert(offsetof(LfLayerUniforms, tilings) == 48);
static_assert(offsetof(LfLayerUniforms, offsets) == 64);
static_assert(offsetof(LfLayerUniforms, count) == 96);
static_assert(offsetof(LfLayerUniforms, mixing) == 100);
static_assert(offsetof(LfLayerUniforms, weight_map) == 104);
static_assert(sizeof(LfLayerUniforms) == 112);

inline constexpr BlockMember kLayerBlockMembers[] = {
    {"u_layers.weights", offsetof(LfLayerUniforms, weights)},
    {"u_layers.strengths", offsetof(LfLayerUniforms, strengths)},
    {"u_layers.scales", offsetof(LfLayerUniforms, scales)},
    {"u_layers.tilings", offsetof(LfLayerUniforms, tilings)},
    {"u_layers.offsets[0]", offsetof(LfLayerUniforms, offsets)},
    {"u_layers.count", offsetof(LfLayerUniforms, count)},
    {"u_layers.mixing", offsetof(LfLayerUniforms, mixing)},
    {"u_layers.weight_map", offsetof(LfLayerUniforms, weight_map)},
    {"u_layers.padding", offsetof(LfLayerUniforms, padding)},
};

}  // namespace leanfade::gl
