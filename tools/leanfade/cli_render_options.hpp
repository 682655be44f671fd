#pragma once
// Command-line binding of the shading settings, of the LEAN map source and of the GL context,
// shared by the subcommands that render (`render`, `view`, `eval`, `calibrate`, `bench`).
//
// The shading flags are derived from the parameter schema (leanfade/core/detail/parameters.hpp): one
// flag per row, named by flag_for_setting (cli_flags.hpp). CLI11 parses every flag into the typed
// structs below once (cli_text.hpp: add_typed_option); the ranges are checked by the libraries
// that own them (validate, check_texture_size, ...), whose leanfade::Error(setting, cause) the
// subcommand reports as one line with the setting's flag.
#include <cstdint>
#include <functional>
#include <map>
#include <string>

#include <CLI/CLI.hpp>

#include "cli_text.hpp"
#include "leanfade/core/detail/bump_source.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/settings.hpp"
#include "leanfade/core/technique.hpp"
#include "leanfade/gl/detail/context.hpp"
#include "leanfade/gl/shader_library.hpp"
#include "leanfade/scene/detail/map_kinds.hpp"
#include "leanfade/scene/scene_source.hpp"

namespace leanfade::cli {

// The flag of a surface map kind that a rendering command takes ("--roughness-map"): `--` and the
// setting of its row in scene::kMapKinds.
std::string map_flag(scene::MapKind kind);

struct ShadingFlags {
    // Every flag of the schema writes its field (vectors "x,y,z", colours also one value for
    // grey, choices by name) when CLI11 parses it.
    ShadingSettings settings;
};

// One flag per row of the parameter schema, in the "Shading" group.
void add_shading_options(CLI::App& app, ShadingFlags& flags);
// The settings of the flags, validated (leanfade::validate).
ShadingSettings resolve_shading(const ShadingFlags& flags);
// `settings` for every row of the schema whose flag was not given on the command line (a
// preset's or a scene's shading under the flags).
void set_shading_defaults(const ShadingSettings& settings, const CLI::App& app,
                          ShadingFlags& flags);

// The plane scene's light unless --light-dir is given: near the mirror direction of the view
// (-v.x, 1.15 v.y, -v.z of the unit view direction), so that the flat ground of any map shows its
// glint. The default light of the other scenes lights them from the upper left.
glm::vec3 plane_glint_light(glm::vec3 view_dir);
void apply_scene_light(ShadingFlags& flags, const CLI::App& app, const std::string& scene,
                       glm::vec3 view_dir);

// --bumps --from --directx --strict-normals --bits --strength-unit --spike --seed --texture-size
// --max-size, in the "Bumps" group, and --roughness-map and --roughness-mips: the bump source of
// the scene (leanfade/scene/scene_source.hpp).
void add_lean_source_options(CLI::App& app, scene::BumpMapSource& flags);

// A comma-separated list of techniques, parsed by parse_techniques (leanfade/core/technique.hpp)
// naming `flag`; the help shows the list's initial value as the default (none when empty).
CLI::Option* add_techniques_option(CLI::App& app, const std::string& flag,
                                   std::vector<Technique>& techniques, const std::string& help);
// A WIDTHxHEIGHT flag (parse_size), its initial value the default.
CLI::Option* add_size_option(CLI::App& app, const std::string& flag, FramebufferSize& size,
                             const std::string& help);

// --distances of eval and calibrate: a sweep "A:B:N" or a comma list (eval::parse_distance_sweep),
// `default_text` the default the help shows.
CLI::Option* add_distance_sweep_option(CLI::App& app, std::vector<float>& distances,
                                       const std::string& help, const std::string& default_text);

// The camera flags of render, view, eval and calibrate: --fov (vertical, degrees, checked by
// check_field_of_view when parsed) and --view-dir (world space, from `view_from` toward the eye,
// not the zero vector), and --target (world units) when `target` is given.
void add_camera_options(CLI::App& app, float& fov, glm::vec3& view_dir, const char* view_from,
                        glm::vec3* target = nullptr);
// --ref-samples: k x k supersamples per pixel of the reference, in [1, kMaxReferenceSamples].
void add_reference_samples_option(CLI::App& app, int& ref_samples);
// --view-dir: "x,y,z", not the zero vector (world space, toward the eye).
glm::vec3 parse_view_direction(const std::string& text);
// --ref-samples: k of the k x k supersampled reference, returned when in [1, 16]; throws Error.
int checked_reference_samples(int k);

struct GlFlags {
    std::string shader_dir;  // empty = the shaders compiled into the binary
    int egl_device = -1;     // -1 = LEANFADE_EGL_DEVICE or automatic
};
// --shader-dir --egl-device, in the "OpenGL" group.
void add_gl_options(CLI::App& app, GlFlags& flags);
// The context options of the flags (--egl-device; the other options at their defaults).
gl::ContextOptions context_options(const GlFlags& flags);
// The shaders of the flags: read from --shader-dir, else the copies compiled into the binary.
gl::ShaderSources shader_sources(const GlFlags& flags);

}  // namespace leanfade::cli
