#pragma once
// The shading parameters of leanfade, described once: each row names a field of ShadingSettings
// (leanfade/core/settings.hpp) with its type, range, unit, help text and the equation it enters.
// validate(ShadingSettings), the preset keys (leanfade/core/detail/preset.hpp), the command-line options
// of `render`, `view`, `eval`, `calibrate` and `bench` (tools/leanfade/cli_render_options.cpp)
// and the viewer's widgets (viewer/src/panel.cpp) are derived from these rows.
//
// Adding a parameter: a field in ShadingSettings, a row here, and its use in the shader
// (LfParams in shaders/lean_shading.glsl, filled by to_lf_params).
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

namespace leanfade {

struct ShadingSettings;

enum class ParameterKind {
    Scalar,     // float in [min, max] ((min, max] when min_exclusive)
    Integer,    // int in [min, max]
    Colour,     // linear RGB, each component in [min, max]
    Direction,  // a vector of any non-zero length (normalised at use)
    Choice,     // one of `choices`
};

struct ParameterInfo {
    std::string_view key{};    // the setting's name: its preset key and the name errors give
    ParameterKind kind{};
    std::string_view group{};  // "Light", "Material", "Fresnel", "Fading", "Fog", "Texturing"
    std::string_view label{};  // for people (the viewer)
    std::string_view unit{};   // "" when dimensionless
    std::string_view help{};   // one line
    std::string_view equation{};  // where it enters the math ("" when nowhere in particular)
    float min = 0.0f;
    float max = 0.0f;
    bool min_exclusive = false;
    bool nonzero = false;      // 0 is refused (a signed value whose sign means something)
    bool logarithmic = false;  // spans decades: a widget should move it on a log scale
    float ui_min = 0.0f;       // the range a widget offers (within [min, max]); for directions,
    float ui_max = 0.0f;       // each component's
    // Exactly one accessor, by kind.
    float ShadingSettings::*scalar = nullptr;
    int ShadingSettings::*integer = nullptr;
    glm::vec3 ShadingSettings::*vector = nullptr;
    std::span<const std::string_view> choices{};
    int (*get_choice)(const ShadingSettings&) = nullptr;
    void (*set_choice)(ShadingSettings&, int) = nullptr;
};

// Every shading parameter, in the order of help texts and presets.
std::span<const ParameterInfo> shading_parameters();
// The groups of shading_parameters(), each once, in the order they first appear in the table.
std::vector<std::string_view> parameter_groups();
// The row of `key`, or nullptr.
const ParameterInfo* find_shading_parameter(std::string_view key);

// The row's value as text ("0.15", "1,0.9,0.8", "eye"), as a command line or a preset writes it.
std::string format_parameter(const ParameterInfo& row, const ShadingSettings& settings);
// Sets the row's field from text as format_parameter writes it (a colour also takes one value
// for grey). Throws leanfade::Error(row.key, cause) for text that is not such a value; the range
// is validate()'s.
void parse_parameter(const ParameterInfo& row, const std::string& text, ShadingSettings& settings);

// Throws leanfade::Error(row.key, cause) when the row's value is not finite or outside its range.
void validate_parameter(const ParameterInfo& row, const ShadingSettings& settings);

}  // namespace leanfade
