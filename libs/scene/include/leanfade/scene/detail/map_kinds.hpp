#pragma once
// The surface maps a material may carry besides its bump map, described once: the renderer's
// upload and bind loop, the uniform block's map mask, scene validation, the command line and the
// docs read this table (docs/architecture.md, "Add a map kind"). GL-free: formats and units are
// named here, the renderer turns them into GL enums.
//
// A scene holds, per kind, a list of textures (Scene::maps), each a MIP chain of images (rows top
// first, uploaded flipped so that +v is up, repeating, trilinear); a material points at one
// texture of each kind or at none (Material::maps, -1).
#include <array>
#include <cstddef>
#include <string>
#include <string_view>

#include "leanfade/core/shading.hpp"

namespace leanfade::scene {

enum class MapKind {
    BaseColor,
    BaseRoughness,
    Plateau,
    Metallic,
    Occlusion,
    Emissive,
    Anisotropy,
    RoughnessMips,
};
inline constexpr std::size_t kMapKindCount = 8;

// The texture's storage on the GPU.
enum class MapFormat {
    Rgba16f,  // 4 channels, half float
    R32f,     // 1 channel, float (values far below half floats' normal range)
};
// How the texture's MIP chain is made.
enum class MapMips {
    Generated,  // the scene holds level 0; the GPU box-filters the rest
    Given,      // the scene holds every level, filtered on the CPU (a full chain down to 1x1)
};
// What the shader reads for a material without the map.
enum class MapFallback {
    White,  // a 1x1 white texture: a factor of 1
    None,   // nothing bound; the map's bit in LfShadingUniforms::maps is 0 and the shader uses
            // the frame's uniform value instead
};

struct MapKindInfo {
    MapKind kind;
    std::string_view name;     // for people and messages: "base colour"
    std::string_view setting;  // the setting (and flag, `--` + setting) that gives the map to
                               // the bump source's material, or "" when none does
    // The shaders' name: LF_BINDING_<name> (its unit), LF_MAP_<name> (its bit) and the sampler
    // u_<name in lower case>, generated into shaders/map_kinds.glsl (map_kinds_glsl()).
    std::string_view glsl_name;
    int binding;               // texture unit
    int mask_bit;              // its bit in LfShadingUniforms::maps
    int uv_transform;          // its texture coordinate transform in
                               // LfShadingUniforms::uv_transforms (LF_UV_* of
                               // shaders/lean_shading.glsl)
    int channels;              // of each level's image
    MapFormat format;
    MapMips mips;
    MapFallback fallback;
    bool cook_torrance_only;   // read by the Cook-Torrance BRDF only (Blinn-Phong ignores it)
    bool lean_sampler_state;   // takes the LEAN map's MIP bias and anisotropy (read with the
                               // moments, as one texture)
    // The shader variants that declare its sampler: those that define this ("" : every one).
    std::string_view variant_define;
    std::string_view gltf_source;  // where a glTF material's map comes from, or ""
    std::string_view meaning;      // what a texel holds (units), one line for docs and help
};

inline constexpr std::array<MapKindInfo, kMapKindCount> kMapKinds{{
    // kind, name, setting, GLSL name, unit, bit, uv transform, channels, format, mips, fallback,
    // Cook-Torrance only, LEAN sampler state, variant define, glTF source, meaning
    {MapKind::BaseColor, "base colour texture", "", "BASE_COLOR", 1, 1,
     shading::LF_UV_BASE_COLOR, 4, MapFormat::Rgba16f, MapMips::Generated, MapFallback::White,
     false, false, "", "pbrMetallicRoughness.baseColorTexture",
     "linear RGB (sRGB decoded) and alpha; Kd is multiplied by its RGB"},
    {MapKind::BaseRoughness, "roughness map", "roughness-map", "BASE_ROUGHNESS", 2, 2,
     shading::LF_UV_BASE_ROUGHNESS, 1, MapFormat::R32f, MapMips::Given, MapFallback::None, true,
     true, "", "",
     "Cook-Torrance's alpha0^2 = r^4 (dimensionless), filtered linearly like the moments "
     "(docs/math.md §9)"},
    {MapKind::Plateau, "plateau layer", "", "PLATEAU", 3, 4, shading::LF_UV_LEAN_MAP, 4,
     MapFormat::Rgba16f, MapMips::Given, MapFallback::None, false, true, "LF_READS_PLATEAU", "",
     "two-lobe LEAN's (f, f Bs.x, f Bs.y, f |Bs|^2): the fraction of texels on a plateau and "
     "their slopes (slope units), filtered linearly like the moments (docs/math.md §10)"},
    {MapKind::Metallic, "metallic map", "", "METALLIC", 4, 8, shading::LF_UV_METALLIC, 1,
     MapFormat::R32f, MapMips::Generated, MapFallback::White, false, false, "",
     "pbrMetallicRoughness.metallicRoughnessTexture (B)",
     "metalness in [0, 1], times the material's metallic factor: F0 = mix(f0, base colour, m) "
     "and Kd (1 - m) with Cook-Torrance, Ks = mix(Ks, base colour, m) with Blinn-Phong"},
    {MapKind::Occlusion, "occlusion map", "", "OCCLUSION", 5, 16, shading::LF_UV_OCCLUSION, 1,
     MapFormat::R32f, MapMips::Generated, MapFallback::White, false, false, "",
     "occlusionTexture (R)",
     "ambient occlusion in [0, 1]: the ambient term Ka times 1 + strength (occlusion - 1)"},
    {MapKind::Emissive, "emissive texture", "", "EMISSIVE", 6, 32, shading::LF_UV_EMISSIVE, 4,
     MapFormat::Rgba16f, MapMips::Generated, MapFallback::White, false, false, "",
     "emissiveTexture",
     "linear RGB (sRGB decoded) times the material's emissive factor: radiance added to the "
     "colour"},
    {MapKind::Anisotropy, "anisotropy texture", "", "ANISOTROPY", 7, 64,
     shading::LF_UV_ANISOTROPY, 4, MapFormat::Rgba16f, MapMips::Generated, MapFallback::None,
     true, false, "", "KHR_materials_anisotropy.anisotropyTexture",
     "RG: the direction of the base roughness's stretch in tangent space (2 RG - 1, rotated by "
     "the material's anisotropy rotation), B: its strength (times the material's); alpha 1"},
    {MapKind::RoughnessMips, "engine roughness MIPs", "roughness-mips", "ROUGHNESS_MIPS", 9, 128,
     shading::LF_UV_LEAN_MAP, 1, MapFormat::R32f, MapMips::Given, MapFallback::None, false, true,
     "LF_ROUGHNESS_MIPS", "",
     "another tool's glTF perceptual roughness r in [0, 1] per MIP level (Filament's "
     "roughness-prefilter, for one): the roughness technique reads it in place of the r it "
     "derives from the LEAN map (docs/roughness.md)"},
}};

// Every row sits at the position of its enum value, and each has its own bit, unit and texture
// coordinate transform within the uniform block's (the plateau layer and the roughness MIPs take
// the LEAN map's).
constexpr bool map_kind_table_is_ordered() {
    for (std::size_t i = 0; i < kMapKinds.size(); ++i) {
        if (std::size_t(kMapKinds[i].kind) != i) return false;
        if (kMapKinds[i].uv_transform < 0 ||
            kMapKinds[i].uv_transform >= shading::LF_UV_TRANSFORM_COUNT)
            return false;
        for (std::size_t j = 0; j < i; ++j)
            if ((kMapKinds[i].mask_bit & kMapKinds[j].mask_bit) != 0 ||
                kMapKinds[i].binding == kMapKinds[j].binding)
                return false;
    }
    return true;
}
static_assert(map_kind_table_is_ordered());

constexpr const MapKindInfo& info(MapKind kind) { return kMapKinds[std::size_t(kind)]; }

// The shader files the table makes, generated, never edited (MapKinds.ShaderFilesAreTheTable
// compares them; `make shader-tables` writes them again):
// shaders/map_kinds.glsl: per row its unit LF_BINDING_<name> and bit LF_MAP_<name> (included by
// shaders/bindings.glsl, so also by its C++ view, leanfade::bindings);
std::string map_kinds_glsl();
// shaders/map_samplers.glsl: every row's sampler u_<name>, within #if defined(<variant define>)
// where the row has one (included by scene.frag, which reads the maps).
std::string map_samplers_glsl();

}  // namespace leanfade::scene
