// The scene flags of the rendering commands (cli_render_scene.hpp).
#include "cli_render_scene.hpp"

#include <cstdio>

#include "cli_flags.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/core/detail/text.hpp"
#include "leanfade/scene/gltf.hpp"

namespace leanfade::cli {

void add_layer_options(CLI::App& app, LayerSettings& f) {
    const std::string group = "Bump layers (docs/math.md §6)";
    add_typed_option(app, "--layers", f.sources, parse_names,
                     "2-4 bump layers mixed on one surface instead of --bumps: built-in sets, "
                     "height/normal images or .ktx2 maps, comma-separated")
        ->group(group);
    add_typed_option(
        app, "--layer-weights", f.weights,
        [](const std::string& text) { return parse_numbers(text, "--layer-weights"); },
        "Weight t of each layer, comma-separated, summing to 1 (default: equal)")
        ->group(group);
    add_typed_option(
        app, "--layer-strengths", f.strengths,
        [](const std::string& text) { return parse_numbers(text, "--layer-strengths"); },
        "Strength k of each layer: slopes times k, < 0 flips the layer (default: 1)")
        ->group(group);
    add_typed_option(
        app, "--layer-tiling", f.tiling,
        [](const std::string& text) { return parse_numbers(text, "--layer-tiling"); },
        "Repeats of each layer per unit of the tiled uv (default: 1)")
        ->group(group);
    add_typed_option(
        app, "--layer-velocity", f.velocity,
        [](const std::string& text) { return parse_velocities(text, "--layer-velocity"); },
        "Velocity U:V of each layer in uv per second, comma-separated (a moving "
        "layer; render --time sets the moment)")
        ->group(group);
    app.add_option("--layer-weight-map", f.weight_map,
                   "Image whose channels give each layer's weight per texel (RGBA = t_0..t_3, "
                   "normalised per texel), instead of --layer-weights")
        ->group(group);
    std::string help = "How the layers' moments mix:";
    for (const LayerMixingInfo& row : kLayerMixings)
        help += std::string(" ") + row.name + " (" + row.description + ");";
    help.back() = '.';
    add_typed_option(
        app, "--mixing", f.mixing,
        [](const std::string& text) { return parse_layer_mixing(text, "--mixing"); }, help,
        to_string(f.mixing))
        ->group(group);
}

std::string layers_text(const LayerSettings& layers) {
    return join(layers.sources) + " (" + to_string(layers.mixing) + ")";
}

scene::Scene load_render_scene(const scene::SceneSource& source, const ShadingSettings& settings) {
    scene::SceneSourceReport report;
    try {
        scene::Scene result = scene::build_scene(source, settings, &report);
        print_scene_report(source.scene, report);
        return result;
    } catch (const Error&) {
        print_scene_report(source.scene, report);
        throw;
    }
}

PackedLeanMap load_lean_map_and_report(const scene::BumpMapSource& source,
                                       const ShadingSettings& settings) {
    scene::SceneSourceReport report;
    PackedLeanMap map = scene::load_lean_map(source, settings, &report);
    print_scene_report(source.source, report);
    return map;
}

}  // namespace leanfade::cli
