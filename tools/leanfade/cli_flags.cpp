// Settings -> flags (cli_flags.hpp).
#include "cli_flags.hpp"

#include <algorithm>
#include <cstdio>
#include <utility>

#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/core/detail/parameters.hpp"
#include "leanfade/scene/gltf.hpp"
#include "leanfade/scene/detail/map_kinds.hpp"

namespace leanfade::cli {
namespace {

// Settings outside the shading schema that the libraries name: camera, sweep and benchmark
// settings, the built-in bump sets and the bump layers (leanfade/core/detail/layers.hpp, whose setting
// names are their flags' already).
constexpr std::string_view kOtherSettings[] = {
    "techniques", "distances", "spp", "frames", "motion", "size", "timing", "warmup", "scenes",
    "fov", "view_dir", "target", "ref_samples", "builtin", "bits", "from", "texture_size",
    "max_size",
    "layers", "layer-weights", "layer-strengths", "layer-tiling", "layer-velocity",
    "layer-weight-map", "strict_normals", "lang", "compress", "ocean_layers", "flow",
    "bake_roughness",
};

// The surface maps' settings ("roughness-map"), from the map kinds' table.
bool is_map_setting(std::string_view name) {
    for (const scene::MapKindInfo& row : scene::kMapKinds)
        if (!row.setting.empty() && row.setting == name) return true;
    return false;
}

// Flags whose names are shorter than their settings'.
constexpr std::pair<std::string_view, std::string_view> kShortFlags[] = {
    {"light_direction", "--light-dir"},
    {"bump_strength", "--strength"},
    {"anisotropy", "--aniso"},
};

}  // namespace

std::string flag_for_setting(std::string_view name) {
    for (const auto& [setting, flag] : kShortFlags)
        if (name == setting) return std::string(flag);
    const bool known = find_shading_parameter(name) != nullptr || is_map_setting(name) ||
                       std::find(std::begin(kOtherSettings), std::end(kOtherSettings), name) !=
                           std::end(kOtherSettings);
    if (!known) return {};
    std::string flag = "--" + std::string(name);
    std::replace(flag.begin(), flag.end(), '_', '-');
    return flag;
}

namespace {

// `text` with "set 'NAME' to 'VALUE'" turned into "use --flag VALUE" and any other quoted
// 'NAME' of a setting into its flag.
std::string quoted_settings_as_flags(const std::string& text) {
    std::string out;
    std::size_t i = 0;
    while (i < text.size()) {
        const std::size_t open = text.find('\'', i);
        const std::size_t close = open == std::string::npos ? open : text.find('\'', open + 1);
        if (close == std::string::npos) break;
        const std::string flag = flag_for_setting(text.substr(open + 1, close - open - 1));
        if (flag.empty()) {
            out.append(text, i, close - i);  // the closing quote may open the next name
            i = close;
            continue;
        }
        std::size_t start = open, end = close + 1;
        std::string replacement = flag;
        constexpr std::string_view kSet = "set ", kTo = " to '";
        if (start >= kSet.size() && text.compare(start - kSet.size(), kSet.size(), kSet) == 0 &&
            text.compare(end, kTo.size(), kTo) == 0) {
            const std::size_t value_end = text.find('\'', end + kTo.size());
            if (value_end != std::string::npos) {
                start -= kSet.size();
                replacement = "use " + flag + " " +
                              text.substr(end + kTo.size(), value_end - end - kTo.size());
                end = value_end + 1;
            }
        }
        out.append(text, i, start - i);
        out += replacement;
        i = end;
    }
    out.append(text, i, std::string::npos);
    return out;
}

}  // namespace

Error with_flag_name(const Error& error) {
    const std::string flag = flag_for_setting(error.file());
    const std::string cause = quoted_settings_as_flags(error.cause());
    return Error(flag.empty() ? error.file() : flag, cause);
}

std::string convention_warning(const std::string& name, bool directx, double ratio) {
    char text[64];
    std::snprintf(text, sizeof text, "%.3g", ratio);
    return name + " looks like " + (directx ? "an OpenGL (+Y)" : "a DirectX (-Y)") +
           " normal map (its slopes fit a height field " + text +
           " times better with green flipped); " +
           (directx ? "bake it without --directx if its bumps look lit from the wrong side"
                    : "bake it with --directx if its bumps look lit from the wrong side");
}

std::string normal_repairs_note(const std::string& name, const NormalRepairs& repairs) {
    std::string note = name + ": ";
    if (repairs.padding_texels > 0)
        note += std::to_string(repairs.padding_texels) + " (0, 0, 0) padding texels taken as flat";
    if (repairs.padding_texels > 0 && repairs.raised_texels > 0) note += ", ";
    if (repairs.raised_texels > 0)
        note += std::to_string(repairs.raised_texels) + " texels with z <= 0 raised";
    return note + " (--strict-normals refuses them)";
}

// glTF normal textures are OpenGL (+Y) by the specification: --directx does not apply.
std::string gltf_convention_warning(const std::string& image) {
    return "warning: " + image +
           " looks like a DirectX (-Y) normal map (its slopes fit a height field clearly better "
           "with green flipped), but glTF normal textures are OpenGL (+Y): if its bumps look lit "
           "from the wrong side, flip the texture's green channel";
}

void print_scene_report(const std::string& scene_file, const scene::SceneSourceReport& report) {
    auto print = [](const std::string& line) {
        std::fprintf(stderr, "leanfade: %s\n", terminal_text(line).c_str());
    };
    for (const std::string& warning : report.warnings) print(scene_file + ": " + warning);
    // A glTF scene's normal textures are named by the image, within the scene file.
    const std::string image_context = scene::is_gltf_path(scene_file) ? scene_file + ": " : "";
    for (const auto& [file, repairs] : report.repaired)
        print(image_context + normal_repairs_note(file, repairs));
    for (const scene::ConventionDoubt& doubt : report.doubts)
        print(doubt.gltf ? scene_file + ": " + gltf_convention_warning(doubt.file)
                         : "warning: " + convention_warning(doubt.file, doubt.read_as_directx,
                                                            doubt.ratio));
}

}  // namespace leanfade::cli
