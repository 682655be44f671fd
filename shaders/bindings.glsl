// Texture units, uniform-block binding points and texture-array slices shared by the renderer
// (C++, libs/gl/include/leanfade/gl/detail/shading_block.hpp) and the shaders: each is named once, here.
#ifndef LEANFADE_BINDINGS_GLSL
#define LEANFADE_BINDINGS_GLSL

const int LF_BINDING_LEAN_MAP = 0;       // texture unit of the LEAN map (2D array, 2 slices)
const int LF_BINDING_SHADING_BLOCK = 0;  // uniform block LfShadingBlock (LfShadingUniforms)
const int LF_BINDING_OBJECT_BLOCK = 1;   // uniform block LfObjectBlock of the vertex stage
// The material's surface maps: a texture unit LF_BINDING_* and a bit LF_MAP_* of
// LfShadingUniforms::maps each, generated from their table (leanfade/scene/detail/map_kinds.hpp).
#include "map_kinds.glsl"

// Slices of the LEAN map's texture array (docs/math.md §3).
const float LF_SLICE_LEAN1 = 0.0f;  // (0.5 n + 0.5, 0.5 Mxy / sc^2 + 0.5)
const float LF_SLICE_LEAN2 = 1.0f;  // (0.5 B / sc + 0.5, Mxx / sc^2, Myy / sc^2)

// Bump layers of a layered material (docs/math.md §6): a LEAN map per layer (units
// LF_BINDING_LAYER_MAPS + i, 2D arrays of 2 slices like the LEAN map), the cross-term textures of
// the pairs (one 2D array, a slice per pair in pair_index order, RGBA = Bi.x Bj.x, Bi.y Bj.y,
// Bi.x Bj.y, Bj.x Bi.y), the per-texel weights (RGBA = t_0..t_3) and the layers' uniform block.
const int LF_BINDING_LAYER_MAPS = 10;    // units 10..13
const int LF_BINDING_CROSS_TERMS = 14;
const int LF_BINDING_LAYER_WEIGHTS = 15;
const int LF_BINDING_LAYER_BLOCK = 2;  // uniform block LfLayerBlock (LfLayerUniforms)

// What the vertex stage hands the fragment stage (interface block VertexData, locations 0-4 in
// this order), each member once as X(type, name):
//   uv         tiled texture coordinates, set 0
//   light_t    direction toward the light, tangent space (normalised per fragment)
//   view_t     Vt: vector to the eye, tangent space, world units (not normalised)
//   eye_depth  distance along the view axis, world units
//   uv1        tiled texture coordinates, set 1
//   linear_normal_change  how far the mesh's normal field is linear (scene::Vertex)
// WGSL has no interface blocks: with LF_SEPARATE_VARYINGS (`leanfade shaders --lang wgsl`) the
// members are variables lf_vertex_<name> at the same locations, copied from/to a private
// VertexData.
#define LF_VERTEX_DATA(X)                                                              \
    X(vec2, uv) X(vec3, light_t) X(vec3, view_t) X(float, eye_depth) X(vec2, uv1) \
    X(float, linear_normal_change)
#define LF_VERTEX_MEMBER(type, name) type name;
#define LF_VERTEX_OUTPUT(type, name) out type lf_vertex_##name;
#define LF_VERTEX_INPUT(type, name) in type lf_vertex_##name;
#define LF_VERTEX_STORE(type, name) lf_vertex_##name = v_out.name;
#define LF_VERTEX_LOAD(type, name) v_in.name = lf_vertex_##name;

#endif  // LEANFADE_BINDINGS_GLSL
