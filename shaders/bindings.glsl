// Texture units, uniform-block binding points and texture-array slices shared by the renderer
// (C++, libs/gl/include/leanfade/gl/detail/shading_block.hpp) and the shaders: each is named once, here.
#ifndef LEANFADE_BINDINGS_GLSL
#define LEANFADE_BINDINGS_GLSL

const int LF_BINDING_LEAN_MAP = 0;       // texture unit of the LEAN map (2D array, 2 slices)
const int LF_BINDING_SHADING_BLOCK = 0;  // uniform block LfShadingBlock (LfShadingUniforms)
const int LF_BINDING_OBJECT_BLOCK = 1;   // uniform block LfObjectBlock of the vertex stage
// The material's surface maps (leanfade/scene/detail/map_kinds.hpp): each a texture unit and a bit of
// LfShadingUniforms::maps, set when the material has the map and the shader reads it.
// Base colour (2D, linear RGBA; Kd is multiplied by its RGB; a 1x1 white texture for materials
// without one).
const int LF_BINDING_BASE_COLOR = 1;
const int LF_MAP_BASE_COLOR = 1;
// Base roughness (2D, R32F: alpha0^2 per texel with its MIP chain filtered as the moments,
// docs/math.md §9), read with Cook-Torrance when its bit is set.
const int LF_BINDING_BASE_ROUGHNESS = 2;
const int LF_MAP_BASE_ROUGHNESS = 2;
// Plateau layer of two-lobe LEAN (2D, RGBA16F: (f, f Bs.x, f Bs.y, f |Bs|^2) with its MIP chain
// filtered as the moments are, docs/math.md §10), read by the two-lobe technique when its bit is
// set; without it f = 0 and two-lobe shades as LEAN.
const int LF_BINDING_PLATEAU = 3;
const int LF_MAP_PLATEAU = 4;
// Metalness (2D, R32F: the glTF metallic-roughness texture's B), times the material's metallic
// factor (LfMaterialFactors::metallic); a 1x1 white texture for materials without one.
const int LF_BINDING_METALLIC = 4;
const int LF_MAP_METALLIC = 8;
// Ambient occlusion (2D, R32F: the glTF occlusion texture's R), weighed by the material's
// occlusion strength (LfMaterialFactors::occlusion_strength); white for materials without one.
const int LF_BINDING_OCCLUSION = 5;
const int LF_MAP_OCCLUSION = 16;
// Emission (2D, linear RGBA, sRGB decoded), times the material's emissive factor
// (LfMaterialFactors::emissive); white for materials without one.
const int LF_BINDING_EMISSIVE = 6;
const int LF_MAP_EMISSIVE = 32;
// Anisotropy of the base roughness (2D, RGBA16F: KHR_materials_anisotropy's texture, RG the
// direction in [0, 1] encoding, B the strength), read with Cook-Torrance when its bit is set;
// without it the direction is the tangent's and the strength the material's.
const int LF_BINDING_ANISOTROPY = 7;
const int LF_MAP_ANISOTROPY = 64;
// Another tool's roughness MIPs (2D, R32F, every level: perceptual r), read by the roughness
// technique in place of its own r when its bit is set (`--roughness-mips`, docs/roughness.md).
const int LF_BINDING_ROUGHNESS_MIPS = 9;
const int LF_MAP_ROUGHNESS_MIPS = 128;

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
