// Settings -> flags (cli_flags.hpp).
#include "cli_flags.hpp"

#include <algorithm>
#include <utility>

#include "leanfade/core/parameters.hpp"

namespace leanfade::cli {
namespace {

// Settings outside the shading schema that the libraries name: camera, sweep and benchmark
// settings, the built-in bump sets and the bump layers (leanfade/core/layers.hpp, whose setting
// names are their flags' already).
constexpr std::string_view kOtherSettings[] = {
    "techniques", "distances", "spp", "frames", "motion", "size", "timing", "warmup", "scenes",
    "fov", "view_dir", "target", "ref_samples", "builtin", "bits", "from",
    "layers", "layer-weights", "layer-strengths", "layer-tiling", "layer-velocity",
    "layer-weight-map",
};

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
    const bool known = find_shading_parameter(name) != nullptr ||
                       std::find(std::begin(kOtherSettings), std::end(kOtherSettings), name) !=
                           std::end(kOtherSettings);
    if (!known) return {};
    std::string flag = "--" + std::string(name);
    std::replace(flag.begin(), flag.end(), '_', '-');
    return flag;
}

Error with_flag_name(const Error& error) {
    const std::string flag = flag_for_setting(error.file());
    return flag.empty() ? error : Error(flag, error.cause());
}

}  // namespace leanfade::cli
