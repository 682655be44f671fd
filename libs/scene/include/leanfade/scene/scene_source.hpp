#pragma once
// What a renderer draws, described by settings: a built-in object, an OBJ file (with or without
// its MTL maps), a glTF scene or the ocean, with the bump map or the bump layers of its material
// and the surface maps of kMapKinds. build_scene turns a SceneSource into a Scene (its LEAN maps
// read, or baked on the fly); the command line's render, view, eval, calibrate and bench build
// every scene here, and so can an engine's tool.
//
// Errors name settings ("layers", "roughness-map", "ocean_layers") or files, never flags; what a
// build repaired or doubts is returned in a SceneSourceReport, as data, for the caller to word.
#include <array>
#include <string>
#include <utility>
#include <vector>

#include "leanfade/core/detail/bump_source.hpp"
#include "leanfade/core/image.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/settings.hpp"
#include "leanfade/scene/detail/ocean.hpp"
#include "leanfade/scene/detail/scene.hpp"

namespace leanfade::scene {

// One bump map (BumpSource) and the settings of its bake on the fly.
struct BumpMapSource : BumpSource {
    // These bumps replace the maps an OBJ's MTL files name (otherwise an OBJ with MTL materials
    // brings its own).
    bool replaces_obj_maps = false;
    bool strict_normals = false;  // normal maps: refuse texels with z <= 0 (NormalRepairs)
    StrengthUnit strength_unit = StrengthUnit::Texel;  // height maps: strength per texel or uv
    SpikeFit spike = SpikeFit::Auto;                   // BakeOptions::spike_fit
    int max_size = kDefaultMaxImageDimension;          // images and .ktx2 maps, texels per side
    // The surface maps that settings give the material of the bumps or layers, by kind: the file
    // of each kMapKinds row with a setting ("roughness-map", "roughness-mips", "specular-map"),
    // read as the row's file_read says; empty: none. Kinds without a setting stay empty.
    std::array<std::string, kMapKindCount> map_files{};
    std::string& map_file(MapKind kind) { return map_files[std::size_t(kind)]; }
    const std::string& map_file(MapKind kind) const { return map_files[std::size_t(kind)]; }
};

// The built-in ocean's source settings (OceanSettings gets the wave tiles' size and seed from the
// bump source).
struct OceanSource {
    int layers = 2;             // wave layers, 2..kMaxLayers
    std::string flow = "none";  // none | gyre | an RG flow-map image
};

struct SceneSource {
    std::string scene =
        "teapot";          // a built-in object (kBuiltinScenes), an .obj, a .gltf/.glb, "ocean"
    BumpMapSource bumps;   // the material's one map (built-in objects and OBJ files)
    LayerSettings layers;  // 2-4 layers instead of `bumps` (docs/math.md §6)
    OceanSource ocean;     // scene "ocean"
};

// A normal map whose slopes fit the other convention clearly better (check_normal_convention).
struct ConventionDoubt {
    std::string file;              // the image
    bool read_as_directx = false;  // the convention it was read in
    double ratio = 0.0;            // curl as read / curl flipped; 0 where not measured (glTF)
    bool gltf = false;             // a glTF normal texture (OpenGL by the specification)
};

// What a build found, in the order met: `warnings` about the scene file (SceneSource::scene)
// and files it names, `repaired` normal maps (by file), `doubts` about conventions.
struct SceneSourceReport {
    std::vector<std::string> warnings;
    std::vector<std::pair<std::string, NormalRepairs>> repaired;
    std::vector<ConventionDoubt> doubts;
};

// A map of one's own on the plane scene (not a built-in set): the plane's uv (0..50, a repeat per
// 0.4 world units of the 20 x 20 plane) times this, so that the map repeats 5 times across.
inline constexpr float kUserMapPlaneUvScale = 0.1f;
// The scene name of the built-in ocean.
inline constexpr const char* kOceanSceneName = "ocean";

bool is_ocean_scene(const std::string& scene);
// True for the name of a built-in bump set (builtin_bump_names()).
bool is_builtin_bumps(const std::string& source);

// BakeOptions of an on-the-fly bake: `bump_strength` (height maps) in the source's strength
// unit, its normal-map convention, strict_normals and spike fit.
BakeOptions on_the_fly_bake_options(const BumpMapSource& source, float bump_strength);

// Reads a .ktx2 LEAN map or a `bake --format png` pair (NAME.lean1.png), or bakes one from a
// built-in set or an image with `settings.bump_strength` (storage `source.bits`: automatic
// bakes are probed as `leanfade bake` probes them). Throws leanfade::Error naming the file or
// setting (a normal map with a strength other than the default: "bump_strength").
PackedLeanMap load_lean_map(const BumpMapSource& source, const ShadingSettings& settings,
                            SceneSourceReport* report = nullptr);

// One bump layer's float LEAN map: a built-in set, an image (baked with `settings`' strength and
// the `bumps` settings' from / directx) or a .ktx2 map (refused with roughness baked in).
LeanMap load_layer_map(const std::string& source, const BumpMapSource& bumps,
                       const ShadingSettings& settings, SceneSourceReport* report = nullptr);
// The 2-channel slopes B of a map's finest level.
Image top_slopes(const LeanMap& map);

// The ocean's settings: the wave tiles' size and seed from `bumps` (texture_size, seed), a flow
// image read within `bumps.max_size`. Throws leanfade::Error naming the setting or the file.
OceanSettings ocean_settings(const OceanSource& ocean, const BumpMapSource& bumps);

// The scene of `source`: one object with one material (built-in objects, an OBJ file without
// MTL maps or with bumps that replace them), an OBJ's or glTF's own objects and materials, or
// the ocean; the roughness map and MIPs on every material the settings build; two-lobe LEAN's
// plateau layer on every single-map material. Layers are baked (or read) at strength 1 in the
// storage of `source.bumps.bits` and mixed as `source.layers.mixing` says (`height` with aligned
// static layers: one map baked from the mixed slopes). glTF and OBJ maps are baked through the
// LEAN-map cache (default_lean_cache_folder). Throws leanfade::Error naming the file or the
// setting; `report` (if given) holds what was found, also when it throws.
Scene build_scene(const SceneSource& source, const ShadingSettings& settings,
                  SceneSourceReport* report = nullptr);

// The files a build of `source` reads that exist (the scene, its glTF buffers and images or
// MTL files and textures, the bump map, the layers, the weight, roughness and flow maps and every
// level of the roughness MIPs), and `extra` when it exists: the inputs an output must not
// replace.
std::vector<std::string> scene_source_inputs(const SceneSource& source,
                                             const std::string& extra = {});

}  // namespace leanfade::scene
