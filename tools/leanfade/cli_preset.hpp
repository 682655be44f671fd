#pragma once
// Presets on the command line (`render --preset FILE`, `view --preset FILE`): the preset sets the
// defaults, and every flag given explicitly overrides it.
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/vec3.hpp>

#include "cli_render_options.hpp"
#include "leanfade/core/preset.hpp"

namespace leanfade::cli {

// The flags' values that reproduce these settings and this bump source.
void set_shading_flags(const ShadingSettings& settings, ShadingFlags& flags);
void set_source_flags(const BumpSource& source, LeanSourceFlags& flags);
// The bump source the flags describe.
BumpSource to_bump_source(const LeanSourceFlags& flags);

// Runs again the callback of every option given on the command line, so that explicit flags win
// over values a preset wrote into the bound variables after parsing.
void reapply_explicit_options(CLI::App& app);

// Checks a preset's technique names; throws Error("<file>: key 'view.techniques'", cause).
void check_preset_techniques(const Preset& preset, const std::string& file);

// The shortest text that reads back as the same float ("0.15", "3", "1e-05").
std::string number_text(float value);
// "x,y,z" with number_text components.
std::string vector_text(const glm::vec3& v);
// "a,b,c".
std::string join(const std::vector<std::string>& names);
// "x,y,z" -> vector; throws Error(flag, cause).
glm::vec3 parse_vector(const std::string& text, const std::string& flag);
// --view-dir: "x,y,z", not the zero vector (world space, toward the eye); throws Error.
glm::vec3 parse_view_direction(const std::string& text);
// --fov: the vertical field of view in degrees, returned when in (1, 170); throws Error otherwise.
float checked_fov(float degrees);
// --ref-samples: k of the k x k supersampled reference, returned when in [1, 16]; throws Error.
int checked_reference_samples(int k);

}  // namespace leanfade::cli
