#pragma once
// C++ view of the shared shading header shaders/lean_shading.glsl (docs/math.md §4). The very same
// source is included by the GLSL shaders, so the CPU reference and the GPU agree by construction.
#include <cmath>

#include <glm/glm.hpp>

#include "leanfade/core/settings.hpp"

namespace leanfade::shading {
struct LfParams;
// to_lf_params(ShadingSettings{}, false): the parameter table's defaults as LfParams
// (settings.cpp), the value of a default-constructed LfShadingUniforms::params.
LfParams lf_default_params();
using namespace glm;
using std::exp;
using std::pow;
using std::sqrt;
#define LF_FN inline
#define LF_DEFAULT(value) = value
// Rows (1, 0, 0, 0), (0, 1, 0, 0) of each of the LF_UV_TRANSFORM_COUNT slots (checked below).
#define LF_UV_IDENTITY_ROWS vec4(1.0f, 0.0f, 0.0f, 0.0f), vec4(0.0f, 1.0f, 0.0f, 0.0f)
#define LF_UV_TRANSFORMS_IDENTITY                                                          \
    = {LF_UV_IDENTITY_ROWS, LF_UV_IDENTITY_ROWS, LF_UV_IDENTITY_ROWS, LF_UV_IDENTITY_ROWS, \
       LF_UV_IDENTITY_ROWS, LF_UV_IDENTITY_ROWS, LF_UV_IDENTITY_ROWS}
#include "lean_shading.glsl"
static_assert(LF_UV_TRANSFORM_COUNT == 7, "LF_UV_TRANSFORMS_IDENTITY names one identity per slot");
#undef LF_UV_TRANSFORMS_IDENTITY
#undef LF_UV_IDENTITY_ROWS
#undef LF_DEFAULT
#undef LF_FN
}  // namespace leanfade::shading
