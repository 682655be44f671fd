#pragma once
// Command-line binding of the shading settings, of the LEAN map source and of the GL context,
// shared by the subcommands that render (`render`, `view`, `eval`, `calibrate`, `bench`).
//
// The shading flags are derived from the parameter schema (leanfade/core/parameters.hpp): one
// flag per row, named by flag_for_setting (cli_flags.hpp). Flags are parsed by CLI11 into the
// structs below; resolve_*() then converts the text values (vectors, names) and validates ranges,
// throwing leanfade::Error(setting, cause), which the subcommand reports as one line with the
// setting's flag.
#include <cstdint>
#include <functional>
#include <map>
#include <string>

#include <CLI/CLI.hpp>

#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/settings.hpp"
#include "leanfade/gl/context.hpp"
#include "leanfade/gl/shader_library.hpp"
#include "leanfade/scene/map_kinds.hpp"

namespace leanfade::cli {

// The flag of a surface map kind that a rendering command takes ("--roughness-map"): `--` and the
// setting of its row in scene::kMapKinds.
std::string map_flag(scene::MapKind kind);

struct ShadingFlags {
    ShadingSettings settings;  // scalar and integer flags are bound to its fields directly
    // Text of the vector and choice flags by parameter key ("x,y,z", "eye"; colours also accept
    // one value for grey); empty = the settings' value.
    std::map<std::string, std::string, std::less<>> text;
};

// One flag per row of the parameter schema, in the "Shading" group.
void add_shading_options(CLI::App& app, ShadingFlags& flags);
// The settings with the text flags applied; validated (leanfade::validate).
ShadingSettings resolve_shading(const ShadingFlags& flags);

struct LeanSourceFlags {
    std::string bumps = "bumps";  // built-in set name, image file, or .ktx2 from `leanfade bake`
    bool bumps_given = false;     // --bumps on the command line (an OBJ's MTL bumps otherwise)
    std::string from = "auto";    // images: auto | height | normal (auto: by channel count)
    bool directx = false;         // normal maps in the DirectX convention
    bool strict_normals = false;  // normal maps: refuse texels with z <= 0 (NormalRepairs)
    std::string bits = "auto";    // on-the-fly bakes: auto | 8 | 16 | 16f | 32f (auto: as bake)
    std::string strength_unit = "texel";  // height maps: texel | uv (as bake's --strength-unit)
    std::uint32_t seed = 1;       // built-in sets
    int texture_size = 256;       // built-in sets, texels per side
    int max_size = kDefaultMaxImageDimension;  // --max-size: images and .ktx2 maps, per side
    // --roughness-map: Cook-Torrance's base roughness per texel, a grey image of perceptual r in
    // [0, 1] or a glTF metallic-roughness texture (r in G), on the material of --bumps or
    // --layers (load_render_scene); empty: the uniform --roughness.
    std::string roughness_map;
};

// --bumps --from --directx --strict-normals --bits --strength-unit --seed --texture-size --max-size, in the
// "Bumps" group, and --roughness-map.
void add_lean_source_options(CLI::App& app, LeanSourceFlags& flags);
// The size of a built-in bump set (--texture-size, or a preset's bumps.texture_size): 4 to
// kDefaultMaxImageDimension texels per side and, when a built-in set is made at that size
// (`builtin`: the --bumps or a --layers source is one, or the ocean's waves), at most --max-size
// as an image's size is. Throws Error("--texture-size", ...).
void check_texture_size(int texture_size, int max_size, bool builtin);
// True for the name of a built-in bump set.
bool is_builtin_bumps(const std::string& source);
// The storage of on-the-fly bakes: --bits, with auto first baked as 16-bit UNORM (a map with
// outliers beyond sc is baked again as 16f by load_lean_map, as `leanfade bake` does).
Storage on_the_fly_storage(const LeanSourceFlags& flags);
// BakeOptions of on-the-fly bakes: strength (settings.bump_strength) in --strength-unit, the
// normal-map convention and --strict-normals.
BakeOptions on_the_fly_bake_options(const LeanSourceFlags& flags, const ShadingSettings& settings);
// Reads a .ktx2 LEAN map (recognised by its extension), or bakes one from a built-in set or an
// image with `settings.bump_strength`. Throws leanfade::Error naming the file or flag.
PackedLeanMap load_lean_map(const LeanSourceFlags& flags, const ShadingSettings& settings);

// The camera flags of render, view, eval and calibrate: --fov (vertical, degrees) and
// --view-dir (world space, from `view_from` toward the eye), and --target (world units) when
// `target` is given. Checked where they are used (cli_preset.hpp).
void add_camera_options(CLI::App& app, float& fov, std::string& view_dir, const char* view_from,
                        std::string* target = nullptr);
// --ref-samples: k x k supersamples per pixel of the reference.
void add_reference_samples_option(CLI::App& app, int& ref_samples);

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

// "3,6,18" -> {3, 6, 18}; every value finite and > 1 (bounding radii). Throws Error(flag, ...).
std::vector<float> parse_distances(const std::string& text, const std::string& flag);
// "400x300" -> {400, 300}; each in [16, 8192]. Throws Error(flag, ...).
std::pair<int, int> parse_size(const std::string& text, const std::string& flag);

}  // namespace leanfade::cli
