// The samplers of the material's surface maps (leanfade/scene/detail/map_kinds.hpp,
// kMapKinds), at their units (map_kinds.glsl); a map whose row names a variant define is
// declared in the variants that define it. Included by scene.frag, which reads the maps.
// Generated from the table by scene::map_samplers_glsl(): do not edit; `make
// shader-tables` writes it again and the test MapKinds.ShaderFilesAreTheTable compares
// the two.
#ifndef LEANFADE_MAP_SAMPLERS_GLSL
#define LEANFADE_MAP_SAMPLERS_GLSL

layout(binding = LF_BINDING_BASE_COLOR) uniform sampler2D u_base_color;
layout(binding = LF_BINDING_BASE_ROUGHNESS) uniform sampler2D u_base_roughness;
#if defined(LF_READS_PLATEAU)
layout(binding = LF_BINDING_PLATEAU) uniform sampler2D u_plateau;
#endif
layout(binding = LF_BINDING_METALLIC) uniform sampler2D u_metallic;
layout(binding = LF_BINDING_OCCLUSION) uniform sampler2D u_occlusion;
layout(binding = LF_BINDING_EMISSIVE) uniform sampler2D u_emissive;
layout(binding = LF_BINDING_ANISOTROPY) uniform sampler2D u_anisotropy;
#if defined(LF_ROUGHNESS_MIPS)
layout(binding = LF_BINDING_ROUGHNESS_MIPS) uniform sampler2D u_roughness_mips;
#endif
layout(binding = LF_BINDING_SPECULAR) uniform sampler2D u_specular;

#endif  // LEANFADE_MAP_SAMPLERS_GLSL
