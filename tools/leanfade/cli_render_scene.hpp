#pragma once
// The one place where the commands that render (`render`, `view`, `eval`, `calibrate`, `bench`)
// build what they draw: a scene::Scene of objects, materials and maps, from the scene name, the
// bump flags and the bump-layer flags. Every kind of scene and material enters here, so that
// every command draws it alike.
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli_ocean.hpp"
#include "cli_render_options.hpp"
#include "leanfade/core/layers.hpp"
#include "leanfade/core/settings.hpp"
#include "leanfade/scene/material.hpp"

namespace leanfade::cli {

// --scene plane with a map of one's own (not a built-in set): its uv (0..50, a repeat per 0.4
// world units of the 20 x 20 plane) times this, so that the map repeats 5 times across.
inline constexpr float kUserMapPlaneUvScale = 0.1f;

struct RenderSourceFlags {
    std::string scene = "teapot";  // --scene: a built-in object or an .obj file
    LeanSourceFlags bumps;         // --bumps and the flags of its bake (also the layers' bake)
    // --layers SRC,SRC[,...] (empty: the one map of --bumps), --layer-weights W,W,...,
    // --layer-strengths K,K,..., --layer-tiling T,T,..., --layer-velocity U:V,U:V,...,
    // --layer-weight-map FILE and --mixing (docs/math.md §6).
    LayerSettings layers;
    OceanFlags ocean;  // --scene ocean: --ocean-layers, --flow (cli_ocean.hpp)
};

// --layers --layer-weights --layer-strengths --layer-tiling --layer-velocity --layer-weight-map
// --mixing, in the "Bump layers" group (the mixing methods' names and help from kLayerMixings).
void add_layer_options(CLI::App& app, LayerSettings& layers);
// "--layers" and "--mixing"'s text as a report names them: "bumps,noise (textures)".
std::string layers_text(const LayerSettings& layers);

// The scene the flags describe: one object (its mesh from scene::make_scene_mesh) with one
// material. Without --layers the material has the one LEAN map of load_lean_map. With --layers
// each source is baked (or read) at strength 1 in the storage of --bits, without baked
// roughness, and the material mixes them: `textures` with the cross-term texture of every pair,
// `approx` without, `height` as one map baked from the mixed slopes (static layers; moving
// layers are refused). With --roughness-map (Cook-Torrance only; not for the ocean or glTF
// scenes) every material gets the map's α0² chain (leanfade::base_alpha_squared_mips).
// `settings` gives the height scale of on-the-fly bakes. Throws leanfade::Error naming the file
// or the flag.
scene::Scene load_render_scene(const RenderSourceFlags& flags, const ShadingSettings& settings);

// One bump layer's float LEAN map: a built-in set, an image (baked with `settings`' height
// scale, the --from and --directx of `f`) or a .ktx2 map (refused with roughness baked in).
LeanMap load_layer_map(const std::string& source, const LeanSourceFlags& f,
                       const ShadingSettings& settings);
// The 2-channel slopes B of a map's finest level.
Image top_slopes(const LeanMap& map);

// The existing files the flags read, and `extra` (a preset) when it exists: the inputs of the
// output plan (an output must not overwrite an input).
std::vector<std::string> render_source_inputs(const RenderSourceFlags& flags,
                                              const std::string& extra = {});

}  // namespace leanfade::cli
