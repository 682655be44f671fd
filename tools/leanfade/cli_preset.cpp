// Presets on the command line: preset values as flag defaults, explicit flags on top.
#include "cli_preset.hpp"

#include <charconv>
#include <cmath>
#include <cstdlib>

#include "leanfade/core/error.hpp"
#include "leanfade/core/input_text.hpp"
#include "leanfade/core/text.hpp"
#include "leanfade/gl/renderer.hpp"
#include "leanfade/core/technique.hpp"
#include "leanfade/core/camera.hpp"

namespace leanfade::cli {

void set_shading_flags(const ShadingSettings& settings, ShadingFlags& flags) {
    flags.settings = settings;
    // Empty text flags keep flags.settings' values (see resolve_shading).
    for (auto& [key, text] : flags.text) text.clear();
}

void set_source_flags(const BumpSource& source, LeanSourceFlags& flags) {
    flags.bumps = source.source;
    flags.from = source.from;
    flags.directx = source.directx;
    flags.bits = source.bits;
    flags.seed = source.seed;
    flags.texture_size = source.texture_size;
}

BumpSource to_bump_source(const LeanSourceFlags& flags) {
    BumpSource source;
    source.source = flags.bumps;
    source.from = flags.from;
    source.directx = flags.directx;
    source.bits = flags.bits;
    source.seed = flags.seed;
    source.texture_size = flags.texture_size;
    return source;
}

void reapply_explicit_options(CLI::App& app) {
    for (CLI::Option* option : app.get_options())
        if (option->count() > 0) option->run_callback();
}

void check_preset_techniques(const Preset& preset, const std::string& file) {
    for (const std::string& name : preset.techniques) {
        try {
            gl::parse_technique(name, file + ": key 'view.techniques'");
        } catch (const Error& error) {  // the name is text of the file: escaped
            throw Error(error.file(), escape_text(error.cause(), 2000));
        }
    }
}

std::string number_text(float value) { return shortest_text(value); }

std::string vector_text(const glm::vec3& v) {
    return number_text(v.x) + "," + number_text(v.y) + "," + number_text(v.z);
}

std::string join(const std::vector<std::string>& names) {
    std::string text;
    for (const std::string& n : names) text += (text.empty() ? "" : ",") + n;
    return text;
}

glm::vec3 parse_vector(const std::string& text, const std::string& flag) {
    glm::vec3 v(0.0f);
    std::size_t start = 0;
    for (int i = 0; i < 3; ++i) {
        const std::size_t comma = text.find(',', start);
        const bool last = i == 2;
        if ((comma == std::string::npos) != last)
            throw Error(flag, "expected X,Y,Z, got '" + text + "'");
        const std::string part = text.substr(start, last ? std::string::npos : comma - start);
        const std::optional<float> value = parse_finite_float(part);
        if (!value) throw Error(flag, "expected X,Y,Z, got '" + text + "'");
        v[i] = *value;
        start = comma + 1;
    }
    return v;
}

glm::vec3 parse_view_direction(const std::string& text) {
    const glm::vec3 direction = parse_vector(text, "--view-dir");
    if (direction == glm::vec3(0.0f)) throw Error("--view-dir", "must not be the zero vector");
    return direction;
}

float checked_fov(float degrees) {
    check_field_of_view(degrees, "--fov");
    return degrees;
}

int checked_reference_samples(int k) {
    if (k < 1 || k > kMaxReferenceSamples)
        throw Error("--ref-samples", "must be in [1, " + std::to_string(kMaxReferenceSamples) +
                                         "], got " + std::to_string(k));
    return k;
}

}  // namespace leanfade::cli
