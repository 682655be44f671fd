// The material's surface maps (leanfade/scene/detail/map_kinds.hpp, kMapKinds): each a
// texture unit LF_BINDING_* and a bit LF_MAP_* of LfShadingUniforms::maps, set when the
// material has the map and the shader reads it (its sampler: map_samplers.glsl).
// Generated from the table by scene::map_kinds_glsl(): do not edit; `make shader-tables`
// writes it again and the test MapKinds.ShaderFilesAreTheTable compares the two.
#ifndef LEANFADE_MAP_KINDS_GLSL
#define LEANFADE_MAP_KINDS_GLSL

// base colour texture: linear RGB (sRGB decoded) and alpha; Kd is multiplied by its RGB
const int LF_BINDING_BASE_COLOR = 1;
const int LF_MAP_BASE_COLOR = 1;

// roughness map: Cook-Torrance's alpha0^2 = r^4 (dimensionless), filtered linearly like the moments
// (docs/math.md §9)
const int LF_BINDING_BASE_ROUGHNESS = 2;
const int LF_MAP_BASE_ROUGHNESS = 2;

// plateau layer: two-lobe LEAN's (f, f Bs.x, f Bs.y, f |Bs|^2): the fraction of texels on a plateau
// and their slopes (slope units), filtered linearly like the moments (docs/math.md §10)
const int LF_BINDING_PLATEAU = 3;
const int LF_MAP_PLATEAU = 4;

// metallic map: metalness in [0, 1], times the material's metallic factor: F0 = mix(f0, base
// colour, m) and Kd (1 - m) with Cook-Torrance, Ks = mix(Ks, base colour, m) with Blinn-Phong
const int LF_BINDING_METALLIC = 4;
const int LF_MAP_METALLIC = 8;

// occlusion map: ambient occlusion in [0, 1]: the ambient term Ka times 1 + strength (occlusion -
// 1)
const int LF_BINDING_OCCLUSION = 5;
const int LF_MAP_OCCLUSION = 16;

// emissive texture: linear RGB (sRGB decoded) times the material's emissive factor: radiance added
// to the colour
const int LF_BINDING_EMISSIVE = 6;
const int LF_MAP_EMISSIVE = 32;

// anisotropy texture: RG: the direction of the base roughness's stretch in tangent space (2 RG - 1,
// rotated by the material's anisotropy rotation), B: its strength (times the material's); alpha 1
const int LF_BINDING_ANISOTROPY = 7;
const int LF_MAP_ANISOTROPY = 64;

// engine roughness MIPs: another tool's glTF perceptual roughness r in [0, 1] per MIP level
// (Filament's roughness-prefilter, for one): the roughness technique reads it in place of the r it
// derives from the LEAN map (docs/roughness.md)
const int LF_BINDING_ROUGHNESS_MIPS = 9;
const int LF_MAP_ROUGHNESS_MIPS = 128;

// specular map: linear RGB in [0, 1] that scales the specular colour: Ks with Blinn-Phong, the
// dielectric's F0 with Cook-Torrance (as KHR_materials_specular's specular colour)
const int LF_BINDING_SPECULAR = 8;
const int LF_MAP_SPECULAR = 256;

#endif  // LEANFADE_MAP_KINDS_GLSL
