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

// Flags whose names are shorter than their settings'.
constexpr std::pair<std::string_view, std::string_view> kShortFlags[] = {
    {"light_direction", "--light-dir"},
    {"bump_strength", "--strength"},
    {"anisotropy", "--aniso"},
};

}  // namespace

std::string flag_for_setting(std::string_view id) {
    if (id.empty() || id.substr(0, 2) == "--") return std::string(id);  // a flag already
    for (const auto& [setting, flag] : kShortFlags)
        if (id == setting) return std::string(flag);
    std::string flag = "--" + std::string(id);
    std::replace(flag.begin(), flag.end(), '_', '-');
    return flag;
}

Error with_flag_name(const Error& error) {
    // The settings the cause quotes, as the library listed them: 'id' -> --flag.
    std::string cause = error.cause();
    for (const std::string& id : error.mentioned_settings()) {
        const std::string quoted = "'" + id + "'", flag = flag_for_setting(id);
        for (std::size_t at = cause.find(quoted); at != std::string::npos;
             at = cause.find(quoted, at + flag.size()))
            cause.replace(at, quoted.size(), flag);
    }
    const std::string subject =
        error.kind() == ErrorKind::Setting ? flag_for_setting(error.setting()) : error.file();
    return Error(error.kind(), subject, cause, {});
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
