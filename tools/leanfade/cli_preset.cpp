// Presets on the command line: preset values for the flags not given (cli_preset.hpp).
#include "cli_preset.hpp"

#include <algorithm>

#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/scene/detail/map_kinds.hpp"

namespace leanfade::cli {

bool given(const CLI::App& app, const std::string& flag) {
    return app.count(flag) > 0;
}

namespace {

// The preset key of a map kind that the rendering commands take as a flag: its row's setting with
// '_' for '-' ("roughness_map"), as the other keys of a preset.
std::string map_setting_key(scene::MapKind kind) {
    std::string setting(scene::info(kind).setting);
    std::replace(setting.begin(), setting.end(), '-', '_');
    return setting;
}

// The preset keys of the map kinds the rendering commands take as flags (the rows with a setting).
std::string map_setting_keys() {
    std::string keys;
    for (const scene::MapKindInfo& row : scene::kMapKinds)
        if (!row.setting.empty()) keys += (keys.empty() ? "" : ", ") + map_setting_key(row.kind);
    return keys;
}

}  // namespace

void set_source_defaults(const Preset& preset, const std::string& file, const CLI::App& app,
                         RenderSourceFlags& flags, ShadingFlags& shading) {
    set_unless_given(app, "--scene", flags.scene, preset.scene);
    scene::BumpMapSource& b = flags.bumps;
    set_unless_given(app, "--bumps", b.source, preset.bumps.source);
    set_unless_given(app, "--from", b.from, preset.bumps.from);
    set_unless_given(app, "--directx", b.directx, preset.bumps.directx);
    set_unless_given(app, "--bits", b.bits, preset.bumps.bits);
    set_unless_given(app, "--seed", b.seed, preset.bumps.seed);
    set_unless_given(app, "--texture-size", b.texture_size, preset.bumps.texture_size);
    // The preset's layers unless the command line gives its own (or --bumps: one map); the
    // layer flags given change them.
    if (!given(app, "--layers") && !given(app, "--bumps")) {
        LayerSettings& l = flags.layers;
        l.sources = preset.layers.sources;
        set_unless_given(app, "--layer-weights", l.weights, preset.layers.weights);
        set_unless_given(app, "--layer-strengths", l.strengths, preset.layers.strengths);
        set_unless_given(app, "--layer-tiling", l.tiling, preset.layers.tiling);
        set_unless_given(app, "--layer-velocity", l.velocity, preset.layers.velocity);
        set_unless_given(app, "--layer-weight-map", l.weight_map, preset.layers.weight_map);
        set_unless_given(app, "--mixing", l.mixing, preset.layers.mixing);
    }
    for (const MapFile& map : preset.maps) {
        const scene::MapKindInfo* known = nullptr;
        for (const scene::MapKindInfo& row : scene::kMapKinds)
            if (!row.setting.empty() && map.kind == map_setting_key(row.kind)) known = &row;
        if (known == nullptr)
            throw Error(file, "key 'maps." + escape_text(map.kind) + "': unknown map (expected " +
                                  map_setting_keys() + ")");
        set_unless_given(app, map_flag(known->kind), b.map_file(known->kind), map.path);
    }
    set_shading_defaults(preset.shading, app, shading);
}

void set_preset_source(const RenderSourceFlags& flags, Preset& preset) {
    preset.scene = flags.scene;
    preset.bumps = flags.bumps;  // the BumpSource part of the flags
    preset.layers = flags.layers;
    preset.maps.clear();
    for (const scene::MapKindInfo& row : scene::kMapKinds)
        if (!row.setting.empty() && !flags.bumps.map_file(row.kind).empty())
            preset.maps.push_back({map_setting_key(row.kind), flags.bumps.map_file(row.kind)});
}

}  // namespace leanfade::cli
