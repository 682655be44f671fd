// Texture units, uniform-block binding points and texture-array slices shared by the renderer
// (C++, libs/gl/include/leanfade/gl/shading_block.hpp) and the shaders: each is named once, here.
#ifndef LEANFADE_BINDINGS_GLSL
#define LEANFADE_BINDINGS_GLSL

const int LF_BINDING_LEAN_MAP = 0;       // texture unit of the LEAN map (2D array, 2 slices)
const int LF_BINDING_SHADING_BLOCK = 0;  // uniform block LfShadingBlock (LfShadingUniforms)
const int LF_BINDING_OBJECT_BLOCK = 1;   // uniform block LfObjectBlock of the vertex stage

// Slices of the LEAN map's texture array (docs/math.md §3).
const float LF_SLICE_LEAN1 = 0.0f;  // (0.5 n + 0.5, 0.5 Mxy / sc^2 + 0.5)
const float LF_SLICE_LEAN2 = 1.0f;  // (0.5 B / sc + 0.5, Mxx / sc^2, Myy / sc^2)

#endif  // LEANFADE_BINDINGS_GLSL
