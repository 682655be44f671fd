#pragma once
// C++ view of the shared shading header shaders/lean_shading.glsl (docs/math.md §4). The very same
// source is included by the GLSL shaders, so the CPU reference and the GPU agree by construction.
#include <cmath>

#include <glm/glm.hpp>

namespace leanfade::shading {
using namespace glm;
using std::exp;
using std::pow;
using std::sqrt;
#define LF_FN inline
#define LF_DEFAULT(value) = value
#include "lean_shading.glsl"
#undef LF_DEFAULT
#undef LF_FN
}  // namespace leanfade::shading
