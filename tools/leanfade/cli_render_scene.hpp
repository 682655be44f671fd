#pragma once
// The scene flags of the commands that render (`render`, `view`, `eval`, `calibrate`, `bench`):
// they fill a scene::SceneSource, which scene::build_scene turns into what they draw
// (leanfade/scene/scene_source.hpp); the report of the build is printed here.
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli_render_options.hpp"
#include "leanfade/core/detail/layers.hpp"
#include "leanfade/core/settings.hpp"
#include "leanfade/scene/scene_source.hpp"

namespace leanfade::cli {

// The scene flags of the rendering commands: the library's SceneSource (--scene, the bump flags,
// the layer flags, --ocean-layers and --flow) and the ocean's cameras of --views.
struct RenderSourceFlags : scene::SceneSource {
    std::vector<std::string> ocean_views{"near", "mid", "far"};  // --views
};

// --layers --layer-weights --layer-strengths --layer-tiling --layer-velocity --layer-weight-map
// --mixing, in the "Bump layers" group (the mixing methods' names and help from kLayerMixings).
void add_layer_options(CLI::App& app, LayerSettings& layers);
// "--layers" and "--mixing"'s text as a report names them: "bumps,noise (textures)".
std::string layers_text(const LayerSettings& layers);

// scene::build_scene of the flags, its report printed (also when it throws). Throws
// leanfade::Error naming the file or the setting.
scene::Scene load_render_scene(const scene::SceneSource& source, const ShadingSettings& settings);
// scene::load_lean_map of the bump flags, its report printed.
PackedLeanMap load_lean_map_and_report(const scene::BumpMapSource& source,
                                       const ShadingSettings& settings);

}  // namespace leanfade::cli
