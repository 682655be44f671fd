#pragma once
// Presets on the command line (`render --preset FILE`, `view --preset FILE`): the preset's typed
// values stand in for every flag that is not given on the command line.
#include <string>

#include <CLI/CLI.hpp>

#include "cli_render_scene.hpp"
#include "leanfade/core/detail/preset.hpp"

namespace leanfade::cli {

// Whether `flag` was given on the command line.
bool given(const CLI::App& app, const std::string& flag);
// `target = value` unless `flag` was given.
template <typename T>
void set_unless_given(const CLI::App& app, const std::string& flag, T& target, const T& value) {
    if (!given(app, flag)) target = value;
}

// The preset's scene, bump source, layers, surface maps and shading under the flags given.
// Throws Error(file, "key 'maps.NAME': ...") for a map kind the rendering commands do not take.
void set_source_defaults(const Preset& preset, const std::string& file, const CLI::App& app,
                         RenderSourceFlags& flags, ShadingFlags& shading);
// The scene, bump source, layers and surface maps of the flags, into `preset`.
void set_preset_source(const RenderSourceFlags& flags, Preset& preset);

}  // namespace leanfade::cli
