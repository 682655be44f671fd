#pragma once
// C++ view of shaders/bindings.glsl: texture units, uniform-block binding points, surface-map
// bits and texture-array slices, named once for the shaders and the renderer.
namespace leanfade::bindings {
#include "bindings.glsl"
}  // namespace leanfade::bindings
